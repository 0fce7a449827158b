#include "dem/contact_law.h"

#include <algorithm>
#include <cmath>

namespace pilelab::dem {

double contact_length(const ContactParameters& p, double lever_a, double lever_b) {
  // An infinite lever (a wall) leaves the other one: r_a r_b / (r_a + r_b) -> r_b.
  const double harmonic = std::isinf(lever_a) ? lever_b
                          : std::isinf(lever_b) ? lever_a
                                                : lever_a * lever_b / (lever_a + lever_b);
  return p.contact_length == ContactLength::book ? 4.0 * harmonic : harmonic;
}

ContactForce contact_force(const ContactParameters& p, const ContactKinematics& k, double l,
                           double spring, double dt) {
  ContactForce f{0.0, 0.0, 0.0};
  // A.1: elastic part from the effective depth d_eff = A / l.
  const double repulsive = p.youngs_modulus * k.area / l;
  // A.1: damping proportional to d(d_eff)/dt = (dA/dt) / l. For rigid motions dA/dt is exactly
  // chord * approach speed (see convex_overlap.h), which we use instead of a finite difference.
  const double d_eff_rate = k.chord * k.approach_speed / l;
  const double damping = p.damping_gamma * d_eff_rate * std::sqrt(p.youngs_modulus * k.normal_mass);
  // The cut-off at -R: damping may cancel the elastic force but never make it attractive.
  f.normal = repulsive + std::max(damping, -repulsive);

  if (p.friction_mu == 0.0 || f.normal <= 0.0) return f;  // no friction, no history
  // A.2: Cundall-Strack spring, advanced by the slip, plus a viscous term; the total is capped
  // at mu F_n. The spring force opposes slip of a relative to b, i.e. acts along -t on a.
  const double k_t = p.tangential_stiffness_ratio * p.youngs_modulus;
  const double viscous = std::sqrt(k_t * k.tangential_mass) * k.slip_speed;
  const double stretched = spring + k_t * k.slip_speed * dt;
  const double trial = stretched + viscous;
  const double cap = p.friction_mu * f.normal;
  if (std::abs(trial) <= cap) {
    f.tangential = trial;
    f.spring = p.tangential_history == TangentialHistory::total ? trial : stretched;
  } else {
    // Sliding: the spring stops stretching and holds the Coulomb value.
    f.tangential = std::copysign(cap, trial);
    f.spring = f.tangential;
  }
  return f;
}

}  // namespace pilelab::dem
