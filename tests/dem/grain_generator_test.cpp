#include "dem/grain_generator.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

using namespace pilelab;
using namespace pilelab::dem;

namespace {
// The axis-aligned ellipse through a polygon's corners. In the body frame the ellipse is
// axis-aligned but centred off the origin (the centroid of the polygon is not the centre of
// the ellipse), so fit the conic A x^2 + C y^2 + D x + E y = 1 and complete the squares.
// With six or more corners exactly on an ellipse the fit is exact to round-off.
struct EllipseFit {
  double semi_x, semi_y, residual;
};
EllipseFit fit_axis_aligned_ellipse(const std::vector<Vec2>& corners) {
  const int n = static_cast<int>(corners.size());
  Eigen::MatrixXd M(n, 4);
  Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
  for (int k = 0; k < n; ++k) {
    const double x = corners[k].x(), y = corners[k].y();
    M.row(k) << x * x, y * y, x, y;
  }
  const Eigen::Vector4d c = M.colPivHouseholderQr().solve(ones);
  const double g = 1.0 + c[2] * c[2] / (4.0 * c[0]) + c[3] * c[3] / (4.0 * c[1]);
  return {std::sqrt(g / c[0]), std::sqrt(g / c[1]), (M * c - ones).lpNorm<Eigen::Infinity>()};
}
}  // namespace

// Each axis is uniform on mean * [1 - p, 1 + p]: every axis lies in that interval, the sample
// mean of N axes is within 5 standard errors (sigma = p mean / sqrt 3) of the mean, and the
// extremes of N draws come within a few N-ths of the width of both ends.
TEST(GrainGenerator, PolygonAxesAreUniformWithinPolydispersityOfTheMean) {
  for (double p : {0.0, 0.3, 0.6}) {
    GrainSpec spec;
    spec.polydispersity = p;
    Rng rng(42);
    const int grains = 4000;
    double sum = 0.0, lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < grains; ++i) {
      const Shape s = random_grain(spec, rng);
      ASSERT_GE(static_cast<int>(s.vertices.size()), spec.corners_min);
      ASSERT_LE(static_cast<int>(s.vertices.size()), spec.corners_max);
      const EllipseFit e = fit_axis_aligned_ellipse(s.vertices);
      ASSERT_LT(e.residual, 1e-9) << "corners of grain " << i << " are not on one ellipse";
      for (double diameter : {2.0 * e.semi_x, 2.0 * e.semi_y}) {
        EXPECT_GE(diameter, spec.smallest_diameter() * (1.0 - 1e-9));
        EXPECT_LE(diameter, spec.largest_diameter() * (1.0 + 1e-9));
        sum += diameter;
        lo = std::min(lo, diameter);
        hi = std::max(hi, diameter);
      }
    }
    const int draws = 2 * grains;
    const double width = spec.largest_diameter() - spec.smallest_diameter();
    const double sigma = width / std::sqrt(12.0);
    EXPECT_NEAR(sum / draws, spec.mean_diameter, 5.0 * sigma / std::sqrt(draws) + 1e-9 * spec.mean_diameter) << "p = " << p;
    // P(no draw within 10/N of an end) = (1 - 10/N)^N ~ e^-10.
    EXPECT_LE(lo - spec.smallest_diameter(), 10.0 * width / draws + 1e-9 * spec.mean_diameter) << "p = " << p;
    EXPECT_LE(spec.largest_diameter() - hi, 10.0 * width / draws + 1e-9 * spec.mean_diameter) << "p = " << p;
  }
}

TEST(GrainGenerator, DiscDiametersSpanThePolydispersityInterval) {
  GrainSpec spec;
  spec.kind = ShapeKind::disc;
  spec.polydispersity = 0.25;
  Rng rng(7);
  const int grains = 4000;
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < grains; ++i) {
    const Shape s = random_grain(spec, rng);
    ASSERT_EQ(s.kind, ShapeKind::disc);
    lo = std::min(lo, 2.0 * s.radius);
    hi = std::max(hi, 2.0 * s.radius);
  }
  const double width = spec.largest_diameter() - spec.smallest_diameter();
  EXPECT_GE(lo, spec.smallest_diameter());
  EXPECT_LE(hi, spec.largest_diameter());
  EXPECT_LE(lo - spec.smallest_diameter(), 10.0 * width / grains);
  EXPECT_LE(spec.largest_diameter() - hi, 10.0 * width / grains);
}

// Round grains (paper section 5): the ellipse fit through the corners has equal axes, and the
// diameters are uniform on mean * [1 - p, 1 + p] (mean within 5 standard errors).
TEST(GrainGenerator, RoundPolygonsHaveCornersOnACircleOfDrawnDiameter) {
  GrainSpec spec;
  spec.outline = GrainOutline::circle;
  spec.polydispersity = 0.25;
  Rng rng(11);
  const int grains = 4000;
  double sum = 0.0;
  for (int i = 0; i < grains; ++i) {
    const Shape s = random_grain(spec, rng);
    ASSERT_EQ(s.kind, ShapeKind::polygon);
    const EllipseFit e = fit_axis_aligned_ellipse(s.vertices);
    ASSERT_LT(e.residual, 1e-9) << "corners of grain " << i << " are not on one circle";
    ASSERT_NEAR(e.semi_x, e.semi_y, 1e-9 * spec.mean_diameter) << "grain " << i << " is not round";
    const double diameter = e.semi_x + e.semi_y;
    EXPECT_GE(diameter, spec.smallest_diameter() * (1.0 - 1e-9));
    EXPECT_LE(diameter, spec.largest_diameter() * (1.0 + 1e-9));
    sum += diameter;
  }
  const double sigma = (spec.largest_diameter() - spec.smallest_diameter()) / std::sqrt(12.0);
  EXPECT_NEAR(sum / grains, spec.mean_diameter, 5.0 * sigma / std::sqrt(grains));
}

// Random corner placement: on 1e5 draws every polygon is convex with no angular gap below the
// floor, and the gaps follow the conditioned uniform spacings: a gap exceeds floor + y with
// probability (1 - y / (2 pi - n floor))^(n - 1), checked at the mean gap within 5 standard
// errors of a binomial count.
TEST(GrainGenerator, RandomCornersAreConvexWithTheMinimumGapOn1e5Draws) {
  Rng rng(11);
  GrainSpec spec;
  spec.corner_placement = CornerPlacement::random;
  spec.corners_min = 3;
  spec.corners_max = 12;
  spec.polydispersity = 0.45;
  for (int i = 0; i < 100000; ++i) {
    const Shape s = random_grain(spec, rng);  // make_polygon throws for a non-convex outline
    const auto& v = s.vertices;
    const int n = static_cast<int>(v.size());
    ASSERT_GE(n, 3);
    for (int k = 0; k < n; ++k) {
      const Vec2 e0 = v[(k + 1) % n] - v[k], e1 = v[(k + 2) % n] - v[(k + 1) % n];
      ASSERT_GT(e0.x() * e1.y() - e0.y() * e1.x(), 0.0) << "draw " << i << ": a corner not strictly convex";
    }
  }
  for (int n : {3, 6, 8}) {
    const double floor_fraction = 0.25, mean_gap = 2 * M_PI / n, floor = floor_fraction * mean_gap;
    const int draws = 100000;
    int above_mean = 0;
    for (int i = 0; i < draws; ++i) {
      const std::vector<double> a = random_corner_angles(n, floor_fraction, rng);
      ASSERT_EQ(static_cast<int>(a.size()), n);
      for (int k = 0; k < n; ++k) {
        const double gap = k + 1 < n ? a[k + 1] - a[k] : a[0] + 2 * M_PI - a[k];
        ASSERT_GE(gap, floor * (1 - 1e-12)) << "n = " << n << ", draw " << i;
        if (k == 0) above_mean += gap > mean_gap;
      }
    }
    const double p = std::pow(1.0 - (mean_gap - floor) / (2 * M_PI - n * floor), n - 1);
    EXPECT_NEAR(above_mean, p * draws, 5 * std::sqrt(draws * p * (1 - p))) << "n = " << n;
  }
}
