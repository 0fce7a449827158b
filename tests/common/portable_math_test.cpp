// The portable sine, cosine and arctangent against long double references: within one unit
// in the last place (a faithful rounding), exactly odd or even, and C's special values.
#include "common/portable_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using pilelab::portable_atan;
using pilelab::portable_atan2;
using pilelab::portable_cos;
using pilelab::portable_sin;
using pilelab::portable_sincos;

namespace {
// Distance of f from the exact value, in units of the last place of the double nearest it.
// long double carries 11 more bits than double, so its own error is below 1/1000 ulp here.
double ulps(double f, long double exact) {
  const double nearest = static_cast<double>(exact);
  const double a = std::abs(nearest);
  const double ulp = a == 0.0 ? std::numeric_limits<double>::denorm_min()
                              : std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
  return static_cast<double>(std::abs(static_cast<long double>(f) - exact) / ulp);
}

std::vector<double> samples(double lo, double hi, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> x(n);
  for (double& v : x) v = u(rng);
  return x;
}

// Arguments spread over many magnitudes: +-10^e for e uniform in [lo, hi].
std::vector<double> log_samples(double lo, double hi, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> e(lo, hi);
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i) x[i] = (i % 2 ? -1.0 : 1.0) * std::pow(10.0, e(rng));
  return x;
}
}  // namespace

TEST(PortableMath, SinAndCosAreFaithfulWhereTheReductionIsExact) {
  std::vector<double> x = samples(-10.0, 10.0, 200000, 1);
  for (double v : samples(-2e8, 2e8, 100000, 2)) x.push_back(v);
  for (double v : log_samples(-300.0, 8.3, 100000, 3)) x.push_back(v);
  // The doubles nearest multiples of pi/2 leave the smallest remainders, where a reduction
  // with a short pi/2 would lose every bit.
  for (long k = 1; k < 2000000; k += 997) x.push_back(static_cast<double>(k * (M_PIl / 2)));
  double worst = 0.0;
  for (double v : x) {
    double s, c;
    portable_sincos(v, s, c);
    worst = std::max({worst, ulps(s, std::sin(static_cast<long double>(v))),
                      ulps(c, std::cos(static_cast<long double>(v)))});
  }
  EXPECT_LE(worst, 1.0);
}

TEST(PortableMath, SinIsOddAndCosIsEvenExactly) {
  for (double v : log_samples(-20.0, 12.0, 100000, 4)) {
    EXPECT_EQ(portable_sin(-v), -portable_sin(v)) << v;
    EXPECT_EQ(portable_cos(-v), portable_cos(v)) << v;
  }
}

TEST(PortableMath, SinAndCosAreExactAtZeroAndBoundedForHugeArguments) {
  EXPECT_EQ(portable_sin(0.0), 0.0);
  EXPECT_EQ(portable_cos(0.0), 1.0);
  EXPECT_TRUE(std::signbit(portable_sin(-0.0)));
  for (double v : log_samples(8.4, 308.0, 20000, 5)) {
    double s, c;
    portable_sincos(v, s, c);
    ASSERT_TRUE(std::abs(s) <= 1.0 && std::abs(c) <= 1.0) << v;
    EXPECT_NEAR(s * s + c * c, 1.0, 4e-16) << v;
  }
  // Beyond the exact reduction the error is that of one fmod by the double nearest 2 pi.
  for (double v : samples(2.2e8, 1e10, 2000, 6))
    EXPECT_NEAR(portable_sin(v), static_cast<double>(std::sin(static_cast<long double>(v))), 4e-17 * v + 1e-15)
        << v;
  EXPECT_TRUE(std::isnan(portable_sin(std::numeric_limits<double>::infinity())));
  EXPECT_TRUE(std::isnan(portable_cos(std::numeric_limits<double>::quiet_NaN())));
}

TEST(PortableMath, AtanIsFaithfulAndOdd) {
  std::vector<double> t = samples(-2.0, 2.0, 200000, 7);
  for (double v : log_samples(-300.0, 300.0, 200000, 8)) t.push_back(v);
  // Each table point and its neighbours, where the reduction switches point.
  for (int j = 0; j <= 32; ++j)
    for (double d : {-1e-12, 0.0, 1e-12}) t.push_back(j / 32.0 + d);
  double worst = 0.0;
  for (double v : t) {
    worst = std::max(worst, ulps(portable_atan(v), std::atan(static_cast<long double>(v))));
    EXPECT_EQ(portable_atan(-v), -portable_atan(v)) << v;
  }
  EXPECT_LE(worst, 1.0);
  EXPECT_EQ(portable_atan(std::numeric_limits<double>::infinity()), M_PI / 2);
  EXPECT_TRUE(std::isnan(portable_atan(std::numeric_limits<double>::quiet_NaN())));
}

TEST(PortableMath, Atan2IsFaithfulInEveryQuadrant) {
  const std::vector<double> x = log_samples(-30.0, 30.0, 300000, 9), y = log_samples(-30.0, 30.0, 300000, 10);
  const std::vector<double> u = samples(-1.0, 1.0, 300000, 11), w = samples(-1.0, 1.0, 300000, 12);
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    worst = std::max(worst, ulps(portable_atan2(y[i], x[i]), std::atan2(static_cast<long double>(y[i]),
                                                                      static_cast<long double>(x[i]))));
    worst = std::max(worst, ulps(portable_atan2(w[i], u[i]), std::atan2(static_cast<long double>(w[i]),
                                                                      static_cast<long double>(u[i]))));
  }
  EXPECT_LE(worst, 1.0);
}

TEST(PortableMath, Atan2SpecialValuesFollowC) {
  const double inf = std::numeric_limits<double>::infinity();
  // C's atan2 returns these exactly (as the doubles nearest pi, pi/2 and pi/4).
  const double cases[][2] = {{0.0, 0.0},  {-0.0, 0.0},  {0.0, -0.0}, {-0.0, -0.0}, {0.0, 3.0},
                             {0.0, -3.0}, {-0.0, -3.0}, {3.0, 0.0},  {-3.0, 0.0},  {3.0, -0.0},
                             {inf, 1.0},  {-inf, 1.0},  {1.0, inf},  {1.0, -inf},  {-1.0, -inf},
                             {inf, inf},  {inf, -inf},  {-inf, inf}, {-inf, -inf}, {1.0, 1.0}};
  for (const auto& c : cases) {
    const double expected = std::atan2(c[0], c[1]), got = portable_atan2(c[0], c[1]);
    EXPECT_EQ(got, expected) << "atan2(" << c[0] << ", " << c[1] << ")";
    EXPECT_EQ(std::signbit(got), std::signbit(expected)) << "atan2(" << c[0] << ", " << c[1] << ")";
  }
  EXPECT_TRUE(std::isnan(portable_atan2(std::nan(""), 1.0)));
}
