// Exact intersection areas against closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "coarse/circle_overlap.h"

using pilelab::coarse::circle_circle_area;
using pilelab::coarse::circle_polygon_area;
using pilelab::dem::Vec2;

namespace {
std::vector<Vec2> square(double half, Vec2 c = {0, 0}) {
  return {c + Vec2(-half, -half), c + Vec2(half, -half), c + Vec2(half, half), c + Vec2(-half, half)};
}
}  // namespace

TEST(CircleOverlap, PolygonInsideCircleIsWhole) {
  EXPECT_NEAR(circle_polygon_area({0.1, 0}, 2.0, square(0.5)), 1.0, 1e-15);
}

TEST(CircleOverlap, CircleInsidePolygonIsWhole) {
  EXPECT_NEAR(circle_polygon_area({0.2, -0.1}, 0.3, square(1.0)), M_PI * 0.09, 1e-15);
}

// Circle of radius r centred in a square of half side s < r < s sqrt(2): the circle minus
// four circular segments r^2 acos(s/r) - s sqrt(r^2 - s^2).
TEST(CircleOverlap, SquareCutByCircleMatchesClosedForm) {
  for (double r : {1.05, 1.2, 1.4}) {
    const double s = 1.0;
    const double exact = M_PI * r * r - 4 * (r * r * std::acos(s / r) - s * std::sqrt(r * r - s * s));
    EXPECT_NEAR(circle_polygon_area({0, 0}, r, square(s)), exact, 1e-14) << r;
  }
}

// A half plane through the centre (a large square with an edge through it) holds half the
// circle; a corner at the centre a quarter, whatever the orientation.
TEST(CircleOverlap, HalfAndQuarterDiscs) {
  EXPECT_NEAR(circle_polygon_area({0, 0}, 1.0, square(10.0, {0, 10.0})), M_PI / 2, 1e-14);
  EXPECT_NEAR(circle_polygon_area({0, 0}, 1.0, square(10.0, {10.0, 10.0})), M_PI / 4, 1e-14);
}

// The area of a non-convex polygon is the sum of its parts: an L of three unit squares.
TEST(CircleOverlap, NonConvexPolygonIsAdditive) {
  const std::vector<Vec2> L = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const Vec2 c(1.0, 0.9);
  const double r = 0.8;
  const double parts = circle_polygon_area(c, r, square(0.5, {0.5, 0.5})) +
                       circle_polygon_area(c, r, square(0.5, {1.5, 0.5})) +
                       circle_polygon_area(c, r, square(0.5, {0.5, 1.5}));
  EXPECT_NEAR(circle_polygon_area(c, r, L), parts, 1e-14);
}

TEST(CircleOverlap, LensOfTwoCircles) {
  EXPECT_EQ(circle_circle_area({0, 0}, 1, {3, 0}, 1), 0.0);
  EXPECT_NEAR(circle_circle_area({0, 0}, 2, {0.5, 0}, 1), M_PI, 1e-15);
  // Equal circles at distance d: 2 r^2 acos(d/2r) - (d/2) sqrt(4 r^2 - d^2).
  const double r = 1, d = 1.2;
  EXPECT_NEAR(circle_circle_area({0, 0}, r, {d, 0}, r),
              2 * r * r * std::acos(d / (2 * r)) - 0.5 * d * std::sqrt(4 * r * r - d * d), 1e-14);
}
