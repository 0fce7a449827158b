// The world step: the broad phase finds every touching pair, results do not depend on the
// number of threads, and free flight is exact.
#include <array>
#include <cmath>
#include <cstring>
#include <set>

#include <gtest/gtest.h>
#include <omp.h>

#include "common/rng.h"
#include "dem/convex_overlap.h"
#include "dem/grain_generator.h"
#include "dem/time_step.h"
#include "dem/world.h"

using namespace pilelab;
using namespace pilelab::dem;

namespace {
// A dense random heap of grains of very different sizes over a plate, overlapping a little.
World random_heap(int grains, std::uint64_t seed, Vec2 gravity, double skin_fraction = 0.3, double speed = 0.1,
                  double lookahead_steps = 100.0, bool skip_separated_pairs = true, bool order_bodies_by_place = true) {
  WorldSettings s;
  s.skip_separated_pairs = skip_separated_pairs;
  s.order_bodies_by_place = order_bodies_by_place;
  s.scheme = Scheme::verlet;
  s.gravity = gravity;
  s.neighbour_skin_fraction = skin_fraction;
  s.neighbour_lookahead_steps = lookahead_steps;
  Rng rng(seed);
  std::vector<Shape> shapes;
  GrainSpec spec;
  spec.polydispersity = 0.45;
  for (int i = 0; i < grains; ++i) {
    spec.kind = (i % 7 == 0) ? ShapeKind::disc : ShapeKind::polygon;
    spec.mean_diameter = (i % 50 == 0) ? 0.03 : 0.0068;  // a few grains four times larger
    shapes.push_back(random_grain(spec, rng));
  }
  s.time_step = 0.5 * stable_time_step(shapes, 5000.0, s.contact, s.scheme).stable_limit;
  World w(s);
  w.add_wall(make_polygon({{-0.3, -0.01}, {0.3, -0.01}, {0.3, 0.0}, {-0.3, 0.0}}), {0, -0.005}, 0.0);  // top at y = 0
  const int per_row = static_cast<int>(std::sqrt(grains)) + 1;
  for (int i = 0; i < grains; ++i) {
    const int id = w.add_grain(shapes[i], 5000.0);
    const Vec2 p(-0.2 + 0.4 * (i % per_row) / per_row + rng.uniform(-0.002, 0.002),
                 0.003 + 0.006 * (i / per_row) + rng.uniform(-0.002, 0.002));
    w.activate(id, p, rng.uniform(0.0, 2 * M_PI), {rng.uniform(-speed, speed), rng.uniform(-speed, speed)}, 0.0);
  }
  return w;
}

Overlap brute_force_overlap(const World& w, int a, int b) {
  const Shape& sa = w.shape(a);
  const Shape& sb = w.shape(b);
  if (sa.kind == ShapeKind::disc && sb.kind == ShapeKind::disc)
    return overlap_discs(w.position(a), sa.radius, w.position(b), sb.radius);
  if (sa.kind == ShapeKind::disc)
    return overlap_disc_polygon(w.position(a), sa.radius, w.corners(b), w.corner_count(b), w.position(b));
  if (sb.kind == ShapeKind::disc)
    return overlap_disc_polygon(w.position(b), sb.radius, w.corners(a), w.corner_count(a), w.position(a));
  return overlap_polygons(w.corners(a), w.corner_count(a), w.position(a), w.corners(b), w.corner_count(b), w.position(b));
}
}  // namespace

TEST(World, BroadPhaseNeverMissesATouchingPair) {
  World w = random_heap(600, 11, {0, 0});
  w.step();  // contacts are found at the predicted positions, which corners() shows
  std::set<std::pair<int, int>> found;
  for (const Contact& c : w.contacts()) found.insert({c.a, c.b});
  std::set<std::pair<int, int>> expected;
  for (int a = 0; a < w.body_count(); ++a)
    for (int b = std::max(a + 1, w.wall_count()); b < w.body_count(); ++b)
      if (brute_force_overlap(w, a, b).touching()) expected.insert({a, b});
  EXPECT_GT(expected.size(), 300u);  // the heap really is dense
  EXPECT_EQ(found, expected);
}

std::set<std::pair<int, int>> touching_pairs(const World& w) {
  std::set<std::pair<int, int>> found;
  for (const Contact& c : w.contacts()) found.insert({c.a, c.b});
  return found;
}

std::set<std::pair<int, int>> brute_force_touching_pairs(const World& w) {
  std::set<std::pair<int, int>> expected;
  for (int a = 0; a < w.body_count(); ++a)
    for (int b = std::max(a + 1, w.wall_count()); b < w.body_count(); ++b)
      if (brute_force_overlap(w, a, b).touching()) expected.insert({a, b});
  return expected;
}

TEST(World, VerletListNeverMissesATouchingPairAsItAges) {
  // Fast grains (the heap's initial overlaps blow it apart at metres per second): the list is
  // reused for several steps between rebuilds, and every step must still find exactly the
  // touching pairs an O(N^2) search finds. A long lookahead gives the fast grains margins
  // several grain sizes wide, which the list searches for apart from the rest.
  for (double lookahead : {0.0, 100.0, 3000.0}) {
    SCOPED_TRACE("lookahead " + std::to_string(lookahead));
    World w = random_heap(250, 17, {0, -9.81}, 0.3, 1.0, lookahead);
    for (int k = 0; k < 300; ++k) {
      w.step();
      ASSERT_EQ(touching_pairs(w), brute_force_touching_pairs(w)) << "step " << k;
    }
    EXPECT_GT(w.neighbour_builds(), 2);    // the grains did cross their margins...
    EXPECT_LT(w.neighbour_builds(), 150);  // ...and the list was reused in between
  }
}

TEST(World, ResultsDoNotDependOnTheSkin) {
  // The skin and the lookahead only decide how often the list is rebuilt: the candidates,
  // hence the motion, are the same bit for bit (skin and lookahead 0 rebuild every step, like
  // a search without a list).
  auto run = [](double skin, double lookahead) {
    World w = random_heap(300, 23, {0, -9.81}, skin, 1.0, lookahead);
    for (int k = 0; k < 200; ++k) w.step();
    return w.motion().d;
  };
  const auto none = run(0.0, 0.0);
  for (const auto& [skin, lookahead] : {std::pair{0.05, 0.0}, std::pair{1.0, 0.0}, std::pair{0.3, 100.0},
                                        std::pair{0.3, 3000.0}, std::pair{0.0, 500.0}}) {
    const auto other = run(skin, lookahead);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(none[k], other[k]) << "skin " << skin << " lookahead " << lookahead << " derivative " << k;
  }
}

TEST(World, SkippingPairsProvenApartChangesNothing) {
  // A polygon pair whose gap exceeds how far its grains have moved since the gap was measured
  // is skipped: the motion must be the same bit for bit as when every pair is tested, in a heap
  // that falls, bounces and settles (grains moving fast and slow, contacts made and broken),
  // for every scheme. A wide skin keeps each list, and so each proof's reference places, for
  // long, so that the grains' displacements at the proof matter to the bound.
  for (const Scheme scheme : {Scheme::gear5, Scheme::verlet, Scheme::leapfrog}) {
    auto run = [scheme](bool skip, std::size_t* skipped) {
      World w = random_heap(300, 29, {0, -9.81}, 1.0, 1.0, 100.0, skip);
      w.set_time_integration(scheme, w.settings().time_step);
      for (int k = 0; k < 600; ++k) {
        w.step();
        if (skipped) *skipped += w.proven_apart_count();
      }
      return w.motion().d;
    };
    std::size_t skipped = 0;
    const auto every_pair = run(false, nullptr), skipping = run(true, &skipped);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(every_pair[k], skipping[k]) << scheme_name(scheme) << ", derivative " << k;
    EXPECT_GT(skipped, 1000u) << "the test must skip pairs to mean anything";
  }
}

TEST(World, TheOrderOfBodiesInMemoryChangesNothing) {
  // The world stores its bodies in the order of their place, renewed every 2000 steps, with the
  // pair list and its spring history moved along. A heap poured row by row (its body order far
  // from a Z curve) falls and lands past two renewals, and is put back into body
  // order once in between (as a checkpoint's reader does, through motion()): the state, the
  // contacts and their forces, each body's sum of forces and the deepest overlap must be those
  // of a world that keeps body order, bit for bit, for every scheme.
  const auto same_bits = [](const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
  };
  for (const Scheme scheme : {Scheme::gear5, Scheme::verlet, Scheme::leapfrog}) {
    std::vector<double> contact_values[2], body_sums[2];
    std::array<std::vector<double>, 6> state[2];
    DeepestOverlap deepest[2];
    for (const bool ordered : {false, true}) {
      World w = random_heap(300, 31, {0, -200.0}, 0.3, 0.1, 100.0, true, ordered);  // falls in 20 ms
      w.set_time_integration(scheme, w.settings().time_step);
      int moved = 0;  // bodies away from their own slot, at steps 2500 and 4500
      for (int k = 0; k < 4500; ++k) {
        w.step();
        if (k == 3000) w.motion();
        if (k == 2500 || k == 4499)
          for (int i = 0; i < w.body_count(); ++i) moved += w.slot(i) != i;
      }
      if (ordered) {
        EXPECT_GT(moved, 2 * 200) << "most bodies must have been moved, twice";
      }
      for (const Contact& c : w.contacts())
        contact_values[ordered].insert(contact_values[ordered].end(),
                                       {double(c.a), double(c.b), c.spring, c.point.x(), c.point.y(), c.normal.x(),
                                        c.normal.y(), c.normal_force, c.tangential_force, c.area, c.chord});
      for (int i = 0; i < w.body_count(); ++i)
        body_sums[ordered].insert(body_sums[ordered].end(), {w.contact_force(i).x(), w.contact_force(i).y(), w.contact_torque(i)});
      state[ordered] = w.motion_state().d;
      deepest[ordered] = w.deepest_overlap();
    }
    SCOPED_TRACE(scheme_name(scheme));
    EXPECT_GT(contact_values[0].size(), 11u * 100u) << "the heap must land: a hundred contacts";
    EXPECT_TRUE(same_bits(contact_values[0], contact_values[1]));
    EXPECT_TRUE(same_bits(body_sums[0], body_sums[1]));
    for (int k = 0; k < 6; ++k) EXPECT_TRUE(same_bits(state[0][k], state[1][k])) << "derivative " << k;
    EXPECT_EQ(deepest[0].fraction, deepest[1].fraction);
    EXPECT_EQ(deepest[0].time, deepest[1].time);
    EXPECT_EQ(deepest[0].a, deepest[1].a);
    EXPECT_EQ(deepest[0].b, deepest[1].b);
  }
}

TEST(World, APairProvenApartCountsTheMotionBeforeTheProof) {
  // The bound behind the skip: between the proof and now, a body's corners moved at most its
  // displacement from the list's places at both times. Here a wall backs away from a grain (its
  // displacement grows while the pair is proven apart at ever larger gaps), turns, and comes
  // back past where it was listed to push the grain: a bound that forgot the displacement at
  // the proof would still skip the pair when the wall arrives. The grain must be pushed exactly
  // as when every pair is tested.
  const double half = 0.005, gap = 1e-4, speed = 0.05;  // [m], [m], [m/s]
  const Shape square = make_polygon({{-half, -half}, {half, -half}, {half, half}, {-half, half}});
  auto run = [&](bool skip, std::size_t* skipped) {
    WorldSettings s;
    s.scheme = Scheme::verlet;
    s.gravity = {0, 0};
    s.neighbour_skin_fraction = 10.0;  // lists that outlive the wall's round trip
    s.skip_separated_pairs = skip;
    s.time_step = 0.5 * stable_time_step({square}, 2600.0, s.contact, s.scheme).stable_limit;
    World w(s);
    const int wall = w.add_wall(square, {-2 * half - gap, 0}, 0.0, {-speed, 0});
    const int grain = w.add_grain(square, 2600.0);
    w.activate(grain, {0, 0}, 0.0, {0, 0}, 0.0);
    // Away until the wall's face is 1.5 mm off (its circle-box test still lists the grain as a
    // candidate), back until well past the grain's face.
    const int away = static_cast<int>(1.4e-3 / speed / s.time_step), back = 2 * away;
    for (int k = 0; k < away + back; ++k) {
      if (k == away) w.set_wall_velocity(wall, {speed, 0});
      w.step();
      if (skipped) *skipped += w.proven_apart_count();
    }
    EXPECT_GT(w.velocity(grain).x(), 0.0) << "the wall must reach and push the grain";
    return w.motion().d;
  };
  std::size_t skipped = 0;
  const auto every_pair = run(false, nullptr), skipping = run(true, &skipped);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(every_pair[k], skipping[k]) << "derivative " << k;
  EXPECT_GT(skipped, 100u) << "the pair must be skipped on the way";
}

TEST(World, ResultsDoNotDependOnTheThreadCount) {
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    World w = random_heap(400, 5, {0, -9.81});  // above the size where the loops go parallel
    for (int k = 0; k < 100; ++k) w.step();
    return w.motion().d;
  };
  // Three threads cut the grains and the pairs at other places than two, and the cuts follow
  // the rates at which the threads got through their parts (WorkShares), which wander.
  const auto one = run(1), two = run(2), three = run(3);
  omp_set_num_threads(2);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(one[k], two[k]) << "derivative " << k;
    EXPECT_EQ(one[k], three[k]) << "derivative " << k;
  }
}

TEST(World, FreeFlightIsExactForEveryScheme) {
  // Constant acceleration: every scheme integrates a parabola exactly (up to round-off).
  for (Scheme scheme : {Scheme::gear5, Scheme::verlet, Scheme::leapfrog}) {
    WorldSettings s;
    s.scheme = scheme;
    s.time_step = 1e-4;
    World w(s);
    const int g = w.add_grain(make_disc(0.003), 5000.0);
    const Vec2 p0(0.0, 1.0), v0(0.3, 0.5);
    w.activate(g, p0, 0.0, v0, 2.0);
    for (int k = 0; k < 5000; ++k) w.step();
    const double t = w.time();
    const Vec2 exact = p0 + v0 * t + 0.5 * s.gravity * t * t;
    EXPECT_NEAR((w.position(g) - exact).norm(), 0.0, 1e-12) << scheme_name(scheme);
    EXPECT_NEAR(w.angle(g), 2.0 * t, 1e-12) << scheme_name(scheme);
  }
}

TEST(World, TheFirstNonFiniteGrainIsFound) {
  // Three free grains, the second and third given a NaN and an infinite velocity: both are not
  // finite, and the lowest body index is reported. Without them, none is.
  WorldSettings s;
  s.time_step = 1e-4;
  World w(s);
  std::vector<int> g;
  for (int k = 0; k < 3; ++k) g.push_back(w.add_grain(make_disc(0.003), 5000.0));
  w.activate(g[0], {0.0, 1.0}, 0.0, {0.1, 0.0}, 0.0);
  EXPECT_EQ(w.first_non_finite_grain(), -1);
  w.activate(g[2], {0.1, 1.0}, 0.0, {INFINITY, 0.0}, 0.0);
  w.activate(g[1], {0.2, 1.0}, 0.0, {0.0, NAN}, 0.0);
  EXPECT_EQ(w.first_non_finite_grain(), g[1]);
  // The step stops before its neighbour list is built over them, naming the body and the step.
  try {
    w.step();
    ADD_FAILURE() << "a step over a NaN state went on";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("body " + std::to_string(g[1]) + " "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(step 0)"), std::string::npos) << e.what();
  }
  w.deactivate(g[1]);
  EXPECT_EQ(w.first_non_finite_grain(), g[2]);
}

TEST(World, DeactivatedGrainLosesItsContacts) {
  World w = random_heap(200, 3, {0, 0});
  w.step();
  ASSERT_FALSE(w.contacts().empty());
  const int gone = w.contacts().front().b;
  w.deactivate(gone);
  for (const Contact& c : w.contacts()) EXPECT_TRUE(c.a != gone && c.b != gone);
  w.step();
  for (const Contact& c : w.contacts()) EXPECT_TRUE(c.a != gone && c.b != gone);
}

TEST(World, RecordsTheDeepestOverlap) {
  // Two squares of side s face to face, overlapping by d: the overlap is an s x d rectangle, so
  // 2 A / chord = 2 d, and the inner radius is s/2: the record is 4 d / s. It keeps the deepest
  // value, with when and where it occurred, as the squares separate.
  const double s = 0.004, d = 1e-4;
  WorldSettings settings;
  settings.scheme = Scheme::verlet;
  settings.gravity = {0, 0};
  settings.time_step = 1e-9;  // the squares barely move in one step
  World w(settings);
  const Shape square = make_polygon({{0, 0}, {s, 0}, {s, s}, {0, s}});
  const int a = w.add_grain(square, 5000.0), b = w.add_grain(square, 5000.0);
  w.activate(a, {0, 0}, 0.0, {0, 0}, 0.0);
  w.activate(b, {s - d, 0}, 0.0, {0, 0}, 0.0);
  EXPECT_EQ(w.deepest_overlap().fraction, 0.0);
  w.step();
  ASSERT_EQ(w.contacts().size(), 1u);
  const DeepestOverlap first = w.deepest_overlap();
  EXPECT_NEAR(first.fraction, 4.0 * d / s, 1e-6 * 4.0 * d / s);
  EXPECT_EQ(first.time, settings.time_step);  // the end of the first step
  EXPECT_EQ(first.a, a);
  EXPECT_EQ(first.b, b);
  // The force point is the middle of the s x d overlap, which lies at x = s/2 - d/2.
  EXPECT_NEAR(first.point.x(), 0.5 * (s - d), 1e-6 * d);
  EXPECT_NEAR(first.point.y(), 0.0, 1e-6 * d);
  for (int k = 0; k < 1000; ++k) w.step();  // pushed apart: shallower
  EXPECT_EQ(w.deepest_overlap().fraction, first.fraction);
  EXPECT_EQ(w.deepest_overlap().time, first.time);
}

// A square resting on the plate, undamped and frictionless: the overlap is an s x d rectangle
// with its force point at its middle, so R = E s d / (s/2 - d/2), a linear spring of stiffness
// k = 2 E s^2 / (s - d)^2 about the depth d_eq = m g / k where it carries the weight (d << s).
// Started 1e-5 of d_eq below that depth it oscillates at omega = sqrt(k / m).
// Above the limit the explicit step amplifies the oscillation through an eigenvalue below -1:
// the depth swings deeper and shallower in turn, step after step, until the square hops off.
// Verlet and leapfrog at omega dt = 2.02 (just above their limit 2): lambda^2 + 2.0804 lambda + 1
// = 0, |lambda| = 1.33 a step, about 40 steps from 1e-5 of the depth to lifting off, all of them
// reversals. Gear-5 at omega dt = 1
// (its map grows by 1.3 a step there; integrator.cpp): about 44.
// Below the limit the phase advances theta < pi a step (Verlet and leapfrog: cos theta =
// 1 - (omega dt)^2 / 2; Gear-5, accurate there: theta = omega dt), and a run of m reversals needs
// m theta >= (m - 1) pi: at most pi / (pi - theta) in a row. (Between its bound 0.31 and about
// 0.8, Gear-5 grows too slowly to show, 1 + 2e-5 a step at 0.4, and not at the period of two
// steps: the swing does not see that range, which the time step's bound excludes.)
TEST(World, AContactAboveItsStabilityLimitSwingsWithAPeriodOfTwoSteps) {
  struct Case {
    Scheme scheme;
    double omega_dt;
    bool stable;
  };
  for (const Case c : {Case{Scheme::verlet, 1.8, true}, Case{Scheme::verlet, 2.02, false}, Case{Scheme::leapfrog, 1.8, true},
                       Case{Scheme::leapfrog, 2.02, false}, Case{Scheme::gear5, 0.9 * stability_limit_omega_dt(Scheme::gear5), true},
                       Case{Scheme::gear5, 1.0, false}}) {
    const double s = 0.004, E = 1e7, g = 9.81;
    WorldSettings settings;
    settings.scheme = c.scheme;
    settings.gravity = {0, -g};
    settings.contact.youngs_modulus = E;
    settings.contact.damping_gamma = 0.0;
    settings.contact.friction_mu = 0.0;
    World probe(settings);
    const Shape square = make_polygon({{0, 0}, {s, 0}, {s, s}, {0, s}});
    const double m = probe.mass(probe.add_grain(square, 5000.0));
    double depth = 0.0, k = 2.0 * E;
    for (int pass = 0; pass < 3; ++pass) {  // d_eq and k(d_eq), each from the other
      depth = m * g / k;
      k = 2.0 * E * s * s / ((s - depth) * (s - depth));
    }
    const double omega = std::sqrt(k / m);
    settings.time_step = c.omega_dt / omega;
    World w(settings);
    w.add_wall(make_polygon({{-0.05, -0.01}, {0.05, -0.01}, {0.05, 0.0}, {-0.05, 0.0}}), {0, -0.005}, 0.0);  // top at y = 0
    const int grain = w.add_grain(square, 5000.0);
    w.activate(grain, {0.0, 0.5 * s - depth * (1.0 + 1e-5)}, 0.0, {0, 0}, 0.0);
    w.motion().d[2][3 * grain + 1] = 0.0;  // at rest in balance, not in free fall (activate's start)
    for (int step = 0; step < 400; ++step) w.step();
    const SwingingContact& swing = w.longest_swing();
    const std::string label = std::string(scheme_name(c.scheme)) + " at omega dt = " + std::to_string(c.omega_dt);
    if (c.stable) {
      const double theta = c.scheme == Scheme::gear5 ? c.omega_dt : std::acos(1.0 - 0.5 * c.omega_dt * c.omega_dt);
      EXPECT_LE(swing.steps, static_cast<int>(M_PI / (M_PI - theta))) << label;
      EXPECT_EQ(w.contact_count(), 1u) << label << ": a stable contact holds the square";
    } else {
      EXPECT_GE(swing.steps, 16) << label;  // PileProtocol::unstable_swing_steps
      EXPECT_EQ(swing.a, 0) << label;       // the plate
      EXPECT_EQ(swing.b, grain) << label;
      EXPECT_NEAR(swing.point.x(), 0.0, 1e-9) << label;
      EXPECT_GT(swing.time, 0.0) << label;
    }
  }
}

TEST(World, TangentialSpringTurnsWithTheContactAndStartsAfreshAfterAJump) {
  // A disc grain against a fixed disc wall: the normal is the line of centres, so carrying the
  // grain around the wall by phi turns the normal by exactly phi. At rest (no slip, so no
  // stretch and no viscous term) the next step keeps the old spring projected on the new
  // tangent, s cos(phi); a turn of more than 60 degrees in one step is a jump to another
  // contact, which starts with no spring.
  for (double phi : {0.0, 0.3, -1.0, 1.1}) {  // 1.1 rad = 63 degrees
    WorldSettings s;
    s.scheme = Scheme::verlet;
    s.gravity = {0, 0};
    s.contact.friction_mu = 1.0;
    s.contact.damping_gamma = 0.0;
    s.time_step = 1e-6;
    World world(s);
    const double R = 0.01, r = 0.004, distance = R + r - 1e-5;
    world.add_wall(make_disc(R), {0, 0}, 0.0);
    const int g = world.add_grain(make_disc(r), 5000.0);
    world.activate(g, {0, distance}, 0.0, {0, 0}, 0.0);
    world.step();
    ASSERT_EQ(world.contacts().size(), 1u);
    const double s0 = 0.2 * world.contacts()[0].normal_force;  // well inside the Coulomb cap
    std::vector<Contact> contacts = world.contacts();
    contacts[0].spring = s0;
    world.restore_contacts(contacts);
    MotionState& m = world.motion();
    for (int k = 1; k < 6; ++k)
      for (int c = 0; c < 3; ++c) m.d[k][3 * g + c] = 0.0;
    m.d[0][3 * g] = -distance * std::sin(phi);
    m.d[0][3 * g + 1] = distance * std::cos(phi);
    world.step();
    ASSERT_EQ(world.contacts().size(), 1u);
    const Contact& c = world.contacts()[0];
    EXPECT_NEAR(c.normal.x(), -std::sin(phi), 1e-12);
    const double expected = std::abs(phi) < M_PI / 3 ? s0 * std::cos(phi) : 0.0;
    EXPECT_NEAR(c.spring, expected, 1e-12 * s0) << "phi " << phi;
    EXPECT_NEAR(c.tangential_force, expected, 1e-12 * s0) << "phi " << phi;
  }
}

TEST(World, AFixedGrainsLeverCountsInTheContactLengthAFlatWallsDoesNot) {
  // A square grain pressed into a square held below it, face on: the normal force is E A / l with
  // l = r_a r_b / (r_a + r_b) for a fixed grain (both levers, as between two grains), and l = r_b
  // for a flat wall (its lever infinite), r the distances from the centroids to the force point.
  const double s = 0.004, E = 1e7, depth = 1e-5;
  const Shape square = make_polygon({{0, 0}, {s, 0}, {s, s}, {0, s}});
  for (bool fixed_grain : {true, false}) {
    WorldSettings settings;
    settings.scheme = Scheme::verlet;
    settings.gravity = {0, 0};
    settings.contact.youngs_modulus = E;
    settings.contact.damping_gamma = 0.0;
    settings.contact.friction_mu = 0.0;
    settings.time_step = 1e-9;
    World w(settings);
    const int below = fixed_grain ? w.add_fixed_grain(square, {0, 0}, 0.0) : w.add_wall(square, {0, 0}, 0.0);
    EXPECT_EQ(w.is_flat_wall(below), !fixed_grain);
    const int grain = w.add_grain(square, 5000.0);
    w.activate(grain, {0.0005, s - depth}, 0.0, {0, 0}, 0.0);
    w.step();
    ASSERT_EQ(w.contacts().size(), 1u);
    const Contact& c = w.contacts()[0];
    const double r_a = (c.point - w.position(below)).norm(), r_b = (c.point - w.position(grain)).norm();
    const double l = fixed_grain ? r_a * r_b / (r_a + r_b) : r_b;
    EXPECT_NEAR(c.normal_force, E * c.area / l, 1e-9 * E * c.area / l) << (fixed_grain ? "fixed grain" : "flat wall");
    EXPECT_EQ(w.velocity(below), Vec2(0, 0)) << "held in place";
  }
}
