// `pilelab run`: the stages a scene asks for, in order (dem, mesh, coarse, solve, compare,
// figures). A stage runs when its table is in the scene; it is skipped, and says so, when its
// table and its input files are unchanged since its outputs were written (OUT/stages.json
// keeps a fingerprint per stage); --force runs every stage.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "coarse/coarse_run.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "common/scene_reader.h"
#include "compare/compare_run.h"
#include "dem/pile_run.h"
#include "mesh/mesh_run.h"
#ifdef PILELAB_WITH_CONTINUUM
#include "continuum/solve.h"
#endif

namespace pilelab::app {

namespace {

struct RunOptions {
  std::string scene_path;
  std::string out_dir;
  bool force = false;
  bool quiet = false;
  int threads = 0;
};

// FNV-1a, 64 bit: a fingerprint, not a security hash.
std::uint64_t fnv1a(const std::string& bytes, std::uint64_t h = 1469598103934665603ULL) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ULL;
  return h;
}

std::string file_fingerprint(const std::string& path) {
  if (!std::filesystem::exists(path)) return "missing";
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return std::to_string(fnv1a(s.str()));
}

struct Stage {
  std::string name;
  std::vector<std::string> tables;   ///< scene tables the stage reads
  std::vector<std::string> inputs;   ///< files in OUT/ it reads
  std::vector<std::string> outputs;  ///< files in OUT/ it writes (all must exist to skip)
  std::function<void()> run;
};

void run_pipeline(const RunOptions& opt) {
  SceneReader scene = SceneReader::from_file(opt.scene_path);
  std::filesystem::create_directories(opt.out_dir);
  const auto out = [&](const std::string& f) { return (std::filesystem::path(opt.out_dir) / f).string(); };
  const std::string state_path = out("stages.json");
  nlohmann::json state = nlohmann::json::object();
  if (std::filesystem::exists(state_path)) {
    try {
      state = nlohmann::json::parse(read_text_file(state_path));
    } catch (const nlohmann::json::exception&) {
      state = nlohmann::json::object();  // unreadable: every stage reruns
    }
  }

  std::vector<Stage> stages;
  stages.push_back({"dem", {"dem"}, {}, {"dem.h5"}, [&] {
                      dem::DemRunOptions o;
                      o.scene_path = opt.scene_path;
                      o.out_dir = opt.out_dir;
                      o.quiet = opt.quiet;
                      o.threads = opt.threads;
                      dem::run_dem(o);
                    }});
  stages.push_back({"mesh", {"mesh"}, {"dem.h5"}, {"pile.msh"}, [&] { mesh::run_mesh({opt.scene_path, opt.out_dir}); }});
  stages.push_back({"coarse", {"coarse"}, {"dem.h5", "pile.msh"}, {"fields.h5", "fields.vtu"},
                    [&] { coarse::run_coarse({opt.scene_path, opt.out_dir}); }});
#ifdef PILELAB_WITH_CONTINUUM
  stages.push_back({"solve", {"continuum", "mesh"}, {"pile.msh", "fields.h5"}, {"models.h5"}, [&] {
                      continuum::SolveOptions o;
                      o.scene_path = opt.scene_path;
                      o.out_dir = opt.out_dir;
                      o.quiet = opt.quiet;
                      continuum::run_solve_command(o);
                    }});
#endif
  stages.push_back({"compare", {"compare"}, {"fields.h5", "models.h5", "profiles.csv"}, {"compare.vtu"},
                    [&] { compare::run_compare({opt.scene_path, opt.out_dir}); }});

  bool upstream_ran = false;
  for (const Stage& stage : stages) {
    if (scene.table_text(stage.tables.front()).empty() && !scene.has(stage.tables.front())) continue;
    auto fingerprint_now = [&] {
      std::string fp;
      for (const auto& t : stage.tables) fp += t + "=" + std::to_string(fnv1a(scene.table_text(t))) + ";";
      for (const auto& f : stage.inputs) fp += f + "=" + file_fingerprint(out(f)) + ";";
      return fp;
    };
    const std::string fingerprint = fingerprint_now();
    bool outputs_present = true;
    for (const auto& f : stage.outputs) outputs_present = outputs_present && std::filesystem::exists(out(f));
    const bool unchanged = state.contains(stage.name) && state[stage.name] == fingerprint && outputs_present;
    if (unchanged && !opt.force && !upstream_ran) {
      std::fprintf(stderr, "pilelab run: %-8s skipped (scene table and inputs unchanged; --force reruns it)\n",
                   stage.name.c_str());
      continue;
    }
    std::fprintf(stderr, "pilelab run: %-8s running\n", stage.name.c_str());
    stage.run();
    upstream_ran = true;
    // The fingerprint after the run: a stage may add to a shared input (compare adds rows to
    // profiles.csv), and must not count its own additions as a change next time.
    state[stage.name] = fingerprint_now();
    write_text_atomically(state_path, state.dump(1));
  }

  // Figures from whatever ran (Debian's python3 with matplotlib and h5py).
  const std::string script = std::string(PILELAB_SOURCE_DIR) + "/scripts/figures.py";
  if (std::filesystem::exists("/usr/bin/python3") && std::filesystem::exists(script)) {
    const std::string cmd = "/usr/bin/python3 '" + script + "' '" + opt.out_dir + "'" + (opt.quiet ? " > /dev/null" : "");
    if (std::system(cmd.c_str()) != 0) throw std::runtime_error("figures: " + cmd + " failed");
  }
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto opt = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand(
      "run", "Run the stages the scene asks for, in order: dem, mesh, coarse, solve, compare, then the figures.\n"
             "A stage runs when its table ([dem], [mesh], [coarse], [continuum], [compare]) is in the scene, and is\n"
             "skipped when its table and input files are unchanged since it last ran (OUT/stages.json).");
  cmd->add_option("scene", opt->scene_path, "Scene file (TOML); see docs/SCENES.md")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", opt->out_dir, "Output directory (created if missing)")->required();
  cmd->add_flag("--force", opt->force, "Run every stage, even those whose inputs have not changed");
  cmd->add_flag("-q,--quiet", opt->quiet, "No progress lines");
  cmd->add_option("-j,--threads", opt->threads, "OpenMP threads for the DEM (default: all cores)")->check(CLI::Range(1, 1024));
  cmd->final_callback([opt] { run_pipeline(*opt); });
}

}  // namespace pilelab::app
