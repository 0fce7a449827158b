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
