#include "dem/time_step.h"

#include <cmath>

namespace pilelab::dem {

TimeStepBound stable_time_step(const std::vector<Shape>& grains, double areal_density,
                               const ContactParameters& contact, Scheme scheme) {
  TimeStepBound b;
  for (std::size_t i = 0; i < grains.size(); ++i) {
    const Shape& s = grains[i];
    const double chord = s.longest_edge;
    const double l = contact_length(contact, s.inner_radius, s.inner_radius);
    const double k = contact.youngs_modulus * chord / l;
    const double m = areal_density * s.area, inertia = areal_density * s.polar_moment;
    const double m_eff = 1.0 / (1.0 / m + s.bounding_radius * s.bounding_radius / inertia);
    const double m_pair = 0.5 * m_eff;
    const double omega = std::sqrt(k / m_pair);
    // The damping force uses the translational reduced mass m/2, the mode the pair's effective
    // mass: zeta = c / (2 sqrt(k m_pair)) with c = gamma (chord/l) sqrt(E m/2).
    const double zeta = 0.5 * contact.damping_gamma * std::sqrt(chord / l * (0.5 * m) / m_pair);
    const double limit = stability_limit_omega_dt(scheme) * (std::sqrt(1.0 + zeta * zeta) - zeta) / omega;
    if (b.stiffest_grain < 0 || limit < b.stable_limit) {
      b.stable_limit = limit;
      b.omega_max = omega;
      b.period_min = 2.0 * M_PI / omega;
      b.damping_ratio = zeta;
      b.stiffest_grain = static_cast<int>(i);
    }
  }
  return b;
}

}  // namespace pilelab::dem
