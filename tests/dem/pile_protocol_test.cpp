// The pile protocol's checks of a stable integration: the energy account
// (PileProtocol::energy_fed_in, mechanical_energy: what the pour puts in bounds what the grains
// can hold, and a step above the stability limit that creates more stops the run), and the
// swing of a contact at the period of two steps, which stops it too.
#include "dem/pile_protocol.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "dem/checkpoint.h"
#include "dem/plate_force.h"

namespace pilelab::dem {
namespace {

// 40 grains from 6 cm onto a 0.3 m plate: a pile in a fraction of a second.
DemScene small_pile(Scheme scheme) {
  DemScene s;
  s.seed = 3;
  s.grain_count = 40;
  s.scheme = scheme;
  s.container.plate_width = 0.3;
  s.pour.funnel_height = 0.06;
  s.pour.rate = 400.0;
  s.pour.outlet_width = 0.02;
  s.settle.min_time = 0.05;
  s.settle.max_time = 0.25;
  return s;
}

TEST(PileProtocolEnergy, AFallingGrainHoldsExactlyWhatThePourPutIn) {
  // Before its first contact the first grain falls freely; Verlet integrates a constant force
  // exactly, so its kinetic plus potential energy is the energy it left the outlet with.
  PileProtocol p(small_pile(Scheme::verlet), "test");
  p.step();
  ASSERT_EQ(p.state().poured, 1);
  const double m = p.world().mass(p.world().active_grains().front());
  const PourSpec& pour = p.scene().pour;
  const double at_outlet =
      m * (0.5 * pour.inflow_speed * pour.inflow_speed + p.scene().gravity * (pour.funnel_height - p.scene().container.lost_below));
  EXPECT_NEAR(p.energy_fed_in(), at_outlet, 1e-14 * at_outlet);
  for (int k = 0; k < 200 && p.state().poured == 1; ++k) {
    p.step();
    if (p.state().poured == 1) {
      EXPECT_NEAR(p.mechanical_energy(), at_outlet, 1e-10 * at_outlet) << "step " << k;
    }
  }
}

TEST(PileProtocolEnergy, AStablePourNeverHoldsMoreThanItWasGiven) {
  // Contacts dissipate and the gravity ramp only lowers g: at a stable step the grains' energy
  // stays below what the pour put in, up to the integrator's energy error. That error is at
  // most of the order of the energy stored in the contacts, F delta / 2 with delta ~ F / E: for
  // grains of 0.2 kg under a few grains' weight at E = 1e7 N/m, some 1e-5 of their fall of
  // 0.16 m. 1e-3 leaves a wide margin.
  for (Scheme scheme : {Scheme::verlet, Scheme::leapfrog, Scheme::gear5}) {
    DemScene scene = small_pile(scheme);
    scene.relax.enabled = true;
    scene.relax.ramp_time = 0.05;
    PileProtocol p(scene, "test");
    double worst = 0.0;
    while (!p.done()) {
      p.step();
      if (p.world().steps() % PileProtocol::check_interval == 0 && p.energy_fed_in() > 0.0)
        worst = std::max(worst, p.mechanical_energy() / p.energy_bound());
    }
    EXPECT_LE(worst, 1.0 + 1e-3) << scheme_name(scheme);
    // The first check comes while the first grain still falls alone, holding all the energy
    // fed in (the falling-grain test above), within the scheme's error on a free fall.
    EXPECT_GT(worst, 1.0 - 1e-3) << scheme_name(scheme);
  }
}

TEST(PileProtocolEnergy, TenTimesTheStabilityLimitStopsNamingTheTimeAndTheFastestGrain) {
  DemScene scene = small_pile(Scheme::verlet);
  PileProtocol stable(scene, "test");
  scene.time_step = 10.0 * stable.time_step_bound().stable_limit;
  scene.allow_unstable_time_step = true;
  PileProtocol p(scene, "test");
  try {
    while (!p.done()) p.step();
    FAIL() << "ten times the limit ran to the end";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    // No number overflows that soon: the energy check stops it, naming the fastest grain.
    EXPECT_NE(what.find("creates energy at t = "), std::string::npos) << what;
    EXPECT_NE(what.find("the fastest is a grain (body "), std::string::npos) << what;
  }
}

TEST(PileProtocolEnergy, LostGrainsTakeTheirEnergyOffTheBound) {
  // Without friction no slope holds and most grains slide off the plate and fall past the loss
  // height. Each takes away what it holds when removed, and the active grains' energy stays
  // below what is left (within the integrator's error, as above: the bound is not loosened by
  // the losses). What a lost grain takes is at least m g |y_lost| less its fall within one
  // check interval below the loss height: it left the plate's top (y >= 0) and fell freely.
  DemScene scene = small_pile(Scheme::verlet);
  scene.contact.friction_mu = 0.0;
  PileProtocol p(scene, "test");
  double worst = 0.0;
  while (!p.done()) {
    p.step();
    if (p.world().steps() % PileProtocol::check_interval == 0)
      worst = std::max(worst, p.mechanical_energy() / p.energy_bound());
  }
  ASSERT_GT(p.state().lost, 0) << "frictionless grains should run off the plate";
  EXPECT_LE(worst, 1.0 + 1e-3);
  double lost_mass = 0.0;
  for (int b = p.world().wall_count(); b < p.world().body_count(); ++b)
    if (!p.world().is_active(b) && b < p.world().wall_count() + p.state().poured) lost_mass += p.world().mass(b);
  const double g = p.scene().gravity, drop = -p.scene().container.lost_below;
  const double fastest = std::sqrt(2.0 * g * (p.scene().pour.funnel_height + drop)) + p.scene().pour.inflow_speed;
  const double overshoot = fastest * PileProtocol::check_interval * p.world().settings().time_step;
  EXPECT_GE(p.state().lost_energy, lost_mass * g * (drop - overshoot));
  EXPECT_NEAR(p.energy_fed_in() - p.energy_bound(), p.state().lost_energy, 1e-12 * p.energy_fed_in());
}

TEST(PileProtocolEnergy, AMovingFunnelPourStaysBelowTheBoundAndARestartKeepsIt) {
  // A funnel moving at u gives a grain at rest that bounces off it at most (2u)^2 / 2 per kg; the
  // bound counts that per poured grain. At u^2 far below the fall (here 4e-5 of g h) that term
  // is an estimate, not a bound, but the pour stays below the plain bound within the
  // integrator's error as a fixed funnel's does (1e-3, as above). A restart recomputes the bound
  // from the poured count and the grains' state, so it and the energy continue bit for bit.
  DemScene scene = small_pile(Scheme::verlet);
  scene.pour.funnel_speed = 0.005;
  scene.pour.funnel_travel = 0.03;
  PileProtocol p(scene, "test");
  for (int k = 0; k < 40 * PileProtocol::check_interval; ++k) p.step();
  ASSERT_GT(p.state().poured, 1);
  ASSERT_FALSE(p.done());
  const std::string path = ::testing::TempDir() + "pile_protocol_moving_funnel_checkpoint.h5";
  write_checkpoint(path, "scene", p, RunCounters{});
  PileProtocol restarted(scene, "test");
  RunCounters counters;
  read_checkpoint(path, "scene", restarted, counters);
  std::remove(path.c_str());
  std::remove((path.substr(0, path.size() - 3) + "_snapshots.h5").c_str());
  EXPECT_EQ(restarted.energy_fed_in(), p.energy_fed_in());
  EXPECT_EQ(restarted.energy_bound(), p.energy_bound());
  EXPECT_EQ(restarted.mechanical_energy(), p.mechanical_energy());
  double worst = 0.0;
  while (!restarted.done()) {
    restarted.step();
    if (restarted.world().steps() % PileProtocol::check_interval == 0)
      worst = std::max(worst, restarted.mechanical_energy() / restarted.energy_bound());
  }
  EXPECT_LE(worst, 1.0 + 1e-3);
}

TEST(PileProtocolStability, ThreeTimesTheLimitStopsNamingTheContactThatSwings) {
  // At three times the bound the stiffest contacts of the pile are above their own limit (the
  // pile's overlaps reach about 0.15 of the inner radius, whose limit is some 1.26 times the
  // bound's), yet the energy stays below the check's bound: contacts that swing at the period
  // of two steps until they open, which World::longest_swing sees (tests/dem/world_test.cpp)
  // and the protocol stops on. Measured on 16 seeds each: every run stops so, Verlet and leapfrog
  // (docs/studies/extremes.md).
  for (Scheme scheme : {Scheme::verlet, Scheme::leapfrog}) {
    DemScene scene = small_pile(scheme);
    PileProtocol stable(scene, "test");
    scene.time_step = 3.0 * stable.time_step_bound().stable_limit;
    scene.allow_unstable_time_step = true;
    PileProtocol p(scene, "test");
    try {
      while (!p.done()) p.step();
      ADD_FAILURE() << scheme_name(scheme) << ": three times the limit ran to the end";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("a contact oscillated with a period of two time steps, found at t = "), std::string::npos) << what;
      EXPECT_NE(what.find("(step "), std::string::npos) << what;
      EXPECT_NE(what.find("the overlap of a grain (body "), std::string::npos) << what;
      EXPECT_NE(what.find("is 3 times the stability limit"), std::string::npos) << what;
      EXPECT_GE(p.world().longest_swing().steps, PileProtocol::unstable_swing_steps) << what;
    }
  }
}

TEST(PilePour, ARainDepositsGrainsOnlyWithinItsWidth) {
  // A rain 0.1 m wide centred at x = 0.05: every grain enters with its centre within the width,
  // at the release height, falling at the inflow speed; over 300 grains the entry points spread
  // over the width (both outer tenths reached), and no funnel is built.
  DemScene scene = small_pile(Scheme::leapfrog);
  scene.grain_count = 300;
  scene.pour.kind = PourKind::rain;
  scene.pour.rain_width = 0.1;
  scene.pour.funnel_x = 0.05;
  scene.pour.funnel_walls = false;
  PileProtocol p(scene, "test");
  EXPECT_EQ(p.world().wall_count(), 1) << "the plate alone";
  int seen = 0;
  double lowest = INFINITY, highest = -INFINITY;
  while (seen < scene.grain_count && !p.done()) {
    p.step();
    const std::vector<int>& active = p.world().active_grains();
    for (; seen < p.state().poured; ++seen) {
      const int body = p.world().wall_count() + seen;  // grains enter in body order
      ASSERT_TRUE(std::find(active.begin(), active.end(), body) != active.end());
      // Its place one step after entering: the entry point moved by at most v dt + g dt^2.
      const Vec2 x = p.world().position(body);
      const double drift = (scene.pour.inflow_speed + 1.0) * p.world().settings().time_step;
      ASSERT_GE(x.x(), 0.0 - drift);
      ASSERT_LE(x.x(), 0.1 + drift);
      ASSERT_NEAR(x.y(), scene.pour.funnel_height, drift);
      lowest = std::min(lowest, x.x());
      highest = std::max(highest, x.x());
    }
  }
  EXPECT_EQ(seen, scene.grain_count);
  EXPECT_LT(lowest, 0.01);
  EXPECT_GT(highest, 0.09);
}

TEST(PileBase, AGrainBaseIsARowOfFixedGrainsStandingOnThePlate) {
  // base = "grains": fixed grains (walls whose lever counts) side by side across the plate, each
  // with its lowest point on the plate's top, none overlapping its neighbour, the row reaching to
  // within a grain of the plate's right end; the pour's grains are drawn as with a flat plate.
  DemScene scene = small_pile(Scheme::leapfrog);
  scene.container.base = BaseKind::grains;
  PileProtocol p(scene, "test");
  const World& w = p.world();
  const std::vector<int>& base = p.base_bodies();
  ASSERT_GT(base.size(), 30u);
  EXPECT_EQ(base.front(), 0);
  EXPECT_TRUE(w.is_flat_wall(0));
  double right_end = -INFINITY, previous_right = -INFINITY;
  for (std::size_t k = 1; k < base.size(); ++k) {
    const int b = base[k];
    ASSERT_TRUE(w.is_wall(b));
    EXPECT_FALSE(w.is_flat_wall(b));
    double lo_x = INFINITY, hi_x = -INFINITY, lo_y = INFINITY;
    for (int c = 0; c < w.corner_count(b); ++c) {
      lo_x = std::min(lo_x, w.corners(b)[c].x());
      hi_x = std::max(hi_x, w.corners(b)[c].x());
      lo_y = std::min(lo_y, w.corners(b)[c].y());
    }
    EXPECT_NEAR(lo_y, 0.0, 1e-12) << "base grain " << k;
    EXPECT_GT(lo_x, previous_right) << "base grain " << k << " overlaps its neighbour";
    previous_right = right_end = hi_x;
  }
  EXPECT_LE(right_end, 0.5 * scene.container.plate_width);
  EXPECT_GT(right_end, 0.5 * scene.container.plate_width - scene.grains.largest_diameter());
  // The same grains are poured as onto the flat plate.
  DemScene flat = small_pile(Scheme::leapfrog);
  PileProtocol q(flat, "test");
  const int first = w.wall_count(), first_flat = q.world().wall_count();
  for (int g = 0; g < scene.grain_count; ++g)
    EXPECT_EQ(w.shape(first + g).vertices, q.world().shape(first_flat + g).vertices) << "grain " << g;
}

TEST(PileBase, APileOnAGrainBaseLoadsItWithItsWeight) {
  // The load on the plate and the base's grains integrates to the weight within the settling
  // residual: the grains' forces on one another cancel, so load - weight = sum of m a, to
  // round-off, only if every contact with the base is counted.
  DemScene scene = small_pile(Scheme::leapfrog);
  scene.container.base = BaseKind::grains;
  PileProtocol p(scene, "test");
  while (!p.done()) p.step();
  const Snapshot& settled = p.snapshots().front();
  const PlateLoad load = plate_load(p.world(), settled, p.base_bodies(), -0.15, 0.3, 6.8e-3);
  double residual = 0.0;
  for (std::size_t i = 0; i < settled.grain_count(); ++i)
    residual += settled.contact_force[2 * i + 1] - p.world().mass(static_cast<int>(settled.body[i])) * settled.gravity;
  EXPECT_NEAR(load.total_force - load.weight, residual, 1e-10 * load.weight) << "a base contact was missed";
  double on_grains = 0.0;  // the base's grains, not the plate, carry the pile
  for (std::size_t c = 0; c < settled.contact_count_total(); ++c)
    if (settled.pair[2 * c] > 0 && std::binary_search(p.base_bodies().begin(), p.base_bodies().end(),
                                                      static_cast<int>(settled.pair[2 * c])))
      on_grains += settled.force[2 * c + 1];
  EXPECT_GT(on_grains, 0.9 * load.total_force);
}

}  // namespace
}  // namespace pilelab::dem
