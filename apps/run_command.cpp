// `pilelab run`: the stages a scene asks for, in order (dem, mesh, coarse, solve, compare,
// figures). A stage runs when its table is in the scene; it is skipped, and says so, when its
// table and its input files are unchanged since its outputs were written (OUT/stages.json
// keeps a fingerprint per stage); --force runs every stage.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "apps/commands.h"
#include "coarse/coarse_run.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "common/report.h"
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
  std::vector<std::string> external; ///< files elsewhere it reads (scene path keys), absolute
  std::vector<std::string> outputs;  ///< files in OUT/ it writes (all must exist to skip)
  std::function<void()> run;
};

#ifdef PILELAB_WITH_CONTINUUM
// Absolute form of a path key of a table (the derived scenes live in OUT/, not beside the scene).
void make_absolute(toml::table& root, const char* table, const char* key, const std::string& scene_dir) {
  toml::table* t = root[table].as_table();
  if (!t) return;
  if (auto v = (*t)[key].value<std::string>(); v && !v->empty() && std::filesystem::path(*v).is_relative())
    t->insert_or_assign(key, (std::filesystem::path(scene_dir) / *v).string());
}

// A number the earlier stages wrote to report.json; a missing or null one (a non-finite value
// is written as null) names the key instead of failing inside the JSON library.
double report_number(const nlohmann::json& report, const std::string& section, const std::string& key) {
  const auto& s = report.contains(section) ? report[section] : nlohmann::json();
  if (!s.is_object() || !s.contains(key) || !s[key].is_number())
    throw InputError("report.json (in the output directory): " + section + "." + key + ": expected a number from the " + section +
                     " stage, found " + (s.is_object() && s.contains(key) ? s[key].dump() : std::string("nothing")));
  return s[key].get<double>();
}

// The scene for the solve stage: the user's, with what the DEM measured filled in where the
// [continuum] table leaves it open: the bulk density of the pile (coarse) and its repose
// angles (dem), so the models carry the same load and closure as the pile they are compared to.
std::string solve_scene(const std::string& scene_path, const std::string& out_dir, const nlohmann::json& report) {
  toml::table root = toml::parse_file(scene_path);
  const std::string scene_dir = std::filesystem::path(scene_path).parent_path().string();
  make_absolute(root, "continuum", "mesh_file", scene_dir);
  make_absolute(root, "mesh", "dem_file", scene_dir);
  if (!root["continuum"].as_table()) root.insert("continuum", toml::table{});
  toml::table& c = *root["continuum"].as_table();
  if (!c.contains("density_kg_per_m2") && report.contains("coarse"))
    c.insert("density_kg_per_m2", report_number(report, "coarse", "rho_bulk_kg_per_m2"));
  if (!c.contains("gravity_m_per_s2") && report.contains("coarse"))
    c.insert("gravity_m_per_s2", report_number(report, "coarse", "gravity_m_per_s2"));
  if (report.contains("dem")) {
    const auto& d = report["dem"];
    const bool measured = d.is_object() && d.value("repose_angle_left_deg", nlohmann::json()).is_number() &&
                          d.value("repose_angle_right_deg", nlohmann::json()).is_number();
    if (!c["fpa"].as_table()) c.insert("fpa", toml::table{});
    toml::table& f = *c["fpa"].as_table();
    if (measured && !f.contains("repose_angle_deg") && !f.contains("left_repose_angle_deg")) {
      const double l = d["repose_angle_left_deg"].get<double>(), r = d["repose_angle_right_deg"].get<double>();
      if (l > 0 && l < 45 && r > 0 && r < 45) {
        f.insert("left_repose_angle_deg", l);
        f.insert("right_repose_angle_deg", r);
      }
    }
  }
  std::ostringstream text;
  text << root;
  const std::string path = (std::filesystem::path(out_dir) / "solve_scene.toml").string();
  write_text_atomically(path, text.str() + "\n");
  return path;
}

// The closed loop of the fit: the gravity change solved with the fitted isotropic constants,
// its displacement and strain against the DEM's. The solver runs as a child process (MPI can
// be initialised once per process, and the solve stage may already have done so).
void closed_loop(const std::string& out_dir, const nlohmann::json& report) {
  if (!report.contains("coarse") || !report.contains("fit") || !report["fit"].is_object() ||
      !report["fit"].value("models", nlohmann::json::object()).contains("isotropic"))
    return;
  const auto& iso = report["fit"]["models"]["isotropic"];
  const auto constant = [&](const char* key) {  // null when the fit had no data
    return iso.contains(key) && iso[key].is_number() ? iso[key].get<double>() : NAN;
  };
  const double lambda = constant("lambda_N_per_m"), mu = constant("mu_N_per_m");
  const double nu = lambda / (2 * (lambda + mu));
  nlohmann::json result = {{"lambda_N_per_m", lambda}, {"mu_N_per_m", mu}};
  if (!(mu > 0) || !(nu > -1 && nu < 0.5)) {
    result["skipped"] = "the fitted constants are not a stable isotropic material";
  } else {
    // The gravity change the DEM's strains come from, as coarse measured it from the snapshots.
    const auto& coarse = report["coarse"];
    const double change = coarse.value("gravity_change", 0.0);
    if (change == 0.0) return;
    toml::table root;
    toml::table c;
    c.insert("models", toml::array{"elastic"});
    // The mesh the fields live on; absolute, since the child resolves paths from its scene's dir.
    c.insert("mesh_file", std::filesystem::absolute(coarse["mesh_file"].get<std::string>()).string());
    c.insert("density_kg_per_m2", report_number(report, "coarse", "rho_bulk_kg_per_m2"));
    c.insert("gravity_m_per_s2", report_number(report, "coarse", "gravity_m_per_s2"));
    toml::table e;
    e.insert("lame_lambda_N_per_m", std::max(lambda, 0.0));
    e.insert("shear_modulus_N_per_m", mu);
    e.insert("gravity_change", change);
    c.insert("elastic", e);
    root.insert("continuum", c);
    const std::string dir = (std::filesystem::path(out_dir) / "closed_loop").string();
    std::filesystem::create_directories(dir);
    std::ostringstream text;
    text << root;
    write_text_atomically(dir + "/scene.toml", text.str() + "\n");
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    const std::string cmd = "'" + self + "' solve '" + dir + "/scene.toml' -o '" + dir + "' > '" + dir + "/solve.log' 2>&1";
    if (std::system(cmd.c_str()) != 0) throw std::runtime_error("closed loop: " + cmd + " failed (see solve.log)");
    result.update(compare::compare_displacements((std::filesystem::path(out_dir) / "fields.h5").string(),
                                                 dir + "/models.h5", "elastic"));
    result["lame_lambda_used_N_per_m"] = std::max(lambda, 0.0);
    result["directory"] = "closed_loop";
  }
  nlohmann::json fit = report["fit"];
  fit["closed_loop"] = result;
  write_report_section((std::filesystem::path(out_dir) / "report.json").string(), "fit", fit);
}
#endif

void run_pipeline(const RunOptions& opt) {
  SceneReader scene = SceneReader::from_file(opt.scene_path);
  std::error_code made;
  std::filesystem::create_directories(opt.out_dir, made);
  if (made) throw InputError(opt.out_dir + ": cannot create the output directory: " + made.message());
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

  std::vector<Stage> stages;
  stages.push_back({"dem", {"dem"}, {}, {}, {"dem.h5"}, [&] {
                      dem::DemRunOptions o;
                      o.scene_path = opt.scene_path;
                      o.out_dir = opt.out_dir;
                      o.quiet = opt.quiet;
                      o.threads = opt.threads;
                      dem::run_dem(o);
                    }});
  stages.push_back({"mesh", {"mesh"}, {"dem.h5"}, scene_paths("mesh", "dem_file"), {"pile.msh"},
                    [&] { mesh::run_mesh({opt.scene_path, opt.out_dir}); }});
  stages.push_back({"coarse", {"coarse"}, {"dem.h5", "pile.msh"},
                    join(scene_paths("coarse", "dem_files"), scene_paths("coarse", "mesh_file")), {"fields.h5", "fields.vtu"},
                    [&] { coarse::run_coarse({opt.scene_path, opt.out_dir}); }});
#ifdef PILELAB_WITH_CONTINUUM
  stages.push_back({"solve", {"continuum", "mesh"}, {"pile.msh", "fields.h5"}, scene_paths("continuum", "mesh_file"), {"models.h5"}, [&] {
                      continuum::SolveOptions o;
                      o.scene_path = solve_scene(opt.scene_path, opt.out_dir, read_report(out("report.json")));
                      o.out_dir = opt.out_dir;
                      o.quiet = opt.quiet;
                      continuum::run_solve_command(o);
                    }});
#endif
  stages.push_back({"compare", {"compare"}, {"fields.h5", "models.h5", "profiles.csv"},
                    join(scene_paths("compare", "fields_file"), scene_paths("compare", "models_file")), {"compare.vtu"}, [&] {
                      compare::run_compare({opt.scene_path, opt.out_dir});
#ifdef PILELAB_WITH_CONTINUUM
                      if (std::filesystem::exists(out("pile.msh"))) closed_loop(opt.out_dir, read_report(out("report.json")));
#endif
                    }});

  bool upstream_ran = false;
  for (const Stage& stage : stages) {
    if (scene.table_text(stage.tables.front()).empty() && !scene.has(stage.tables.front())) continue;
    auto fingerprint_now = [&] {
      std::string fp;
      for (const auto& t : stage.tables) fp += t + "=" + std::to_string(fnv1a(scene.table_text(t))) + ";";
      for (const auto& f : stage.inputs) fp += f + "=" + file_fingerprint(out(f)) + ";";
      for (const auto& f : stage.external) fp += f + "=" + file_fingerprint(f) + ";";
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
