// The pilelab command: one subcommand per stage of the pipeline. Thin by design: each
// subcommand parses its options and calls the library; errors are printed once, plainly.
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "common/error.h"
#include "dem/pile_run.h"

namespace {

void add_dem_command(CLI::App& app, pilelab::dem::DemRunOptions& opt) {
  CLI::App* dem = app.add_subcommand(
      "dem", "Pour a pile from the scene's [dem] section: pour, settle, optional gravity ramp.\n"
             "Writes OUT/dem.h5, OUT/dem.pvd with grains_*.vtu and contacts_*.vtu frames, OUT/checkpoint.h5\n"
             "and the \"dem\" section of OUT/report.json (see docs/FORMAT.md).");
  dem->add_option("scene", opt.scene_path, "Scene file (TOML); see docs/SCENES.md")->required()->check(CLI::ExistingFile);
  dem->add_option("-o,--out", opt.out_dir, "Output directory (created if missing)")->required();
  dem->add_flag("--restart", opt.restart, "Continue from OUT/checkpoint.h5 (bit for bit as if never stopped)");
  dem->add_flag("-q,--quiet", opt.quiet, "No progress lines");
  dem->add_option("-j,--threads", opt.threads, "OpenMP threads for the force loop (default: all cores)")
      ->check(CLI::Range(1, 1024));
  dem->add_option("--stop-after-steps", opt.stop_after_steps,
                  "Write a checkpoint and stop after this many steps (for testing --restart)")
      ->check(CLI::Range(std::int64_t(1), INT64_MAX));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pilelab: 2D sand piles by DEM, coarse-grained and compared with continuum models"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "pilelab 0.1.0");
  pilelab::dem::DemRunOptions dem_options;
  add_dem_command(app, dem_options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (app.got_subcommand("dem")) pilelab::dem::run_dem(dem_options);
  } catch (const pilelab::InputError& e) {
    std::fprintf(stderr, "pilelab: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pilelab: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
