// Lucy's polynomial, (1 + 3s)(1 - s)^3 on s < 1 (Lucy 1977; Weinhart et al. 2012).
#include "coarse/kernel.h"

namespace pilelab::coarse {

extern const KernelShape lucy_kernel = {
    "lucy", "(1 + 3 r/w)(1 - r/w)^3 for r < w", 1.0,
    [](double s) { return (1 + 3 * s) * (1 - s) * (1 - s) * (1 - s); },
    [](double s) { return s * s * (0.5 + s * s * (-1.5 + s * (1.6 - 0.5 * s))); },  // s^2/2 - 3s^4/2 + 8s^5/5 - s^6/2
};

}  // namespace pilelab::coarse
