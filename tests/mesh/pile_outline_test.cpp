// The free surface of piles: Douglas-Peucker keeps every point farther than the tolerance, and
// the mean outline of an ensemble is the mean of the members' height functions, exactly on its
// grid for the piecewise-linear surfaces outlines are.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "mesh/pile_outline.h"

using namespace pilelab::mesh;
using pilelab::dem::Vec2;

namespace {
constexpr double degree = M_PI / 180;

// Height of a wedge at x (zero beyond its feet).
double wedge_height(const Wedge& w, double x) {
  const double left = w.height_m - (w.apex_x_m - x) * std::tan(w.left_angle_deg * degree);
  const double right = w.height_m - (x - w.apex_x_m) * std::tan(w.right_angle_deg * degree);
  return std::max(0.0, x < w.apex_x_m ? left : right);
}
}  // namespace

TEST(SimplifyPolyline, KeepsEndsAndEveryPointBeyondTheTolerance) {
  // A straight line with one bump of 0.1: at tolerance 0.05 the bump stays, at 0.2 it goes.
  const std::vector<Vec2> line = {{0, 0}, {1, 0}, {2, 0.1}, {3, 0}, {4, 0}};
  const auto kept = simplify_polyline(line, 0.05);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept[1], Vec2(2, 0.1));
  const auto flat = simplify_polyline(line, 0.2);
  ASSERT_EQ(flat.size(), 2u);
  EXPECT_EQ(flat.front(), line.front());
  EXPECT_EQ(flat.back(), line.back());
}

TEST(MeanOutline, IsTheMeanOfTheMembersHeightsOnItsGrid) {
  // Three wedges of different heights, flanks and apex positions: each grid point of the mean
  // outline lies at the mean of the three exact heights there (linear interpolation is exact
  // on straight flanks, so only rounding remains).
  const std::vector<Wedge> wedges = {{0.30, 28, 26, 0.0}, {0.34, 25, 30, 0.02}, {0.28, 31, 24, -0.03}};
  std::vector<Outline> outlines;
  for (const Wedge& w : wedges) outlines.push_back(wedge_outline(w));
  const double spacing = 0.004;
  const Outline mean = mean_outline(outlines, spacing);
  double left = INFINITY, right = -INFINITY;
  for (const Outline& o : outlines) left = std::min(left, o.surface.front().x()), right = std::max(right, o.surface.back().x());
  EXPECT_EQ(mean.surface.front().x(), left);
  EXPECT_EQ(mean.surface.back().x(), right);
  EXPECT_EQ(mean.surface.front().y(), 0.0);
  EXPECT_EQ(mean.surface.back().y(), 0.0);
  for (std::size_t i = 1; i < mean.surface.size(); ++i) {
    EXPECT_LE(mean.surface[i].x() - mean.surface[i - 1].x(), spacing * (1 + 1e-12));
    double expected = 0;
    for (const Wedge& w : wedges) expected += wedge_height(w, mean.surface[i].x()) / wedges.size();
    EXPECT_NEAR(mean.surface[i].y(), expected, 1e-14) << "at x = " << mean.surface[i].x();
  }
  // The apex is the highest point.
  for (const Vec2& p : mean.surface) EXPECT_LE(p.y(), mean.surface[mean.apex_index].y());
}

TEST(MeanOutline, OfOneOutlineIsThatOutlineOnTheGrid) {
  // The grid misses the apex by at most half a spacing, so the peak is cut by at most the
  // steeper flank's rise over that distance.
  const Wedge w{0.3, 27, 25, 0.01};
  const double spacing = 0.01;
  const Outline mean = mean_outline({wedge_outline(w)}, spacing);
  for (const Vec2& p : mean.surface) EXPECT_NEAR(p.y(), wedge_height(w, p.x()), 1e-15);
  EXPECT_LE(w.height_m - mean.surface[mean.apex_index].y(), std::tan(27 * degree) * spacing / 2 * (1 + 1e-12));
}

TEST(MeanOutline, OfNothingIsAnError) { EXPECT_THROW(mean_outline({}, 0.01), pilelab::InputError); }

// The moving average of a tent h(x) (flanks of slope t = tan(phi), apex height H) over a window w
// narrower than a flank: linear parts stay exactly as they were; the apex drops to H - w t / 4
// (the mean of the tent over the window centred on it); the toes spread by w / 2; the area is
// kept (an average moves no material), up to the trapezoid error of the w / 16 sampling on the
// three quadratic pieces, sum of slope changes x spacing^2 / 12 = 4 t (w / 16)^2 / 12.
TEST(SmoothedOutline, KeepsStraightFlanksAndAreaAndRoundsTheApexAsTheoryGives) {
  const double t = std::tan(28.0 * M_PI / 180.0), H = 0.3, w = 0.02;
  Outline tent;
  tent.surface = {{-H / t, 0.0}, {0.0, H}, {H / t, 0.0}};
  tent.apex_index = 1;
  const Outline s = smoothed_outline(tent, w);
  EXPECT_DOUBLE_EQ(s.surface.front().x(), -H / t - w / 2);
  EXPECT_DOUBLE_EQ(s.surface.back().x(), H / t + w / 2);
  const double spacing = (2 * H / t + w) / (s.surface.size() - 1);
  double area = 0, top = 0;
  for (std::size_t i = 0; i + 1 < s.surface.size(); ++i)
    area += 0.5 * (s.surface[i].y() + s.surface[i + 1].y()) * (s.surface[i + 1].x() - s.surface[i].x());
  for (const Vec2& p : s.surface) {
    top = std::max(top, p.y());
    const double x = std::abs(p.x());
    if (x > w / 2 && x < H / t - w / 2) {
      EXPECT_NEAR(p.y(), H - t * x, 1e-14) << "x = " << p.x();
    }
  }
  EXPECT_NEAR(area, H * H / t, 4 * t * spacing * spacing / 12);
  // The sampled peak is the smoothed apex, or a sample at most half a spacing from it on the
  // parabola of curvature 2 t / w.
  EXPECT_LE(top, H - w * t / 4 + 1e-15);
  EXPECT_GE(top, H - w * t / 4 - t * spacing * spacing / (4 * w));
  EXPECT_EQ(s.surface[s.apex_index].y(), top);
  // No smoothing: the outline as it was.
  EXPECT_EQ(smoothed_outline(tent, 0.0).surface.size(), tent.surface.size());
}
