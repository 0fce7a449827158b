// `pilelab run`: the stages a scene asks for, in order (dem, mesh, coarse, solve, compare,
// figures). A stage runs when its table is in the scene; it is skipped, and says so, when its
// table and its input files are unchanged since its outputs were written (OUT/stages.json
// keeps a fingerprint per stage); --force runs every stage.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "apps/child_process.h"
#include "apps/commands.h"
#include "apps/ensemble_members.h"
#include "apps/parallel.h"
#include "apps/run_log.h"
#include "apps/run_status.h"
#include "apps/scene_check.h"
#include "coarse/coarse_run.h"
#include "common/atomic_file.h"
#include "common/ensemble.h"
#include "common/error.h"
#include "common/fields_attributes.h"
#include "common/output_lock.h"
#include "common/report.h"
#include "common/scene_reader.h"
#include "common/scene_tables.h"
#include "compare/compare_run.h"
#include "dem/dem_result.h"
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
  bool restart = false;  ///< the DEM continues from OUT/checkpoint.h5 (members always continue from theirs)
  bool figures = true;   ///< scripts/figures.py after the stages
  int threads = 0;
  int processes = 1;     ///< ensemble members poured side by side as processes
  bool allow_unsettled = false;  ///< a pile unfit for the later stages only warns (apps/run_status.h)
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
  std::vector<std::string> external; ///< files elsewhere it reads (scene path keys), absolute
  std::vector<std::string> outputs;  ///< files in OUT/ it writes (all must exist to skip; none: never skipped)
  bool every_rank = false;           ///< under mpirun, every rank takes part (else rank 0 alone)
  std::function<void()> run;
};

#ifdef PILELAB_WITH_CONTINUUM
// What the solve takes from the stages before it where the scene leaves it open: the bulk
// density and gravity of coarse's fields (OUT/fields.h5), the repose angles of the pile (or the
// members' means).
continuum::MeasuredPile measured_for_solve(const std::string& fields_h5, const std::optional<mesh::Wedge>& pile,
                                           bool poured) {
  continuum::MeasuredPile m;
  if (std::filesystem::exists(fields_h5)) {
    const FieldsAttributes fields = read_fields_attributes(fields_h5);
    if (fields.rho_bulk_kg_per_m2 > 0) m.density_kg_per_m2 = fields.rho_bulk_kg_per_m2;
    if (fields.gravity_m_per_s2 > 0) m.gravity_m_per_s2 = fields.gravity_m_per_s2;
  }
  if (pile) {
    m.left_repose_angle_deg = pile->left_angle_deg;
    m.right_repose_angle_deg = pile->right_angle_deg;
  } else if (poured) {
    m.repose_unmeasured = true;  // a pile, but a flank without an angle
  }
  return m;
}

#endif

// Runs f on rank 0 only, inside a stage every rank takes part in: if it throws, every rank
// learns of it at once (rank 0 rethrows the error, the others report that rank 0 failed), so
// that no rank waits in a collective call that rank 0 never reaches.
template <class F>
void on_root(MpiWorld* world, F&& f) {
  std::exception_ptr error;
  if (!world || world->root()) {
    try {
      f();
    } catch (...) {
      error = std::current_exception();
      if (!world) throw;
    }
  }
  if (!world) return;
  if (world->any(error != nullptr)) {
    if (error) std::rethrow_exception(error);
    throw std::runtime_error("rank 0 failed (its message is in its output)");
  }
}

// The last lines of a run, on stdout: where the results are, and what they cost. The whole
// run's time adds the stages' own wall times from report.json (the DEM's over all its sessions).
void print_summary(const std::string& out_dir, double invocation_s) {
  const auto out = [&](const std::string& f) { return (std::filesystem::path(out_dir) / f).string(); };
  std::string files;
  for (const char* f : {"report.json", "dem.h5", "dem.pvd", "pile.msh", "fields.h5", "fields.vtu", "models.h5",
                        "compare.vtu", "profiles.csv", "figures"})
    if (std::filesystem::exists(out(f))) files += std::string(files.empty() ? "" : ", ") + f;
  double whole = 0;
  if (std::filesystem::exists(out("report.json"))) {
    const nlohmann::json report = read_report(out("report.json"));
    for (const auto& [section, values] : report.items())
      if (values.is_object() && values.contains("wall_time_s") && values["wall_time_s"].is_number())
        whole += section == "ensemble" ? 0.0 : values["wall_time_s"].get<double>();
    if (report.contains("ensemble") && report["ensemble"].contains("members"))
      for (const auto& m : report["ensemble"]["members"])
        if (m.contains("wall_time_s") && m["wall_time_s"].is_number()) whole += m["wall_time_s"].get<double>();
  }
  std::printf("pilelab run: results in %s: %s\n", out_dir.c_str(), files.empty() ? "(none)" : files.c_str());
  std::printf("pilelab run: wall time of this invocation %.1f s; of the whole run, all stages and sessions, %.1f s\n",
              invocation_s, whole);
}

// The pile the later stages work on, as the DEM measured it: one pile's flanks and height, or
// the means over an ensemble's members.
std::optional<mesh::Wedge> measured_pile(const std::string& out_dir, const EnsembleSpec& ensemble) {
  const auto out = [&](const std::string& f) { return (std::filesystem::path(out_dir) / f).string(); };
  if (ensemble.empty()) {
    if (!std::filesystem::exists(out("report.json")) || !read_report(out("report.json")).contains("dem")) return std::nullopt;
    const dem::DemResult d = dem::read_dem_result(out("report.json"));
    if (!d.repose_measured()) return std::nullopt;
    return mesh::Wedge{d.height_m, d.repose_left_deg, d.repose_right_deg, d.apex_x_m};
  }
  std::vector<double> height, left, right, apex;
  for (std::int64_t seed : ensemble.seeds) {
    const dem::DemResult d = dem::read_dem_result((std::filesystem::path(member_directory(out_dir, seed)) / "report.json").string());
    height.push_back(d.height_m);
    left.push_back(d.repose_left_deg);
    right.push_back(d.repose_right_deg);
    apex.push_back(d.apex_x_m);
  }
  const SampleStatistics l = sample_statistics(left), r = sample_statistics(right);
  if (l.count == 0 || r.count == 0) return std::nullopt;
  return mesh::Wedge{sample_statistics(height).mean, l.mean, r.mean, sample_statistics(apex).mean};
}

// The angles the FPA will take (continuum/models/fpa.cpp): the scene's [continuum.fpa] angles
// if it gives any and does not ask for the DEM's, else the measured pile's.
std::optional<std::array<double, 2>> fpa_angles_of(const toml::table& scene, const std::optional<mesh::Wedge>& pile) {
  const auto fpa = scene["continuum"]["fpa"];
  const bool from_dem = fpa["repose_angle_source"].value_or(std::string("scene")) == "dem";
  const std::optional<double> both = fpa["repose_angle_deg"].value<double>();
  const std::optional<double> left = fpa["left_repose_angle_deg"].value<double>();
  const std::optional<double> right = fpa["right_repose_angle_deg"].value<double>();
  if (!from_dem && (both || left || right))
    return std::array<double, 2>{left.value_or(both.value_or(28.0)), right.value_or(both.value_or(28.0))};
  if (pile) return std::array<double, 2>{pile->left_angle_deg, pile->right_angle_deg};
  return std::nullopt;
}

// Runs a stage where it runs (every rank, or rank 0 alone); a stage that failed on one rank
// ends the run on all, with the message where it arose.
void run_on_ranks(const Stage& stage, MpiWorld* world, bool root) {
  if (stage.every_rank || root) {
    bool failed = false;
    std::string message;
    try {
      stage.run();
    } catch (...) {
      if (!world) throw;
      failed = true;
      try {
        throw;
      } catch (const std::exception& e) {
        message = e.what();
      }
    }
    if (world && world->any(failed)) {
      if (failed) throw std::runtime_error(message);
      throw std::runtime_error("stage " + stage.name + " failed on another rank");
    }
  } else if (world) {
    world->any(false);
  }
}

// Figures from whatever ran (Debian's python3 with matplotlib and h5py), by a child that dies
// with this process: a killed run leaves no script writing into OUT.
// The run's status: every pile's findings and the later stages', into report.json and on the
// console; a fail ends the run with exit code 3.
void report_status(const RunOptions& opt, const EnsembleSpec& ensemble, bool stopped) {
  RunStatus status;
  status.allow_unsettled = opt.allow_unsettled;
  assess_piles(opt.out_dir, ensemble, status);
  const std::string report_path = (std::filesystem::path(opt.out_dir) / "report.json").string();
  if (!stopped && std::filesystem::exists(report_path)) assess_later_stages(read_report(report_path), status);
  nlohmann::json section = status.to_json();
  section["later_stages_ran"] = !stopped;
  write_report_section(report_path, "status", section);
  std::fflush(stdout);  // after the summary, whatever the buffering
  std::fprintf(stderr, "pilelab run: status %s", status.level().c_str());
  if (!status.items.empty()) std::fprintf(stderr, " (%zu finding%s):", status.items.size(), status.items.size() == 1 ? "" : "s");
  std::fprintf(stderr, "\n");
  for (const StatusItem& i : status.items)
    std::fprintf(stderr, "  [%s]%s %s\n", i.stage.c_str(), i.fails ? " (fails)" : "", i.message.c_str());
  if (status.level() == "fail")
    throw FailedRun(stopped ? "the pile is unfit for the later stages (see the status above and report.json's \"status\")"
                            : "see the status above and report.json's \"status\"");
}

void run_pipeline(const RunOptions& opt) {
  const auto invocation_start = std::chrono::steady_clock::now();
  // MPI, if a stage starts it, ends with the run (also when a stage throws).
  struct StopMpi {
    ~StopMpi() { MpiWorld::stop(); }
  } stop_mpi;
  check_scene(opt.scene_path);  // every table, before hours of pouring
  SceneReader scene = SceneReader::from_file(opt.scene_path);
  const EnsembleSpec ensemble = read_ensemble_scene(scene);
  scene.reject_unknown({"ensemble"}, scene_tables());
  // Under mpirun every rank runs this function: rank 0 runs the serial stages and decides what
  // runs; the ranks share the ensemble's members and the continuum solve.
  MpiWorld* world = launched_by_mpi() ? &MpiWorld::get() : nullptr;
  const bool root = world == nullptr || world->root();
  // srun without its MPI plugin starts N processes that each think they are alone: N whole
  // runs into the same OUT. srun tells its tasks how many it started (the batch script itself,
  // which may run `pilelab run -P N`, has no step variables).
  const char* tasks = std::getenv("SLURM_STEP_NUM_TASKS");
  if (tasks && std::atoi(tasks) > 1 && (world == nullptr || world->size() == 1))
    throw InputError(std::string("pilelab run: Slurm started ") + tasks +
                     " tasks, but MPI sees this process alone: each would run the whole pipeline into " + opt.out_dir +
                     ". Start the ranks with srun's MPI plugin (srun --mpi=pmix; srun --mpi=list shows the site's), "
                     "or run one task (docs/ENSEMBLES.md)");
  if (!ensemble.empty() && !scene.has("dem"))
    throw InputError(opt.scene_path + ": [ensemble] needs a [dem] table: the members are poured from it");
  // One writer per output folder: rank 0 holds OUT's lock for the whole run (the ranks are one
  // writer; members poured as child processes lock their own folders).
  std::optional<OutputLock> lock;
  if (root) lock.emplace(opt.out_dir, "pilelab run " + opt.scene_path);
  on_root(world, [&] { prepare_output_directory(opt.out_dir); });
  const auto out = [&](const std::string& f) { return (std::filesystem::path(opt.out_dir) / f).string(); };
  // OUT/run.log keeps what the console shows. It lives until the process ends, so that the
  // error main prints after a failed stage is in it too.
  static std::unique_ptr<RunLog> log;
  if (root && (!log || log->path() != out("run.log"))) {
    log.reset();  // a log of another folder gives stdout and stderr back before the new one takes them
    log = std::make_unique<RunLog>(out("run.log"), "pilelab run " + opt.scene_path + " -o " + opt.out_dir);
  }
  const std::string state_path = out("stages.json");
  nlohmann::json state = nlohmann::json::object();
  if (std::filesystem::exists(state_path)) {
    try {
      state = nlohmann::json::parse(read_text_file(state_path));
    } catch (const nlohmann::json::exception&) {
      state = nlohmann::json::object();  // unreadable: every stage reruns
    }
  }

  // Files named in the scene (resolved like the stages resolve them) are inputs too: a changed
  // ensemble member or user mesh must rerun the stage that reads it.
  const toml::table toml_scene = toml::parse_file(opt.scene_path);
  const std::string scene_dir = std::filesystem::path(opt.scene_path).parent_path().string();
  auto scene_paths = [&](const char* table, const char* key) {
    std::vector<std::string> paths;
    auto resolve = [&](const std::string& p) {
      paths.push_back(std::filesystem::path(p).is_absolute() ? p : (std::filesystem::path(scene_dir) / p).string());
    };
    const toml::node_view<const toml::node> v = toml_scene[table][key];
    if (auto s = v.value<std::string>(); s && !s->empty()) resolve(*s);
    if (const toml::array* a = v.as_array())
      for (const auto& e : *a)
        if (auto s = e.value<std::string>()) resolve(*s);
    return paths;
  };
  auto join = [](std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  // An ensemble's members are inputs of every later stage, as OUT/dem.h5 is of one pile's.
  std::vector<std::string> piles = {"dem.h5"}, member_files;
  if (!ensemble.empty()) {
    piles.clear();
    member_files = member_dem_files(ensemble, opt.out_dir);
  }

  // The pile as the DEM measured it (one pile, or the members' means), read once the pour is
  // done, by the first later stage that needs it, and handed to every later stage.
  std::optional<std::optional<mesh::Wedge>> measured;
  const auto pile_measured = [&]() -> const std::optional<mesh::Wedge>& {
    if (!measured) measured = measured_pile(opt.out_dir, ensemble);
    return *measured;
  };

  const auto fpa_angles = [&] { return fpa_angles_of(toml_scene, pile_measured()); };

  // Each stage: its tables, its inputs, its outputs, whether every rank takes part, its action.
  std::vector<Stage> stages;
  if (ensemble.empty()) {
    stages.push_back({"dem", {"dem"}, {}, {}, {"dem.h5"}, false, [&] {
                        dem::DemRunOptions o;
                        o.scene_path = opt.scene_path;
                        o.out_dir = opt.out_dir;
                        o.quiet = opt.quiet;
                        o.threads = opt.threads;
                        o.restart = opt.restart && std::filesystem::exists(out("checkpoint.h5"));
                        if (o.restart && !opt.quiet) std::fprintf(stderr, "pilelab run: dem      continues from its checkpoint\n");
                        dem::run_dem(o);
                      }});
  } else {
    // Every member's own files decide whether it is poured (members already poured are kept),
    // so this stage always looks at them; the summary follows the members.
    stages.push_back({"members", {"dem", "ensemble"}, {}, {}, {}, true, [&] {
                        MemberRunOptions o;
                        o.scene_path = opt.scene_path;
                        o.out_dir = opt.out_dir;
                        o.processes = opt.processes;
                        o.threads = opt.threads;
                        o.quiet = opt.quiet;
                        pour_members(ensemble, o);
                        if (root) write_report_section(out("report.json"), "ensemble", summarize_members(ensemble, opt.out_dir));
                      }});
  }
  stages.push_back({"mesh", {"mesh"}, piles, join(scene_paths("mesh", "dem_file"), member_files), {"pile.msh"}, false, [&] {
                      // The wedge of the pile's flanks and height (an ensemble's: the members'
                      // means) where the scene sets none, or (kind = "dem_outline") the pile's
                      // outline (an ensemble's: the mean outline).
                      mesh::MeshRunOptions o{opt.scene_path, opt.out_dir, std::nullopt, member_files, std::nullopt};
                      o.measured_pile = pile_measured();
                      o.measured_repose_angles_deg = fpa_angles();  // where a DEM outline's rays go
                      mesh::run_mesh(o);
                    }});
  stages.push_back({"coarse", {"coarse"}, join(piles, {"pile.msh"}),
                    join(join(scene_paths("coarse", "dem_files"), scene_paths("coarse", "mesh_file")), member_files),
                    {"fields.h5", "fields.vtu"}, false, [&] {
                      coarse::run_coarse({opt.scene_path, opt.out_dir, member_files});
                    }});
#ifdef PILELAB_WITH_CONTINUUM
  stages.push_back({"solve", {"continuum", "mesh"}, {"pile.msh", "fields.h5"}, scene_paths("continuum", "mesh_file"),
                    {"models.h5"}, true, [&] {
                      MpiWorld::get();  // MPI and PETSc, for this and any later solve
                      // Every rank reads the same files, so every rank hands the same values.
                      continuum::SolveOptions o;
                      o.scene_path = opt.scene_path;
                      o.out_dir = opt.out_dir;
                      o.quiet = opt.quiet;
                      // The run pours its pile (one, or an ensemble's members) or takes one poured elsewhere.
                      const bool poured = !ensemble.empty() || scene.has("dem");
                      o.measured = measured_for_solve(out("fields.h5"), pile_measured(), poured);
                      continuum::run_solve(o);
                    }});
#endif
  stages.push_back({"compare", {"compare"}, {"fields.h5", "models.h5", "profiles.csv"},
                    join(scene_paths("compare", "fields_file"), scene_paths("compare", "models_file")), {"compare.vtu"}, true, [&] {
#ifdef PILELAB_WITH_CONTINUUM
                      MpiWorld::get();  // PETSc, for the fit's closed loop that compare solves on rank 0
#endif
                      on_root(world, [&] {
                        const auto& pile = pile_measured();
                        compare::CompareRunOptions o{opt.scene_path, opt.out_dir, std::nullopt, {}};
                        if (pile) o.measured_repose_angle_deg = 0.5 * (pile->left_angle_deg + pile->right_angle_deg);
#ifdef PILELAB_WITH_CONTINUUM
                        // The fit's closed loop: the continuum's elasticity, on this rank alone.
                        if (std::filesystem::exists(out("pile.msh")))
                          o.solve_models = [](const std::string& text, const std::string& source, const std::string& dir) {
                            continuum::solve_scene_text(text, source, dir);
                          };
#endif
                        compare::run_compare(o);
                      });
                    }});

  bool upstream_ran = false, piles_checked = false, stopped = false;
  for (const Stage& stage : stages) {
    // A pile unfit for the later stages (never settled, grains lost) stops the run before them.
    if (!piles_checked && stage.name != "dem" && stage.name != "members") {
      piles_checked = true;
      bool unfit = false;
      if (root) {
        RunStatus piles;
        assess_piles(opt.out_dir, ensemble, piles);
        unfit = piles.pile_fails() && !opt.allow_unsettled;
      }
      if (world) unfit = world->broadcast(unfit);
      if (unfit) {
        if (root)
          std::fprintf(stderr, "pilelab run: the pile is unfit for the later stages (below); they do not run "
                               "(--allow-unsettled runs them)\n");
        stopped = true;
        break;
      }
    }
    if (scene.table_text(stage.tables.front()).empty() && !scene.has(stage.tables.front())) continue;
    auto fingerprint_now = [&] {
      std::string fp;
      for (const auto& t : stage.tables) fp += t + "=" + std::to_string(fnv1a(scene.table_text(t))) + ";";
      for (const auto& f : stage.inputs) fp += f + "=" + file_fingerprint(out(f)) + ";";
      for (const auto& f : stage.external) fp += f + "=" + file_fingerprint(f) + ";";
      return fp;
    };
    // Rank 0 decides, from the files, and tells the others.
    bool skip = false;
    if (root) {
      const std::string fingerprint = fingerprint_now();
      bool outputs_present = true;
      for (const auto& f : stage.outputs) outputs_present = outputs_present && std::filesystem::exists(out(f));
      const bool unchanged = state.contains(stage.name) && state[stage.name] == fingerprint && outputs_present;
      skip = unchanged && !opt.force && !upstream_ran && !stage.outputs.empty();
    }
    if (world) skip = world->broadcast(skip);
    if (skip) {
      if (root)
        std::fprintf(stderr, "pilelab run: %-8s skipped (scene table and inputs unchanged; --force reruns it)\n",
                     stage.name.c_str());
      continue;
    }
    if (root) std::fprintf(stderr, "pilelab run: %-8s running\n", stage.name.c_str());
    const auto start = std::chrono::steady_clock::now();
    run_on_ranks(stage, world, root);
    upstream_ran = true;
    if (root) {
      if (!opt.quiet)
        std::fprintf(stderr, "pilelab run: %-8s done in %.1f s\n", stage.name.c_str(),
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      // The fingerprint after the run: a stage may add to a shared input (compare adds rows to
      // profiles.csv), and must not count its own additions as a change next time.
      state[stage.name] = fingerprint_now();
      write_text_atomically(state_path, state.dump(1));
    }
  }

  if (root && opt.figures && !stopped) draw_figures(opt.out_dir, {false, false, opt.quiet});
  if (root) print_summary(opt.out_dir, std::chrono::duration<double>(std::chrono::steady_clock::now() - invocation_start).count());
  if (root) report_status(opt, ensemble, stopped);
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
  cmd->add_option("-j,--threads", opt->threads,
                  "OpenMP threads for the DEM, per ensemble member (default: the cores, shared among the members poured at once)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("-P,--processes", opt->processes,
                  "Pour this many ensemble members at once, as child processes (without MPI; with mpirun the ranks share them)")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--restart", opt->restart,
                "The DEM continues from OUT/checkpoint.h5 where one is left (ensemble members always continue from theirs)");
  cmd->add_flag("--allow-unsettled", opt->allow_unsettled,
                "Run the later stages on a pile that never settled or lost more than 2 % of its grains (the status is "
                "then warn, not fail)");
  cmd->add_flag("!--no-figures", opt->figures,
                "No figures after the stages (scripts/figures.py): where a study makes its own, or matplotlib is missing");
  cmd->final_callback([opt] { run_pipeline(*opt); });
}

}  // namespace pilelab::app
