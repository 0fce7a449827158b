#include "dem/contact_law_x4.h"

namespace pilelab::dem {

PILELAB_AVX2_AND_SSE2
void contact_law_x4(const ContactParameters& law, double dt, const ContactLanes& in, ContactLaneForces& out) { contact_law_lanes(law, dt, in, out); }

}  // namespace pilelab::dem
