#include "dem/rotation_x4.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "common/portable_math.h"
#include "dem/four_lanes.h"

namespace pilelab::dem {

PILELAB_AVX2_AND_SSE2
void rotation_sincos_x4(const double* x_in, double* s, double* c, int count) {
  namespace d = portable_math_detail;
  for (int first = 0; first < count; first += 4) {
    const int lanes = count - first < 4 ? count - first : 4;
    Double4 x = {0.0, 0.0, 0.0, 0.0};
    for (int lane = 0; lane < lanes; ++lane) x[lane] = x_in[first + lane];
    // rotation_sincos's fast path, operation for operation (see there for the mathematics).
    const Double4 round_shift = {0x1.8p52, 0x1.8p52, 0x1.8p52, 0x1.8p52};
    const Double4 shifted = x * d::two_over_pi + round_shift;
    const Double4 k = shifted - round_shift;
    const Double4 r = ((x - k * d::pio2_1) - k * d::pio2_2) - k * d::pio2_3;
    const Double4 z = r * r;
    const Double4 p = -1.0 / 6 + z * (1.0 / 120 + z * (-1.0 / 5040 + z * (1.0 / 362880 + z * (-1.0 / 39916800 +
                      z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0 + z * (1.0 / 355687428096000.0)))))));
    const Double4 q = 1.0 / 24 + z * (-1.0 / 720 + z * (1.0 / 40320 + z * (-1.0 / 3628800 + z * (1.0 / 479001600.0 +
                      z * (-1.0 / 87178291200.0 + z * (1.0 / 20922789888000.0 + z * (-1.0 / 6402373705728000.0)))))));
    const Double4 sr = r + r * z * p;
    const Double4 half_z = 0.5 * z, w = 1.0 - half_z;
    const Double4 cr = w + (((1.0 - w) - half_z) + z * z * q);
    // The quadrant, k mod 4: shifted is 1.5 2^52 + k, whose last bits are k's (k is an integer
    // and 2^51 a multiple of 4). Quadrants 0-3 give (sin, cos) = (sr, cr), (cr, -sr), (-sr, -cr),
    // (-cr, sr): odd ones swap the two, the sine is negated in 2 and 3, the cosine in 1 and 2.
    const Mask4 quadrant = (Mask4)shifted & 3;
    const Mask4 odd = (quadrant & 1) != 0;
    const Double4 sine = odd ? cr : sr, cosine = odd ? sr : cr;
    const Double4 flip_sine = (quadrant & 2) != 0 ? -sine : sine;
    const Double4 flip_cosine = ((quadrant + 1) & 2) != 0 ? -cosine : cosine;
    const Double4 ax = lane_abs(x);
    const Mask4 slow = ~(ax < 0x1p20) | (ax < 0x1p-27);  // the slow path's arguments (NaN too)
    if (lanes == 4 && !(slow[0] | slow[1] | slow[2] | slow[3])) {
      std::memcpy(s + first, &flip_sine, sizeof flip_sine);
      std::memcpy(c + first, &flip_cosine, sizeof flip_cosine);
      continue;
    }
    for (int lane = 0; lane < lanes; ++lane) {
      if (slow[lane]) {
        rotation_sincos(x[lane], s[first + lane], c[first + lane]);
      } else {
        s[first + lane] = flip_sine[lane];
        c[first + lane] = flip_cosine[lane];
      }
    }
  }
}

}  // namespace pilelab::dem
