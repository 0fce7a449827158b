// The pile protocol's energy account (PileProtocol::energy_fed_in, mechanical_energy): what the
// pour puts in bounds what the grains can hold, and a step above the stability limit that
// creates more stops the run.
#include "dem/pile_protocol.h"

#include <gtest/gtest.h>

#include <algorithm>
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
        worst = std::max(worst, p.mechanical_energy() / p.energy_fed_in());
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

}  // namespace
}  // namespace pilelab::dem
