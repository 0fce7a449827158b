// The four-lane rotation against rotation_sincos, bit for bit: the World places grains four at
// a time, and a grain's corners must not depend on which lane it fell into.
#include "dem/rotation_x4.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "common/portable_math.h"

namespace pilelab::dem {
namespace {

bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0 || (std::isnan(x) && std::isnan(y)); }

// Each angle in every lane, beside three random others: the lanes must not interact.
void expect_lanes_match_scalar(const std::vector<double>& angles, std::mt19937_64& random) {
  std::uniform_int_distribution<std::size_t> pick(0, angles.size() - 1);
  for (double angle : angles) {
    for (int lane = 0; lane < 4; ++lane) {
      double x[4], s[4], c[4];
      for (double& other : x) other = angles[pick(random)];
      x[lane] = angle;
      rotation_sincos_x4(x, s, c, 4);
      for (int k = 0; k < 4; ++k) {
        double expected_s, expected_c;
        rotation_sincos(x[k], expected_s, expected_c);
        ASSERT_TRUE(same_bits(s[k], expected_s) && same_bits(c[k], expected_c))
            << "angle " << x[k] << " in lane " << k << ": sin " << s[k] << " vs " << expected_s << ", cos " << c[k]
            << " vs " << expected_c;
      }
    }
  }
}

TEST(RotationX4, EveryLaneHasTheScalarBits) {
  std::mt19937_64 random(2010);
  std::vector<double> angles;
  // The angles grains turn through in a pour, and far more.
  std::uniform_real_distribution<double> turn(-50.0, 50.0), exponent(-30.0, 19.0);
  for (int k = 0; k < 20000; ++k) angles.push_back(turn(random));
  for (int k = 0; k < 5000; ++k) angles.push_back((k % 2 ? 1.0 : -1.0) * std::pow(2.0, exponent(random)));
  // Each quadrant's edges, where the reduction's k changes.
  for (int k = -40; k <= 40; ++k) {
    const double edge = k * M_PI / 4;
    angles.push_back(edge);
    angles.push_back(std::nextafter(edge, -INFINITY));
    angles.push_back(std::nextafter(edge, INFINITY));
  }
  expect_lanes_match_scalar(angles, random);
}

TEST(RotationX4, ArgumentsOffTheFastPathHaveTheScalarBits) {
  // Zeros of both signs and angles below 2^-27 (sin x = x), 2^20 and beyond, infinities and NaN.
  std::mt19937_64 random(7);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> angles = {0.0, -0.0, 1e-300, -1e-20, 0x1p-27, std::nextafter(0x1p-27, 0.0), 0x1p20,
                                      std::nextafter(0x1p20, 0.0), -0x1p20, 1e21, -3e300, inf, -inf, nan, 0.5};
  expect_lanes_match_scalar(angles, random);
}

TEST(RotationX4, AnyCountHasTheScalarBitsAndWritesNothingBeyond) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> turn(-10.0, 10.0);
  for (int count = 0; count <= 37; ++count) {
    std::vector<double> x(count), s(count + 4, -7.0), c(count + 4, -7.0);  // x exactly count long: ASan sees a read past it
    for (double& a : x) a = turn(random);
    if (count % 4 == 3) x[count - 1] = count % 8 == 3 ? 0.0 : std::numeric_limits<double>::quiet_NaN();  // slow lanes in partial groups
    rotation_sincos_x4(x.data(), s.data(), c.data(), count);
    for (int k = 0; k < count; ++k) {
      double expected_s, expected_c;
      rotation_sincos(x[k], expected_s, expected_c);
      ASSERT_TRUE(same_bits(s[k], expected_s) && same_bits(c[k], expected_c)) << "angle " << k << " of " << count;
    }
    for (int k = count; k < count + 4; ++k) ASSERT_TRUE(s[k] == -7.0 && c[k] == -7.0) << "wrote past " << count;
  }
}

}  // namespace
}  // namespace pilelab::dem
