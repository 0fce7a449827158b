#pragma once
// The oriented stress linearity (OSL) closure of Wittmer, Claudin, Cates and Bouchaud (Nature
// 382, 336, 1996): in a symmetric pile, with compressive stresses and x measured from the axis,
//   sigma_xx = eta sigma_yy + mu sigma_xy sign(x),
// two constants for the whole pile. The fixed principal axes are its member eta = 1,
// mu = 2 tan(phi) (models/fpa.h). Tension positive, on side s = sign(x), it is the linear
// closure s_yy = (s_xx - s mu s_xy) / eta, solved as every linear closure is
// (continuum/closure_problem.h); it is hyperbolic for eta > 0.
//
// The exact stress in a symmetric wedge of flank angle phi (docs/CONTINUUM.md derives it):
// with the apex at (x_a, h), depth Z = h - y, X = |x - x_a|, t = tan(phi), q = -s p_xy, in
// units of rho g, and tau = (sqrt(mu^2 + 4 eta) - mu) / 2 the slope dX/dZ of the
// characteristic ray from the apex:
//   outer region, tau Z <= X <= Z / t: a function of the depth below the surface, e = Z - t X,
//     p_xx = f e,  q = t f e,  p_yy = (1 + t^2 f) e,   f = eta / (1 + mu t - eta t^2);
//   inner region, X <= tau Z (fed by the axis, where q = 0 by symmetry):
//     p_xx = eta (1 - a) Z,  p_yy = (mu a / eta) X + (1 - a) Z,  q = a X,
//     a = (tau + (1 - t tau) (t f - tau (1 + t^2 f))) / (tau (2 - mu tau / eta)),
// the traction across the ray continuous (the weak form's condition on a characteristic).
// At eta = 1, mu = 2 t this is the FPA's wedge solution (a = sin(phi)).
#include <cmath>

#include "continuum/closure_problem.h"
#include "continuum/stress_fields.h"

namespace pilelab::continuum {

struct OslSettings : ClosureSettings {
  double eta = 1.0;  ///< sigma_xx / sigma_yy where sigma_xy = 0
  double mu = 0.0;   ///< the weight of sign(x) sigma_xy
};

/// The OSL's closure, the same on both sides up to the sign of x.
inline LinearClosure osl_closure(double eta, double mu) {
  LinearClosure c;
  c.right = {1.0 / eta, -mu / eta};
  c.left = {1.0 / eta, mu / eta};
  return c;
}

class OslProblem : public ClosureProblem {
 public:
  OslProblem(const Triangulation2& tria, const OslSettings& settings, double density_kg_per_m2,
             double gravity_m_per_s2, double apex_x_m)
      : ClosureProblem("osl", tria, settings, osl_closure(settings.eta, settings.mu), density_kg_per_m2,
                       gravity_m_per_s2, apex_x_m) {}
};

/// The slope dX/dZ of the characteristic ray from the apex into each side.
inline double osl_apex_ray_slope(double eta, double mu) { return 0.5 * (std::sqrt(mu * mu + 4.0 * eta) - mu); }

/// Whether the wedge solution exists: the ray from the apex inside the wedge (tau t < 1), the
/// flank not a characteristic (1 + mu t - eta t^2 > 0), and a finite inner slope.
inline bool osl_wedge_solution_exists(double eta, double mu, double phi_deg) {
  const double t = std::tan(phi_deg * M_PI / 180.0), tau = osl_apex_ray_slope(eta, mu);
  return eta > 0 && tau * t < 1 && 1 + mu * t - eta * t * t > 0 && std::abs(2 - mu * tau / eta) > 1e-12;
}

/// Compressive-positive stress (N/m) at (x, y) in the symmetric wedge of flank angle phi_deg
/// with apex (apex_x, h) (see above; osl_wedge_solution_exists must hold).
inline Stress2 osl_symmetric_wedge_stress(double eta, double mu, double phi_deg, double height, double apex_x,
                                          double rho_g, double x, double y) {
  const double t = std::tan(phi_deg * M_PI / 180.0), tau = osl_apex_ray_slope(eta, mu);
  const double f = eta / (1 + mu * t - eta * t * t);
  const double Z = height - y, X = std::abs(x - apex_x), side = x < apex_x ? -1.0 : 1.0;
  double pxx, pyy, q;
  if (X <= tau * Z) {
    const double a = (tau + (1 - t * tau) * (t * f - tau * (1 + t * t * f))) / (tau * (2 - mu * tau / eta));
    pxx = eta * (1 - a) * Z;
    pyy = mu * a / eta * X + (1 - a) * Z;
    q = a * X;
  } else {
    const double e = std::max(0.0, Z - t * X);
    pxx = f * e;
    pyy = (1 + t * t * f) * e;
    q = t * f * e;
  }
  return {rho_g * pxx, rho_g * pyy, -side * rho_g * q};
}

}  // namespace pilelab::continuum
