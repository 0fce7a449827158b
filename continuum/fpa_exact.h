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

/// The asymmetric wedge: phi_left on the left of the apex, phi_right on its right. Each side has
/// the outer field of its own flank and a linear inner field behind its own ray; the two inner
/// fields are joined at the axis by the continuity of p_xx and p_xy (docs/CONTINUUM.md). In (X, Z)
/// with q = p_XZ = -p_xy, and the left side mirrored (X' = -X, q' = -q), each inner field is
///   p_ZZ = (2 t a - b) X + (1 - a) Z,   q = a X + b Z,   b = A - a tau,   A = sin cos (1 - tau t);
/// the axis gives a_R tau_R + a_L tau_L = A_R + A_L and
///   a_R (2 t_R tau_R - 1) - a_L (2 t_L tau_L - 1) = 2 t_R A_R - 2 t_L A_L.
/// Equal angles give a_R = a_L = A / tau, b = 0: the symmetric solution above.
inline Stress2 fpa_wedge_stress(double phi_left_deg, double phi_right_deg, double height, double apex_x, double rho_g,
                                double x, double y) {
  struct Side {
    double t, tau, A, s, c;
  };
  auto side = [](double phi_deg) {
    const double phi = phi_deg * M_PI / 180.0, psi = M_PI / 4 - phi / 2;
    const double t = std::tan(phi), tau = std::tan(psi), s = std::sin(phi), c = std::cos(phi);
    return Side{t, tau, s * c * (1 - tau * t), s, c};
  };
  const Side L = side(phi_left_deg), R = side(phi_right_deg);
  // Two equations for the inner slopes a_R, a_L (Cramer's rule).
  const double m11 = R.tau, m12 = L.tau, r1 = R.A + L.A;
  const double m21 = 2 * R.t * R.tau - 1, m22 = -(2 * L.t * L.tau - 1), r2 = 2 * R.t * R.A - 2 * L.t * L.A;
  const double det = m11 * m22 - m12 * m21;
  const double aR = (r1 * m22 - m12 * r2) / det, aL = (m11 * r2 - m21 * r1) / det;

  const double Z = height - y, X = x - apex_x;
  const bool right = X >= 0;
  const Side& S = right ? R : L;
  const double a = right ? aR : aL, Xs = std::abs(X);  // mirrored onto the right-hand form
  double pzz, q, pxx;
  if (Xs <= Z * S.tau) {
    const double b = S.A - a * S.tau;
    pzz = (2 * S.t * a - b) * Xs + (1 - a) * Z;
    q = a * Xs + b * Z;
  } else {
    const double eta = std::max(0.0, Z - S.t * Xs);
    pzz = (1 + S.s * S.s) * eta;
    q = S.s * S.c * eta;
  }
  pxx = pzz - 2 * S.t * q;
  const double pxy = right ? -q : q;  // p_xy = -p_XZ; mirroring flips the sign of the shear
  return {rho_g * pxx, rho_g * pzz, rho_g * pxy};
}

}  // namespace pilelab::continuum
