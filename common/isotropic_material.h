#pragma once
// An isotropic linear elastic material of the 2D pile, its moduli per unit depth (N/m, like the
// DEM's contact stiffness): held as Young's modulus and Poisson's ratio and converted to the
// other usual pairs in this one place, with its stress law. deal.II-free, so that compare/ fits
// and reports in the same terms as continuum/ solves.
#include <array>

namespace pilelab {

struct IsotropicMaterial {
  double youngs_modulus_N_per_m = 1.0e7;
  double poisson_ratio = 0.3;

  /// The material of Lame's constants lambda, mu (N/m).
  static IsotropicMaterial from_lame(double lambda, double mu) {
    return {mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu), lambda / (2.0 * (lambda + mu))};
  }
  double shear_modulus() const { return youngs_modulus_N_per_m / (2.0 * (1.0 + poisson_ratio)); }
  double lame_lambda() const {
    const double nu = poisson_ratio;
    return youngs_modulus_N_per_m * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  }
  /// The lambda of the 2D problem: Lame's for plane strain; for plane stress the reduced
  /// lambda* = 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2).
  double lambda_2d(bool plane_stress) const {
    const double lambda = lame_lambda(), mu = shear_modulus();
    return plane_stress ? 2.0 * lambda * mu / (lambda + 2.0 * mu) : lambda;
  }
  /// A stable material: positive stiffness, -1 < nu < 1/2.
  bool stable() const { return youngs_modulus_N_per_m > 0 && poisson_ratio > -1.0 && poisson_ratio < 0.5; }
  /// The stress law sigma = lambda tr(eps) I + 2 mu eps of the 2D problem, on (xx, yy, xy)
  /// components (tensor shear, not engineering).
  std::array<double, 3> stress(const std::array<double, 3>& eps, bool plane_stress) const {
    const double lambda = lambda_2d(plane_stress), mu = shear_modulus(), trace = eps[0] + eps[1];
    return {lambda * trace + 2.0 * mu * eps[0], lambda * trace + 2.0 * mu * eps[1], 2.0 * mu * eps[2]};
  }
};

}  // namespace pilelab
