#include "compare/stress_strain_fit.h"

#include "common/isotropic_material.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace pilelab::compare {

namespace {

double mean_pressure_of(const std::vector<FitSample>& s) {
  double p = 0;
  for (const auto& x : s) p += x.pressure;
  return s.empty() ? 1.0 : p / s.size();
}

Tensor rotation_to_fabric(const Tensor& fabric) {
  Eigen::SelfAdjointEigenSolver<Tensor> eig(0.5 * (fabric + fabric.transpose()));
  Tensor q;
  q.col(0) = eig.eigenvectors().col(1);  // major axis first
  q.col(1) = eig.eigenvectors().col(0);
  return q;  // columns: the fabric's principal axes in the lab frame
}

// Rows (3 per sample) of the design matrix for the linear parameters of a model, and the
// matching right-hand side; for the pressure-dependent model at exponent n.
void design(const std::vector<FitSample>& s, FitModel model, double n, double p_mean, Eigen::MatrixXd& A,
            Eigen::VectorXd& b) {
  const int k = model == FitModel::orthotropic_fabric ? 4 : 2;
  A.setZero(3 * s.size(), k);
  b.setZero(3 * s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Tensor& e = s[i].strain;
    const Tensor& ds = s[i].stress_change;
    if (model == FitModel::orthotropic_fabric) {
      const Tensor q = rotation_to_fabric(s[i].fabric);
      const Tensor el = q.transpose() * e * q, sl = q.transpose() * ds * q;
      A.row(3 * i) << el(0, 0), el(1, 1), 0, 0;
      A.row(3 * i + 1) << 0, el(0, 0), el(1, 1), 0;
      A.row(3 * i + 2) << 0, 0, 0, 2 * el(0, 1);
      b.segment<3>(3 * i) << sl(0, 0), sl(1, 1), sl(0, 1);
    } else {
      const double scale = model == FitModel::pressure_dependent
                               ? std::pow(std::max(s[i].pressure, 0.0) / p_mean, n)
                               : 1.0;
      const double tr = e.trace();
      A.row(3 * i) << scale * tr, scale * 2 * e(0, 0);
      A.row(3 * i + 1) << scale * tr, scale * 2 * e(1, 1);
      A.row(3 * i + 2) << 0, scale * 2 * e(0, 1);
      b.segment<3>(3 * i) << ds(0, 0), ds(1, 1), 0.5 * (ds(0, 1) + ds(1, 0));
    }
  }
}

// Least squares through QR with column scaling; false if the columns are dependent.
bool solve_ls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, Eigen::VectorXd& x, double& rss) {
  Eigen::VectorXd scale = A.colwise().norm().transpose();
  for (int j = 0; j < scale.size(); ++j)
    if (!(scale(j) > 0)) return false;
  const Eigen::MatrixXd As = A * scale.cwiseInverse().asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(As);
  qr.setThreshold(1e-10);
  if (qr.rank() < As.cols()) return false;
  x = qr.solve(b).cwiseQuotient(scale);
  rss = (A * x - b).squaredNorm();
  return true;
}

// p_ref: the reference pressure of the pressure-dependent law, fixed by the caller so that
// every bootstrap resample and fold refers its lambda0, mu0 to the same pressure.
FitResult fit_once(const std::vector<FitSample>& s, FitModel model, double p_ref) {
  FitResult r;
  r.model = model;
  r.samples = static_cast<int>(s.size());
  const double p_mean = p_ref;
  Eigen::MatrixXd A;
  Eigen::VectorXd b, x;
  double n_best = 0;
  if (model == FitModel::pressure_dependent) {
    double best = INFINITY;
    for (int step = 0; step <= 150; ++step) {  // n = 0, 0.01, ..., 1.5
      const double n = 0.01 * step;
      design(s, model, n, p_mean, A, b);
      double rss;
      Eigen::VectorXd xn;
      if (solve_ls(A, b, xn, rss) && rss < best) best = rss, x = xn, n_best = n, r.rss = rss, r.ok = true;
    }
    design(s, model, n_best, p_mean, A, b);
  } else {
    design(s, model, 0.0, p_mean, A, b);
    r.ok = solve_ls(A, b, x, r.rss);
  }
  if (!r.ok) return r;
  switch (model) {
    case FitModel::isotropic:
      r.name = "isotropic";
      r.parameter_names = {"lambda_N_per_m", "mu_N_per_m", "E_N_per_m", "nu"};
      r.parameters = {x(0), x(1), youngs_modulus(x(0), x(1)), poisson_ratio(x(0), x(1))};
      break;
    case FitModel::orthotropic_fabric:
      r.name = "orthotropic_fabric";
      r.parameter_names = {"C11_N_per_m", "C12_N_per_m", "C22_N_per_m", "C66_N_per_m"};
      r.parameters = {x(0), x(1), x(2), x(3)};
      break;
    case FitModel::pressure_dependent:
      r.name = "pressure_dependent";
      r.parameter_names = {"lambda0_N_per_m", "mu0_N_per_m", "exponent_n", "p_mean_N_per_m"};
      r.parameters = {x(0), x(1), n_best, p_mean};
      break;
  }
  const double m = static_cast<double>(b.size());
  const double total = (b.array() - b.mean()).square().sum();
  r.r2 = total > 0 ? 1.0 - r.rss / total : 0.0;
  const int k = model == FitModel::isotropic ? 2 : model == FitModel::orthotropic_fabric ? 4 : 3;
  r.aic = m * std::log(std::max(r.rss, 1e-300) / m) + 2.0 * k;
  return r;
}

}  // namespace

double youngs_modulus(double lambda, double mu) { return IsotropicMaterial::from_lame(lambda, mu).youngs_modulus_N_per_m; }
double poisson_ratio(double lambda, double mu) { return IsotropicMaterial::from_lame(lambda, mu).poisson_ratio; }

FitResult fit(const std::vector<FitSample>& samples, FitModel model) {
  return fit_once(samples, model, mean_pressure_of(samples));
}

FitResult fit(const std::vector<FitSample>& samples, FitModel model, double reference_pressure) {
  return fit_once(samples, model, reference_pressure);
}

Tensor predict(const FitResult& f, const FitSample& s, double p_mean) {
  const Tensor I = Tensor::Identity();
  switch (f.model) {
    case FitModel::isotropic:
      return f.parameters[0] * s.strain.trace() * I + 2 * f.parameters[1] * s.strain;
    case FitModel::pressure_dependent: {
      const double scale = std::pow(std::max(s.pressure, 0.0) / p_mean, f.parameters[2]);
      return scale * (f.parameters[0] * s.strain.trace() * I + 2 * f.parameters[1] * s.strain);
    }
    case FitModel::orthotropic_fabric: {
      const Tensor q = rotation_to_fabric(s.fabric);
      const Tensor e = q.transpose() * s.strain * q;
      Tensor sl;
      sl(0, 0) = f.parameters[0] * e(0, 0) + f.parameters[1] * e(1, 1);
      sl(1, 1) = f.parameters[1] * e(0, 0) + f.parameters[2] * e(1, 1);
      sl(0, 1) = sl(1, 0) = 2 * f.parameters[3] * e(0, 1);
      return q * sl * q.transpose();
    }
  }
  return Tensor::Zero();
}

FitResult fit_with_uncertainty(const std::vector<FitSample>& samples, FitModel model, int resamples,
                               unsigned seed, int folds) {
  const double p_ref = mean_pressure_of(samples);
  FitResult r = fit_once(samples, model, p_ref);
  if (!r.ok) return r;
  std::mt19937_64 rng(seed);
  // Bootstrap: refit on samples drawn with replacement; percentile intervals.
  std::vector<std::vector<double>> draws(r.parameters.size());
  std::uniform_int_distribution<std::size_t> pick(0, samples.size() - 1);
  for (int b = 0; b < resamples; ++b) {
    std::vector<FitSample> s(samples.size());
    for (auto& x : s) x = samples[pick(rng)];
    const FitResult f = fit_once(s, model, p_ref);
    if (!f.ok) continue;
    for (std::size_t j = 0; j < f.parameters.size(); ++j) draws[j].push_back(f.parameters[j]);
  }
  for (auto& d : draws) {
    std::sort(d.begin(), d.end());
    r.ci_low.push_back(d.empty() ? NAN : d[static_cast<std::size_t>(0.025 * (d.size() - 1))]);
    r.ci_high.push_back(d.empty() ? NAN : d[static_cast<std::size_t>(0.975 * (d.size() - 1))]);
  }
  // k-fold cross-validation on a fixed shuffle: rms of the held-out residuals.
  std::vector<std::size_t> order(samples.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  double sq = 0;
  std::size_t count = 0;
  for (int k = 0; k < folds; ++k) {
    std::vector<FitSample> train, test;
    for (std::size_t i = 0; i < order.size(); ++i) (static_cast<int>(i % folds) == k ? test : train).push_back(samples[order[i]]);
    const FitResult f = fit_once(train, model, p_ref);
    if (!f.ok) continue;
    for (const auto& s : test) {
      const Tensor d = predict(f, s, p_ref) - s.stress_change;
      sq += d(0, 0) * d(0, 0) + d(1, 1) * d(1, 1) + 0.25 * (d(0, 1) + d(1, 0)) * (d(0, 1) + d(1, 0));
      count += 3;
    }
  }
  r.cv_rms = count ? std::sqrt(sq / count) : NAN;
  return r;
}

}  // namespace pilelab::compare
