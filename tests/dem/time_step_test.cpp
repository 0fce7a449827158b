// The stable time step against its closed form for shapes where every term is known.
#include <cmath>

#include <gtest/gtest.h>

#include "dem/time_step.h"

using namespace pilelab::dem;

namespace {
// omega = sqrt(2 k (1/m + arm^2/I)), zeta = (gamma/2) sqrt(chord/l * m (1/m + arm^2/I)),
// limit = c_scheme (sqrt(1 + zeta^2) - zeta) / omega.
double expected_limit(double c_scheme, double E, double gamma, double chord, double l, double m, double inertia,
                      double arm) {
  const double inv_m_eff = 1.0 / m + arm * arm / inertia;
  const double omega = std::sqrt(2.0 * E * chord / l * inv_m_eff);
  const double zeta = 0.5 * gamma * std::sqrt(chord / l * m * inv_m_eff);
  return c_scheme * (std::sqrt(1.0 + zeta * zeta) - zeta) / omega;
}
}  // namespace

TEST(TimeStep, DiscMatchesTheClosedForm) {
  // A disc: chord up to 2r, force through the centre (arm 0), levers r so l = r/2 (paper).
  const double r = 0.003, rho = 5000.0;
  ContactParameters c;
  const TimeStepBound b = stable_time_step({make_disc(r)}, rho, c, Scheme::verlet);
  const double m = rho * M_PI * r * r;
  EXPECT_NEAR(b.stable_limit, expected_limit(2.0, c.youngs_modulus, c.damping_gamma, 2 * r, r / 2, m, 1.0, 0.0),
              1e-12 * b.stable_limit);
}

TEST(TimeStep, SquareMatchesTheClosedFormForBothSchemesAndContactLengths) {
  // A square of side s: every edge has chord s, inner radius s/2, and the centroid's foot at the
  // edge midpoint, so the arm is s/2; I = rho s^4 / 6.
  const double s = 0.004, rho = 5000.0;
  const Shape square = make_polygon({{0, 0}, {s, 0}, {s, s}, {0, s}});
  const double m = rho * s * s, inertia = rho * s * s * s * s / 6.0;
  for (ContactLength length : {ContactLength::paper, ContactLength::book})
    for (Scheme scheme : {Scheme::gear5, Scheme::verlet}) {
      ContactParameters c;
      c.contact_length = length;
      const double l = (length == ContactLength::paper ? 1.0 : 4.0) * s / 4.0;
      const double expected = expected_limit(stability_limit_omega_dt(scheme), c.youngs_modulus, c.damping_gamma, s,
                                              l, m, inertia, s / 2);
      EXPECT_NEAR(stable_time_step({square}, rho, c, scheme).stable_limit, expected, 1e-12 * expected);
    }
}

TEST(TimeStep, TheSmallestGrainSetsTheBound) {
  ContactParameters c;
  const TimeStepBound b = stable_time_step({make_disc(0.004), make_disc(0.002), make_disc(0.003)}, 5000.0, c,
                                           Scheme::verlet);
  EXPECT_EQ(b.stiffest_grain, 1);
  // Undamped, the limit scales with sqrt(m / k) ~ r: halving the grain halves the step.
  c.damping_gamma = 0.0;
  EXPECT_NEAR(stable_time_step({make_disc(0.002)}, 5000.0, c, Scheme::verlet).stable_limit,
              0.5 * stable_time_step({make_disc(0.004)}, 5000.0, c, Scheme::verlet).stable_limit, 1e-15);
}

TEST(TimeStep, LiteralTangentialHistoryIsBoundedByItsTangentialMode) {
  // Eq. A.2 read literally stores the viscous term too: the tangential spring becomes
  // k_t + sqrt(k_t m_t) / dt. For two discs touching at the rim, 1/m_t = 2 (1/m + r^2/I) = 6/m
  // (I = m r^2 / 2); with omega_t = sqrt(k_t / m_t) the scheme is stable while
  // (omega_t dt)^2 + omega_t dt <= L^2.
  const double r = 0.003, rho = 5000.0, m = rho * M_PI * r * r;
  for (Scheme scheme : {Scheme::gear5, Scheme::verlet}) {
    ContactParameters spring, total;
    total.tangential_history = TangentialHistory::total;
    const double L = stability_limit_omega_dt(scheme);
    const double omega_t = std::sqrt(total.tangential_stiffness_ratio * total.youngs_modulus * 6.0 / m);
    const double tangential = 0.5 * (std::sqrt(1.0 + 4.0 * L * L) - 1.0) / omega_t;
    const double normal = stable_time_step({make_disc(r)}, rho, spring, scheme).stable_limit;
    const double expected = std::min(normal, tangential);
    EXPECT_NEAR(stable_time_step({make_disc(r)}, rho, total, scheme).stable_limit, expected, 1e-12 * expected);
  }
}
