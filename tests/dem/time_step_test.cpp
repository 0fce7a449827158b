// The stable time step: its closed form where every term is known, the heaviest chord against a
// brute-force search over all chords, and the tangential spring's limits against the contact law
// itself integrated by each scheme.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "dem/contact_law.h"
#include "dem/time_step.h"

using namespace pilelab::dem;

namespace {
// omega = sqrt(2 E w / l), zeta = (gamma/2) sqrt(w m / l), limit = L(scheme, zeta) / omega.
double expected_normal_limit(Scheme scheme, const ContactParameters& c, double weight, double l, double m) {
  const double omega = std::sqrt(2.0 * c.youngs_modulus * weight / l);
  const double zeta = 0.5 * c.damping_gamma * std::sqrt(weight * m / l);
  return stability_limit_omega_dt(scheme, zeta) / omega;
}

// The heaviest chord by brute force: both ends anywhere on the boundary (n points per edge), the
// part cut off no deeper than max_depth; with count_levers, times r_in / lever (lever the
// midpoint's distance from the centroid, clamped to [r_in/2, r_in]).
double brute_force_heaviest_chord(const Shape& s, double m, double inertia, double max_depth, int per_edge,
                                  bool count_levers = false) {
  std::vector<Vec2> boundary;
  std::vector<int> edge_of;
  const int n = static_cast<int>(s.vertices.size());
  for (int e = 0; e < n; ++e)
    for (int k = 0; k < per_edge; ++k) {
      boundary.push_back(s.vertices[e] + (double(k) / per_edge) * (s.vertices[(e + 1) % n] - s.vertices[e]));
      edge_of.push_back(e);
    }
  double best = 0.0;
  const int total = static_cast<int>(boundary.size());
  for (int a = 0; a < total; ++a)
    for (int b = 0; b < total; ++b) {
      if (b == a) continue;
      const Vec2 p = boundary[a], q = boundary[b];
      const double c = (q - p).norm();
      if (!(c > 0.0)) continue;
      const Vec2 t = (q - p) / c;
      // Corners passed going counter-clockwise from p to q are cut off; they lie right of p -> q.
      const int last = edge_of[b] + (b < a ? n : 0);
      double depth = 0.0;
      for (int e = edge_of[a] + 1; e <= last; ++e) depth = std::max(depth, cross(s.vertices[e % n] - p, t));
      if (depth > max_depth) continue;
      const double arm = t.dot(0.5 * (p + q));
      const double r = s.inner_radius, lever = std::clamp((0.5 * (p + q)).norm(), 0.5 * r, r);
      best = std::max(best, c * (1.0 / m + arm * arm / inertia) * (count_levers ? r / lever : 1.0));
    }
  return best;
}
}  // namespace

namespace {
// The deepest contact the default bound admits on a disc of radius r: cut a quarter of r deep,
// chord 2 r sqrt(1/4 (2 - 1/4)) = r sqrt(7)/2 through the centre's line (arm 0), lever 3r/4.
struct DiscDeepestContact {
  double chord, lever;
};
DiscDeepestContact disc_deepest_contact(double r) {
  EXPECT_EQ(max_overlap_depth_fraction, 0.25);
  return {0.5 * std::sqrt(7.0) * r, 0.75 * r};
}
}  // namespace

TEST(TimeStep, DiscMatchesTheClosedForm) {
  // A disc: the chord of its deepest admitted contact, with l from both levers (paper: l = lever/2).
  const double r = 0.003, rho = 5000.0, m = rho * M_PI * r * r;
  const DiscDeepestContact d = disc_deepest_contact(r);
  for (Scheme scheme : {Scheme::gear5, Scheme::verlet, Scheme::leapfrog}) {
    ContactParameters c;
    const double expected = expected_normal_limit(scheme, c, d.chord / m, contact_length(c, d.lever, d.lever), m);
    EXPECT_NEAR(stable_time_step({make_disc(r)}, rho, c, scheme).stable_limit, expected, 1e-12 * expected)
        << scheme_name(scheme);
  }
}

TEST(TimeStep, ADeepContactOnADiscHasItsChordAndLever) {
  // A disc cut f r deep has the chord 2 r sqrt(f (2 - f)) through its centre's line and acts at
  // the lever r (1 - f), floored at r/2 as the contact law floors levers: l = lever / 2.
  const double r = 0.003, rho = 5000.0, m = rho * M_PI * r * r;
  for (Scheme scheme : {Scheme::gear5, Scheme::verlet, Scheme::leapfrog})
    for (double f : {0.1, 0.25, 0.4, 0.8}) {
      ContactParameters c;
      c.friction_mu = 0.0;  // the normal mode alone
      const double chord = 2.0 * r * std::sqrt(f * (2.0 - f)), lever = std::max(1.0 - f, 0.5) * r;
      const double expected = expected_normal_limit(scheme, c, chord / m, contact_length(c, lever, lever), m);
      EXPECT_NEAR(stable_time_step_at_depth({make_disc(r)}, rho, c, scheme, f).stable_limit, expected, 1e-12 * expected)
          << scheme_name(scheme) << ", depth " << f;
    }
  // A disc barely touched has no chord, so no stiffness: without friction nothing limits the step,
  // and the bound says so with infinity, not NaN.
  ContactParameters frictionless;
  frictionless.friction_mu = 0.0;
  EXPECT_EQ(stable_time_step_at_depth({make_disc(r)}, rho, frictionless, Scheme::leapfrog, 0.0).stable_limit, INFINITY);
}

TEST(TimeStep, DeeperContactsAreStableOnlyAtSmallerSteps) {
  // Each chord counted at its own lever, against the brute-force search: a chord across corners
  // may pass nearer the centroid than the inner radius, which shortens l. Undamped and
  // frictionless, the limit is L / omega with omega^2 = 2 E w / l, so the bound at depth f is
  // the default bound (depth 0.25, levers counted) times sqrt(w(0.25) / w(f)) exactly. With the
  // paper's damping and friction, deeper contacts never allow a larger step.
  const Shape s = make_polygon({{0.004, 0.0}, {0.002, 0.003}, {-0.003, 0.0025}, {-0.004, -0.001}, {0.0, -0.003}});
  const double rho = 5000.0, m = rho * s.area, inertia = rho * s.polar_moment;
  ContactParameters plain;
  plain.damping_gamma = 0.0;
  plain.friction_mu = 0.0;
  const double base = stable_time_step({s}, rho, plain, Scheme::verlet).stable_limit;
  const double w_assumed = heaviest_chord(s, m, inertia, max_overlap_depth_fraction * s.inner_radius, true).weight;
  EXPECT_GT(w_assumed, heaviest_chord(s, m, inertia, max_overlap_depth_fraction * s.inner_radius).weight)
      << "this grain's heaviest admitted chord passes nearer the centroid than its inner radius";
  for (double f : {0.0, 0.1, 0.25, 0.4, 0.7}) {
    const double depth = f * s.inner_radius;
    const double w = heaviest_chord(s, m, inertia, depth, true).weight;
    EXPECT_GE(w, heaviest_chord(s, m, inertia, depth).weight) << "a lever below r_in only stiffens, depth " << f;
    const double brute = brute_force_heaviest_chord(s, m, inertia, depth, 1600, true);
    EXPECT_NEAR(w, brute, 2e-3 * brute) << "depth " << f;
    const double expected = base * std::sqrt(w_assumed / w);
    EXPECT_NEAR(stable_time_step_at_depth({s}, rho, plain, Scheme::verlet, f).stable_limit, expected, 1e-12 * base)
        << "depth " << f;
  }
  for (Scheme scheme : {Scheme::gear5, Scheme::verlet, Scheme::leapfrog}) {
    ContactParameters paper;
    double previous = stable_time_step_at_depth({s}, rho, paper, scheme, 0.0).stable_limit;
    for (double f : {0.1, 0.25, 0.4, 0.7, 1.0}) {
      const double limit = stable_time_step_at_depth({s}, rho, paper, scheme, f).stable_limit;
      EXPECT_LE(limit, previous) << scheme_name(scheme) << ", depth " << f;
      previous = limit;
    }
  }
}

TEST(TimeStep, ChordsAlongASquaresEdgeAreHeaviestAtTheMiddle) {
  // Along an edge of a square of side s (I = m s^2 / 6) the weight of a chord with midpoint at
  // distance t s from the edge's middle is s (1 - 2t)(1 + 6 t^2) / m, which only falls with t:
  // the whole edge at arm 0. Counting the whole edge at the arm of its end, s/2, would give
  // 2.5 s / m.
  const double s = 0.004, rho = 5000.0, m = rho * s * s, inertia = m * s * s / 6.0;
  const HeaviestChord h = heaviest_chord(make_polygon({{0, 0}, {s, 0}, {s, s}, {0, s}}), m, inertia, 0.0);
  EXPECT_NEAR(h.chord, s, 1e-15);
  EXPECT_NEAR(h.arm, 0.0, 1e-15);
  EXPECT_NEAR(h.weight, s / m, 1e-12 * s / m);
}

TEST(TimeStep, ChordsAlongALongEdgeTradeLengthForArm) {
  // The triangle (0,0), (10,0), (3,1): m = 5 (unit density), I/m = (100 + 50 + 10)/36 = 40/9,
  // centroid (13/3, 1/3). Along the base the chords end between s_p = -13/3 and s_q = 17/3 of
  // the centroid's foot, and beyond the middle the weight 2 (s_q - s)(1/m + s^2/I) peaks where
  // 6 s^2 - 4 s_q s + 2 I/m = 0, at s = 10/3: chord 14/3, weight 14/3 (1/5 + 1/2) = 49/15, just
  // above the best chord on the other long edge.
  const Shape triangle = make_polygon({{0, 0}, {10, 0}, {3, 1}});
  const double m = triangle.area, inertia = triangle.polar_moment;
  ASSERT_NEAR(m, 5.0, 1e-12);
  ASSERT_NEAR(inertia / m, 40.0 / 9.0, 1e-12);
  const HeaviestChord h = heaviest_chord(triangle, m, inertia, 0.0);
  EXPECT_NEAR(h.arm, 10.0 / 3.0, 1e-12);
  EXPECT_NEAR(h.chord, 14.0 / 3.0, 1e-12);
  EXPECT_NEAR(h.weight, 49.0 / 15.0, 1e-12);
}

TEST(TimeStep, HeaviestChordAgreesWithABruteForceSearch) {
  // Random convex polygons of 3 to 8 corners, elongated up to 2:1, and cut depths from none
  // to a third of the inner radius. The brute force samples 400 points per edge, so both
  // searches approximate the same maximum from below; they must agree to 0.2 %.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 24; ++trial) {
    const int corners = 3 + trial % 6;
    const double a = 1.0 + unit(rng), b = 1.0;
    std::vector<Vec2> v;
    for (int k = 0; k < corners; ++k) {
      const double phi = 2.0 * M_PI * (k + 0.4 * unit(rng)) / corners;
      v.emplace_back(a * std::cos(phi), b * std::sin(phi));
    }
    const Shape s = make_polygon(v);
    const double m = s.area, inertia = s.polar_moment;
    const double depth = (trial % 4) / 9.0 * s.inner_radius;
    const double found = heaviest_chord(s, m, inertia, depth).weight;
    const double brute = brute_force_heaviest_chord(s, m, inertia, depth, 400);
    EXPECT_NEAR(found, brute, 2e-3 * brute) << "trial " << trial << ", " << corners << " corners, depth " << depth;
  }
}

TEST(TimeStep, TheSmallestGrainSetsTheBound) {
  ContactParameters c;
  const TimeStepBound b = stable_time_step({make_disc(0.004), make_disc(0.002), make_disc(0.003)}, 5000.0, c,
                                           Scheme::verlet);
  EXPECT_EQ(b.stiffest_grain, 1);
  // Undamped and frictionless, the limit scales with sqrt(m / k) ~ r: halving the grain halves
  // the step.
  c.damping_gamma = 0.0;
  c.friction_mu = 0.0;
  EXPECT_NEAR(stable_time_step({make_disc(0.002)}, 5000.0, c, Scheme::verlet).stable_limit,
              0.5 * stable_time_step({make_disc(0.004)}, 5000.0, c, Scheme::verlet).stable_limit, 1e-15);
}

TEST(TimeStep, AStiffTangentialSpringSetsTheBound) {
  // Two discs touching at the rim: 1/m_t = 2 (1/m + r^2/I) = 6/m (I = m r^2 / 2). With
  // k_t = 2 E and no damping, the tangential mode (omega_t^2 = 12 E/m) is stiffer than the
  // normal one (2 E (sqrt(7)/2 r / m) / (3r/8) = 7.06 E/m), and its own limit decides.
  const double r = 0.003, rho = 5000.0, m = rho * M_PI * r * r;
  for (TangentialHistory history : {TangentialHistory::spring, TangentialHistory::total})
    for (Scheme scheme : {Scheme::gear5, Scheme::verlet, Scheme::leapfrog}) {
      ContactParameters c;
      c.damping_gamma = 0.0;
      c.tangential_stiffness_ratio = 2.0;
      c.tangential_history = history;
      const double omega_t = std::sqrt(c.tangential_stiffness_ratio * c.youngs_modulus * 6.0 / m);
      const double tangential = tangential_limit_omega_dt(scheme, history) / omega_t;
      const DiscDeepestContact d = disc_deepest_contact(r);
      const double normal =
          expected_normal_limit(scheme, c, d.chord / m, contact_length(c, d.lever, d.lever), m);
      const double expected = std::min(tangential, normal);
      const TimeStepBound b = stable_time_step({make_disc(r)}, rho, c, scheme);
      EXPECT_NEAR(b.stable_limit, expected, 1e-12 * expected) << scheme_name(scheme);
      EXPECT_NEAR(b.omega_max, omega_t, 1e-9 * omega_t) << scheme_name(scheme) << ": the tangential mode decides";
    }
}

namespace {
// One tangential degree of freedom of mass m_t = 1 on the contact law's spring (k_t = 1, normal
// force far above the Coulomb cap), integrated by the scheme from a slip of 1 at rest. Returns
// the largest energy relative to the start: bounded if stable, huge if not.
double tangential_energy_growth(Scheme scheme, TangentialHistory history, double omega_dt, int steps) {
  ContactParameters law;
  law.youngs_modulus = 1.0 / law.tangential_stiffness_ratio;  // k_t = 1
  law.friction_mu = 1.0;
  law.tangential_history = history;
  const double dt = omega_dt;  // omega_t = sqrt(k_t / m_t) = 1
  MotionState m;
  m.resize(1);
  const std::vector<int> bodies{0};
  std::vector<double> accel(3, 0.0);
  // The body is grain a of the pair, b is fixed: the slip is its coordinate, and the law's
  // tangential force f acts on it as -f. Start from a slip of 1 with the spring at k_t * 1.
  double spring = 1.0;
  m.d[0][0] = 1.0;
  m.d[2][0] = -spring;
  double worst = 0.0;
  for (int k = 0; k < steps; ++k) {
    predict(scheme, m, bodies, dt);
    ContactKinematics kin;
    kin.area = 1e12;  // R = E A / l: no cap
    kin.chord = 1.0;
    kin.approach_speed = 0.0;
    kin.slip_speed = m.d[1][0];
    kin.normal_mass = kin.tangential_mass = 1.0;
    const ContactForce f = contact_force(law, kin, 1.0, spring, dt);
    spring = f.spring;
    accel[0] = -f.tangential;
    correct(scheme, m, accel, bodies, dt);
    // The spring's own energy is spring^2 / (2 k_t); it differs from the displacement's when
    // the history stores the viscous term too, so bound both.
    const double e = 0.5 * m.d[1][0] * m.d[1][0] + 0.5 * std::max(m.d[0][0] * m.d[0][0], spring * spring);
    worst = std::max(worst, e / 0.5);
    if (!std::isfinite(e)) return INFINITY;
  }
  return worst;
}
}  // namespace

TEST(TimeStep, TangentialSpringLimitsHoldForTheContactLaw) {
  for (TangentialHistory history : {TangentialHistory::spring, TangentialHistory::total}) {
    for (Scheme scheme : {Scheme::verlet, Scheme::leapfrog}) {  // exact: both sides
      const double limit = tangential_limit_omega_dt(scheme, history);
      EXPECT_LT(tangential_energy_growth(scheme, history, 0.99 * limit, 20000), 10.0) << scheme_name(scheme);
      EXPECT_GT(tangential_energy_growth(scheme, history, 1.01 * limit, 20000), 1e3) << scheme_name(scheme);
    }
    // Gear: safe at its bound, unstable 10 % above.
    const double limit = tangential_limit_omega_dt(Scheme::gear5, history);
    EXPECT_LT(tangential_energy_growth(Scheme::gear5, history, limit, 100000), 10.0);
    EXPECT_GT(tangential_energy_growth(Scheme::gear5, history, 1.1 * limit, 100000), 1e3);
  }
}
