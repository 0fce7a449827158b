// The repose-angle fit on piles whose flanks are known exactly.
#include <cmath>

#include <gtest/gtest.h>

#include "dem/pile_shape.h"
#include "dem/snapshot.h"
#include "dem/world.h"

using namespace pilelab::dem;

namespace {
constexpr double deg = M_PI / 180.0;

// Discs of radius r resting with their tops on the surface y = h - tan(left) |x| (x < 0) and
// y = h - tan(right) x (x > 0), at 1 mm spacing, down to the plate.
Snapshot triangle_pile(World& w, double left_deg, double right_deg, double height) {
  const double r = 0.002;
  const double x_left = -height / std::tan(left_deg * deg), x_right = height / std::tan(right_deg * deg);
  for (double x = x_left + 0.0005; x < x_right; x += 0.001) {
    const double top = x < 0 ? height + std::tan(left_deg * deg) * x : height - std::tan(right_deg * deg) * x;
    if (top < 2 * r) continue;
    const int id = w.add_grain(make_disc(r), 5000.0);
    w.activate(id, {x, top - r}, 0.0, {0, 0}, 0.0);
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
  const int id = w.add_grain(make_disc(0.002), 5000.0);
  w.activate(id, {0.0, 0.002}, 0.0, {0, 0}, 0.0);
  const PileShape p = measure_pile(w, take_snapshot(w, "settled"), 0.01);
  EXPECT_TRUE(std::isnan(p.repose_left_deg));
  EXPECT_TRUE(std::isnan(p.repose_right_deg));
}
