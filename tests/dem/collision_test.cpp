// Two-grain collisions and a grain on an incline: the contact law and the integrators
// together, against conservation laws and Coulomb's law.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "dem/time_step.h"
#include "dem/world.h"

using namespace pilelab::dem;

namespace {
constexpr double density = 5000.0;  // kg/m^2
const Shape square = make_polygon({{-0.005, -0.005}, {0.005, -0.005}, {0.005, 0.005}, {-0.005, 0.005}});

Shape hexagon(double radius, double squash) {
  std::vector<Vec2> v;
  for (int k = 0; k < 6; ++k) v.emplace_back(radius * std::cos(k * M_PI / 3 + 0.1), squash * radius * std::sin(k * M_PI / 3 + 0.1));
  return make_polygon(v);
}

struct Collision {
  double energy_ratio;     // kinetic energy after / before
  double restitution;      // -(relative normal velocity after) / before
  double momentum_error;   // |P_after - P_before| / |P_before|
  double angular_momentum_error;
  bool attractive = false; // any normal force < 0 seen
  int steps_in_contact = 0;
};

// Shoots grain b at grain a (both free, no gravity) and runs until they separate.
Collision collide(const Shape& sa, const Shape& sb, Vec2 offset, Vec2 velocity, double angle_b, Scheme scheme,
                  double dt_fraction, double gamma, double mu) {
  WorldSettings w;
  w.contact.damping_gamma = gamma;
  w.contact.friction_mu = mu;
  w.scheme = scheme;
  w.gravity = {0, 0};
  const TimeStepBound bound = stable_time_step({sa, sb}, density, w.contact, scheme);
  w.time_step = dt_fraction * bound.stable_limit;
  World world(w);
  const int a = world.add_grain(sa, density), b = world.add_grain(sb, density);
  world.activate(a, {0, 0}, 0.0, {0, 0}, 0.0);
  world.activate(b, offset, angle_b, velocity, 0.0);
  auto momentum = [&] { return Vec2(world.mass(a) * world.velocity(a) + world.mass(b) * world.velocity(b)); };
  auto angular_momentum = [&] {
    double l = 0;
    for (int i : {a, b}) l += world.mass(i) * cross(world.position(i), world.velocity(i)) + world.inertia(i) * world.angular_velocity(i);
    return l;
  };
  const Vec2 p0 = momentum();
  const double l0 = angular_momentum(), e0 = world.kinetic_energy();
  const Vec2 n0 = -velocity.normalized();
  const double vn0 = n0.dot(world.velocity(b) - world.velocity(a));
  Collision c{};
  bool touched = false;
  for (int k = 0; k < 2000000; ++k) {
    world.step();
    if (!world.contacts().empty()) {
      touched = true;
      ++c.steps_in_contact;
      for (const Contact& ct : world.contacts()) c.attractive = c.attractive || ct.normal_force < 0.0;
    } else if (touched) {
      break;
    }
  }
  EXPECT_TRUE(touched);
  c.energy_ratio = world.kinetic_energy() / e0;
  c.restitution = -n0.dot(world.velocity(b) - world.velocity(a)) / vn0;
  c.momentum_error = (momentum() - p0).norm() / p0.norm();
  c.angular_momentum_error = std::abs(angular_momentum() - l0) / (world.mass(b) * velocity.norm() * 0.01);
  return c;
}
}  // namespace

TEST(Collision, MomentumAndAngularMomentumAreConservedToRoundOff) {
  // Forces act pairwise, equal and opposite, at one point: both momenta are exact invariants
  // of the discrete scheme up to round-off, even with damping and friction.
  for (Scheme s : {Scheme::gear5, Scheme::verlet, Scheme::leapfrog}) {
    const Collision c = collide(hexagon(0.004, 0.8), hexagon(0.0035, 0.7), {0.011, 0.003}, {-1.0, -0.2}, 0.4, s,
                                0.5, 0.75, 0.54);
    EXPECT_LT(c.momentum_error, 1e-12) << scheme_name(s);
    EXPECT_LT(c.angular_momentum_error, 1e-10) << scheme_name(s);
    EXPECT_FALSE(c.attractive);
  }
}

TEST(Collision, HeadOnElasticCollisionReturnsEnergyAtTheIntegratorsOrder) {
  // A 9.6 mm square b meets a 10 mm square a face on, along their common axis. The chord is b's
  // face width w inside a's face: A = w d for an overlap depth d, at the chord midpoint c on a's
  // face, so l = r_a r_b / (r_a + r_b) with r_a = 5 mm and r_b = 4.8 mm - d (A.1 with
  // r = |c - centroid|). R = E w d / l(d) depends on d only: the motion has a potential, and
  // gamma = 0 must return all kinetic energy as dt -> 0. In contact the relative motion is close
  // to half a period of omega = sqrt(E w / l(0) / m_red), lasting T = pi / omega.
  //
  // The force has a kink at first and last contact (A grows linearly from 0). A step that the
  // kink falls into at fraction theta of its length makes a velocity error of order
  // omega^2 v dt^2 theta (1 - theta) in a second-order scheme: the energy error is O(dt^2) for
  // every scheme, Gear's included, with a prefactor set by where in their steps the entry and
  // the exit fall. Entry and exit errors partly cancel, and how much depends on T / dt mod 1, so
  // a prefactor read at one step size would drift with dt. Both phases are therefore averaged:
  // the entry over 16 starting offsets across one step, the exit over 8 steps dt = T / (K + s)
  // with s spread over [0, 1). Each error is scaled to the nominal step T / (K + 1/2) as dt^2.
  // The averaged error is then C dt^2 (1 + O(dt)), and its order between K = 12, 24, 48 and 96
  // steps per contact must be 2 up to the O(dt) term: with at least 12 steps that term is at
  // most about 1/12 of the error, which moves a measured order by log2(1 + 1/12) = 0.12.
  // The size is bounded too: theta (1 - theta) <= 1/4 makes each kink's velocity error at most
  // omega^2 v dt^2 / 8, a relative energy error of (omega dt)^2 / 4, so the two kinks of a
  // collision cost at most (omega dt)^2 / 2.
  ContactParameters elastic;  // as collide() sets them
  elastic.damping_gamma = 0.0;
  elastic.friction_mu = 0.0;
  const Shape small = make_polygon({{-0.0048, -0.0048}, {0.0048, -0.0048}, {0.0048, 0.0048}, {-0.0048, 0.0048}});
  const double ma = density * square.area, mb = density * small.area;
  const double stiffness = elastic.youngs_modulus * 0.0096 / (0.005 * 0.0048 / 0.0098);
  const double contact_time = M_PI / std::sqrt(stiffness * (ma + mb) / (ma * mb));
  const std::vector<int> steps_per_contact = {12, 24, 48, 96};
  constexpr int entry_phases = 16, exit_phases = 8;
  for (Scheme s : {Scheme::verlet, Scheme::leapfrog, Scheme::gear5}) {
    const double bound = stable_time_step({square, small}, density, elastic, s).stable_limit;
    std::vector<double> dts, errors;
    for (int k : steps_per_contact) {
      const double nominal_dt = contact_time / (k + 0.5);
      double sum = 0.0;
      for (int j = 0; j < exit_phases; ++j) {
        const double dt = contact_time / (k + (j + 0.5) / exit_phases);
        ASSERT_LT(dt, bound) << scheme_name(s);
        for (int phase = 0; phase < entry_phases; ++phase) {
          // b starts 0.2 mm clear of a at 0.5 m/s: spread its first contact over one step.
          const Vec2 start(0.0100 + 0.5 * dt * phase / entry_phases, 0.0);
          const Collision c = collide(square, small, start, {-0.5, 0.0}, 0.0, s, dt / bound, 0.0, 0.0);
          sum += std::abs(c.energy_ratio - 1.0) * (nominal_dt / dt) * (nominal_dt / dt);
          EXPECT_NEAR(c.restitution, 1.0, 0.05);
        }
      }
      dts.push_back(nominal_dt);
      errors.push_back(sum / (entry_phases * exit_phases));
    }
    std::string listed;
    for (std::size_t i = 0; i < errors.size(); ++i) {
      const double omega_dt = M_PI / contact_time * dts[i];
      EXPECT_LT(errors[i], 0.5 * omega_dt * omega_dt) << scheme_name(s) << " at dt = " << dts[i] << " s";
      char text[32];
      std::snprintf(text, sizeof text, "%.3e ", errors[i]);
      listed += text;
    }
    RecordProperty(std::string(scheme_name(s)) + "_energy_errors", listed);
    for (std::size_t i = 0; i + 1 < errors.size(); ++i) {
      const double order = std::log(errors[i] / errors[i + 1]) / std::log(dts[i] / dts[i + 1]);
      EXPECT_NEAR(order, 2.0, 0.12) << scheme_name(s) << " between dt = " << dts[i] << " and " << dts[i + 1]
                                   << " s: errors " << errors[i] << " and " << errors[i + 1];
    }
  }
}

TEST(Collision, ObliqueElasticCollisionEnergyDriftIsMeasured) {
  // E A / l with l changing along the path is not a potential force: report the drift.
  for (Scheme s : {Scheme::verlet, Scheme::leapfrog, Scheme::gear5}) {
    const Collision c = collide(hexagon(0.004, 0.8), hexagon(0.0035, 0.7), {0.011, 0.003}, {-1.0, -0.2}, 0.4, s,
                                0.2, 0.0, 0.0);
    RecordProperty(std::string(scheme_name(s)) + "_oblique_energy_ratio", std::to_string(c.energy_ratio));
    EXPECT_TRUE(std::isfinite(c.energy_ratio));
    EXPECT_NEAR(c.energy_ratio, 1.0, 0.2) << scheme_name(s);
  }
}

TEST(Collision, RestitutionFallsAsDampingGrows) {
  double previous = 1.0 + 1e-3;
  for (double gamma : {0.0, 0.25, 0.5, 0.75, 1.0, 1.5}) {
    const Collision c = collide(square, square, {0.0102, 0.0}, {-0.5, 0.0}, 0.0, Scheme::gear5, 0.3, gamma, 0.0);
    EXPECT_LT(c.restitution, previous) << "gamma " << gamma;
    EXPECT_GE(c.restitution, 0.0);
    EXPECT_FALSE(c.attractive);
    previous = c.restitution;
  }
  EXPECT_LT(previous, 0.5);
}

namespace {
// A flat block resting on a plate tilted by alpha; returns the block's displacement along the
// slope after `duration` seconds, and its mean acceleration over the last half.
struct IncineResult {
  double travel, acceleration;
};
IncineResult slide_on_incline(double alpha, double mu, double duration,
                              TangentialHistory history = TangentialHistory::spring) {
  WorldSettings w;
  w.contact.friction_mu = mu;
  w.contact.tangential_history = history;
  w.contact.damping_gamma = 0.75;
  w.scheme = Scheme::gear5;
  const Shape block = make_polygon({{-0.01, -0.004}, {0.01, -0.004}, {0.01, 0.004}, {-0.01, 0.004}});
  w.time_step = 0.8 * stable_time_step({block}, density, w.contact, w.scheme).stable_limit;
  World world(w);
  const Shape plate = make_polygon({{-0.5, -0.01}, {0.5, -0.01}, {0.5, 0.01}, {-0.5, 0.01}});
  const Vec2 down_slope(std::cos(alpha), -std::sin(alpha)), up_normal(std::sin(alpha), std::cos(alpha));
  world.add_wall(plate, -0.01 * up_normal, -alpha);
  const int g = world.add_grain(block, density);
  // Start resting with the static overlap m g cos(alpha) l / (E chord) already in place.
  world.activate(g, (0.004 - 1e-6) * up_normal, -alpha, {0, 0}, 0.0);
  const int n = static_cast<int>(duration / w.time_step);
  double v_half = 0, t_half = 0;
  for (int k = 0; k < n; ++k) {
    world.step();
    if (k == n / 2) {
      v_half = world.velocity(g).dot(down_slope);
      t_half = world.time();
    }
  }
  const double travel = world.position(g).dot(down_slope);
  return {travel, (world.velocity(g).dot(down_slope) - v_half) / (world.time() - t_half)};
}
}  // namespace

// Both readings of the tangential history (eq. A.2), each at its own stable time step.
const TangentialHistory both_histories[] = {TangentialHistory::spring, TangentialHistory::total};

TEST(Incline, GrainSticksBelowTheFrictionAngle) {
  const double mu = 0.5;  // friction angle 26.6 degrees
  for (TangentialHistory history : both_histories) {
    const IncineResult r = slide_on_incline(20.0 * M_PI / 180.0, mu, 0.3, history);
    // Stuck: only the elastic creep of the tangential spring, mu m g / k_t = O(1e-7) m.
    EXPECT_LT(std::abs(r.travel), 1e-5) << int(history);
  }
}

TEST(Incline, GrainSlidesAboveTheFrictionAngleWithCoulombAcceleration) {
  const double mu = 0.5, alpha = 35.0 * M_PI / 180.0;
  for (TangentialHistory history : both_histories) {
    const IncineResult r = slide_on_incline(alpha, mu, 0.3, history);
    const double expected = 9.81 * (std::sin(alpha) - mu * std::cos(alpha));
    EXPECT_GT(r.travel, 0.01) << int(history);
    EXPECT_NEAR(r.acceleration, expected, 0.02 * expected) << int(history);
  }
}

TEST(Wall, StiffnessDoesNotDependOnWhereAlongTheWallAGrainRests) {
  // Two identical blocks resting under gravity on one long plate, one over its centre and one
  // near its end: the wall is flat on their scale, so both sink to the same static depth
  // E A / l = m g with l the block's lever, to round-off.
  WorldSettings w;
  w.scheme = Scheme::verlet;
  const Shape block = make_polygon({{-0.005, -0.003}, {0.005, -0.003}, {0.005, 0.003}, {-0.005, 0.003}});
  w.time_step = 0.8 * stable_time_step({block}, density, w.contact, w.scheme).stable_limit;
  World world(w);
  world.add_wall(make_polygon({{-1.0, -0.01}, {1.0, -0.01}, {1.0, 0.01}, {-1.0, 0.01}}), {0.0, -0.01}, 0.0);
  const int centre = world.add_grain(block, density), end = world.add_grain(block, density);
  world.activate(centre, {0.0, 0.003}, 0.0, {0, 0}, 0.0);
  world.activate(end, {0.95, 0.003}, 0.0, {0, 0}, 0.0);
  for (int k = 0; k < 20000; ++k) world.step();
  const double depth = 0.003 - world.position(centre).y();
  EXPECT_GT(depth, 0.0);
  EXPECT_NEAR(world.position(end).y(), world.position(centre).y(), 1e-6 * depth);
}

namespace {
// The restitution of a face-on collision from eq. A.1 alone, by integrating the relative motion
// m_perp x'' = -F(x, x') with a fine RK4. Square b (half side cb) hits the larger square a
// (half side ca) face on: the outlines cross where b's face meets a's, so the chord is b's face,
// 2 cb, the force point lies on a's face (lever ca) and b's lever is cb - x at overlap depth x.
// Then A = 2 cb x, dA/dt = 2 cb x', l = ca (cb - x) / (ca + cb - x), and
// F = E A / l + max(gamma (dA/dt) / l sqrt(E m_perp), -E A / l).
double face_on_restitution(double ca, double cb, double speed, double gamma) {
  const double E = ContactParameters{}.youngs_modulus;
  const double ma = density * 4 * ca * ca, mb = density * 4 * cb * cb, m = ma * mb / (ma + mb);
  auto acceleration = [&](double x, double v) {
    const double l = ca * (cb - x) / (ca + cb - x);
    const double elastic = E * 2 * cb * x / l, damping = gamma * 2 * cb * v / l * std::sqrt(E * m);
    return -(elastic + std::max(damping, -elastic)) / m;
  };
  const double period = 2 * M_PI * std::sqrt(m * ca * cb / ((ca + cb) * E * 2 * cb));
  const double h = period * 1e-5;
  double x = 0, v = speed;
  while (x >= 0) {
    const double k1x = v, k1v = acceleration(x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = acceleration(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = acceleration(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = acceleration(x + h * k3x, v + h * k3v);
    x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
  return -v / speed;
}
}  // namespace

TEST(Collision, RestitutionMatchesTheContactLawIntegratedExactly) {
  // The size of the damping force, not only its sign: a wrong factor in m_perp (sqrt 2), a
  // missing square root or another contact length moves the restitution by tens of per cent.
  // The schemes' error is dominated by the kink where contact begins somewhere inside a step:
  // the force history is shifted by up to one step of the N in contact, so the restitution is
  // off by O(1/N); we allow 1/N.
  const double ca = 0.006, cb = 0.005, speed = 0.5;
  const Shape big = make_polygon({{-ca, -ca}, {ca, -ca}, {ca, ca}, {-ca, ca}});
  const Shape small = make_polygon({{-cb, -cb}, {cb, -cb}, {cb, cb}, {-cb, cb}});
  for (double gamma : {0.25, 0.75, 1.5}) {
    const double exact = face_on_restitution(ca, cb, speed, gamma);
    for (Scheme s : {Scheme::gear5, Scheme::verlet, Scheme::leapfrog}) {
      for (double fraction : {0.2, 0.1, 0.05}) {
        const Collision c = collide(big, small, {ca + cb + 2e-4, 0.0}, {-speed, 0.0}, 0.0, s, fraction, gamma, 0.0);
        EXPECT_NEAR(c.restitution, exact, 1.0 / c.steps_in_contact)
            << "gamma " << gamma << ", " << scheme_name(s) << " at " << fraction << " of its bound";
      }
    }
  }
}
