#include "dem/grain_generator.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/portable_math.h"

namespace pilelab::dem {

std::vector<double> jittered_corner_angles(int n, double jitter, Rng& rng) {
  std::vector<double> angles(n);
  for (int k = 0; k < n; ++k) angles[k] = 2.0 * M_PI * (k + rng.uniform(-jitter, jitter)) / n;
  return angles;
}

std::vector<double> random_corner_angles(int n, double min_gap_fraction, Rng& rng) {
  // n uniform points on the circle conditioned on every gap being at least g: their gaps are
  // g plus (2 pi - n g) times the spacings of n - 1 uniform points on [0, 1] (the uniform
  // spacings conditioned on a floor are the shifted, scaled uniform spacings), turned by a
  // uniform angle.
  const double floor = min_gap_fraction * 2.0 * M_PI / n, spare = 2.0 * M_PI - n * floor;
  std::vector<double> cuts(n - 1);
  for (double& u : cuts) u = rng.uniform();
  std::sort(cuts.begin(), cuts.end());
  std::vector<double> angles(n);
  double angle = rng.uniform(0.0, 2.0 * M_PI), previous_cut = 0.0;
  for (int k = 0; k < n; ++k) {
    angles[k] = angle;
    const double cut = k < n - 1 ? cuts[k] : 1.0;
    angle += floor + spare * (cut - previous_cut);
    previous_cut = cut;
  }
  return angles;
}

Shape random_grain(const GrainSpec& spec, Rng& rng) {
  const double lo = spec.smallest_diameter(), hi = spec.largest_diameter();
  if (spec.kind == ShapeKind::disc) return make_disc(0.5 * rng.uniform(lo, hi));
  const double semi_a = 0.5 * rng.uniform(lo, hi);
  const double semi_b = spec.outline == GrainOutline::circle ? semi_a : 0.5 * rng.uniform(lo, hi);
  const int n = rng.uniform_int(spec.corners_min, spec.corners_max);
  const std::vector<double> angles = spec.corner_placement == CornerPlacement::random
                                         ? random_corner_angles(n, spec.corner_min_gap, rng)
                                         : jittered_corner_angles(n, spec.corner_jitter, rng);
  std::vector<Vec2> corners(n);
  for (int k = 0; k < n; ++k) {
    double s, c;
    portable_sincos(angles[k], s, c);
    corners[k] = Vec2(semi_a * c, semi_b * s);
  }
  // Points in angular order on an ellipse always form a convex polygon.
  return make_polygon(std::move(corners));
}

}  // namespace pilelab::dem
