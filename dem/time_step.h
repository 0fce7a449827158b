#pragma once
// The stable time step: the largest dt at which the scheme stays stable on the stiffest contact
// a grain of the scene can form, pressed against its twin.
//
// Normal mode. R = E A / l has stiffness k = E c / l for a contact of chord c, and its force acts
// along the chord's normal through the chord's midpoint, at moment arm a about the centroid, so a
// pair of twins moves the effective mass 1/(2 (1/m + a^2/I)). Both the frequency and the damping
// ratio then grow with the chord's weight w = c (1/m + a^2/I):
//   omega^2 = 2 E w / l,   zeta = (gamma/2) sqrt(w m / l)
// (the paper's damping D = gamma (dA/dt)/l sqrt(E m_n) with m_n = m/2, against critical damping),
// and the scheme's limit stability_limit_omega_dt(scheme, zeta) / omega falls as w grows. So the
// bound needs the heaviest chord a contact can have on each grain, with l at its smallest.
//
// Which chords can a contact have? Its two end points lie on the grain's boundary, and the part
// of the grain beyond the chord lies inside the other grain: it is no thicker than the overlap.
// The bound admits every chord that cuts off no more than max_overlap_depth_fraction of the inner
// radius (a flat contact along one edge cuts off nothing; a chord across a corner cuts the corner
// off). A chord along an edge has its midpoint inside the edge, so a long chord has a short arm
// and a long arm a short chord: counting the whole edge at the arm of its far end, as this bound
// did until 2026-11-22, overstated w by up to 3x. l is proportional to the lever (the distance
// of the chord's midpoint from the centroid), which is the inner radius for a chord along an
// edge but shorter for one across a corner: on an elongated grain of the paper the heaviest
// chord a quarter-radius deep lies at 0.77 of the inner radius. The bound counts each chord at
// its own lever; until 2026-11-23 it took every lever at the inner radius, and its default step
// was then about 1 % above the limit of the deepest contact it admitted. World records the
// deepest overlap of a run, so a run can tell whether it stayed inside the bound's assumption.
//
// Tangential mode. The Cundall-Strack spring k_t with its viscous term sqrt(k_t m_t) has damping
// ratio 1/2 whatever the geometry, and is stiffest for a force at the bounding radius:
// omega_t^2 = 2 k_t (1/m + r^2/I). Its limit depends on how the spring is advanced
// (tangential_limit_omega_dt).
//
// Discs: a chord cut f r deep is 2 r sqrt(f (2 - f)) long, at arm 0 and lever r (1 - f).
#include <vector>

#include "dem/contact_law.h"
#include "dem/integrator.h"
#include "dem/shape.h"

namespace pilelab::dem {

/// The bound admits contacts whose overlap is no thicker than this fraction of the smaller
/// grain's inner radius (World::deepest_overlap reports what a run reached).
constexpr double max_overlap_depth_fraction = 0.25;

struct TimeStepBound {
  double omega_max = 0.0;      ///< angular frequency of the mode that sets the bound [1/s]
  double period_min = 0.0;     ///< 2 pi / omega_max [s]
  double stable_limit = 0.0;   ///< largest stable dt for the scheme [s]
  double damping_ratio = 0.0;  ///< zeta of that mode
  int stiffest_grain = -1;     ///< index (in the list given) of the grain that sets the bound
};

TimeStepBound stable_time_step(const std::vector<Shape>& grains, double areal_density,
                               const ContactParameters& contact, Scheme scheme);

/// The same bound for contacts as deep as depth_fraction of the inner radius (stable_time_step is
/// this at max_overlap_depth_fraction), with both effects of depth: chords that cut that deep,
/// and each chord at its own lever, the distance of its midpoint from the centroid. A chord
/// across a corner can pass closer to the centroid than any edge, so its l is shorter than an
/// edge's (levers floored at half the inner radius, as the contact law floors them). Discs: the
/// chord cut f r deep, at lever r (1 - f). A run evaluates it for the deepest overlap it reached
/// (World::deepest_overlap): whether its step stayed stable for the contacts it actually made.
TimeStepBound stable_time_step_at_depth(const std::vector<Shape>& grains, double areal_density,
                                        const ContactParameters& contact, Scheme scheme, double depth_fraction);

/// The largest omega_t dt at which the tangential spring of A.2 (damping ratio 1/2) stays
/// stable under the scheme, for either way of storing its history.
double tangential_limit_omega_dt(Scheme scheme, TangentialHistory history);

/// The chord of largest weight c (1/m + a^2/I) that a contact can have on a polygon, among
/// chords that cut off no more than max_depth [m] of it (see above). Chords along one edge are
/// maximised exactly; chords across corners are searched on a grid refined around its best
/// point, which finds the maximum to within a fraction of a per cent.
/// With count_levers, a chord whose midpoint lies nearer the centroid than the inner radius
/// (lever < r_in) weighs r_in / lever times more, since l shrinks with the lever.
struct HeaviestChord {
  double chord = 0.0;   ///< c [m]
  double arm = 0.0;     ///< a [m]
  double weight = 0.0;  ///< c (1/m + a^2/I) [m/kg], times r_in / lever with count_levers
  double lever = 0.0;   ///< the lever it was counted at [m] (count_levers only)
};
HeaviestChord heaviest_chord(const Shape& polygon, double mass, double inertia, double max_depth,
                             bool count_levers = false);

}  // namespace pilelab::dem
