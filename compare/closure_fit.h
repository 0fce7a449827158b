#pragma once
// The oriented stress linearity (OSL) closure fitted to the DEM's own stress: the constants of
// sigma_xx = eta sigma_yy + mu sigma_xy sign(x - x_apex) (Wittmer, Claudin, Cates & Bouchaud
// 1996; continuum/models/osl.h) that minimise the closure's misfit over the pile,
//   int (sigma_xx - eta sigma_yy - mu s sigma_xy)^2 dA,
// a linear least-squares problem in (eta, mu). The same relation holds with tension-positive
// stresses, so the fields are taken as fields.h5 stores them. The FPA is the member eta = 1,
// mu = 2 tan(phi): its misfit at the pile's repose angle is reported beside the fit's, so a
// reader sees how much the two constants gain over the angle alone.
#include <nlohmann/json.hpp>

#include "compare/point_fields.h"

namespace pilelab::compare {

/// {eta, mu, r_squared (1 - misfit / variance of sigma_xx), relative_misfit (||misfit|| /
/// ||sigma_xx||), fpa_relative_misfit (at eta = 1, mu = 2 tan(repose); absent without an
/// angle), area_m2}, integrated with the vertex rule over the triangles whose three nodes carry
/// the stress; NaN constants if fewer than three such triangles or a singular system.
nlohmann::json osl_closure_fit(const Triangulation& mesh, const PointFields& dem, double apex_x, double repose_deg);

}  // namespace pilelab::compare
