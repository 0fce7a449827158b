#pragma once
// The exact FPA stress in a symmetric wedge (docs/CONTINUUM.md derives it). With the apex at
// (x_a, h), depth Z = h - y, X = x - x_a, t = tan(phi), psi = pi/4 - phi/2, and compressive
// stresses in units of rho g:
//   outer region, Z tan(psi) <= |X| <= Z / t (reached by both characteristics from the surface):
//     a function of the depth below the surface, eta = Z - t |X|:
//     p_xx = cos^2(phi) eta,  p_yy = (1 + sin^2(phi)) eta,  p_xy = -sign(X) sin(phi) cos(phi) eta;
//   inner region, |X| <= Z tan(psi) (behind the characteristic ray from the apex, fed by the axis):
//     p_xx = (1 - a) Z,  p_yy = (1 - a) Z + 2 t a |X|,  p_xy = -a X,
//     a = sin(phi) cos(phi) (1 - tan(psi) t) / tan(psi).
// Linear in each of the four sectors, continuous, with kinks on the rays |X| = Z tan(psi) and
// on the axis. The base pressure dips to (1 - a) rho g h under the apex and peaks at
// (1 - a + 2 t a tan(psi)) rho g h at |X| = h tan(psi).
#include <cmath>

#include "continuum/stress_fields.h"

namespace pilelab::continuum {

inline double fpa_wedge_inner_coefficient(double phi_deg) {
  const double phi = phi_deg * M_PI / 180.0, psi = M_PI / 4 - phi / 2;
  return std::sin(phi) * std::cos(phi) * (1.0 - std::tan(psi) * std::tan(phi)) / std::tan(psi);
}

/// Compressive-positive stress (N/m) at (x, y) in the wedge with apex (apex_x, h).
inline Stress2 fpa_symmetric_wedge_stress(double phi_deg, double height, double apex_x, double rho_g, double x,
                                          double y) {
  const double phi = phi_deg * M_PI / 180.0, psi = M_PI / 4 - phi / 2, t = std::tan(phi);
  const double Z = height - y, X = x - apex_x, sign = X < 0 ? -1.0 : 1.0, ax = std::abs(X);
  if (ax <= Z * std::tan(psi)) {
    const double a = fpa_wedge_inner_coefficient(phi_deg);
    return {rho_g * (1 - a) * Z, rho_g * ((1 - a) * Z + 2 * t * a * ax), -rho_g * a * X};
  }
  const double eta = std::max(0.0, Z - t * ax);
  const double s = std::sin(phi), c = std::cos(phi);
  return {rho_g * c * c * eta, rho_g * (1 + s * s) * eta, -sign * rho_g * s * c * eta};
}

}  // namespace pilelab::continuum
