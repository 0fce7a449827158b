#include "continuum/settings.h"

#include <filesystem>
#include <set>

#include "common/error.h"
#include "common/report.h"
#include "common/scene_tables.h"

namespace pilelab::continuum {

double ElasticSettings::mu() const { return youngs_modulus_N_per_m / (2.0 * (1.0 + poisson_ratio)); }

double ElasticSettings::lambda_2d() const {
  const double nu = poisson_ratio, E = youngs_modulus_N_per_m;
  const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  if (plane == Plane::strain) return lambda;
  return 2.0 * lambda * mu() / (lambda + 2.0 * mu());  // = E nu / (1 - nu^2)
}

namespace {

// SceneReader has no list-of-strings accessor, so `models` is read from the parsed TOML here.
// To keep the unknown-key check exact for the whole [continuum] table we record every key we
// ask for and walk the table ourselves (SceneReader::reject_unknown still checks the names of
// the top-level tables).
class KeyLog {
 public:
  explicit KeyLog(SceneReader& r) : r_(r) {}
  const std::string& key(const std::string& k) {
    asked_.insert(k);
    return k;
  }
  bool asked(const std::string& k) const { return asked_.count(k) > 0; }
  SceneReader& reader() { return r_; }

 private:
  SceneReader& r_;
  std::set<std::string> asked_;
};

void check_unknown(const toml::table& t, const std::string& prefix, const KeyLog& log,
                   const std::string& source) {
  for (const auto& [k, v] : t) {
    const std::string path = prefix + "." + std::string(k.str());
    if (const toml::table* sub = v.as_table()) {
      if (path != "continuum.elastic" && path != "continuum.fpa")
        throw InputError(source + ": unknown table [" + path +
                         "] (known: [continuum], [continuum.elastic], [continuum.fpa])");
      check_unknown(*sub, path, log, source);
    } else if (!log.asked(path)) {
      throw InputError(source + ": unknown key '" + path + "' (see docs/SCENES.md, section [continuum])");
    }
  }
}

SolverSettings read_solver(KeyLog& log, const std::string& table, SolverSettings s) {
  SceneReader& r = log.reader();
  const std::string fallback = s.kind == SolverSettings::Kind::direct ? "direct" : "iterative";
  const std::string kind = r.get_choice(log.key(table + ".solver"), fallback, {"iterative", "direct"});
  s.kind = kind == "direct" ? SolverSettings::Kind::direct : SolverSettings::Kind::iterative;
  s.relative_tolerance = r.get_double(log.key(table + ".solver_tolerance"), s.relative_tolerance,
                                      Range{0.0, 1e-2, true});
  s.max_iterations = static_cast<int>(
      r.get_int(log.key(table + ".solver_max_iterations"), s.max_iterations, 1, 1000000));
  return s;
}

double read_repose_angle(SceneReader& r, const std::string& key, double fallback) {
  // Open interval (0, 45) degrees, the range of repose angles of dry granular matter: phi -> 0
  // is a flat "pile" (cot(2 psi) -> infinity in the closure); beyond 45 degrees no sand pile
  // stands, and such a value is more likely a typo than a material.
  const double phi = r.get_double(key, fallback, Range{});
  if (!(phi > 0.0 && phi < 45.0))
    throw InputError(r.source() + ": " + key + ": " + std::to_string(phi) +
                     " degrees is outside the FPA's range: expected 0 < angle of repose < 45 degrees");
  return phi;
}

}  // namespace

void apply_dem_repose_angles(FpaSettings& fpa, const std::string& report_path) {
  const nlohmann::json report = read_report(report_path);
  auto angle = [&](const char* key) {
    const auto dem = report.find("dem");
    if (dem == report.end() || !dem->contains(key) || !(*dem)[key].is_number())
      throw InputError(report_path + ": dem." + key + ": missing (repose_angle_source = \"dem\" needs a `pilelab dem` "
                       "run whose pile has both flanks)");
    const double phi = (*dem)[key].get<double>();
    if (!(phi > 0.0 && phi < 45.0))
      throw InputError(report_path + ": dem." + key + ": " + std::to_string(phi) +
                       " degrees is outside the FPA's range: expected 0 < angle of repose < 45 degrees");
    return phi;
  };
  fpa.left_repose_angle_deg = angle("repose_angle_left_deg");
  fpa.right_repose_angle_deg = angle("repose_angle_right_deg");
}

ContinuumSettings read_continuum_scene(SceneReader& r, const std::string& scene_dir) {
  ContinuumSettings s;
  KeyLog log(r);
  const std::string& src = r.source();

  // models: a list of strings, read from the parsed table (see KeyLog).
  toml::table root;
  try {
    root = toml::parse(r.text(), src);
  } catch (const toml::parse_error&) {
    throw InputError(src + ": not valid TOML");
  }
  log.key("continuum.models");
  if (const toml::node* models = root.at_path("continuum.models").node()) {
    const toml::array* a = models->as_array();
    if (!a || a->empty())
      throw InputError(src + ": continuum.models: expected a non-empty list such as [\"elastic\", \"fpa\"]");
    s.elastic = s.fpa = false;
    for (const auto& e : *a) {
      const auto name = e.value_exact<std::string>();
      if (name && *name == "elastic") s.elastic = true;
      else if (name && *name == "fpa") s.fpa = true;
      else
        throw InputError(src + ": continuum.models: expected a list of \"elastic\" and/or \"fpa\", found " +
                         (name ? "\"" + *name + "\"" : std::string("a value that is not a string")));
    }
  }

  const std::string mesh_file = r.get_string(log.key("continuum.mesh_file"), "");
  if (!mesh_file.empty())
    s.mesh_file = std::filesystem::path(mesh_file).is_absolute()
                      ? mesh_file
                      : (std::filesystem::path(scene_dir) / mesh_file).string();
  s.has_mesh_table = r.has("mesh");
  s.density_kg_per_m2 = r.get_double(log.key("continuum.density_kg_per_m2"), s.density_kg_per_m2, Range::positive());
  s.gravity_m_per_s2 = r.get_double(log.key("continuum.gravity_m_per_s2"), s.gravity_m_per_s2, Range::positive());
  s.profile_heights = r.get_double_list(log.key("continuum.profile_heights"), s.profile_heights, Range{0.0, 1.0, false});
  for (double y : s.profile_heights)
    if (y >= 1.0)
      throw InputError(src + ": continuum.profile_heights: " + std::to_string(y) +
                       " is at or above the apex: expected 0 <= y/h < 1");
  s.profile_points = static_cast<int>(r.get_int(log.key("continuum.profile_points"), s.profile_points, 3, 100000));

  // [continuum.elastic]
  ElasticSettings& e = s.elastic_model;
  const bool lame = r.has("continuum.elastic.lame_lambda_N_per_m") || r.has("continuum.elastic.shear_modulus_N_per_m");
  if (lame) {
    if (r.has("continuum.elastic.youngs_modulus_N_per_m") || r.has("continuum.elastic.poisson_ratio"))
      throw InputError(src + ": [continuum.elastic]: give either youngs_modulus_N_per_m and poisson_ratio, "
                             "or lame_lambda_N_per_m and shear_modulus_N_per_m, not both pairs");
    const double lambda = r.require_double(log.key("continuum.elastic.lame_lambda_N_per_m"), Range::at_least(0.0));
    const double mu = r.require_double(log.key("continuum.elastic.shear_modulus_N_per_m"), Range::positive());
    e.poisson_ratio = lambda / (2.0 * (lambda + mu));
    e.youngs_modulus_N_per_m = mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu);
  } else {
    e.youngs_modulus_N_per_m =
        r.get_double(log.key("continuum.elastic.youngs_modulus_N_per_m"), e.youngs_modulus_N_per_m, Range::positive());
    e.poisson_ratio = r.get_double(log.key("continuum.elastic.poisson_ratio"), e.poisson_ratio, Range{});
    if (!(e.poisson_ratio < 0.5))
      throw InputError(src + ": continuum.elastic.poisson_ratio: " + std::to_string(e.poisson_ratio) +
                       " is not allowed: expected -1 < nu < 0.5 (nu = 0.5 is incompressible, which "
                       "the displacement formulation cannot represent)");
    if (!(e.poisson_ratio > -1.0))
      throw InputError(src + ": continuum.elastic.poisson_ratio: expected -1 < nu < 0.5");
  }
  e.plane = r.get_choice(log.key("continuum.elastic.plane"), "strain", {"strain", "stress"}) == "stress"
                ? ElasticSettings::Plane::stress
                : ElasticSettings::Plane::strain;
  e.base = r.get_choice(log.key("continuum.elastic.base"), "rough", {"rough", "smooth"}) == "smooth"
               ? ElasticSettings::Base::smooth
               : ElasticSettings::Base::rough;
  e.degree = static_cast<int>(r.get_int(log.key("continuum.elastic.degree"), e.degree, 1, 2));
  e.gravity_change = r.get_double(log.key("continuum.elastic.gravity_change"), e.gravity_change, Range{-1.0, 1.0, false});
  e.solver = read_solver(log, "continuum.elastic", e.solver);

  // [continuum.fpa]
  FpaSettings& f = s.fpa_model;
  if (r.has("continuum.fpa.repose_angle_deg") &&
      (r.has("continuum.fpa.left_repose_angle_deg") || r.has("continuum.fpa.right_repose_angle_deg")))
    throw InputError(src + ": [continuum.fpa]: give either repose_angle_deg (both sides) or "
                           "left_repose_angle_deg and right_repose_angle_deg, not both");
  f.angles_from_dem =
      r.get_choice(log.key("continuum.fpa.repose_angle_source"), "scene", {"scene", "dem"}) == "dem";
  // With "dem" the measured angles replace any given here (`pilelab run` fills in the DEM's angles
  // itself, which are then the same); the keys are still checked.
  const double phi = read_repose_angle(r, log.key("continuum.fpa.repose_angle_deg"), 28.0);
  f.left_repose_angle_deg = read_repose_angle(r, log.key("continuum.fpa.left_repose_angle_deg"), phi);
  f.right_repose_angle_deg = read_repose_angle(r, log.key("continuum.fpa.right_repose_angle_deg"), phi);
  f.degree = static_cast<int>(r.get_int(log.key("continuum.fpa.degree"), f.degree, 1, 2));
  f.surface = r.get_choice(log.key("continuum.fpa.surface"), "strong", {"strong", "weak"}) == "weak"
                  ? FpaSettings::Surface::weak
                  : FpaSettings::Surface::strong;
  f.surface_weight = r.get_double(log.key("continuum.fpa.surface_weight"), f.surface_weight, Range::positive());
  f.solver = read_solver(log, "continuum.fpa", f.solver);

  if (const toml::table* t = root["continuum"].as_table()) check_unknown(*t, "continuum", log, src);
  r.reject_unknown({}, scene_tables());  // names of the top-level tables
  return s;
}

}  // namespace pilelab::continuum
