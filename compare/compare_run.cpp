#include "compare/compare_run.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/fields_attributes.h"
#include "common/hdf5_file.h"
#include "common/isotropic_material.h"
#include "common/principal_axes.h"
#include "common/profiles_csv.h"
#include "common/report.h"
#include "common/scene_reader.h"
#include "common/scene_tables.h"
#include "common/triangle_vtu.h"
#include "compare/closure_fit.h"
#include "compare/field_norms.h"
#include "compare/stress_strain_fit.h"
#include "dem/dem_result.h"

namespace pilelab::compare {

namespace {

std::string in_dir(const std::string& dir, const std::string& file) { return (std::filesystem::path(dir) / file).string(); }

std::vector<char> both(const std::vector<char>& a, const std::vector<char>& b) {
  std::vector<char> out(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out[i] = a[i] && b[i];
  return out;
}

// Orientation of the major compressive axis of (xx, yy, xy), tension positive, in [0, 180)
// degrees from the horizontal: the convention of coarse/.
double compressive_axis_deg(double xx, double yy, double xy) { return principal_axes(-xx, -yy, -xy).orientation_deg; }

// Points thinned greedily to about `spacing` apart (a regular subsample of correlated RVEs).
std::vector<std::size_t> thin(const std::vector<Vec2>& points, const std::vector<char>& ok, double spacing) {
  std::vector<std::size_t> kept;
  std::map<std::pair<long, long>, std::vector<std::size_t>> grid;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!ok[i]) continue;
    const long cx = std::lround(std::floor(points[i].x() / spacing)), cy = std::lround(std::floor(points[i].y() / spacing));
    bool near = false;
    for (long a = cx - 1; a <= cx + 1 && !near; ++a)
      for (long b = cy - 1; b <= cy + 1 && !near; ++b) {
        auto it = grid.find({a, b});
        if (it == grid.end()) continue;
        for (std::size_t j : it->second) near = near || (points[j] - points[i]).norm() < spacing;
      }
    if (near) continue;
    kept.push_back(i);
    grid[{cx, cy}].push_back(i);
  }
  return kept;
}

// The fit's quantities of each pile of an ensemble (fields.h5 /piles/K/Q), or none.
using PileValues = std::vector<std::map<std::string, std::vector<double>>>;

// What a stress-strain fit samples at each point.
const char* const fit_quantities[] = {"stress_change_xx", "stress_change_yy", "stress_change_xy", "strain_xx", "strain_yy",
                                      "strain_xy", "fabric_xx", "fabric_yy", "fabric_xy", "pressure"};

PileValues read_pile_values(const std::string& fields_path) {
  PileValues piles;
  const H5File f = H5File::open_read(fields_path);
  if (!f.exists("/piles")) return piles;
  for (const std::string& k : f.list("/piles")) {
    std::map<std::string, std::vector<double>> values;
    for (const std::string& q : f.list("/piles/" + k)) values[q] = f.read_doubles("/piles/" + k + "/" + q);
    piles.push_back(std::move(values));
  }
  return piles;
}

// A sample at point i from the mean over the chosen piles (false if a quantity has no data).
bool pile_mean_sample(const PileValues& piles, const std::vector<std::size_t>& chosen, std::size_t i,
                      const Vec2& point, FitSample& s) {
  std::map<std::string, double> mean;
  for (const char* name : fit_quantities) {
    double sum = 0;
    int n = 0;
    for (std::size_t k : chosen) {
      const double v = piles[k].at(name)[i];
      if (std::isfinite(v)) sum += v, ++n;
    }
    if (n == 0) return false;
    mean[name] = sum / n;
  }
  s.point = point;
  s.stress_change << mean["stress_change_xx"], mean["stress_change_xy"], mean["stress_change_xy"], mean["stress_change_yy"];
  s.strain << mean["strain_xx"], mean["strain_xy"], mean["strain_xy"], mean["strain_yy"];
  s.fabric << mean["fabric_xx"], mean["fabric_xy"], mean["fabric_xy"], mean["fabric_yy"];
  s.pressure = mean["pressure"];
  return true;
}

nlohmann::json fit_section(const PointFields& dem, const PileValues& piles, double spacing, int resamples, int folds,
                           unsigned seed, std::vector<FitSample>* samples_out, std::vector<FitResult>* fits_out) {
  for (const char* q : fit_quantities)
    if (!dem.has(q))
      throw InputError(dem.source + ": the fit needs the field '" + std::string(q) +
                       "' (run coarse with a `relaxed` snapshot for strains and stress changes)");
  std::vector<char> ok(dem.points.size(), 1);
  for (const char* q : fit_quantities) ok = both(ok, dem.valid.at(q));
  const std::vector<std::size_t> kept = thin(dem.points, ok, spacing);
  std::vector<FitSample> samples;
  for (std::size_t i : kept) {
    FitSample s;
    s.point = dem.points[i];
    s.stress_change << dem.at("stress_change_xx")[i], dem.at("stress_change_xy")[i], dem.at("stress_change_xy")[i],
        dem.at("stress_change_yy")[i];
    s.strain << dem.at("strain_xx")[i], dem.at("strain_xy")[i], dem.at("strain_xy")[i], dem.at("strain_yy")[i];
    s.fabric << dem.at("fabric_xx")[i], dem.at("fabric_xy")[i], dem.at("fabric_xy")[i], dem.at("fabric_yy")[i];
    s.pressure = dem.at("pressure")[i];
    samples.push_back(s);
  }
  // With an ensemble, the intervals come from resampling whole piles (the fields at every
  // point re-averaged over the drawn piles); with one pile, from resampling the points.
  const bool over_piles = piles.size() >= 2;
  nlohmann::json section = {{"samples", samples.size()}, {"sample_spacing_m", spacing}, {"bootstrap_resamples", resamples},
                            {"bootstrap_over", over_piles ? "piles" : "points"}, {"piles", std::max<std::size_t>(piles.size(), 1)},
                            {"folds", folds}};
  double p_ref = 0;
  for (const auto& x : samples) p_ref += x.pressure / std::max<std::size_t>(samples.size(), 1);
  std::map<FitModel, std::vector<std::vector<double>>> pile_draws;  // model -> parameter -> draws
  if (over_piles) {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, piles.size() - 1);
    for (int b = 0; b < resamples; ++b) {
      std::vector<std::size_t> chosen(piles.size());
      for (auto& k : chosen) k = pick(rng);
      std::vector<FitSample> drawn;
      FitSample x;
      for (std::size_t i : kept)
        if (pile_mean_sample(piles, chosen, i, dem.points[i], x)) drawn.push_back(x);
      for (FitModel m : {FitModel::isotropic, FitModel::orthotropic_fabric, FitModel::pressure_dependent}) {
        const FitResult f = fit(drawn, m, p_ref);
        if (!f.ok) continue;
        auto& d = pile_draws[m];
        d.resize(f.parameters.size());
        for (std::size_t k = 0; k < f.parameters.size(); ++k) d[k].push_back(f.parameters[k]);
      }
    }
  }
  nlohmann::json models = nlohmann::json::object();
  std::string best;
  double best_aic = INFINITY;
  for (FitModel m : {FitModel::isotropic, FitModel::orthotropic_fabric, FitModel::pressure_dependent}) {
    const FitResult f = fit_with_uncertainty(samples, m, resamples, seed, folds);
    if (fits_out) fits_out->push_back(f);
    if (!f.ok) continue;
    nlohmann::json j = {{"r2", f.r2}, {"rss", f.rss}, {"aic", f.aic}, {"cv_rms_N_per_m", f.cv_rms}};
    for (std::size_t k = 0; k < f.parameters.size(); ++k) {
      j[f.parameter_names[k]] = f.parameters[k];
      if (over_piles && k < pile_draws[m].size() && !pile_draws[m][k].empty()) {
        auto d = pile_draws[m][k];
        std::sort(d.begin(), d.end());
        j[f.parameter_names[k] + "_ci95"] = {d[static_cast<std::size_t>(0.025 * (d.size() - 1))],
                                             d[static_cast<std::size_t>(0.975 * (d.size() - 1))]};
      } else if (k < f.ci_low.size()) {
        j[f.parameter_names[k] + "_ci95"] = {f.ci_low[k], f.ci_high[k]};
      }
    }
    models[f.name] = j;
    if (f.aic < best_aic) best_aic = f.aic, best = f.name;
  }
  section["models"] = models;
  section["best_by_aic"] = best;
  if (samples_out) *samples_out = samples;
  return section;
}

// OUT/fit_samples.csv: each sample's measured stress change beside every model's prediction.
void write_fit_samples(const std::string& path, const std::vector<FitSample>& samples, const std::vector<FitResult>& fits) {
  double p_mean = 0;
  for (const auto& s : samples) p_mean += s.pressure / std::max<std::size_t>(samples.size(), 1);
  std::ostringstream out;
  out << "x_m,y_m,component,measured_N_per_m";
  for (const auto& f : fits)
    if (f.ok) out << ',' << f.name << "_N_per_m";
  out << '\n';
  const char* names[] = {"xx", "yy", "xy"};
  for (const auto& s : samples) {
    std::vector<Tensor> predicted;
    for (const auto& f : fits)
      if (f.ok) predicted.push_back(predict(f, s, f.model == FitModel::pressure_dependent ? f.parameters[3] : p_mean));
    for (int c = 0; c < 3; ++c) {
      const int i = c == 1 ? 1 : 0, j = c == 0 ? 0 : 1;
      out << s.point.x() << ',' << s.point.y() << ',' << names[c] << ',' << s.stress_change(i, j);
      for (const Tensor& t : predicted) out << ',' << t(i, j);
      out << '\n';
    }
  }
  write_text_atomically(path, out.str());
}

const char* const change_fields[] = {"displacement_x", "displacement_y", "strain_xx", "strain_yy", "strain_xy"};

// What a model's fields are multiplied by to be put on the DEM's scale.
struct Scales {
  double stress = 1.0;  ///< (rho g)_DEM / (rho g)_model
  double change = 1.0;  ///< (rho g Delta)_DEM / (rho g Delta)_model, Delta = the relative change of g
  bool has_change = false;
  std::string skipped;  ///< why displacement and strain are not compared (a change of 0), or empty
};

// Both sources are sampled at the same points. A gravity stress scales with rho g, so model
// stresses are multiplied by the DEM's rho g over the model's; the displacement and strain of
// a change Delta of g in a linear model scale with rho g Delta, so they are multiplied by the
// DEM's rho g Delta over the model's. A model compares by the shape of its fields, whatever
// density and gravity change it was solved with (its modulus is what it is).
Scales scale_to_dem(PointFields& model, const std::string& name, const std::string& fields_path,
                    const std::string& models_path, const PointFields& dem) {
  const FieldsAttributes fields = read_fields_attributes(fields_path);
  const H5File models = H5File::open_read(models_path);
  const double dem_rho_g = fields.rho_g();
  const double model_rho_g = models.attribute_double("/", "rho_g_h_N_per_m") / models.attribute_double("/", "height_m");
  if (!(dem_rho_g > 0) || !(model_rho_g > 0) || !std::isfinite(dem_rho_g) || !std::isfinite(model_rho_g))
    throw InputError(fields_path + ", " + models_path + ": rho g is " + std::to_string(dem_rho_g) + " and " +
                     std::to_string(model_rho_g) + " N/m^2 (2D: kg/m^2 times m/s^2); expected both finite and > 0 (root attributes "
                     "rho_bulk_kg_per_m2 * gravity_m_per_s2, and rho_g_h_N_per_m / height_m)");
  Scales k;
  k.stress = dem_rho_g / model_rho_g;
  for (const char* c : {"stress_xx", "stress_yy", "stress_xy"})
    if (model.has(c))
      for (double& v : model.values[c]) v *= k.stress;
  // Compared only where the DEM has data: without a later snapshot its displacement and
  // strain fields exist but are empty, and its gravity change is 0.
  bool compared = false;
  for (const char* c : change_fields)
    if (model.has(c) && dem.has(c))
      for (char ok : dem.valid.at(c)) compared = compared || ok;
  if (!compared) return k;
  // A fields file without a gravity change (0, FieldsAttributes' default) skips the comparison below.
  const double dem_change = fields.gravity_change;
  double model_change = 0;
  try {
    model_change = models.attribute_double("/" + name, "gravity_change");
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (model '" + name + "' has displacements or strains, and comparing "
                     "them with the DEM's needs the change of g each is for: rerun pilelab solve and coarse)");
  }
  if (!std::isfinite(dem_change) || !std::isfinite(model_change))
    throw InputError(fields_path + ", " + models_path + ": gravity_change is " + std::to_string(dem_change) +
                     " (DEM) and " + std::to_string(model_change) + " (model '" + name + "'); expected finite numbers");
  if (dem_change == 0 || model_change == 0) {
    // No common scale (e.g. DEM strains from a snapshot at the same g): not compared, and said so.
    k.skipped = "gravity_change is " + std::to_string(dem_change) + " (DEM) and " + std::to_string(model_change) +
                " (model): no rho g Delta to scale the displacements and strains by";
    for (const char* c : change_fields) model.values.erase(c), model.valid.erase(c);
    return k;
  }
  k.change = dem_rho_g * dem_change / (model_rho_g * model_change);
  k.has_change = true;
  for (const char* c : change_fields)
    if (model.has(c))
      for (double& v : model.values[c]) v *= k.change;
  return k;
}

// Relative L2 differences of the elastic displacement (both components together) and of the
// strain components, model against DEM, on the DEM's mesh.
nlohmann::json displacement_and_strain_differences(const Triangulation& mesh, const PointFields& model,
                                                   const PointFields& dem) {
  nlohmann::json out = nlohmann::json::object();
  if (model.has("displacement_x") && dem.has("displacement_x")) {
    const L2Difference x = l2_difference(mesh, model.at("displacement_x"), model.valid.at("displacement_x"),
                                         dem.at("displacement_x"), dem.valid.at("displacement_x"));
    const L2Difference y = l2_difference(mesh, model.at("displacement_y"), model.valid.at("displacement_y"),
                                         dem.at("displacement_y"), dem.valid.at("displacement_y"));
    const double ref = std::hypot(x.reference, y.reference);
    out["relative_l2_displacement"] = x.area == 0 ? NAN : ref > 0 ? std::hypot(x.difference, y.difference) / ref : 0.0;
    out["relative_l2_displacement_y"] = y.relative;
  }
  for (const char* c : {"strain_xx", "strain_yy", "strain_xy"})
    if (model.has(c) && dem.has(c))
      out[std::string("relative_l2_") + c] = l2_difference(mesh, model.at(c), model.valid.at(c), dem.at(c), dem.valid.at(c)).relative;
  return out;
}


}  // namespace

nlohmann::json compare_displacements(const std::string& fields_path, const std::string& models_path,
                                     const std::string& name) {
  Triangulation mesh;
  bool on_nodes = true;
  const PointFields dem = read_dem_fields(fields_path, &mesh, &on_nodes);
  if (!on_nodes)
    throw InputError(fields_path + ": the comparison needs the fields at the mesh nodes (coarse.location = \"nodes\")");
  PointFields raw = read_model_fields(models_path, name);
  const Scales k = scale_to_dem(raw, name, fields_path, models_path, dem);
  double height = 0;
  for (const Vec2& p : mesh.nodes) height = std::max(height, p.y());
  const PointFields model =
      reindex(raw, match_model_points(raw, dem, 1e-9 * height, models_path, name, fields_path), dem.points.size());
  nlohmann::json out = displacement_and_strain_differences(mesh, model, dem);
  if (k.has_change) out["displacement_scale_dem_over_model"] = k.change;
  if (!k.skipped.empty()) out["displacement_comparison_skipped"] = k.skipped;
  return out;
}

double fit_sample_spacing(const std::string& fields_path, double requested_m) {
  if (requested_m > 0) return requested_m;
  const FieldsAttributes file = read_fields_attributes(fields_path);
  if (file.rve_radius_m > 0) return file.rve_radius_m;
  const double height = file.height_m;
  if (!(height > 0))
    throw InputError(fields_path + ": attribute /height_m: expected a positive pile height, found " + std::to_string(height));
  return height / 20;
}

CompareSettings read_compare_scene(SceneReader& reader, const std::string& scene_dir, const std::string& out_dir) {
  auto path_key = [&](const char* key, const std::string& fallback) {
    const std::string p = reader.get_string(key, "");
    if (p.empty()) return fallback;
    return std::filesystem::path(p).is_absolute() ? p : (std::filesystem::path(scene_dir) / p).string();
  };
  CompareSettings s;
  s.fields_path = path_key("compare.fields_file", in_dir(out_dir, "fields.h5"));
  s.models_path = path_key("compare.models_file", in_dir(out_dir, "models.h5"));
  s.fit_resamples = static_cast<int>(reader.get_int("compare.fit_resamples", s.fit_resamples, 0, 100000));
  s.fit_folds = static_cast<int>(reader.get_int("compare.fit_folds", s.fit_folds, 2, 100));
  s.fit_seed = static_cast<unsigned>(reader.get_int("compare.fit_seed", s.fit_seed, 0, 1L << 31));
  s.fit_sample_spacing_m = reader.get_double("compare.fit_sample_spacing_m", 0.0, Range::at_least(0.0));
  s.repose_angle_deg = reader.get_double("compare.repose_angle_deg", 0.0, Range::closed(0.0, 45.0));
  return s;
}

nlohmann::json run_fit(const FitOptions& opt) {
  Triangulation mesh;
  const PointFields dem = read_dem_fields(opt.fields_path, &mesh);
  const double spacing = fit_sample_spacing(opt.fields_path, opt.sample_spacing_m);
  prepare_output_directory(opt.out_dir);
  std::vector<FitSample> samples;
  std::vector<FitResult> fits;
  const nlohmann::json section =
      fit_section(dem, read_pile_values(opt.fields_path), spacing, opt.resamples, opt.folds, opt.seed, &samples, &fits);
  write_fit_samples(in_dir(opt.out_dir, "fit_samples.csv"), samples, fits);
  write_report_section(in_dir(opt.out_dir, "report.json"), "fit", section);
  return section;
}

namespace {

// --- The steps of the comparison -------------------------------------------------------------

// At each point, the angle between the model's major compressive axis and the DEM's (0-90
// degrees), where both have one (ok); none if either source has no stress axes.
std::optional<std::vector<double>> axis_angle_to_dem(const PointFields& model, const PointFields& dem, std::vector<char>& ok) {
  if (!(model.has("stress_xx") && model.has("stress_yy") && model.has("stress_xy") && dem.has("stress_orientation_deg")))
    return std::nullopt;
  std::vector<double> angle(dem.points.size(), 0.0);
  ok = both(both(model.valid.at("stress_xx"), model.valid.at("stress_yy")), dem.valid.at("stress_orientation_deg"));
  for (std::size_t i = 0; i < angle.size(); ++i)
    if (ok[i])
      angle[i] = axis_angle_deg(dem.at("stress_orientation_deg")[i],
                                compressive_axis_deg(model.at("stress_xx")[i], model.at("stress_yy")[i], model.at("stress_xy")[i]));
  return angle;
}

// The numbers report.json gives for one model against the DEM's fields (both on the DEM's
// points): relative L2 differences of the stresses (whole pile and lower half), the mean angle
// between the principal axes, and the differences of the displacements and strains of the
// gravity change.
nlohmann::json model_differences(const Triangulation& mesh, const PointFields& model, const PointFields& dem,
                                 const Region& lower_half) {
  nlohmann::json m = nlohmann::json::object();
  for (const char* c : {"stress_xx", "stress_yy", "stress_xy"}) {
    if (!model.has(c) || !dem.has(c)) continue;
    m[std::string("relative_l2_") + c] = l2_difference(mesh, model.at(c), model.valid.at(c), dem.at(c), dem.valid.at(c)).relative;
    m[std::string("relative_l2_lower_half_") + c] =
        l2_difference(mesh, model.at(c), model.valid.at(c), dem.at(c), dem.valid.at(c), lower_half).relative;
  }
  std::vector<char> ok;
  if (const auto angle = axis_angle_to_dem(model, dem, ok)) m["principal_axis_angle_mean_deg"] = area_mean(mesh, *angle, ok);
  m.update(displacement_and_strain_differences(mesh, model, dem));
  return m;
}

// The FPA angle that best fits the DEM's stress axes: psi = deviation of the major axis from
// the vertical, towards the axis of the pile (left: 90 - theta, right: theta - 90), averaged
// over each flank's triangles (the side is the centroid's) with the linear interpolant.
nlohmann::json fpa_angle_fit(const Triangulation& mesh, const PointFields& dem, double apex_x) {
  const auto& th = dem.at("stress_orientation_deg");
  const auto& ok = dem.valid.at("stress_orientation_deg");
  double integral[2] = {0, 0}, area[2] = {0, 0};
  for (const auto& t : mesh.triangles) {
    if (!(ok[t[0]] && ok[t[1]] && ok[t[2]])) continue;
    const Vec2 c = (mesh.nodes[t[0]] + mesh.nodes[t[1]] + mesh.nodes[t[2]]) / 3.0;
    if (c.x() == apex_x) continue;
    const int side = c.x() < apex_x ? 0 : 1;
    const double a = 0.5 * dem::cross(mesh.nodes[t[1]] - mesh.nodes[t[0]], mesh.nodes[t[2]] - mesh.nodes[t[0]]);
    double mean = 0;
    for (int k : t) mean += (side == 0 ? 90.0 - th[k] : th[k] - 90.0) / 3.0;
    integral[side] += a * mean;
    area[side] += a;
  }
  const double left = area[0] > 0 ? integral[0] / area[0] : NAN;
  const double right = area[1] > 0 ? integral[1] / area[1] : NAN;
  return {{"psi_fit_left_deg", left}, {"psi_fit_right_deg", right}, {"psi_fit_deg", 0.5 * (left + right)}};
}

// The base-pressure dip of every source in profiles.csv: at the lowest cut, sigma_yy at the
// axis over its maximum, and where the maximum lies (in half-widths from the axis).
nlohmann::json base_pressure_dips(const std::vector<ProfileValue>& rows, double apex_x) {
  std::map<std::string, std::vector<std::pair<double, double>>> base;  // source -> (x, sigma_yy) at lowest cut
  std::map<std::string, double> lowest;
  for (const auto& r : rows)
    if (r.quantity == "sigma_yy") lowest[r.source] = std::min(lowest.count(r.source) ? lowest[r.source] : 1e300, r.y_over_h);
  for (const auto& r : rows)
    if (r.quantity == "sigma_yy" && r.y_over_h == lowest[r.source]) base[r.source].emplace_back(r.x_m, r.value);
  nlohmann::json dips = nlohmann::json::object();
  for (auto& [source, pts] : base) {
    std::sort(pts.begin(), pts.end());
    if (pts.size() < 3) continue;
    const double x0 = pts.front().first, x1 = pts.back().first;
    const double half_width = 0.5 * (x1 - x0);
    auto best = std::max_element(pts.begin(), pts.end(), [](auto& a, auto& b) { return a.second < b.second; });
    // sigma_yy at the axis, linearly interpolated.
    double centre = pts.front().second;
    for (std::size_t i = 0; i + 1 < pts.size(); ++i)
      if (pts[i].first <= apex_x && apex_x <= pts[i + 1].first) {
        const double t = (apex_x - pts[i].first) / std::max(pts[i + 1].first - pts[i].first, 1e-300);
        centre = (1 - t) * pts[i].second + t * pts[i + 1].second;
      }
    dips[source] = {{"y_over_h", lowest[source]},
                    {"centre_over_max", best->second > 0 ? centre / best->second : 0.0},
                    {"max", best->second},
                    {"x_of_max_over_R", half_width > 0 ? (best->first - apex_x) / half_width : 0.0}};
  }
  return dips;
}

// The DEM's misalignment profiles along its cuts (from its orientation rows at the same points),
// written back into profiles.csv in place of any earlier ones.
void write_misalignment_profiles(const std::string& csv, const std::vector<ProfileValue>& rows,
                                 const std::vector<std::pair<const char*, const char*>>& pairs) {
  std::map<std::tuple<std::string, double, double>, double> orientation;
  for (const auto& r : rows)
    if (r.source == "dem" && r.quantity.size() > 16 && r.quantity.substr(r.quantity.size() - 16) == "_orientation_deg")
      orientation[{r.quantity.substr(0, r.quantity.size() - 16), r.y_over_h, r.x_m}] = r.value;
  std::vector<ProfileValue> extra;
  for (const auto& r : rows) {
    if (r.source == "dem" && r.quantity.rfind("misalignment_", 0) != 0) extra.push_back(r);
    if (r.source != "dem" || r.quantity != "stress_orientation_deg") continue;
    for (const auto& [a, b] : pairs) {
      const auto ia = orientation.find({a, r.y_over_h, r.x_m}), ib = orientation.find({b, r.y_over_h, r.x_m});
      if (ia == orientation.end() || ib == orientation.end()) continue;
      extra.push_back({"dem", std::string("misalignment_") + a + "_" + b + "_deg", r.y_over_h, r.x_m,
                       axis_angle_deg(ia->second, ib->second), 0.0, false});
    }
  }
  write_profile_values(csv, extra);
}

// --- Standard errors over the ensemble's piles --------------------------------------------------
//
// The comparison's numbers are functions of the ensemble-mean DEM fields, and most are not
// linear in them (a relative L2 norm, an axis angle), so their standard errors are taken by the
// jackknife over piles: theta_(k) is the number computed with pile k left out of the mean, and
//     SE^2 = (n - 1) / n  sum_k (theta_(k) - mean_k theta_(k))^2,
// which for a mean is exactly the textbook s / sqrt(n). The model is held fixed: the errors say
// how far the member-to-member scatter of the DEM moves each number, not how the model would
// move with the ensemble's angles.

// The fields the jackknife re-averages, as coarse/ keeps them per pile. The stress orientation
// is derived again from the re-averaged tensor, as coarse/ derives the mean's.
const char* const pile_fields[] = {"stress_xx", "stress_yy", "stress_xy", "displacement_x", "displacement_y",
                                   "strain_xx", "strain_yy", "strain_xy"};

// The piles of fields.h5 that carry every field of the DEM's that the jackknife re-averages
// (older files kept only the fit's quantities per pile: no errors then).
bool piles_carry_compared_fields(const PointFields& dem, const PileValues& piles) {
  if (piles.size() < 2) return false;
  for (const auto& pile : piles)
    for (const char* q : pile_fields)
      if (dem.has(q) && !pile.count(q)) return false;
  return true;
}

// The DEM's fields with pile `left_out` taken out of the ensemble mean.
PointFields without_pile(const PointFields& dem, const PileValues& piles, std::size_t left_out) {
  PointFields out = dem;
  const std::size_t n = dem.points.size();
  for (const char* q : pile_fields) {
    if (!dem.has(q)) continue;
    std::vector<double> mean(n, 0.0);
    std::vector<char> ok(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      double sum = 0;
      int count = 0;
      for (std::size_t k = 0; k < piles.size(); ++k) {
        const double v = piles[k].at(q)[i];
        if (k != left_out && std::isfinite(v)) sum += v, ++count;
      }
      if (count > 0) mean[i] = sum / count, ok[i] = 1;
    }
    out.set(q, std::move(mean), std::move(ok));
  }
  if (dem.has("stress_orientation_deg") && dem.has("stress_xx") && dem.has("stress_yy") && dem.has("stress_xy")) {
    std::vector<double> angle(n, 0.0);
    const std::vector<char> ok = both(both(out.valid.at("stress_xx"), out.valid.at("stress_yy")), out.valid.at("stress_xy"));
    for (std::size_t i = 0; i < n; ++i)
      if (ok[i]) angle[i] = compressive_axis_deg(out.at("stress_xx")[i], out.at("stress_yy")[i], out.at("stress_xy")[i]);
    out.set("stress_orientation_deg", std::move(angle), ok);
  }
  return out;
}

// The numbers `numbers_of` gives for the ensemble-mean fields, each number with "<key>_stderr"
// beside it from the jackknife replicates theta_(k) (where every replicate has it as a finite
// number); without replicates (one pile), the numbers alone.
nlohmann::json with_jackknife_errors(const std::function<nlohmann::json(const PointFields&)>& numbers_of, const PointFields& dem,
                                     const std::vector<PointFields>& jackknife) {
  nlohmann::json estimate = numbers_of(dem);
  if (jackknife.empty()) return estimate;
  std::vector<nlohmann::json> replicates;
  for (const PointFields& d : jackknife) replicates.push_back(numbers_of(d));
  const double n = static_cast<double>(replicates.size());
  nlohmann::json errors = nlohmann::json::object();
  for (const auto& [key, value] : estimate.items()) {
    if (!value.is_number()) continue;
    std::vector<double> theta;
    for (const auto& r : replicates)
      if (r.contains(key) && r[key].is_number() && std::isfinite(r[key].get<double>())) theta.push_back(r[key].get<double>());
    if (theta.size() != replicates.size()) continue;
    double mean = 0;
    for (double t : theta) mean += t / n;
    double ss = 0;
    for (double t : theta) ss += (t - mean) * (t - mean);
    errors[key + "_stderr"] = std::sqrt((n - 1) / n * ss);
  }
  estimate.update(errors);
  return estimate;
}

}  // namespace

// The mesh the fields were averaged on, as a gmsh file: coarse's (its report section names it),
// else OUT/pile.msh.
std::string fields_mesh_file(const std::string& out_dir) {
  const std::string report = in_dir(out_dir, "report.json");
  if (std::filesystem::exists(report)) {
    const nlohmann::json r = read_report(report);
    if (r.contains("coarse") && r["coarse"].contains("mesh_file") && r["coarse"]["mesh_file"].is_string())
      return std::filesystem::absolute(r["coarse"]["mesh_file"].get<std::string>()).string();
  }
  return in_dir(out_dir, "pile.msh");
}

namespace {

// Scene text for a closed loop's [continuum] table: numbers that read back to the same double,
// strings quoted as TOML basic strings.
std::string toml_number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  std::string text = buffer;
  if (text.find_first_of(".eE") == std::string::npos) text += ".0";  // a float, not an integer
  return text;
}
std::string toml_string(const std::string& v) {
  std::string text = "\"";
  for (char c : v) text += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return text + "\"";
}

// The [continuum] table of a closed loop: one model on the fields' mesh, with the DEM's bulk
// density and gravity, and the model's own keys.
std::string closed_loop_scene(const std::string& model, const std::string& mesh_file, const FieldsAttributes& fields,
                              const std::vector<std::pair<std::string, double>>& keys) {
  std::string text = "[continuum]\nmodels = [" + toml_string(model) + "]\nmesh_file = " + toml_string(mesh_file) +
                     "\ndensity_kg_per_m2 = " + toml_number(fields.rho_bulk_kg_per_m2) +
                     "\ngravity_m_per_s2 = " + toml_number(fields.gravity_m_per_s2) + "\n[continuum." + model + "]\n";
  for (const auto& [key, value] : keys) text += key + " = " + toml_number(value) + "\n";
  return text;
}

}  // namespace

// The closed loop of the fit: the gravity change of the fields (the DEM's relaxation) solved
// with the fitted isotropic constants on the fields' mesh, into OUT/closed_loop/, and its
// displacements and strains against the DEM's. Null when there is nothing to close (no fitted
// constants, no gravity change); a note instead of numbers when the constants are no stable
// isotropic material.
nlohmann::json closed_loop(const nlohmann::json& fit, const std::string& fields_path, const std::string& out_dir,
                           const ModelSolver& solve) {
  if (!fit.contains("models") || !fit["models"].contains("isotropic")) return nullptr;
  const auto& iso = fit["models"]["isotropic"];
  const auto constant = [&](const char* key) {  // null when the fit had no data
    return iso.contains(key) && iso[key].is_number() ? iso[key].get<double>() : NAN;
  };
  const double lambda = constant("lambda_N_per_m"), mu = constant("mu_N_per_m");
  if (!std::isfinite(lambda) || !std::isfinite(mu)) return nullptr;  // the fit had no data
  const FieldsAttributes fields = read_fields_attributes(fields_path);
  if (fields.gravity_change == 0.0) return nullptr;
  nlohmann::json result = {{"lambda_N_per_m", lambda}, {"mu_N_per_m", mu}};
  if (!(mu > 0) || !IsotropicMaterial::from_lame(lambda, mu).stable()) {
    result["skipped"] = "the fitted constants are not a stable isotropic material";
    return result;
  }
  const double lambda_used = std::max(lambda, 0.0);  // a negative lambda with nu > -1 is clipped, as reported
  const std::string dir = in_dir(out_dir, "closed_loop");
  prepare_output_directory(dir);  // also clears what a killed run left there
  solve(closed_loop_scene("elastic", fields_mesh_file(out_dir), fields,
                          {{"lame_lambda_N_per_m", lambda_used}, {"shear_modulus_N_per_m", mu},
                           {"gravity_change", fields.gravity_change}}),
        "(the closed loop of the fit)", dir);
  result.update(compare_displacements(fields_path, in_dir(dir, "models.h5"), "elastic"));
  result["lame_lambda_used_N_per_m"] = lambda_used;
  result["directory"] = "closed_loop";
  return result;
}

namespace {

// One model of a models.h5 against the DEM: its fields on the DEM's points and on its scale,
// and its numbers with their errors over the piles.
struct ComparedModel {
  PointFields fields;
  nlohmann::json numbers;
  double stress_scale = 1.0;  ///< (rho g)_DEM / (rho g)_model
};
ComparedModel compare_model(const std::string& name, const std::string& models_path, const std::string& fields_path,
                            const PointFields& dem, const Triangulation& mesh, double height,
                            const std::vector<PointFields>& jackknife) {
  PointFields raw = read_model_fields(models_path, name);
  const Scales k = scale_to_dem(raw, name, fields_path, models_path, dem);
  const std::vector<int> index =
      match_model_points(raw, dem, 1e-9 * std::max(height, 1e-300), models_path, name, fields_path);
  ComparedModel out{reindex(raw, index, dem.points.size()), nlohmann::json::object(), k.stress};
  nlohmann::json& m = out.numbers;
  m["matched_points"] = std::count_if(index.begin(), index.end(), [](int i) { return i >= 0; });
  if (k.has_change) m["displacement_scale_dem_over_model"] = k.change;
  if (!k.skipped.empty()) m["displacement_comparison_skipped"] = k.skipped;
  const Region lower_half = [&](const Vec2& c) { return c.y() < 0.5 * height; };
  m.update(with_jackknife_errors([&](const PointFields& d) { return model_differences(mesh, out.fields, d, lower_half); },
                                 dem, jackknife));
  return out;
}

// The OSL closure's closed loop: the OSL solved with the constants fitted to the DEM's stress
// (osl_closure_fit) on the fields' mesh, into OUT/closed_loop_osl/, and compared with the DEM as
// every model is. Null without constants; a note where the solve refuses them.
nlohmann::json osl_closed_loop(const nlohmann::json& fit, const std::string& fields_path, const std::string& out_dir,
                               const ModelSolver& solve, const PointFields& dem, const Triangulation& mesh,
                               double height, const std::vector<PointFields>& jackknife) {
  const double eta = fit["eta"].get<double>(), mu = fit["mu"].get<double>();
  if (!std::isfinite(eta) || !std::isfinite(mu)) return nullptr;
  if (!(eta > 0)) return {{"skipped", "the fitted eta is not positive: the closure is not hyperbolic"}};
  const std::string dir = in_dir(out_dir, "closed_loop_osl");
  prepare_output_directory(dir);
  solve(closed_loop_scene("osl", fields_mesh_file(out_dir), read_fields_attributes(fields_path), {{"eta", eta}, {"mu", mu}}),
        "(the closed loop of the OSL closure fit)", dir);
  const ComparedModel compared = compare_model("osl", in_dir(dir, "models.h5"), fields_path, dem, mesh, height, jackknife);
  nlohmann::json result = compared.numbers;
  result["stress_scale_dem_over_model"] = compared.stress_scale;
  result["directory"] = "closed_loop_osl";
  return result;
}

}  // namespace

namespace {

// The fields of compare.vtu, each 0 where its source has no value (a mask beside it says where).
struct VtuFields {
  std::vector<VtuField> fields;
  void add(const std::string& name, const std::vector<double>& v, const std::vector<char>& ok) {
    VtuField f{name, v};
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!ok[i]) f.values[i] = 0.0;
    fields.push_back(std::move(f));
  }
  // 1 where the source has a value, since a field written as 0 where it has none cannot tell
  // "no data" from zero.
  void add_mask(const std::string& name, const std::vector<char>& ok) {
    VtuField f{name, std::vector<double>(ok.size())};
    for (std::size_t i = 0; i < ok.size(); ++i) f.values[i] = ok[i] ? 1.0 : 0.0;
    fields.push_back(std::move(f));
  }
  // Displacements as vectors, for ParaView's Glyph and Warp.
  void add_vector(const std::string& name, const PointFields& p) {
    if (!p.has("displacement_x") || !p.has("displacement_y")) return;
    VtuField f{name, std::vector<double>(3 * p.points.size(), 0.0), 3};
    for (std::size_t i = 0; i < p.points.size(); ++i)
      if (p.valid.at("displacement_x")[i] && p.valid.at("displacement_y")[i]) {
        f.values[3 * i] = p.at("displacement_x")[i];
        f.values[3 * i + 1] = p.at("displacement_y")[i];
      }
    fields.push_back(std::move(f));
  }
};

const std::vector<std::pair<const char*, const char*>> axis_pairs = {{"stress", "strain"}, {"stress", "fabric"}, {"strain", "fabric"}};

// The comparison of one run, step by step (run()): the DEM's fields read once, with the
// ensemble's jackknife replicates; each step adds its numbers to the report section and its
// fields to compare.vtu.
class Comparison {
 public:
  explicit Comparison(const CompareRunOptions& opt);
  nlohmann::json run();

 private:
  void compare_models();
  void dem_misalignment();
  void profiles();
  void fpa_angle();
  void osl_closure();
  void stress_strain_fits();
  void write_outputs();

  const CompareRunOptions& opt_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  CompareSettings settings_;
  Triangulation mesh_;
  PointFields dem_;
  double height_ = 0, apex_x_ = 0, repose_deg_ = 0;
  FieldsAttributes attributes_;  ///< of the DEM's fields: rho g, height, the snapshot's time
  PileValues piles_;
  std::vector<PointFields> jackknife_;  ///< an ensemble's fields with each pile left out in turn
  Region lower_half_;
  nlohmann::json section_;
  VtuFields vtu_;
};

Comparison::Comparison(const CompareRunOptions& opt) : opt_(opt) {
  SceneReader reader = SceneReader::from_file(opt.scene_path);
  settings_ = read_compare_scene(reader, std::filesystem::path(opt.scene_path).parent_path().string(), opt.out_dir);
  reader.reject_unknown({"compare"}, scene_tables());
  const std::string& fields_path = settings_.fields_path;
  bool on_nodes = true;
  dem_ = read_dem_fields(fields_path, &mesh_, &on_nodes);
  if (!on_nodes)
    throw InputError(fields_path + ": compare needs the fields at the mesh nodes (coarse.location = \"nodes\")");
  attributes_ = read_fields_attributes(fields_path);
  height_ = attributes_.height_m;
  if (!(height_ > 0))
    throw InputError(fields_path + ": root attribute height_m: expected the pile's height (> 0), found " +
                     std::to_string(height_));
  piles_ = read_pile_values(fields_path);
  if (piles_carry_compared_fields(dem_, piles_))
    for (std::size_t k = 0; k < piles_.size(); ++k) jackknife_.push_back(without_pile(dem_, piles_, k));
  // The FPA's repose angle: the scene's, else the one the DEM measured (handed over by
  // `pilelab run`, or read from the DEM's report section); without any, no FPA angle.
  repose_deg_ = settings_.repose_angle_deg;
  if (repose_deg_ <= 0 && opt.measured_repose_angle_deg) repose_deg_ = *opt.measured_repose_angle_deg;
  if (repose_deg_ <= 0 && !opt.measured_repose_angle_deg)
    repose_deg_ = dem::mean_repose_angle_deg(read_report(in_dir(opt.out_dir, "report.json"))).value_or(0.0);
  // The axis: through the apex, the highest node, or the middle of the highest nodes of a flat
  // top, as the continuum models place it (continuum/pile_domain.cpp, measure_pile).
  double top = -INFINITY, xmin = INFINITY, xmax = -INFINITY;
  for (const Vec2& p : mesh_.nodes) top = std::max(top, p.y()), xmin = std::min(xmin, p.x()), xmax = std::max(xmax, p.x());
  const double tolerance = 1e-9 * std::max(1.0, xmax - xmin);
  double sum = 0;
  int highest = 0;
  for (const Vec2& p : mesh_.nodes)
    if (p.y() >= top - tolerance) sum += p.x(), ++highest;
  apex_x_ = sum / highest;
  const double h = height_;
  lower_half_ = [h](const Vec2& c) { return c.y() < 0.5 * h; };
}

nlohmann::json Comparison::run() {
  section_ = {{"fields_file", settings_.fields_path}, {"height_m", height_}, {"apex_x_m", apex_x_}};
  section_["standard_errors"] =
      jackknife_.empty() ? nlohmann::json("none (a single pile)")
                         : nlohmann::json("jackknife over " + std::to_string(jackknife_.size()) +
                                          " piles, the model held fixed: KEY_stderr next to each KEY");
  for (const char* q : {"stress_xx", "stress_yy", "stress_xy", "stress_orientation_deg", "displacement_x", "displacement_y"})
    if (dem_.has(q)) vtu_.add(std::string("dem_") + q, dem_.at(q), dem_.valid.at(q));
  if (dem_.has("pressure")) vtu_.add("dem_pressure", dem_.at("pressure"), dem_.valid.at("pressure"));
  // The vertical stress as the figures and the paper draw it: compression positive, in rho g h.
  const double rho_g_h = attributes_.rho_g() * height_;
  if (dem_.has("stress_yy") && rho_g_h > 0) {
    std::vector<double> v = dem_.at("stress_yy");
    for (double& x : v) x /= -rho_g_h;
    vtu_.add("dem_sigma_yy_over_rho_g_h", v, dem_.valid.at("stress_yy"));
  }
  if (dem_.has("stress_yy")) vtu_.add_mask("dem_has_data", dem_.valid.at("stress_yy"));
  vtu_.add_vector("dem_displacement", dem_);

  compare_models();
  dem_misalignment();
  profiles();
  fpa_angle();
  osl_closure();
  stress_strain_fits();
  write_outputs();
  return section_;
}

// 1. Each model against the DEM: its numbers with their errors, and its fields for ParaView.
void Comparison::compare_models() {
  const std::string& models_path = settings_.models_path;
  nlohmann::json models = nlohmann::json::object();
  section_["stress_scale_dem_over_model"] = 1.0;
  if (std::filesystem::exists(models_path)) {
    for (const std::string& name : model_names(models_path)) {
      const ComparedModel compared = compare_model(name, models_path, settings_.fields_path, dem_, mesh_, height_, jackknife_);
      section_["stress_scale_dem_over_model"] = compared.stress_scale;
      const PointFields& model = compared.fields;
      for (const char* c : {"stress_xx", "stress_yy", "stress_xy"}) {
        if (!model.has(c) || !dem_.has(c)) continue;
        vtu_.add(name + "_" + c, model.at(c), model.valid.at(c));
        std::vector<double> d(dem_.points.size());
        for (std::size_t i = 0; i < d.size(); ++i) d[i] = model.at(c)[i] - dem_.at(c)[i];
        vtu_.add(name + "_minus_dem_" + c, d, both(model.valid.at(c), dem_.valid.at(c)));
      }
      std::vector<char> axis_ok;
      if (const auto angle = axis_angle_to_dem(model, dem_, axis_ok)) vtu_.add(name + "_axis_angle_to_dem_deg", *angle, axis_ok);
      if (model.has("displacement_x") && dem_.has("displacement_x")) {
        vtu_.add(name + "_displacement_x", model.at("displacement_x"), model.valid.at("displacement_x"));
        vtu_.add(name + "_displacement_y", model.at("displacement_y"), model.valid.at("displacement_y"));
        vtu_.add_vector(name + "_displacement", model);
      }
      if (model.has("stress_yy")) vtu_.add_mask(name + "_has_data", model.valid.at("stress_yy"));
      models[name] = compared.numbers;
    }
  }
  section_["models_file"] = std::filesystem::exists(models_path) ? models_path : "";
  section_["models"] = models;
}

// 2. Within the DEM: misalignment of stress, strain and fabric axes (the paper's Fig. 15).
void Comparison::dem_misalignment() {
  nlohmann::json misalignment = nlohmann::json::object();
  for (const auto& [a, b] : axis_pairs) {
    const std::string qa = std::string(a) + "_orientation_deg", qb = std::string(b) + "_orientation_deg";
    if (!dem_.has(qa) || !dem_.has(qb)) continue;
    std::vector<char> ok = both(dem_.valid.at(qa), dem_.valid.at(qb));
    std::vector<double> angle(dem_.points.size(), 0.0);
    for (std::size_t i = 0; i < angle.size(); ++i)
      if (ok[i]) angle[i] = axis_angle_deg(dem_.at(qa)[i], dem_.at(qb)[i]);
    const std::string name = std::string("misalignment_") + a + "_" + b + "_deg";
    misalignment[name] = {{"mean", area_mean(mesh_, angle, ok)}, {"mean_lower_half", area_mean(mesh_, angle, ok, lower_half_)}};
    vtu_.add("dem_" + name, angle, ok);
  }
  section_["dem_misalignment"] = misalignment;
}

// 3. Profiles: the base dip of every source, and the misalignment along the DEM's cuts.
void Comparison::profiles() {
  const std::string csv = in_dir(opt_.out_dir, "profiles.csv");
  if (!std::filesystem::exists(csv)) return;
  const auto rows = read_profile_values(csv);
  section_["base_pressure_dip"] = base_pressure_dips(rows, apex_x_);
  write_misalignment_profiles(csv, rows, axis_pairs);
}

// 4. The FPA angle that best fits the DEM's stress axes, with its error over the piles.
void Comparison::fpa_angle() {
  if (!dem_.has("stress_orientation_deg")) return;
  nlohmann::json fpa =
      with_jackknife_errors([&](const PointFields& d) { return fpa_angle_fit(mesh_, d, apex_x_); }, dem_, jackknife_);
  // Without an angle (none in the scene, none measured) there is no FPA angle to set beside the fit.
  fpa["repose_angle_deg"] = repose_deg_ > 0 ? nlohmann::json(repose_deg_) : nlohmann::json();
  fpa["psi_fpa_deg"] = repose_deg_ > 0 ? nlohmann::json(45.0 - 0.5 * repose_deg_) : nlohmann::json();
  section_["fpa_angle"] = fpa;
}

// 5. The OSL closure's two constants that best fit the DEM's stress, with their errors, and the
// OSL solved with them.
void Comparison::osl_closure() {
  if (!dem_.has("stress_xx") || !dem_.has("stress_yy") || !dem_.has("stress_xy")) return;
  nlohmann::json osl = with_jackknife_errors(
      [&](const PointFields& d) { return osl_closure_fit(mesh_, d, apex_x_, repose_deg_); }, dem_, jackknife_);
  if (opt_.solve_models) {
    const nlohmann::json loop =
        osl_closed_loop(osl, settings_.fields_path, opt_.out_dir, opt_.solve_models, dem_, mesh_, height_, jackknife_);
    if (!loop.is_null()) osl["closed_loop"] = loop;
  }
  section_["osl_closure_fit"] = osl;
}

// 6. Stress-strain fits, when the DEM has strains, and the fit's closed loop.
void Comparison::stress_strain_fits() {
  if (!dem_.has("strain_xx") || !dem_.has("stress_change_xx")) return;
  std::vector<FitSample> samples;
  std::vector<FitResult> fits;
  const double spacing = fit_sample_spacing(settings_.fields_path, settings_.fit_sample_spacing_m);
  nlohmann::json fit = fit_section(dem_, piles_, spacing, settings_.fit_resamples, settings_.fit_folds,
                                   settings_.fit_seed, &samples, &fits);
  write_fit_samples(in_dir(opt_.out_dir, "fit_samples.csv"), samples, fits);
  if (opt_.solve_models) {
    const nlohmann::json loop = closed_loop(fit, settings_.fields_path, opt_.out_dir, opt_.solve_models);
    if (!loop.is_null()) fit["closed_loop"] = loop;
  }
  write_report_section(in_dir(opt_.out_dir, "report.json"), "fit", fit);
}

// 7. Everything side by side for ParaView, and the report.
void Comparison::write_outputs() {
  std::vector<std::array<double, 2>> nodes;
  for (const auto& p : mesh_.nodes) nodes.push_back({p.x(), p.y()});
  // At the DEM snapshot's time, so that ParaView shows the comparison beside that frame of dem.pvd.
  const double time = attributes_.snapshot_time_s;
  write_triangle_vtu(in_dir(opt_.out_dir, "compare.vtu"), nodes, mesh_.triangles, vtu_.fields, {}, time);
  // A one-entry collection, so ParaView opens the comparison like the DEM's dem.pvd.
  std::ostringstream pvd;
  pvd.precision(17);
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n"
      << "    <DataSet timestep=\"" << time << "\" part=\"0\" file=\"compare.vtu\"/>\n  </Collection>\n</VTKFile>\n";
  write_text_atomically(in_dir(opt_.out_dir, "compare.pvd"), pvd.str());
  section_["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  write_report_section(in_dir(opt_.out_dir, "report.json"), "compare", section_);
}

}  // namespace

nlohmann::json run_compare(const CompareRunOptions& opt) { return Comparison(opt).run(); }

}  // namespace pilelab::compare
