// The integrators on the undamped oscillator x'' = -omega^2 x, whose exact solution is known:
// stability on both sides of each scheme's limit, and the convergence order of the error.
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

OscillatorRun run_oscillator(Scheme s, double omega, double dt, int steps) {
  MotionState m;
  m.resize(1);
  m.d[0][0] = 1.0;
  m.d[2][0] = -omega * omega;
  std::vector<int> bodies{0};
  std::vector<double> accel(3, 0.0);
  OscillatorRun r{0.0, 0.0, 0.0};
  const double e0 = 0.5 * omega * omega;
  for (int k = 0; k < steps; ++k) {
    predict(s, m, bodies, dt);
    accel[0] = -omega * omega * m.d[0][0];
    correct(s, m, accel, bodies, dt);
    const double e = 0.5 * m.d[1][0] * m.d[1][0] + 0.5 * omega * omega * m.d[0][0] * m.d[0][0];
    r.max_energy_error = std::max(r.max_energy_error, std::abs(e - e0) / e0);
    r.max_energy_gain = std::max(r.max_energy_gain, (e - e0) / e0);
    if (!std::isfinite(e)) break;
  }
  r.final_error = std::abs(m.d[0][0] - std::cos(omega * dt * steps));
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
  EXPECT_GT(order(Scheme::gear5, 0.02), 3.8);
}
