// Fits recover the constants of synthetic stress-strain data made from known laws.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "compare/stress_strain_fit.h"

using namespace pilelab::compare;

namespace {
Tensor sym(double xx, double yy, double xy) {
  Tensor t;
  t << xx, xy, xy, yy;
  return t;
}
Tensor rotation(double a) {
  Tensor q;
  q << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return q;
}

// Random strains, pressures and fabric orientations; stresses from the given law.
std::vector<FitSample> samples(int n, unsigned seed, const std::function<Tensor(const FitSample&)>& law,
                               double noise = 0.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<FitSample> out(n);
  for (auto& s : out) {
    s.strain = 1e-4 * sym(u(rng), u(rng), u(rng));
    s.pressure = 1000.0 * (1.5 + u(rng));
    const Tensor q = rotation(3.0 * u(rng));
    s.fabric = q * sym(2.0, 1.0, 0.0) * q.transpose();
    s.stress_change = law(s);
    if (noise > 0) s.stress_change += noise * sym(g(rng), g(rng), g(rng));
  }
  return out;
}
}  // namespace

TEST(StressStrainFit, IsotropicConstantsAreRecoveredExactly) {
  const double lambda = 4.0e6, mu = 2.5e6;
  const auto s = samples(50, 1, [&](const FitSample& x) {
    return Tensor(lambda * x.strain.trace() * Tensor::Identity() + 2 * mu * x.strain);
  });
  const FitResult f = fit(s, FitModel::isotropic);
  ASSERT_TRUE(f.ok);
  EXPECT_NEAR(f.parameters[0], lambda, 1e-8 * lambda);
  EXPECT_NEAR(f.parameters[1], mu, 1e-8 * mu);
  EXPECT_NEAR(f.parameters[2], mu * (3 * lambda + 2 * mu) / (lambda + mu), 1e-6 * mu);
  EXPECT_NEAR(f.parameters[3], lambda / (2 * (lambda + mu)), 1e-9);
  EXPECT_NEAR(f.r2, 1.0, 1e-12);
}

// With noise the estimate is unbiased: the 95 % bootstrap interval holds the truth, and the
// cross-validated residual is close to the noise level.
TEST(StressStrainFit, NoisyDataGiveIntervalsAroundTheTruth) {
  const double lambda = 4.0e6, mu = 2.5e6, noise = 50.0;
  const auto s = samples(400, 2, [&](const FitSample& x) {
    return Tensor(lambda * x.strain.trace() * Tensor::Identity() + 2 * mu * x.strain);
  }, noise);
  const FitResult f = fit_with_uncertainty(s, FitModel::isotropic, 300, 7, 5);
  ASSERT_TRUE(f.ok);
  EXPECT_LE(f.ci_low[0], lambda);
  EXPECT_GE(f.ci_high[0], lambda);
  EXPECT_LE(f.ci_low[1], mu);
  EXPECT_GE(f.ci_high[1], mu);
  // Off-diagonal rows carry noise on (xy + yx)/2 of two independent draws: variance 1/2.
  EXPECT_GT(f.cv_rms, 0.8 * noise * std::sqrt((1 + 1 + 0.5) / 3));
  EXPECT_LT(f.cv_rms, 1.2 * noise * std::sqrt((1 + 1 + 0.5) / 3));
}

// Data from an orthotropic law whose axes follow the fabric: the orthotropic fit recovers it
// and wins on AIC against isotropy.
TEST(StressStrainFit, FabricOrthotropyIsRecoveredAndPreferred) {
  const double c11 = 9e6, c12 = 3e6, c22 = 5e6, c66 = 2e6;
  FitResult truth;
  truth.model = FitModel::orthotropic_fabric;
  truth.parameters = {c11, c12, c22, c66};
  const auto s = samples(80, 3, [&](const FitSample& x) { return predict(truth, x, 1.0); }, 1.0);
  const FitResult o = fit(s, FitModel::orthotropic_fabric), i = fit(s, FitModel::isotropic);
  ASSERT_TRUE(o.ok && i.ok);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(o.parameters[k], truth.parameters[k], 1e-3 * c11) << k;
  EXPECT_LT(o.aic, i.aic);
}

TEST(StressStrainFit, PressureExponentIsFound) {
  const double lambda0 = 3e6, mu0 = 2e6, n = 0.5;
  auto s = samples(60, 4, [](const FitSample&) { return Tensor(Tensor::Zero()); });
  double p_mean = 0;
  for (const auto& x : s) p_mean += x.pressure / s.size();
  for (auto& x : s)
    x.stress_change = std::pow(x.pressure / p_mean, n) * (lambda0 * x.strain.trace() * Tensor::Identity() + 2 * mu0 * x.strain);
  const FitResult f = fit(s, FitModel::pressure_dependent);
  ASSERT_TRUE(f.ok);
  EXPECT_NEAR(f.parameters[2], n, 1e-9);  // on the scan's grid
  EXPECT_NEAR(f.parameters[0], lambda0, 1e-6 * lambda0);
  EXPECT_NEAR(f.parameters[1], mu0, 1e-6 * mu0);
}

TEST(StressStrainFit, DegenerateDataAreRefusedNotNan) {
  std::vector<FitSample> s(5);  // zero strain everywhere
  const FitResult f = fit(s, FitModel::isotropic);
  EXPECT_FALSE(f.ok);
}
