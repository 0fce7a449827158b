// The tangential force of eq. A.2 in both readings of what the contact carries to the next step.
#include <cmath>

#include <gtest/gtest.h>

#include "dem/contact_law.h"

using namespace pilelab::dem;

namespace {
ContactKinematics sticking_contact(double slip_speed) {
  ContactKinematics k;
  k.area = 1e-8;  // F_n = E A / l = 2 N, so the Coulomb cap mu F_n = 1.08 N
  k.chord = 2e-3;
  k.lever_a = k.lever_b = 1e-1;  // l = 0.05 m
  k.approach_speed = 0.0;        // no normal damping
  k.slip_speed = slip_speed;
  k.normal_mass = 0.05;
  k.tangential_mass = 0.02;
  return k;
}
}  // namespace

TEST(ContactLaw, SpringHistoryKeepsTheViscousTermOut) {
  ContactParameters p;
  const ContactKinematics k = sticking_contact(1e-3);
  const double l = contact_length(p, k.lever_a, k.lever_b), dt = 1e-5, spring = 0.1;
  const ContactForce f = contact_force(p, k, l, spring, dt);
  const double k_t = p.tangential_stiffness_ratio * p.youngs_modulus;
  const double viscous = std::sqrt(k_t * k.tangential_mass) * k.slip_speed;
  EXPECT_NEAR(f.normal, p.youngs_modulus * k.area / l, 1e-12);
  EXPECT_NEAR(f.spring, spring + k_t * k.slip_speed * dt, 1e-12);
  EXPECT_NEAR(f.tangential, f.spring + viscous, 1e-12);
}

TEST(ContactLaw, TotalHistoryStoresTheWholeForceAsA2Reads) {
  // F(t + dt) = F(t) + v dt k_t + v sqrt(k_t m): the stored value is the force itself.
  ContactParameters p;
  p.tangential_history = TangentialHistory::total;
  const ContactKinematics k = sticking_contact(1e-3);
  const double l = contact_length(p, k.lever_a, k.lever_b), dt = 1e-5, previous = 0.1;
  const ContactForce f = contact_force(p, k, l, previous, dt);
  const double k_t = p.tangential_stiffness_ratio * p.youngs_modulus;
  EXPECT_NEAR(f.tangential, previous + k_t * k.slip_speed * dt + std::sqrt(k_t * k.tangential_mass) * k.slip_speed,
              1e-12);
  EXPECT_EQ(f.spring, f.tangential);
}

TEST(ContactLaw, BothHistoriesSlideAtTheCoulombCap) {
  for (TangentialHistory history : {TangentialHistory::spring, TangentialHistory::total}) {
    ContactParameters p;
    p.tangential_history = history;
    const ContactKinematics k = sticking_contact(-5.0);  // fast slip: the trial force exceeds mu F_n
    const double l = contact_length(p, k.lever_a, k.lever_b);
    const ContactForce f = contact_force(p, k, l, 0.0, 1e-5);
    EXPECT_NEAR(f.tangential, -p.friction_mu * f.normal, 1e-12) << int(history);
    EXPECT_EQ(f.spring, f.tangential) << int(history);
  }
}

TEST(ContactLaw, NormalDampingIsEqA1WithTheCutOffAtZeroForce) {
  // E = 1e7 N/m, A = 1e-8 m^2, l = 0.05 m: R = 2 N. Approaching at 0.1 m/s over a 2 mm chord:
  // d(A/l)/dt = 2e-3 * 0.1 / 0.05 = 4e-3 m/s, sqrt(E m) = sqrt(1e7 * 0.05) = 707.107 kg/s,
  // so D = 0.75 * 4e-3 * 707.107 = 2.12132 N.
  ContactParameters p;
  p.friction_mu = 0.0;
  ContactKinematics k = sticking_contact(0.0);
  const double l = contact_length(p, k.lever_a, k.lever_b);
  EXPECT_DOUBLE_EQ(l, 0.05);
  k.approach_speed = 0.1;
  EXPECT_NEAR(contact_force(p, k, l, 0.0, 1e-5).normal, 2.0 + 0.75 * 4e-3 * std::sqrt(5e5), 1e-12);
  // Separating at half that speed, the damping subtracts half as much...
  k.approach_speed = -0.05;
  EXPECT_NEAR(contact_force(p, k, l, 0.0, 1e-5).normal, 2.0 - 0.75 * 2e-3 * std::sqrt(5e5), 1e-12);
  // ...until it would pull: the force stops at zero, never attractive.
  k.approach_speed = -1.0;
  EXPECT_EQ(contact_force(p, k, l, 0.0, 1e-5).normal, 0.0);
}

TEST(ContactLaw, ContactLengthsOfBothReadings) {
  // paper: the harmonic combination r_i r_j / (r_i + r_j); a wall's infinite lever leaves the
  // grain's. book: four times as long, so that equal levers r give l = 2 r.
  ContactParameters p;
  EXPECT_DOUBLE_EQ(contact_length(p, 0.003, 0.006), 0.002);
  EXPECT_DOUBLE_EQ(contact_length(p, INFINITY, 0.004), 0.004);
  p.contact_length = ContactLength::book;
  EXPECT_DOUBLE_EQ(contact_length(p, 0.005, 0.005), 0.010);
  EXPECT_DOUBLE_EQ(contact_length(p, 0.003, 0.006), 0.008);
}
