// The FPA model: its scene table [continuum.fpa], its angles (the scene's or the DEM's), and
// its solve with the figures that tell how far its stress is to be trusted.
#include "continuum/models/fpa.h"

#include <cmath>
#include <filesystem>
#include <iostream>

#include "common/error.h"
#include "common/report.h"
#include "continuum/model_context.h"

namespace pilelab::continuum {

LinearClosure fpa_closure(double left_deg, double right_deg) {
  // psi = pi/4 - phi/2, so cot(2 psi) = tan(phi): the closure s_xx - s_yy = 2 s cot(2 psi) s_xy.
  constexpr double degree = M_PI / 180.0;
  LinearClosure c;
  c.right = {1.0, -(2.0 * std::tan(right_deg * degree))};
  c.left = {1.0, 2.0 * std::tan(left_deg * degree)};
  return c;
}

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

namespace {

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

std::shared_ptr<const ModelSettings> read(ModelTable& t) {
  auto f = std::make_shared<FpaSettings>();
  SceneReader& r = t.reader();
  if (t.has("repose_angle_deg") && (t.has("left_repose_angle_deg") || t.has("right_repose_angle_deg")))
    throw InputError(t.source() + ": [continuum.fpa]: give either repose_angle_deg (both sides) or "
                                  "left_repose_angle_deg and right_repose_angle_deg, not both");
  f->angles_from_dem = r.get_choice(t.key("repose_angle_source"), "scene", {"scene", "dem"}) == "dem";
  f->angles_in_scene = t.has("repose_angle_deg") || t.has("left_repose_angle_deg") || t.has("right_repose_angle_deg");
  // With "dem" the measured angles replace any given here (`pilelab run` fills in the DEM's angles
  // itself, which are then the same); the keys are still checked.
  const double phi = read_repose_angle(r, t.key("repose_angle_deg"), 28.0);
  f->left_repose_angle_deg = read_repose_angle(r, t.key("left_repose_angle_deg"), phi);
  f->right_repose_angle_deg = read_repose_angle(r, t.key("right_repose_angle_deg"), phi);
  read_closure_settings(t, *f);
  return f;
}

// The angles: the scene's; or the DEM's, handed over by `pilelab run` (one pile or an
// ensemble's mean) where the scene sets none or asks for the DEM's, or, for `pilelab solve`
// with repose_angle_source = "dem", read from the DEM's report section.
FpaSettings with_angles(FpaSettings f, const ModelContext& c) {
  const MeasuredPile& m = c.measured;
  const bool measured = m.left_repose_angle_deg && m.right_repose_angle_deg && *m.left_repose_angle_deg > 0 &&
                        *m.left_repose_angle_deg < 45 && *m.right_repose_angle_deg > 0 && *m.right_repose_angle_deg < 45;
  if (measured && (!f.angles_in_scene || f.angles_from_dem)) {
    f.left_repose_angle_deg = *m.left_repose_angle_deg;
    f.right_repose_angle_deg = *m.right_repose_angle_deg;
    f.angles_from_dem = true;  // reported as repose_angle_source = "dem"
  } else if (f.angles_from_dem) {
    apply_dem_repose_angles(f, (std::filesystem::path(c.out_dir) / "report.json").string());
  } else if (!f.angles_in_scene && m.repose_unmeasured) {
    f.angles_defaulted = true;  // reported as repose_angle_source = "default", with a warning
  }
  return f;
}

// The FPA closure with the pile's repose angles, and how well its stress balances gravity.
nlohmann::json solve(const ModelSettings& settings, ModelContext& c) {
  const FpaSettings f = with_angles(dynamic_cast<const FpaSettings&>(settings), c);
  FpaProblem problem(c.tria, f, c.settings.density_kg_per_m2, c.settings.gravity_m_per_s2, c.pile.apex_x_m);
  nlohmann::json j = solve_model(problem, "fpa", f.solver, c);
  const ClosureResult& r = problem.result();
  j["left_repose_angle_deg"] = f.left_repose_angle_deg;
  j["right_repose_angle_deg"] = f.right_repose_angle_deg;
  j["repose_angle_source"] = f.angles_from_dem ? "dem" : f.angles_defaulted ? "default" : "scene";
  if (f.angles_defaulted)
    warn(c, j, "the DEM pile has a flank whose angle of repose could not be measured (too few surface bins), so the "
               "FPA takes the default " + std::to_string(f.left_repose_angle_deg) + " / " +
               std::to_string(f.right_repose_angle_deg) + " degrees; set continuum.fpa.repose_angle_deg to choose");
  // Where p_xy has the side's sign the FPA's fixed direction is the minor principal axis.
  j["minor_axis_fixed_area_fraction"] = problem.result().reversed_shear_area_fraction;
  report_closure(f, problem.result(), "FPA", c, j);
  return j;
}

}  // namespace

extern const ModelDefinition fpa_model = {"fpa", "fixed principal axes (Wittmer, Cates & Claudin), least squares", read,
                                          solve};

}  // namespace pilelab::continuum
