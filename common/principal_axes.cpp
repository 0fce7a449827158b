#include "common/principal_axes.h"

#include <cmath>

namespace pilelab {

PrincipalAxes principal_axes(double xx, double yy, double xy, double zero_scale) {
  // Eigenvalues: the centre of Mohr's circle plus and minus its radius.
  PrincipalAxes p;
  p.mean = 0.5 * (xx + yy);
  const double radius = std::hypot(0.5 * (xx - yy), xy);
  p.major = p.mean + radius;
  p.minor = p.mean - radius;
  // The major axis makes the angle theta with x where tan(2 theta) = 2 xy / (xx - yy), on the
  // branch that maximises the normal value: theta = atan2(2 xy, xx - yy) / 2 in (-90, 90],
  // then taken into [0, 180) (an axis, not a direction).
  // An isotropic tensor has no major axis: it reads 90 degrees (vertical, the axis gravity
  // picks out in a pile), whatever the signs of its zeros.
  double theta = radius > 0.0 ? 0.5 * std::atan2(2.0 * xy, xx - yy) * 180.0 / M_PI : 90.0;
  if (theta < 0.0) theta += 180.0;
  if (theta >= 180.0) theta -= 180.0;
  p.orientation_deg = theta;
  // |major| + |minor| rather than |major + minor|: bounded by 1 where a tension appears, and
  // equal to (major - minor) / (major + minor) wherever both have one sign.
  const double size = std::abs(p.major) + std::abs(p.minor);
  p.anisotropy = size > zero_scale ? (p.major - p.minor) / size : 0.0;
  return p;
}

}  // namespace pilelab
