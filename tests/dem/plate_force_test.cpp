// The plate's load (dem/plate_force): its integral is the weight the plate carries, within the
// pile's settling residual, and the dip statistic is exact on profiles whose answer is known.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "common/rng.h"
#include "dem/grain_generator.h"
#include "dem/plate_force.h"
#include "dem/snapshot.h"
#include "dem/time_step.h"
#include "dem/world.h"

using namespace pilelab;
using namespace pilelab::dem;

namespace {
// Bins 0.01 R wide whose centres sit symmetrically about the apex at x' = +-(k + 1/2) / 100.
void symmetric_bins(double apex, double R, std::vector<double>& x) {
  for (int k = -100; k < 100; ++k) x.push_back(apex + (k + 0.5) * 0.01 * R);
}
}  // namespace

TEST(PlateForce, TheDipStatisticIsExactOnKnownProfiles) {
  const double apex = 0.013, R = 0.2;
  std::vector<double> x;
  symmetric_bins(apex, R, x);
  std::vector<double> flat(x.size(), 3.0), height(x.size()), dip(x.size(), 2.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double u = std::abs(x[i] - apex) / R;
    height[i] = 5.0 * (1.0 - u);  // a load proportional to the height of a wedge above the point
    if (u < 0.1) dip[i] = 1.6;    // the centre carries 80 % of the ring's load
  }
  EXPECT_NEAR(centre_over_ring(x, flat, apex, R), 0.0, 1e-14);
  // Mean |x'| over the centre's bins is 0.05, over the ring's 0.25: (1 - 0.05) / (1 - 0.25) - 1.
  EXPECT_NEAR(centre_over_ring(x, height, apex, R), 0.95 / 0.75 - 1.0, 1e-13);
  EXPECT_NEAR(centre_over_ring(x, dip, apex, R), -0.2, 1e-14);
  // No ring load, or no bin in a window: no statistic.
  EXPECT_TRUE(std::isnan(centre_over_ring(x, std::vector<double>(x.size(), 0.0), apex, R)));
  EXPECT_TRUE(std::isnan(centre_over_ring({apex + 0.5 * R}, {1.0}, apex, R)));
}

TEST(PlateForce, TheLoadOfASettledHeapIsItsWeightWithinTheSettlingResidual) {
  // Thirty paper grains dropped onto the plate and left 8 s to settle. The grains' forces on
  // one another cancel in pairs, so the plate's load minus the weight is exactly the sum of
  // m a over the grains: the settling residual, which the profile's integral must meet to
  // round-off; and the load is the weight within that residual.
  Rng rng(1);
  std::vector<Shape> shapes;
  for (int i = 0; i < 30; ++i) shapes.push_back(random_grain(GrainSpec{}, rng));
  WorldSettings s;
  s.scheme = Scheme::leapfrog;
  s.time_step = 0.8 * stable_time_step(shapes, 5000.0, s.contact, s.scheme).stable_limit;
  World w(s);
  const double plate_width = 0.6;
  w.add_wall(make_polygon({{-0.3, -0.01}, {0.3, -0.01}, {0.3, 0.0}, {-0.3, 0.0}}), {0, -0.005}, 0.0);
  double top = 0.0;
  for (const Shape& shape : shapes) {
    const int g = w.add_grain(shape, 5000.0);
    top += shape.bounding_radius;
    w.activate(g, {rng.uniform(-0.01, 0.01), top + 1e-4}, rng.uniform(0.0, 2 * M_PI), {0, 0}, 0.0);
    top += shape.bounding_radius + 1e-4;
  }
  while (w.time() < 8.0) w.step();
  const Snapshot snapshot = take_snapshot(w, "settled");
  const PlateLoad load = plate_load(w, snapshot, {0}, -0.5 * plate_width, plate_width, 6.8e-3);

  double integral = 0.0;
  for (double q : load.load) integral += q * load.bin_width;
  EXPECT_NEAR(integral, load.total_force, 1e-12 * load.weight) << "every plate contact falls in a bin";
  double weight = 0.0, residual = 0.0;  // sum m g, and sum (F_contact + m g)_y = sum m a_y
  for (std::size_t i = 0; i < snapshot.grain_count(); ++i) {
    const double mg = w.mass(static_cast<int>(snapshot.body[i])) * 9.81;
    weight += mg;
    residual += snapshot.contact_force[2 * i + 1] - mg;
  }
  EXPECT_NEAR(load.weight, weight, 1e-12 * weight);
  EXPECT_NEAR(load.total_force - load.weight, residual, 1e-10 * weight) << "internal forces cancel in pairs";
  EXPECT_LE(std::abs(load.total_force / load.weight - 1.0), std::abs(residual) / weight + 1e-10);
  EXPECT_LT(std::abs(residual) / weight, 1e-6) << "eight seconds settle these thirty grains";
}
