// The pile protocol's energy account (PileProtocol::energy_fed_in, mechanical_energy): what the
// pour puts in bounds what the grains can hold, and a step above the stability limit that
// creates more stops the run.
#include "dem/pile_protocol.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

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
  // stays below what the pour put in, up to the integrator's bounded energy error on the small
  // part of it stored in contacts (1e-3 of the total is far above it).
  for (Scheme scheme : {Scheme::verlet, Scheme::leapfrog, Scheme::gear5}) {
    DemScene scene = small_pile(scheme);
    scene.relax.enabled = true;
    scene.relax.ramp_time = 0.05;
    PileProtocol p(scene, "test");
    double worst = 0.0;
    while (!p.done()) {
      p.step();
      if (p.world().steps() % PileProtocol::check_interval == 0 && p.energy_fed_in() > 0.0)
        worst = std::max(worst, p.mechanical_energy() / p.energy_fed_in());
    }
    EXPECT_LE(worst, 1.0 + 1e-3) << scheme_name(scheme);
    EXPECT_GT(worst, 0.5) << "the first grain's fall holds all the energy fed in: " << scheme_name(scheme);
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
    // The finite-state check runs first and may catch an overflow before the energy check.
    EXPECT_TRUE(what.find("creates energy at t = ") != std::string::npos ||
                what.find("no longer finite at t = ") != std::string::npos)
        << what;
    EXPECT_NE(what.find("body "), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace pilelab::dem
