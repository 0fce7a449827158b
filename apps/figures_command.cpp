// `pilelab figures`: the figures of a run's outputs (scripts/figures.py), and with --paraview the
// ParaView pictures (scripts/paraview_pictures.py, under a virtual X display).
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "apps/child_process.h"
#include "apps/commands.h"
#include "common/error.h"
#include "common/output_lock.h"

namespace pilelab::app {

namespace {

// The program's path on PATH, or "".
std::string on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::filesystem::path candidate = std::filesystem::path(dir.empty() ? "." : dir) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return "";
}

// Runs a figure script; its exit code 2 (a folder it cannot write) is the user's to fix.
void run_script(const std::vector<std::string>& argv, bool quiet) {
  const int code = wait_for_child(start_child(argv, quiet ? "/dev/null" : ""));
  if (code == 0) return;
  std::string command;
  for (const std::string& a : argv) command += (command.empty() ? "" : " ") + a;
  const std::string message = "figures: " + command + " failed (exit code " + std::to_string(code) + ")";
  if (code == 2) throw InputError(message + ": see its message above");
  throw std::runtime_error(message);
}

}  // namespace

void draw_figures(const std::string& out_dir, const FigureOptions& options) {
  const std::string scripts = std::string(PILELAB_SOURCE_DIR) + "/scripts/";
  const std::string python = "/usr/bin/python3", script = scripts + "figures.py";
  if (!std::filesystem::exists(python) || !std::filesystem::exists(script)) {
    if (!options.required) return;  // `pilelab run` draws them where it can
    throw InputError("figures: " + python + " and " + script + " are needed (Debian: python3-matplotlib, python3-h5py)");
  }
  run_script({python, script, out_dir}, options.quiet);
  if (!options.paraview) return;
  const std::string pvpython = on_path("pvpython"), xvfb_run = on_path("xvfb-run");
  if (pvpython.empty())
    throw InputError("figures --paraview: pvpython is not on PATH (Debian: python3-paraview)");
  // ParaView 5.11 renders only through an X display: a virtual one unless the session has one.
  std::vector<std::string> argv = {pvpython, scripts + "paraview_pictures.py", out_dir};
  if (!std::getenv("DISPLAY")) {
    if (xvfb_run.empty()) throw InputError("figures --paraview: no X display and no xvfb-run (Debian: xvfb)");
    argv.insert(argv.begin(), {xvfb_run, "-a", "-s", "-screen 0 1920x1080x24"});
  }
  run_script(argv, options.quiet);
}

void add_figures_command(CLI::App& app) {
  auto out_dir = std::make_shared<std::string>();
  auto options = std::make_shared<FigureOptions>();
  options->required = true;
  CLI::App* cmd = app.add_subcommand(
      "figures", "Draw the figures of a run's outputs into OUT/figures (scripts/figures.py: PNG, PDF and SVG);\n"
                 "with --paraview also the ParaView pictures of the force network and the stress field\n"
                 "(scripts/paraview_pictures.py, under xvfb-run when there is no X display). `pilelab run` draws\n"
                 "the first kind itself.");
  cmd->add_option("out", *out_dir, "A run's output directory")->required()->check(CLI::ExistingDirectory);
  cmd->add_flag("--paraview", options->paraview, "Also the ParaView pictures (needs pvpython, and xvfb-run without a display)");
  cmd->add_flag("-q,--quiet", options->quiet, "No output from the scripts");
  cmd->final_callback([out_dir, options] {
    const OutputLock lock(*out_dir, "pilelab figures " + *out_dir);
    draw_figures(*out_dir, *options);
  });
}

}  // namespace pilelab::app
