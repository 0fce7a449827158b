#include "dem/grain_generator.h"

#include <cmath>
#include <vector>

#include "common/portable_math.h"

namespace pilelab::dem {

Shape random_grain(const GrainSpec& spec, Rng& rng) {
  const double lo = spec.smallest_diameter(), hi = spec.largest_diameter();
  if (spec.kind == ShapeKind::disc) return make_disc(0.5 * rng.uniform(lo, hi));
  const double semi_a = 0.5 * rng.uniform(lo, hi);
  const double semi_b = spec.outline == GrainOutline::circle ? semi_a : 0.5 * rng.uniform(lo, hi);
  const int n = rng.uniform_int(spec.corners_min, spec.corners_max);
  std::vector<Vec2> corners(n);
  for (int k = 0; k < n; ++k) {
    const double phi = 2.0 * M_PI * (k + rng.uniform(-spec.corner_jitter, spec.corner_jitter)) / n;
    double s, c;
    portable_sincos(phi, s, c);
    corners[k] = Vec2(semi_a * c, semi_b * s);
  }
  // Points in angular order on an ellipse always form a convex polygon.
  return make_polygon(std::move(corners));
}

}  // namespace pilelab::dem
