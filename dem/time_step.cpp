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
    const double omega = std::sqrt(k / (0.5 * m_eff));
    if (omega > b.omega_max) {
      b.omega_max = omega;
      b.stiffest_grain = static_cast<int>(i);
      b.damping_ratio = 0.5 * contact.damping_gamma * std::sqrt(chord / l);
    }
  }
  if (b.omega_max > 0) {
    b.period_min = 2.0 * M_PI / b.omega_max;
    const double zeta = b.damping_ratio;
    b.stable_limit = stability_limit_omega_dt(scheme) * (std::sqrt(1.0 + zeta * zeta) - zeta) / b.omega_max;
  }
  return b;
}

}  // namespace pilelab::dem
