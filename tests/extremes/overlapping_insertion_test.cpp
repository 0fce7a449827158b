// A grain put into the world overlapping another (ctest -L extremes; docs/studies/extremes.md):
// two hexagons at rest, flat edge on flat edge, a quarter, half and nine tenths of the inner
// radius into each other, with the paper's contact law at 0.8 of the stability bound for that
// depth. The overlap pushes them apart: every number stays finite, the contact ends, and the
// kinetic energy they fly apart with is at most the work of the initial force over the initial
// depth, F0 delta0 (the overlap of two flat faces shrinks as they separate and the contact
// length grows, so the repulsive force only falls: its work is below F0 delta0; damping only
// takes energy away).
#include <gtest/gtest.h>

#include <cmath>

#include "dem/time_step.h"
#include "dem/world.h"

using namespace pilelab::dem;

namespace {
Shape hexagon(double circumradius) {
  std::vector<Vec2> v;
  for (int k = 0; k < 6; ++k) {
    const double a = (30.0 + 60.0 * k) * M_PI / 180.0;  // flat edges facing +-x
    v.emplace_back(circumradius * std::cos(a), circumradius * std::sin(a));
  }
  return make_polygon(v);
}
}  // namespace

class OverlappingInsertion : public ::testing::TestWithParam<double> {};

TEST_P(OverlappingInsertion, PushesApartWithBoundedEnergy) {
  const double fraction = GetParam();
  const Shape grain = hexagon(3.4e-3);
  const double density = 5000.0, r = grain.inner_radius;
  ContactParameters contact;
  const TimeStepBound bound = stable_time_step_at_depth({grain}, density, contact, Scheme::verlet, fraction);
  WorldSettings s;
  s.contact = contact;
  s.scheme = Scheme::verlet;
  s.time_step = 0.8 * bound.stable_limit;
  s.gravity = {0.0, 0.0};
  World w(s);
  const int a = w.add_grain(grain, density), b = w.add_grain(grain, density);
  const double depth = 2.0 * fraction * r;  // the faces cut fraction * r into each grain
  w.activate(a, {0.0, 0.0}, 0.0, {0.0, 0.0}, 0.0);
  w.activate(b, {2.0 * r - depth, 0.0}, 0.0, {0.0, 0.0}, 0.0);

  w.step();
  ASSERT_EQ(w.contact_count(), 1u);
  const double f0 = w.contacts().front().normal_force;
  ASSERT_GT(f0, 0.0);
  int steps = 1;
  while (w.contact_count() > 0 && steps < 200000) {
    w.step();
    ++steps;
    ASSERT_EQ(w.first_non_finite_grain(), -1) << "step " << steps;
  }
  EXPECT_EQ(w.contact_count(), 0u) << "still touching after " << steps << " steps";
  const double energy = w.kinetic_energy();
  std::printf("EXTREMES inserted %.2f of the inner radius deep: apart after %d steps of %.3g s, kinetic energy %.3g J "
              "<= F0 delta0 = %.3g J\n",
              fraction, steps, s.time_step, energy, f0 * depth);
  EXPECT_GT(energy, 0.0);
  EXPECT_LE(energy, f0 * depth);
  // Head on, the push is along the line of centres: no spin, no sideways motion.
  EXPECT_NEAR(w.velocity(a).y(), 0.0, 1e-12);
  EXPECT_NEAR(w.velocity(a).x(), -w.velocity(b).x(), 1e-9 * std::abs(w.velocity(b).x()));
}

INSTANTIATE_TEST_SUITE_P(Depths, OverlappingInsertion, ::testing::Values(0.25, 0.5, 0.9),
                         [](const ::testing::TestParamInfo<double>& info) {
                           return "depth_" + std::to_string(static_cast<int>(info.param * 100)) + "_percent";
                         });
