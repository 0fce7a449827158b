#pragma once
// The stable time step. The stiffest contact a grain can form is flat edge on edge: the overlap
// grows as A = chord * depth, so R = E A / l has stiffness k = E * chord / l, with the chord
// at most the grain's longest edge and l at its smallest when both lever arms are the inner
// radius. The lightest effective mass couples translation and rotation about the force point:
// m_eff = 1 / (1/m + r_max^2 / I), halved for two such grains. The contact frequency is
// omega = sqrt(k / m_pair); a scheme is stable for omega dt below its limit (integrator.h).
// Damping lowers that limit: with damping ratio zeta = (gamma/2) sqrt(chord/l * m_n/m_pair)
// (the paper's D = gamma (dA/dt)/l sqrt(E m_n) against critical damping 2 sqrt(k m_pair)), an
// explicit scheme's limit shrinks by the factor sqrt(1 + zeta^2) - zeta, which we apply to both
// schemes. The bound is the smallest limit over all grains.
#include <vector>

#include "dem/contact_law.h"
#include "dem/integrator.h"
#include "dem/shape.h"

namespace pilelab::dem {

struct TimeStepBound {
  double omega_max = 0.0;      ///< contact angular frequency of the grain that sets the bound [1/s]
  double period_min = 0.0;     ///< 2 pi / omega_max [s]
  double stable_limit = 0.0;   ///< largest stable dt for the scheme [s]
  double damping_ratio = 0.0;  ///< zeta of that grain's stiffest contact
  int stiffest_grain = -1;     ///< index (in the list given) of the grain that sets the bound
};

TimeStepBound stable_time_step(const std::vector<Shape>& grains, double areal_density,
                               const ContactParameters& contact, Scheme scheme);

}  // namespace pilelab::dem
