// The Gaussian, exp(-s^2), cut at three widths (Goldhirsch 2010).
#include <cmath>

#include "coarse/kernel.h"

namespace pilelab::coarse {

extern const KernelShape gaussian_kernel = {
    "gaussian", "exp(-r^2/w^2), cut at 3 w", 3.0,
    [](double s) { return std::exp(-s * s); },
    [](double s) { return -0.5 * std::expm1(-s * s); },  // (1 - e^-s^2) / 2, exact for small s
};

}  // namespace pilelab::coarse
