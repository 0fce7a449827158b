#include "dem/time_step.h"

#include <cmath>

namespace pilelab::dem {

namespace {
// The pair frequency and damping ratio when a contact of chord `chord` acts at moment arm `arm`
// (the distance from the centroid to the force's line of action) on two grains like this one.
struct ContactMode {
  double omega, zeta;
};
ContactMode contact_mode(const ContactParameters& contact, double chord, double l, double m, double inertia,
                         double arm) {
  const double k = contact.youngs_modulus * chord / l;
  const double inv_m_eff = 1.0 / m + arm * arm / inertia;  // translation coupled with rotation
  const double omega = std::sqrt(2.0 * k * inv_m_eff);      // two such grains: m_pair = m_eff / 2
  // The damping uses the translational reduced mass m/2; the mode moves the effective mass.
  const double zeta = 0.5 * contact.damping_gamma * std::sqrt(chord / l * inv_m_eff * m);
  return {omega, zeta};
}
}  // namespace

TimeStepBound stable_time_step(const std::vector<Shape>& grains, double areal_density,
                               const ContactParameters& contact, Scheme scheme) {
  TimeStepBound b;
  const double scheme_limit = stability_limit_omega_dt(scheme);
  for (std::size_t i = 0; i < grains.size(); ++i) {
    const Shape& s = grains[i];
    const double m = areal_density * s.area, inertia = areal_density * s.polar_moment;
    // The levers are at least the inner radius for a force point on the boundary.
    const double l = contact_length(contact, s.inner_radius, s.inner_radius);
    // Keeps the smallest limit over all modes, with the mode that sets it.
    auto record = [&](double limit, double omega, double zeta) {
      if (b.stiffest_grain < 0 || limit < b.stable_limit) {
        b.stable_limit = limit;
        b.omega_max = omega;
        b.period_min = 2.0 * M_PI / omega;
        b.damping_ratio = zeta;
        b.stiffest_grain = static_cast<int>(i);
      }
    };
    auto consider = [&](double chord, double arm) {
      const ContactMode mode = contact_mode(contact, chord, l, m, inertia, arm);
      const double z = mode.zeta;
      record(scheme_limit * (std::sqrt(1.0 + z * z) - z) / mode.omega, mode.omega, z);
    };
    if (contact.tangential_history == TangentialHistory::total && contact.friction_mu > 0.0) {
      // A.2 read literally: the stored tangential force gains k_t v dt + sqrt(k_t m_t) v each
      // step, a spring of stiffness k_t + sqrt(k_t m_t) / dt on the slip v dt. With
      // omega_t = sqrt(k_t / m_t) the scheme is stable while (omega_t dt)^2 + omega_t dt <= L^2.
      // m_t is smallest for a force at the bounding radius, on two such grains.
      const double k_t = contact.tangential_stiffness_ratio * contact.youngs_modulus;
      const double r = s.bounding_radius;
      const double omega_t = std::sqrt(2.0 * k_t * (1.0 / m + r * r / inertia));
      record(0.5 * (std::sqrt(1.0 + 4.0 * scheme_limit * scheme_limit) - 1.0) / omega_t, omega_t, 0.0);
    }
    if (s.kind == ShapeKind::disc) {
      consider(2.0 * s.radius, 0.0);  // a disc's normal force passes through its centre
      continue;
    }
    // A polygon pressed flat on edge e: the chord is at most the edge, and the force acts along
    // the edge's normal at a point of the edge, so its moment arm is at most the distance, along
    // the edge, from the foot of the centroid to the edge's far end.
    const std::size_t n = s.vertices.size();
    for (std::size_t e = 0; e < n; ++e) {
      const Vec2 p = s.vertices[e], q = s.vertices[(e + 1) % n];
      const double length = (q - p).norm();
      const Vec2 along = (q - p) / length;
      const double arm = std::max(std::abs(along.dot(p)), std::abs(along.dot(q)));
      consider(length, arm);
    }
  }
  return b;
}

}  // namespace pilelab::dem
