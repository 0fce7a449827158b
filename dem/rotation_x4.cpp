#include "dem/rotation_x4.h"

#include <cmath>
#include <cstdint>

#include "common/portable_math.h"
#include "dem/four_lanes.h"

namespace pilelab::dem {

// AVX2 where the processor has it, SSE2 otherwise: the same operations, the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void rotation_sincos_x4(const double* x_in, double* s, double* c, int count) {
  namespace d = portable_math_detail;
  for (int first = 0; first < count; first += 4) {
    const int lanes = count - first < 4 ? count - first : 4;
    Double4 x = {0.0, 0.0, 0.0, 0.0};
    for (int lane = 0; lane < lanes; ++lane) x[lane] = x_in[first + lane];
    // rotation_sincos's fast path, operation for operation (see there for the mathematics).
    const Double4 round_shift = {0x1.8p52, 0x1.8p52, 0x1.8p52, 0x1.8p52};
    const Double4 k = (x * d::two_over_pi + round_shift) - round_shift;
    const Double4 r = ((x - k * d::pio2_1) - k * d::pio2_2) - k * d::pio2_3;
    const Double4 z = r * r;
    const Double4 p = -1.0 / 6 + z * (1.0 / 120 + z * (-1.0 / 5040 + z * (1.0 / 362880 + z * (-1.0 / 39916800 +
                      z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0 + z * (1.0 / 355687428096000.0)))))));
    const Double4 q = 1.0 / 24 + z * (-1.0 / 720 + z * (1.0 / 40320 + z * (-1.0 / 3628800 + z * (1.0 / 479001600.0 +
                      z * (-1.0 / 87178291200.0 + z * (1.0 / 20922789888000.0 + z * (-1.0 / 6402373705728000.0)))))));
    const Double4 sr = r + r * z * p;
    const Double4 half_z = 0.5 * z, w = 1.0 - half_z;
    const Double4 cr = w + (((1.0 - w) - half_z) + z * z * q);
    for (int lane = 0; lane < lanes; ++lane) {
      const double a = x[lane];
      double& sine = s[first + lane];
      double& cosine = c[first + lane];
      if (!(std::abs(a) < 0x1p20) || std::abs(a) < 0x1p-27) {  // the slow path's arguments
        rotation_sincos(a, sine, cosine);
        continue;
      }
      const int quadrant = static_cast<int>(static_cast<std::int64_t>(k[lane]) & 3);
      const double turn[4] = {sr[lane], cr[lane], -sr[lane], -cr[lane]};
      sine = turn[quadrant];
      cosine = turn[(quadrant + 1) & 3];
    }
  }
}

}  // namespace pilelab::dem
