#include "continuum/settings.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include "common/error.h"
#include "common/report.h"
#include "common/scene_tables.h"

namespace pilelab::continuum {

namespace {

// The unknown-key check of [continuum] and its model tables: every key the stage and the
// models asked for is recorded, and the table is walked (SceneReader::reject_unknown still
// checks the names of the top-level tables).
void check_unknown(const toml::table& t, const std::string& prefix, const std::set<std::string>& asked,
                   const std::string& source) {
  for (const auto& [k, v] : t) {
    const std::string path = prefix + "." + std::string(k.str());
    if (const toml::table* sub = v.as_table()) {
      if (prefix != "continuum" || !find_model(std::string(k.str()))) {
        std::string known = "[continuum]";
        for (const std::string& m : model_names()) known += ", [continuum." + m + "]";
        throw InputError(source + ": unknown table [" + path + "] (known: " + known + ")");
      }
      check_unknown(*sub, path, asked, source);
    } else if (!asked.count(path)) {
      throw InputError(source + ": unknown key '" + path + "' (see docs/SCENES.md, section [continuum])");
    }
  }
}

}  // namespace

bool ContinuumSettings::wants(const std::string& model) const {
  return std::find(models.begin(), models.end(), model) != models.end();
}

SolverSettings read_solver(ModelTable& table, SolverSettings s) {
  SceneReader& r = table.reader();
  const std::string fallback = s.kind == SolverSettings::Kind::direct ? "direct" : "iterative";
  const std::string kind = r.get_choice(table.key("solver"), fallback, {"iterative", "direct"});
  s.kind = kind == "direct" ? SolverSettings::Kind::direct : SolverSettings::Kind::iterative;
  s.relative_tolerance = r.get_double(table.key("solver_tolerance"), s.relative_tolerance, Range{0.0, 1e-2, true});
  s.max_iterations = static_cast<int>(r.get_int(table.key("solver_max_iterations"), s.max_iterations, 1, 1000000));
  return s;
}

ContinuumSettings read_continuum_scene(SceneReader& r, const std::string& scene_dir) {
  ContinuumSettings s;
  std::set<std::string> asked;
  const auto key = [&](const char* k) -> const std::string& { return *asked.insert(k).first; };
  const std::string& src = r.source();

  // models: a list of strings, read from the parsed table (SceneReader has no accessor for it).
  toml::table root;
  try {
    root = toml::parse(r.text(), src);
  } catch (const toml::parse_error&) {
    throw InputError(src + ": not valid TOML");
  }
  key("continuum.models");
  if (const toml::node* models = root.at_path("continuum.models").node()) {
    std::string known;
    for (const std::string& m : model_names()) known += (known.empty() ? "\"" : ", \"") + m + "\"";
    const toml::array* a = models->as_array();
    if (!a || a->empty())
      throw InputError(src + ": continuum.models: expected a non-empty list of model names (" + known + ")");
    std::set<std::string> listed;
    for (const auto& e : *a) {
      const auto name = e.value_exact<std::string>();
      if (!name || !find_model(*name))
        throw InputError(src + ": continuum.models: expected a list of " + known + ", found " +
                         (name ? "\"" + *name + "\"" : std::string("a value that is not a string")));
      listed.insert(*name);
    }
    s.models.clear();
    for (const std::string& m : model_names())  // solved in the registry's order
      if (listed.count(m)) s.models.push_back(m);
  }

  const std::string mesh_file = r.get_string(key("continuum.mesh_file"), "");
  if (!mesh_file.empty())
    s.mesh_file = std::filesystem::path(mesh_file).is_absolute()
                      ? mesh_file
                      : (std::filesystem::path(scene_dir) / mesh_file).string();
  s.has_mesh_table = r.has("mesh");
  s.density_kg_per_m2 = r.get_double(key("continuum.density_kg_per_m2"), s.density_kg_per_m2, Range::positive());
  s.gravity_m_per_s2 = r.get_double(key("continuum.gravity_m_per_s2"), s.gravity_m_per_s2, Range::positive());
  s.profile_heights = r.get_double_list(key("continuum.profile_heights"), s.profile_heights, Range{0.0, 1.0, false});
  for (double y : s.profile_heights)
    if (y >= 1.0)
      throw InputError(src + ": continuum.profile_heights: " + std::to_string(y) +
                       " is at or above the apex: expected 0 <= y/h < 1");
  s.profile_points = static_cast<int>(r.get_int(key("continuum.profile_points"), s.profile_points, 3, 100000));

  // Every registered model's table, [continuum.<name>].
  for (const ModelDefinition* model : model_definitions()) {
    ModelTable table(r, model->name, s.wants(model->name), asked);
    s.model_settings[model->name] = model->read(table);
  }

  if (const toml::table* t = root["continuum"].as_table()) check_unknown(*t, "continuum", asked, src);
  r.reject_unknown({}, scene_tables());  // names of the top-level tables
  return s;
}

}  // namespace pilelab::continuum
