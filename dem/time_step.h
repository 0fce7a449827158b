#pragma once
// The stable time step. The stiffest contact a grain can form is an edge pressed flat: the
// overlap grows as A = chord * depth, so R = E A / l has stiffness k = E * chord / l, with the
// chord at most that edge's length and l at its smallest when both lever arms are the inner
// radius. The force acts along the edge's normal at a point of the edge, so its moment arm about
// the centroid is at most the distance along the edge from the centroid's foot to the edge's far
// end; translation and rotation then move the effective mass m_eff = 1/(1/m + arm^2/I), halved
// for two such grains: omega_e = sqrt(2 k (1/m + arm^2/I)) for every edge e of every grain
// (discs: chord 2r, arm 0). A scheme is stable for omega dt below its limit (integrator.h).
// Damping lowers that limit: with damping ratio zeta = (gamma/2) sqrt(chord/l * m/m_eff)
// (the paper's D = gamma (dA/dt)/l sqrt(E m_n), m_n = m/2, against critical damping
// 2 sqrt(k m_eff/2)), an explicit scheme's limit shrinks by sqrt(1 + zeta^2) - zeta, which we
// apply to both schemes. The bound is the smallest limit over all edges of all grains. With
// the literal reading of A.2 (TangentialHistory::total) the tangential spring stiffens to
// k_t + sqrt(k_t m_t)/dt, and its mode bounds dt as well (time_step.cpp).
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
