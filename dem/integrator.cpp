#include "dem/integrator.h"

#include <cmath>
#include <stdexcept>

namespace pilelab::dem {

Scheme scheme_from_name(const std::string& name) {
  if (name == "gear5") return Scheme::gear5;
  if (name == "verlet") return Scheme::verlet;
  if (name == "leapfrog") return Scheme::leapfrog;
  throw std::invalid_argument("unknown integrator '" + name + "'");
}

const char* scheme_name(Scheme s) {
  switch (s) {
    case Scheme::gear5: return "gear5";
    case Scheme::verlet: return "verlet";
    case Scheme::leapfrog: return "leapfrog";
  }
  return "?";
}

void MotionState::resize(std::size_t bodies) {
  for (auto& v : d) v.resize(3 * bodies, 0.0);
  half_velocity.resize(3 * bodies, 0.0);
}

namespace {
// Below this many bodies a parallel loop costs more than it saves.
constexpr int parallel_threshold = 256;

// Gear's corrector coefficients for a second-order equation whose forces depend on velocity,
// in the scaled form (r_k = dt^k / k! * k-th derivative): r_k += alpha_k * (dt^2/2) * (a - a_p).
constexpr double gear_alpha[6] = {3.0 / 16.0, 251.0 / 360.0, 1.0, 11.0 / 18.0, 1.0 / 6.0, 1.0 / 60.0};
}  // namespace

void predict(Scheme s, MotionState& m, const std::vector<int>& bodies, double dt) {
  auto& d = m.d;
  if (s == Scheme::gear5) {
    const double h = dt, h2 = h * h / 2.0, h3 = h2 * h / 3.0, h4 = h3 * h / 4.0, h5 = h4 * h / 5.0;
    const int n = static_cast<int>(bodies.size());
#pragma omp parallel for schedule(static) if (n >= parallel_threshold)
    for (int k = 0; k < n; ++k)
      for (int c = 3 * bodies[k]; c < 3 * bodies[k] + 3; ++c) {
        // Taylor series of every derivative to t + dt (the Pascal-triangle predictor).
        d[0][c] += h * d[1][c] + h2 * d[2][c] + h3 * d[3][c] + h4 * d[4][c] + h5 * d[5][c];
        d[1][c] += h * d[2][c] + h2 * d[3][c] + h3 * d[4][c] + h4 * d[5][c];
        d[2][c] += h * d[3][c] + h2 * d[4][c] + h3 * d[5][c];
        d[3][c] += h * d[4][c] + h2 * d[5][c];
        d[4][c] += h * d[5][c];
      }
  } else {
    // The velocity the forces see: extrapolated to t + dt (Verlet, second order) or the
    // half-step one (leapfrog, first order in the damping but more stable with it).
    const double force_velocity_lead = s == Scheme::verlet ? dt : 0.5 * dt;
    const int n = static_cast<int>(bodies.size());
#pragma omp parallel for schedule(static) if (n >= parallel_threshold)
    for (int k = 0; k < n; ++k)
      for (int c = 3 * bodies[k]; c < 3 * bodies[k] + 3; ++c) {
        m.half_velocity[c] = d[1][c] + 0.5 * dt * d[2][c];
        d[0][c] += dt * m.half_velocity[c];
        d[1][c] += force_velocity_lead * d[2][c];
      }
  }
}

void correct(Scheme s, MotionState& m, const std::vector<double>& accel, const std::vector<int>& bodies,
             double dt) {
  auto& d = m.d;
  if (s == Scheme::gear5) {
    // Unscaled form of r_k += alpha_k * (dt^2/2) * delta_a, with r_k = dt^k/k! d_k.
    const double c0 = gear_alpha[0] * dt * dt / 2.0;
    const double c1 = gear_alpha[1] * dt / 2.0;
    const double c3 = gear_alpha[3] * 3.0 / dt;
    const double c4 = gear_alpha[4] * 12.0 / (dt * dt);
    const double c5 = gear_alpha[5] * 60.0 / (dt * dt * dt);
    const int n = static_cast<int>(bodies.size());
#pragma omp parallel for schedule(static) if (n >= parallel_threshold)
    for (int k = 0; k < n; ++k)
      for (int c = 3 * bodies[k]; c < 3 * bodies[k] + 3; ++c) {
        const double delta = accel[c] - d[2][c];
        d[0][c] += c0 * delta;
        d[1][c] += c1 * delta;
        d[2][c] = accel[c];
        d[3][c] += c3 * delta;
        d[4][c] += c4 * delta;
        d[5][c] += c5 * delta;
      }
  } else {
    const int n = static_cast<int>(bodies.size());
#pragma omp parallel for schedule(static) if (n >= parallel_threshold)
    for (int k = 0; k < n; ++k)
      for (int c = 3 * bodies[k]; c < 3 * bodies[k] + 3; ++c) {
        d[2][c] = accel[c];
        d[1][c] = m.half_velocity[c] + 0.5 * dt * accel[c];
      }
  }
}

double stability_limit_omega_dt(Scheme s, double zeta) {
  // With x = omega dt and y = 2 zeta omega dt, one step maps (x, v, a) linearly. Verlet's
  // characteristic polynomial is 2 l^3 + (2 x^2 + 3 y - 4) l^2 + (2 - 4 y) l + y; a root leaves
  // the unit circle at l = -1 when x^2 + 8 zeta x = 4. Leapfrog's forces see v + a dt/2: its
  // root reaches -1 when x^2 + 4 zeta x = 4 (the central-difference bound). Undamped, both
  // give 2.
  switch (s) {
    case Scheme::verlet: return 2.0 * (std::sqrt(1.0 + 4.0 * zeta * zeta) - 2.0 * zeta);
    case Scheme::leapfrog: return 2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta);
    case Scheme::gear5: {
      // Undamped: the spectral radius of the predictor-corrector map is <= 1 for omega dt <
      // 0.313 and grows past it (1 + 2e-5 per step at 0.4, 1 + 0.3 at 1.0); this is Matuttis and
      // Chen's dt <= T/20. Damped, the predicted velocity makes the damping the weak point: the
      // limit falls like 0.0817 / zeta for strong damping (y = 0.163). L0 k / (k + L0 zeta) with
      // k = 0.08 joins the two and stays below the measured limit for every zeta.
      const double undamped = 0.31, strong = 0.08;
      return undamped * strong / (strong + undamped * zeta);
    }
  }
  return 0.0;
}

}  // namespace pilelab::dem
