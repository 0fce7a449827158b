// The four-lane contact law against the scalar one (contact_law.h), bit for bit: the DEM's pair
// loop relies on it for results that do not depend on how its contacts fall into lanes.
#include "dem/contact_law_x4.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace pilelab::dem {
namespace {

bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; }

// One lane's contact, as the scalar law sees it.
struct Lane {
  double area, chord, px, py, nx, ny, ax, ay, bx, by, vax, vay, wa, vbx, vby, wb;
  double inverse_mass_a, inverse_mass_b, inverse_inertia_a, inverse_inertia_b, floor_a, floor_b;
  bool a_has_no_lever;
  double old_spring, old_nx, old_ny;
};

// The scalar law: the kinematics by their definitions (ContactKinematics), l, the forces, and
// the force on b with its torques about both centroids.
struct Expected {
  double normal, tangential, spring, fx, fy, torque_a, torque_b;
};
Expected scalar_law(const ContactParameters& law, double dt, const Lane& c) {
  const double rax = c.px - c.ax, ray = c.py - c.ay, rbx = c.px - c.bx, rby = c.py - c.by;
  // Velocity of each body's material point at the force point: v + omega x r.
  const double uax = c.vax + -c.wa * ray, uay = c.vay + c.wa * rax;
  const double ubx = c.vbx + -c.wb * rby, uby = c.vby + c.wb * rbx;
  const double dux = uax - ubx, duy = uay - uby;
  const double ra2 = rax * rax + ray * ray, rb2 = rbx * rbx + rby * rby;
  ContactKinematics k;
  k.area = c.area;
  k.chord = c.chord;
  k.lever_a = c.a_has_no_lever ? INFINITY : std::max(std::sqrt(ra2), c.floor_a);
  k.lever_b = std::max(std::sqrt(rb2), c.floor_b);
  k.approach_speed = c.nx * dux + c.ny * duy;
  k.slip_speed = -c.ny * dux + c.nx * duy;
  const double inverse_masses = c.inverse_mass_a + c.inverse_mass_b;
  k.normal_mass = 1.0 / inverse_masses;
  k.tangential_mass = 1.0 / (inverse_masses + ra2 * c.inverse_inertia_a + rb2 * c.inverse_inertia_b);
  const double turn = c.old_nx * c.nx + c.old_ny * c.ny;
  const ContactForce f = contact_force(law, k, contact_length(law, k.lever_a, k.lever_b),
                                       turn > 0.5 ? turn * c.old_spring : 0.0, dt);
  const double fx = f.normal * c.nx + f.tangential * -c.ny, fy = f.normal * c.ny + f.tangential * c.nx;
  return {f.normal, f.tangential, f.spring, fx, fy, -(rax * fy - ray * fx), rbx * fy - rby * fx};
}

// A random contact between two paper-sized grains (or a grain and a wall): the force point
// between the centroids, any motion, a spring from the last step along a normal turned by up to
// 90 degrees, or none.
Lane random_lane(std::mt19937_64& random) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Lane c;
  const double angle = M_PI * u(random), turned = angle + 0.5 * M_PI * u(random);
  c.nx = std::cos(angle), c.ny = std::sin(angle);
  c.ax = 0.3 + 0.01 * u(random), c.ay = 0.1 + 0.01 * u(random);
  c.px = c.ax + 3e-3 * c.nx + 1e-3 * u(random), c.py = c.ay + 3e-3 * c.ny + 1e-3 * u(random);
  c.bx = c.px + 3e-3 * c.nx + 1e-3 * u(random), c.by = c.py + 3e-3 * c.ny + 1e-3 * u(random);
  c.area = 1e-9 * (1.0 + u(random)), c.chord = 1e-3 * (1.0 + u(random));
  c.vax = 0.2 * u(random), c.vay = 0.2 * u(random), c.wa = 20 * u(random);
  c.vbx = 0.2 * u(random), c.vby = 0.2 * u(random), c.wb = 20 * u(random);
  c.a_has_no_lever = u(random) > 0.6;
  c.inverse_mass_a = c.a_has_no_lever ? 0.0 : 1.0 / (0.1 * (1.5 + u(random)));
  c.inverse_mass_b = 1.0 / (0.1 * (1.5 + u(random)));
  c.inverse_inertia_a = c.a_has_no_lever ? 0.0 : 1.0 / (1e-6 * (1.5 + u(random)));
  c.inverse_inertia_b = 1.0 / (1e-6 * (1.5 + u(random)));
  c.floor_a = 1.5e-3 * (1.0 + 0.5 * u(random)), c.floor_b = 1.5e-3 * (1.0 + 0.5 * u(random));
  const bool continues = u(random) > -0.6;
  c.old_spring = continues ? 2.0 * u(random) : 0.0;
  c.old_nx = continues ? std::cos(turned) : 0.0, c.old_ny = continues ? std::sin(turned) : 0.0;
  return c;
}

TEST(ContactLawX4, EveryLaneGivesTheScalarLawsBits) {
  std::mt19937_64 random(2010);
  const double dt = 2e-6;
  int lanes = 0, sliding = 0, sticking = 0, loose = 0;
  for (int variant = 0; variant < 4; ++variant) {
    ContactParameters law;
    if (variant == 1) law.contact_length = ContactLength::book;
    if (variant == 2) law.tangential_history = TangentialHistory::total;
    if (variant == 3) law.friction_mu = 0.0;
    for (int trial = 0; trial < 2000; ++trial) {
      Lane c[4];
      ContactLanes in;
      for (int lane = 0; lane < 4; ++lane) {
        c[lane] = random_lane(random);
        in.area[lane] = c[lane].area, in.chord[lane] = c[lane].chord;
        in.point_x[lane] = c[lane].px, in.point_y[lane] = c[lane].py;
        in.normal_x[lane] = c[lane].nx, in.normal_y[lane] = c[lane].ny;
        in.centre_a_x[lane] = c[lane].ax, in.centre_a_y[lane] = c[lane].ay;
        in.centre_b_x[lane] = c[lane].bx, in.centre_b_y[lane] = c[lane].by;
        in.velocity_a_x[lane] = c[lane].vax, in.velocity_a_y[lane] = c[lane].vay, in.spin_a[lane] = c[lane].wa;
        in.velocity_b_x[lane] = c[lane].vbx, in.velocity_b_y[lane] = c[lane].vby, in.spin_b[lane] = c[lane].wb;
        in.inverse_mass_a[lane] = c[lane].inverse_mass_a, in.inverse_mass_b[lane] = c[lane].inverse_mass_b;
        in.inverse_inertia_a[lane] = c[lane].inverse_inertia_a, in.inverse_inertia_b[lane] = c[lane].inverse_inertia_b;
        in.lever_floor_a[lane] = c[lane].floor_a, in.lever_floor_b[lane] = c[lane].floor_b;
        in.a_has_no_lever[lane] = c[lane].a_has_no_lever ? -1 : 0;
        in.old_spring[lane] = c[lane].old_spring;
        in.old_normal_x[lane] = c[lane].old_nx, in.old_normal_y[lane] = c[lane].old_ny;
      }
      ContactLaneForces out;
      contact_law_x4(law, dt, in, out);
      for (int lane = 0; lane < 4; ++lane) {
        const Expected e = scalar_law(law, dt, c[lane]);
        ++lanes;
        if (e.normal <= 0.0 || law.friction_mu == 0.0)
          ++loose;
        else if (std::abs(e.tangential) < law.friction_mu * e.normal)
          ++sticking;
        else
          ++sliding;
        ASSERT_TRUE(same_bits(out.normal[lane], e.normal)) << "variant " << variant << " trial " << trial;
        ASSERT_TRUE(same_bits(out.tangential[lane], e.tangential)) << "variant " << variant << " trial " << trial;
        ASSERT_TRUE(same_bits(out.spring[lane], e.spring)) << "variant " << variant << " trial " << trial;
        ASSERT_TRUE(same_bits(out.force_x[lane], e.fx)) << "variant " << variant << " trial " << trial;
        ASSERT_TRUE(same_bits(out.force_y[lane], e.fy)) << "variant " << variant << " trial " << trial;
        ASSERT_TRUE(same_bits(out.torque_a[lane], e.torque_a)) << "variant " << variant << " trial " << trial;
        ASSERT_TRUE(same_bits(out.torque_b[lane], e.torque_b)) << "variant " << variant << " trial " << trial;
      }
    }
  }
  // Every branch of the law was taken many times: a contact that sticks, one that slides at
  // the Coulomb cap, and one without friction (separating faster than it is pressed, or mu = 0).
  EXPECT_GT(sticking, lanes / 20);
  EXPECT_GT(sliding, lanes / 20);
  EXPECT_GT(loose, lanes / 20);
}

}  // namespace
}  // namespace pilelab::dem
