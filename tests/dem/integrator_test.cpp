// The integrators on the oscillator x'' = -omega^2 x - 2 zeta omega x', whose exact solution is
// known: stability on both sides of each scheme's limit, with and without damping, and the
// convergence order of the error.
#include <cmath>

#include <gtest/gtest.h>

#include "dem/integrator.h"

using namespace pilelab::dem;

namespace {
// Integrates one body's x coordinate for n steps from x = 1, v = 0; returns max |energy - 1/2|
// relative to the initial energy, and the final position error.
struct OscillatorRun {
  double max_energy_error;  ///< max |E - E0| / E0
  double max_energy_gain;   ///< max (E - E0) / E0: growth, the sign of instability
  double final_error;
};

OscillatorRun run_oscillator(Scheme s, double omega, double dt, int steps, double zeta = 0.0) {
  MotionState m;
  m.resize(1);
  m.d[0][0] = 1.0;
  // Gear carries higher derivatives: start them exact too (each from differentiating the ODE).
  const double w2 = omega * omega, c = 2.0 * zeta * omega;
  m.d[2][0] = -w2;
  m.d[3][0] = -c * m.d[2][0];
  m.d[4][0] = -w2 * m.d[2][0] - c * m.d[3][0];
  m.d[5][0] = -w2 * m.d[3][0] - c * m.d[4][0];
  std::vector<int> bodies{0};
  std::vector<double> accel(3, 0.0);
  OscillatorRun r{0.0, 0.0, 0.0};
  const double e0 = 0.5 * omega * omega;
  for (int k = 0; k < steps; ++k) {
    predict(s, m, bodies, dt);
    accel[0] = -omega * omega * m.d[0][0] - 2.0 * zeta * omega * m.d[1][0];  // d[1]: the force's velocity
    correct(s, m, accel, bodies, dt);
    const double e = 0.5 * m.d[1][0] * m.d[1][0] + 0.5 * omega * omega * m.d[0][0] * m.d[0][0];
    r.max_energy_error = std::max(r.max_energy_error, std::abs(e - e0) / e0);
    r.max_energy_gain = std::max(r.max_energy_gain, (e - e0) / e0);
    if (!std::isfinite(e)) break;
  }
  // Underdamped exact solution from x = 1, v = 0.
  const double t = dt * steps, omega_d = omega * std::sqrt(1.0 - zeta * zeta);
  r.final_error = std::abs(m.d[0][0] - std::exp(-zeta * omega * t) *
                                           (std::cos(omega_d * t) + zeta * omega / omega_d * std::sin(omega_d * t)));
  return r;
}
}  // namespace

TEST(Integrator, VerletIsStableJustBelowItsLimitAndUnstableAbove) {
  const double limit = stability_limit_omega_dt(Scheme::verlet);
  EXPECT_LT(run_oscillator(Scheme::verlet, 1.0, 0.99 * limit, 20000).max_energy_error, 100.0);
  // Symplectic: bounded energy error far below the limit.
  EXPECT_LT(run_oscillator(Scheme::verlet, 1.0, 0.1, 100000).max_energy_error, 0.01);
  EXPECT_GT(run_oscillator(Scheme::verlet, 1.0, 1.01 * limit, 20000).max_energy_error, 1e3);
}

TEST(Integrator, Gear5IsStableBelowItsLimitAndGrowsAbove) {
  const double limit = stability_limit_omega_dt(Scheme::gear5);
  // Below the limit the amplitude never grows: the scheme is slightly dissipative there, and the
  // energy only oscillates within the few per cent of its modified-energy error.
  const OscillatorRun below = run_oscillator(Scheme::gear5, 1.0, limit, 100000);
  EXPECT_LT(below.max_energy_gain, 0.05);
  const OscillatorRun late = run_oscillator(Scheme::gear5, 1.0, limit, 200000);
  EXPECT_LE(late.max_energy_gain, below.max_energy_gain * (1.0 + 1e-9));  // no secular growth
  // At omega dt = 0.5 the spectral radius is 1 + 1.85e-4: over 1e5 steps the energy grows by
  // about exp(2 * 18.5), certainly by more than a factor 1e3.
  EXPECT_GT(run_oscillator(Scheme::gear5, 1.0, 0.5, 100000).max_energy_error, 1e3);
}

TEST(Integrator, VerletAndLeapfrogDampedLimitsAreExact) {
  // A damped scheme that is stable loses energy; past its limit the energy grows without bound.
  for (Scheme s : {Scheme::verlet, Scheme::leapfrog})
    for (double zeta : {0.1, 0.5, 1.0, 3.0}) {
      const double limit = stability_limit_omega_dt(s, zeta);
      EXPECT_LT(run_oscillator(s, 1.0, 0.99 * limit, 20000, zeta).max_energy_error, 10.0)
          << scheme_name(s) << " zeta " << zeta;
      EXPECT_GT(run_oscillator(s, 1.0, 1.01 * limit, 20000, zeta).max_energy_error, 1e3)
          << scheme_name(s) << " zeta " << zeta;
    }
  // Leapfrog's forces see the half-step velocity, which damps less abruptly: its limit is the
  // larger, e.g. about 1.7 x Verlet's at zeta = 0.9.
  EXPECT_GT(stability_limit_omega_dt(Scheme::leapfrog, 0.9), 1.7 * stability_limit_omega_dt(Scheme::verlet, 0.9));
}

TEST(Integrator, Gear5DampedLimitIsSafeAndNearlyTightForStrongDamping) {
  for (double zeta : {0.0, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0, 5.0, 20.0}) {
    const OscillatorRun r = run_oscillator(Scheme::gear5, 1.0, stability_limit_omega_dt(Scheme::gear5, zeta), 100000, zeta);
    EXPECT_LT(r.max_energy_gain, zeta == 0.0 ? 0.05 : 1e-9) << "zeta " << zeta;
  }
  // Strong damping: the true limit is 0.0817 / zeta, within 10 % of the bound.
  const double zeta = 5.0;
  EXPECT_GT(run_oscillator(Scheme::gear5, 1.0, 1.1 * stability_limit_omega_dt(Scheme::gear5, zeta), 100000, zeta)
                .max_energy_error,
            1e3);
}

TEST(Integrator, ConvergenceOrders) {
  // Global error at a fixed end time T = 10 (about 1.6 periods) for halving dt. Verlet is second
  // order; Gear's predictor-corrector for second-order equations is at least fourth order in
  // position on this smooth problem (Gear 1971).
  auto order = [](Scheme s, double dt) {
    const int n = static_cast<int>(std::lround(10.0 / dt));
    const double e1 = run_oscillator(s, 1.0, dt, n).final_error;
    const double e2 = run_oscillator(s, 1.0, dt / 2, 2 * n).final_error;
    return std::log2(e1 / e2);
  };
  EXPECT_NEAR(order(Scheme::verlet, 0.01), 2.0, 0.1);
  EXPECT_NEAR(order(Scheme::leapfrog, 0.01), 2.0, 0.1);
  EXPECT_GT(order(Scheme::gear5, 0.02), 3.8);
}

TEST(Integrator, DampingKeepsVerletSecondOrderAndLeapfrogFirst) {
  // The price of leapfrog's larger damped step: its damping force lags half a step, an O(dt)
  // error in the force, so the global error falls only linearly; Verlet's extrapolated velocity
  // keeps it quadratic.
  auto order = [](Scheme s, double dt) {
    const int n = static_cast<int>(std::lround(10.0 / dt));
    const double e1 = run_oscillator(s, 1.0, dt, n, 0.3).final_error;
    const double e2 = run_oscillator(s, 1.0, dt / 2, 2 * n, 0.3).final_error;
    return std::log2(e1 / e2);
  };
  EXPECT_NEAR(order(Scheme::verlet, 0.005), 2.0, 0.15);
  EXPECT_NEAR(order(Scheme::leapfrog, 0.005), 1.0, 0.15);
  EXPECT_GT(order(Scheme::gear5, 0.02), 2.8);
}
