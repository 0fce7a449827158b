// The repose-angle fit on piles whose flanks are known exactly.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "dem/pile_shape.h"
#include "dem/snapshot.h"
#include "dem/world.h"

using namespace pilelab::dem;

namespace {
constexpr double deg = M_PI / 180.0;

// A resting disc of radius r whose top is at (x, top).
void place_disc(World& w, double r, double x, double top) {
  const int id = w.add_grain(make_disc(r), 5000.0);
  w.activate(id, {x, top - r}, 0.0, {0, 0}, 0.0);
}

// Discs of radius r resting with their tops on the surface y = h - tan(left) |x| (x < 0) and
// y = h - tan(right) x (x > 0), at 1 mm spacing, down to the plate.
Snapshot triangle_pile(World& w, double left_deg, double right_deg, double height) {
  const double r = 0.002;
  const double x_left = -height / std::tan(left_deg * deg), x_right = height / std::tan(right_deg * deg);
  for (double x = x_left + 0.0005; x < x_right; x += 0.001) {
    const double top = x < 0 ? height + std::tan(left_deg * deg) * x : height - std::tan(right_deg * deg) * x;
    if (top >= 2 * r) place_disc(w, r, x, top);
  }
  return take_snapshot(w, "settled");
}
}  // namespace

TEST(PileShape, RecoversTheFlankAnglesOfAnExactTriangle) {
  World w(WorldSettings{});
  const Snapshot s = triangle_pile(w, 28.0, 21.0, 0.2);
  const PileShape p = measure_pile(w, s, 0.01);
  EXPECT_NEAR(p.height, 0.2, 0.002);  // the apex bin's top is within one grain spacing x slope
  // Within a bin the highest point always sits at the same offset, so the fitted slope is exact
  // up to the one-grain-spacing quantisation of the bins' contents.
  EXPECT_NEAR(p.repose_left_deg, 28.0, 0.05);
  EXPECT_NEAR(p.repose_right_deg, 21.0, 0.05);
  EXPECT_GE(p.left_points, 3);
  EXPECT_GE(p.right_points, 3);
}

TEST(PileShape, ASideWithoutEnoughSurfaceHasNoAngle) {
  World w(WorldSettings{});
  place_disc(w, 0.002, 0.0, 0.004);
  const PileShape p = measure_pile(w, take_snapshot(w, "settled"), 0.01);
  EXPECT_TRUE(std::isnan(p.repose_left_deg));
  EXPECT_TRUE(std::isnan(p.repose_right_deg));
}

// The reported standard error of an angle is calibrated: over many piles whose flank tops scatter
// independently about the same line, the angles' spread equals the standard error each pile reports.
TEST(PileShape, TheFitsStandardErrorMatchesTheSpreadOfTheAngle) {
  const double slope_deg = 28.0, height = 0.2, bin = 0.01, r = 0.002, noise = 0.001;  // [m]
  const double tan_slope = std::tan(slope_deg * deg);
  std::mt19937_64 random(2010);
  std::normal_distribution<double> jitter(0.0, noise);
  constexpr int piles = 400;
  std::vector<double> left;
  double sum_squared_se = 0.0;
  for (int k = 0; k < piles; ++k) {
    World w(WorldSettings{});
    // One disc per bin, its top on the line y = height - tan |x| plus independent noise; the
    // apex disc stands clear above the rest, so the apex bin and the height are fixed.
    // The bins start at the leftmost grain: a low grain half a bin left of the first bin centre.
    const int half = static_cast<int>(height / tan_slope / bin);
    place_disc(w, r, -(half + 1.5) * bin, 2 * r);
    for (int b = -half; b <= half; ++b) {
      const double x = b * bin;  // a bin centre
      const double top = b == 0 ? height : height - tan_slope * std::abs(x) + jitter(random);
      if (b == 0 || top < height - 4 * noise) place_disc(w, r, x, top);  // the apex stays the highest bin
    }
    const PileShape p = measure_pile(w, take_snapshot(w, "settled"), bin);
    ASSERT_TRUE(std::isfinite(p.repose_left_deg) && std::isfinite(p.repose_left_se_deg));
    left.push_back(p.repose_left_deg);
    sum_squared_se += p.repose_left_se_deg * p.repose_left_se_deg;
  }
  double mean = 0.0;
  for (double a : left) mean += a / piles;
  double variance = 0.0;
  for (double a : left) variance += (a - mean) * (a - mean) / (piles - 1);
  const double spread = std::sqrt(variance), reported = std::sqrt(sum_squared_se / piles);
  // A standard deviation from 400 samples is known to 1/sqrt(2 * 399) = 3.5 %: allow 4 of those.
  EXPECT_NEAR(reported / spread, 1.0, 0.14) << "spread " << spread << " deg, reported " << reported << " deg";
  // Unbiased too: the mean lies within 4 standard errors of the true angle.
  EXPECT_NEAR(mean, slope_deg, 4.0 * spread / std::sqrt(piles));
  EXPECT_GT(reported, 0.05);  // the noise is seen (about 0.2 degrees for these numbers)
}
