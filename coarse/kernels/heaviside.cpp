// MercuryCG's Heaviside kernel: a top hat of radius w (the RVE's disc, unclipped).
#include "coarse/kernel.h"

namespace pilelab::coarse {

extern const KernelShape heaviside_kernel = {
    "heaviside", "1 for r < w (a top hat)", 1.0,
    [](double) { return 1.0; },
    [](double s) { return 0.5 * s * s; },
};

}  // namespace pilelab::coarse
