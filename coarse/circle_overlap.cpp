#include "coarse/circle_overlap.h"

#include <algorithm>
#include <cmath>

#include "common/portable_math.h"

namespace pilelab::coarse {

using dem::Vec2;

namespace {
// Signed sector area between directions p and q (radius r, angle from p to q in (-pi, pi]).
double sector(const Vec2& p, const Vec2& q, double r) {
  return 0.5 * r * r * portable_atan2(dem::cross(p, q), p.dot(q));
}
}  // namespace

double circle_sector_clip_area(const Vec2& c, double r, const Vec2& a_world, const Vec2& b_world) {
  const Vec2 a = a_world - c, b = b_world - c;
  const double r2 = r * r;
  const bool a_in = a.squaredNorm() <= r2, b_in = b.squaredNorm() <= r2;
  if (a_in && b_in) return 0.5 * dem::cross(a, b);
  // Points a + t (b - a) on the circle: |d|^2 t^2 + 2 (a.d) t + |a|^2 - r^2 = 0.
  const Vec2 d = b - a;
  const double A = d.squaredNorm();
  if (A == 0) return 0.0;
  const double B = a.dot(d), C = a.squaredNorm() - r2;
  const double disc = B * B - A * C;
  if (disc <= 0) return sector(a, b, r);  // the chord misses the circle
  const double root = std::sqrt(disc);
  const double t1 = (-B - root) / A, t2 = (-B + root) / A;  // t1 <= t2
  if (a_in) {  // leaves the circle at t2
    const Vec2 p = a + t2 * d;
    return 0.5 * dem::cross(a, p) + sector(p, b, r);
  }
  if (b_in) {  // enters at t1
    const Vec2 p = a + t1 * d;
    return sector(a, p, r) + 0.5 * dem::cross(p, b);
  }
  if (t1 >= 1 || t2 <= 0) return sector(a, b, r);  // the segment lies outside
  const Vec2 p = a + t1 * d, q = a + t2 * d;
  return sector(a, p, r) + 0.5 * dem::cross(p, q) + sector(q, b, r);
}

double circle_polygon_area(const Vec2& centre, double radius, const std::vector<Vec2>& polygon) {
  double area = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
    area += circle_sector_clip_area(centre, radius, polygon[i], polygon[(i + 1) % polygon.size()]);
  return area;
}

double circle_circle_area(const Vec2& c1, double r1, const Vec2& c2, double r2) {
  const double d = (c2 - c1).norm();
  if (d >= r1 + r2) return 0.0;
  const double rmin = std::min(r1, r2);
  if (d <= std::abs(r1 - r2)) return M_PI * rmin * rmin;
  // Two circular segments cut by the common chord.
  const double x1 = (d * d + r1 * r1 - r2 * r2) / (2 * d);  // chord distance from c1
  const double x2 = d - x1;
  const double h = std::sqrt(std::max(0.0, r1 * r1 - x1 * x1));
  const double seg1 = r1 * r1 * std::acos(std::clamp(x1 / r1, -1.0, 1.0)) - x1 * h;
  const double seg2 = r2 * r2 * std::acos(std::clamp(x2 / r2, -1.0, 1.0)) - x2 * h;
  return seg1 + seg2;
}

}  // namespace pilelab::coarse
