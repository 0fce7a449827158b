#pragma once
// The fixed-principal-axes (FPA) closure of Wittmer, Cates and Claudin: the principal axes at
// +-psi = +-(pi/4 - phi/2) from the vertical on the two sides of the apex. With t = tan(phi)
// = cot(2 psi) and s = +1 right of the axis, -1 left of it, the closure is linear on each side,
//   s_yy = s_xx - 2 s t s_xy   (tension positive),
// and is solved as every linear closure is (continuum/closure_problem.h). Its exact wedge
// solution is continuum/fpa_exact.h.
#include <string>

#include "continuum/closure_problem.h"

namespace pilelab::continuum {

struct FpaSettings : ClosureSettings {
  double left_repose_angle_deg = 28.0;
  double right_repose_angle_deg = 28.0;
  /// true: the angles are the DEM pile's, read from the "dem" section of OUT/report.json
  /// (apply_dem_repose_angles) or handed over by `pilelab run`, not from the scene.
  bool angles_from_dem = false;
  bool angles_in_scene = false;  ///< the scene sets an angle key
  bool angles_defaulted = false;  ///< the DEM measured no angle on a flank: the defaults stand in
};

/// The FPA's closure for the two repose angles.
LinearClosure fpa_closure(double left_repose_angle_deg, double right_repose_angle_deg);

class FpaProblem : public ClosureProblem {
 public:
  FpaProblem(const Triangulation2& tria, const FpaSettings& settings, double density_kg_per_m2, double gravity_m_per_s2,
             double apex_x_m)
      : ClosureProblem("fpa", tria, settings, fpa_closure(settings.left_repose_angle_deg, settings.right_repose_angle_deg),
                       density_kg_per_m2, gravity_m_per_s2, apex_x_m) {}
};

/// For angles_from_dem: takes repose_angle_left_deg and repose_angle_right_deg from the "dem"
/// section of report_path. InputError naming the file and key if absent or outside (0, 45).
void apply_dem_repose_angles(FpaSettings& fpa, const std::string& report_path);

}  // namespace pilelab::continuum
