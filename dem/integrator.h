#pragma once
// Time integration of the equations of motion (paper eq. 1) for the generalised coordinates
// q = (x, y, theta) of every mobile body. Two schemes, chosen in the scene:
//  - Gear's fifth-order predictor-corrector (the paper's): six stored derivatives, a Taylor
//    predictor, one force evaluation at the predicted state, and a corrector with Gear's
//    coefficients for second-order equations with velocity-dependent forces.
//  - Velocity Verlet (second order, three stored derivatives): cheaper, symplectic for
//    conservative forces; velocity-dependent forces see the first-order predicted velocity.
#include <array>
#include <string>
#include <vector>

namespace pilelab::dem {

enum class Scheme { gear5, verlet };
Scheme scheme_from_name(const std::string& name);  ///< "gear5" or "verlet"
const char* scheme_name(Scheme s);

/// The derivatives of q for all bodies, interleaved (x, y, theta) per body: d[k][3*i + c] is
/// the k-th time derivative of coordinate c of body i. Verlet uses d[0..2] and keeps the half-
/// step velocity in half_velocity.
struct MotionState {
  std::array<std::vector<double>, 6> d;
  std::vector<double> half_velocity;
  void resize(std::size_t bodies);
  std::size_t bodies() const { return d[0].size() / 3; }
};

/// Advances positions (and for Gear all derivatives) from t to t + dt for the listed bodies;
/// afterwards d[1] holds the velocity the force law should use.
void predict(Scheme s, MotionState& m, const std::vector<int>& bodies, double dt);

/// Applies the accelerations evaluated at the predicted state (accel: 3 per body, interleaved
/// like d) to complete the step.
void correct(Scheme s, MotionState& m, const std::vector<double>& accel, const std::vector<int>& bodies, double dt);

/// The largest omega * dt for which the scheme is stable on the undamped oscillator
/// x'' = -omega^2 x (measured by tests/dem/integrator_test.cpp for Gear).
double stability_limit_omega_dt(Scheme s);

}  // namespace pilelab::dem
