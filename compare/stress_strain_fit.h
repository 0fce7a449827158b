#pragma once
// Stress-strain relations fitted to the DEM's incremental stress and strain (the gravity
// reduction between `settled` and `relaxed`), by least squares over sample points.
//
// Every model is linear in its constants C for fixed shape parameters: each sample gives three
// equations  d sigma_xx, d sigma_yy, d sigma_xy = M(strain, ...) C. The models:
//  - isotropic (plane strain): d sigma = lambda tr(eps) I + 2 mu eps; E = mu (3 lambda + 2 mu) /
//    (lambda + mu), nu = lambda / (2 (lambda + mu)) as in three dimensions;
//  - orthotropic in the fabric frame: rotated to the principal axes of the local fabric,
//    d sigma'_11 = C11 eps'_11 + C12 eps'_22, d sigma'_22 = C12 eps'_11 + C22 eps'_22,
//    d sigma'_12 = 2 C66 eps'_12 (the material's axes follow the contact network);
//  - pressure dependent: lambda and mu proportional to (p / p_mean)^n, p the pressure
//    before the change; n by a scan, lambda_0 and mu_0 by least squares for each n.
// The comparison uses Akaike's information criterion on the residuals and k-fold
// cross-validation; confidence intervals come from a bootstrap over the sample points.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dem/vec2.h"

namespace pilelab::compare {

using Tensor = Eigen::Matrix2d;

struct FitSample {
  dem::Vec2 point{0, 0};
  Tensor stress_change = Tensor::Zero();  ///< [N/m]
  Tensor strain = Tensor::Zero();
  Tensor fabric = Tensor::Identity();
  double pressure = 0.0;                  ///< before the change, compression positive [N/m]
};

enum class FitModel { isotropic, orthotropic_fabric, pressure_dependent };

struct FitResult {
  FitModel model = FitModel::isotropic;
  std::string name;
  std::vector<std::string> parameter_names;
  std::vector<double> parameters;
  std::vector<double> ci_low, ci_high;   ///< 95 % bootstrap intervals (empty if not computed)
  int samples = 0;
  double rss = 0.0;                      ///< sum of squared residuals [N^2/m^2]
  double r2 = 0.0;                       ///< 1 - rss / total sum of squares
  double aic = 0.0;                      ///< 3n ln(rss / 3n) + 2k
  double cv_rms = 0.0;                   ///< k-fold cross-validated rms residual [N/m]
  bool ok = false;                       ///< false: too few samples or a singular system
};

FitResult fit(const std::vector<FitSample>& samples, FitModel model);
/// As above with the pressure-dependent law's reference pressure given (for resampling).
FitResult fit(const std::vector<FitSample>& samples, FitModel model, double reference_pressure);

/// The fit with bootstrap intervals (resamples, seed) and k-fold cross-validation.
FitResult fit_with_uncertainty(const std::vector<FitSample>& samples, FitModel model, int resamples,
                               unsigned seed, int folds);

/// The stress change a fitted model predicts for one sample.
Tensor predict(const FitResult& fit, const FitSample& sample, double mean_pressure);

/// E and nu (plane strain, three-dimensional reading) from lambda and mu.
double youngs_modulus(double lambda, double mu);
double poisson_ratio(double lambda, double mu);

}  // namespace pilelab::compare
