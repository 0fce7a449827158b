#pragma once
// Time integration of the equations of motion (paper eq. 1) for the generalised coordinates
// q = (x, y, theta) of every mobile body. Three schemes, chosen in the scene:
//  - Gear's fifth-order predictor-corrector (the paper's): six stored derivatives, a Taylor
//    predictor, one force evaluation at the predicted state, and a corrector with Gear's
//    coefficients for second-order equations with velocity-dependent forces.
//  - Velocity Verlet (second order, three stored derivatives): cheaper, symplectic for
//    conservative forces; velocity-dependent forces see the extrapolated velocity v + a dt,
//    which keeps the damping second order.
//  - Leapfrog (kick-drift-kick): Verlet's positions, but the forces see the half-step velocity
//    v + a dt/2, as in LAMMPS. Second order for conservative forces, first order in the damping,
//    and stable with strong damping at steps up to twice Verlet's (stability_limit_omega_dt).
#include <array>
#include <string>
#include <vector>

namespace pilelab::dem {

enum class Scheme { gear5, verlet, leapfrog };
Scheme scheme_from_name(const std::string& name);  ///< "gear5", "verlet" or "leapfrog"
const char* scheme_name(Scheme s);

/// The derivatives of q for all bodies, interleaved (x, y, theta) per body: d[k][3*i + c] is
/// the k-th time derivative of coordinate c of body i. Verlet and leapfrog use d[0..2] and keep
/// the half-step velocity in half_velocity.
struct MotionState {
  std::array<std::vector<double>, 6> d;
  std::vector<double> half_velocity;
  void resize(std::size_t bodies);
  std::size_t bodies() const { return d[0].size() / 3; }
};

/// One time step of a scheme with its coefficients worked out once, applied body by body: the
/// World calls it inside its own loops over the grains.
class Stepper {
 public:
  Stepper(Scheme s, double dt);
  /// Advances body i's positions (and for Gear all derivatives) from t to t + dt; afterwards
  /// d[1] holds the velocity the force law should use.
  void predict(MotionState& m, int i) const;
  /// Applies the accelerations evaluated at the predicted state (x, y, theta) to complete the
  /// step of body i.
  void correct(MotionState& m, int i, const double* accel) const;

 private:
  Scheme scheme_;
  double dt_;
  double taylor_[5];  // Gear: h, h^2/2, h^3/6, h^4/24, h^5/120
  double gain_[6];    // Gear's corrector coefficients in unscaled form (gain_[2] unused)
  double force_velocity_lead_;  // Verlet dt, leapfrog dt / 2
};

// Inline: the World calls both for every grain of every step.
[[gnu::always_inline]] inline void Stepper::predict(MotionState& m, int i) const {
  auto& d = m.d;
  if (scheme_ == Scheme::gear5) {
    const double h = taylor_[0], h2 = taylor_[1], h3 = taylor_[2], h4 = taylor_[3], h5 = taylor_[4];
    for (int c = 3 * i; c < 3 * i + 3; ++c) {
      // Taylor series of every derivative to t + dt (the Pascal-triangle predictor).
      d[0][c] += h * d[1][c] + h2 * d[2][c] + h3 * d[3][c] + h4 * d[4][c] + h5 * d[5][c];
      d[1][c] += h * d[2][c] + h2 * d[3][c] + h3 * d[4][c] + h4 * d[5][c];
      d[2][c] += h * d[3][c] + h2 * d[4][c] + h3 * d[5][c];
      d[3][c] += h * d[4][c] + h2 * d[5][c];
      d[4][c] += h * d[5][c];
    }
  } else {
    for (int c = 3 * i; c < 3 * i + 3; ++c) {
      m.half_velocity[c] = d[1][c] + 0.5 * dt_ * d[2][c];
      d[0][c] += dt_ * m.half_velocity[c];
      d[1][c] += force_velocity_lead_ * d[2][c];
    }
  }
}

inline void Stepper::correct(MotionState& m, int i, const double* accel) const {
  auto& d = m.d;
  if (scheme_ == Scheme::gear5) {
    for (int c = 0; c < 3; ++c) {
      const int q = 3 * i + c;
      const double delta = accel[c] - d[2][q];
      d[0][q] += gain_[0] * delta;
      d[1][q] += gain_[1] * delta;
      d[2][q] = accel[c];
      d[3][q] += gain_[3] * delta;
      d[4][q] += gain_[4] * delta;
      d[5][q] += gain_[5] * delta;
    }
  } else {
    for (int c = 0; c < 3; ++c) {
      const int q = 3 * i + c;
      d[2][q] = accel[c];
      d[1][q] = m.half_velocity[q] + 0.5 * dt_ * accel[c];
    }
  }
}

/// Advances positions (and for Gear all derivatives) from t to t + dt for the listed bodies;
/// afterwards d[1] holds the velocity the force law should use.
void predict(Scheme s, MotionState& m, const std::vector<int>& bodies, double dt);

/// Applies the accelerations evaluated at the predicted state (accel: 3 per body, interleaved
/// like d) to complete the step.
void correct(Scheme s, MotionState& m, const std::vector<double>& accel, const std::vector<int>& bodies, double dt);

/// The largest omega * dt for which the scheme is stable on the damped oscillator
/// x'' = -omega^2 x - 2 zeta omega x', its force evaluated as World does (at the velocity d[1]
/// holds after predict). Exact for Verlet and leapfrog; for Gear a lower bound
/// (tests/dem/integrator_test.cpp checks both sides).
double stability_limit_omega_dt(Scheme s, double zeta = 0.0);

}  // namespace pilelab::dem
