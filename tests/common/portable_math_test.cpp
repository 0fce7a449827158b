// The portable sine, cosine and arctangent against long double references: faithfully rounded
// (one of the two doubles either side of the exact value), exactly odd or even, and C's
// special values.
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
using pilelab::rotation_sincos;

namespace {
static_assert(std::numeric_limits<long double>::digits >= 64,
              "the reference values need a long double with at least 11 more bits than double");

// Faithful rounding: f is one of the two doubles either side of the exact value (or the exact
// value itself, where it is a double). long double's own error is below 1/1000 ulp of a double.
bool faithful(double f, long double exact) {
  const double nearest = static_cast<double>(exact);
  if (static_cast<long double>(nearest) == exact) return f == nearest;
  const double other = static_cast<long double>(nearest) < exact
                           ? std::nextafter(nearest, std::numeric_limits<double>::infinity())
                           : std::nextafter(nearest, -std::numeric_limits<double>::infinity());
  return f == nearest || f == other;
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
  for (double v : x) {
    double s, c;
    portable_sincos(v, s, c);
    ASSERT_TRUE(faithful(s, std::sin(static_cast<long double>(v)))) << std::hexfloat << "sin " << v;
    ASSERT_TRUE(faithful(c, std::cos(static_cast<long double>(v)))) << std::hexfloat << "cos " << v;
  }
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
  // Subnormal arguments, where atan t = t must come out exactly.
  for (double k : {1.0, 2.0, 3.0, 5.0, 1e6, 4.5e15}) t.push_back(k * std::numeric_limits<double>::denorm_min());
  // Each table point and its neighbours, where the reduction switches point.
  for (int j = 0; j <= 32; ++j)
    for (double d : {-1e-12, 0.0, 1e-12}) t.push_back(j / 32.0 + d);
  for (double v : t) {
    ASSERT_TRUE(faithful(portable_atan(v), std::atan(static_cast<long double>(v)))) << std::hexfloat << v;
    EXPECT_EQ(portable_atan(-v), -portable_atan(v)) << v;
  }
  EXPECT_EQ(portable_atan(std::numeric_limits<double>::infinity()), M_PI / 2);
  EXPECT_TRUE(std::isnan(portable_atan(std::numeric_limits<double>::quiet_NaN())));
}

TEST(PortableMath, Atan2IsFaithfulInEveryQuadrant) {
  const std::vector<double> x = log_samples(-30.0, 30.0, 300000, 9), y = log_samples(-30.0, 30.0, 300000, 10);
  const std::vector<double> u = samples(-1.0, 1.0, 300000, 11), w = samples(-1.0, 1.0, 300000, 12);
  // Extreme ratios, subnormal quotients and subnormal pairs.
  const std::vector<double> far_x = log_samples(-320.0, 308.0, 300000, 13), far_y = log_samples(-320.0, 308.0, 300000, 14);
  const auto check = [](double y, double x) {
    return faithful(portable_atan2(y, x), std::atan2(static_cast<long double>(y), static_cast<long double>(x)));
  };
  for (std::size_t i = 0; i < x.size(); ++i) {
    ASSERT_TRUE(check(y[i], x[i])) << std::hexfloat << y[i] << " " << x[i];
    ASSERT_TRUE(check(w[i], u[i])) << std::hexfloat << w[i] << " " << u[i];
    ASSERT_TRUE(check(far_y[i], far_x[i])) << std::hexfloat << far_y[i] << " " << far_x[i];
  }
  const double tiny = std::numeric_limits<double>::denorm_min();
  for (const auto& [a, b] : {std::pair{1e-320, 2e-320}, {tiny, tiny}, {-1e-310, -3e-310}, {3 * tiny, 1.0},
                             {0x1.5e2eb8ca02af5p-581, 0x1.013dc54bdb91ap+462}, {1.0, 7 * tiny}})
    EXPECT_TRUE(check(a, b)) << std::hexfloat << a << " " << b;
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
  EXPECT_FALSE(std::signbit(portable_atan2(-std::nan(""), 1.0)));  // one NaN on every machine
}

TEST(PortableMath, RotationSinCosIsWithinTwoUlp) {
  // The cheaper sine and cosine that place the grains' corners: within two ulp of the true
  // value plus 1e-18 (the part of pi/2 left out, times k), over the angles grains reach and
  // tiny ones, including the doubles nearest multiples of pi/2.
  std::vector<double> x = samples(-10.0, 10.0, 200000, 7);
  for (double v : samples(-1e6, 1e6, 100000, 8)) x.push_back(v);
  for (double v : log_samples(-300.0, 6.0, 100000, 9)) x.push_back(v);
  for (long k = 1; k < 600000; k += 613) x.push_back(static_cast<double>(k * (M_PIl / 2)));
  const auto within = [](double got, long double truth) {
    const double t = std::abs(static_cast<double>(truth));
    const double ulp = std::nextafter(t, INFINITY) - t;
    return std::abs(static_cast<long double>(got) - truth) <= 2.0L * ulp + 1e-18L;
  };
  for (double v : x) {
    double s, c;
    rotation_sincos(v, s, c);
    ASSERT_TRUE(within(s, std::sin(static_cast<long double>(v)))) << std::hexfloat << "sin " << v;
    ASSERT_TRUE(within(c, std::cos(static_cast<long double>(v)))) << std::hexfloat << "cos " << v;
    double s_minus, c_minus;
    rotation_sincos(-v, s_minus, c_minus);
    ASSERT_EQ(s_minus, -s) << "odd " << v;
    ASSERT_EQ(c_minus, c) << "even " << v;
  }
  double s, c;
  rotation_sincos(-0.0, s, c);
  EXPECT_TRUE(s == 0.0 && std::signbit(s) && c == 1.0);
  // Beyond 2^20 rad, and for infinities and NaN, the faithful version answers.
  for (double v : {0x1p20, -3e7, 1e300, std::numeric_limits<double>::infinity()}) {
    double ps, pc;
    rotation_sincos(v, s, c);
    portable_sincos(v, ps, pc);
    EXPECT_TRUE((s == ps || (std::isnan(s) && std::isnan(ps))) && (c == pc || (std::isnan(c) && std::isnan(pc)))) << v;
  }
}
