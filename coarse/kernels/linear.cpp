// MercuryCG's Linear kernel: a cone, 1 - s on s < 1.
#include "coarse/kernel.h"

namespace pilelab::coarse {

extern const KernelShape linear_kernel = {
    "linear", "1 - r/w for r < w (a cone)", 1.0,
    [](double s) { return 1.0 - s; },
    [](double s) { return s * s * (0.5 - s / 3.0); },
};

}  // namespace pilelab::coarse
