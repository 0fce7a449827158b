#include "dem/shape.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pilelab::dem {

PolygonMoments polygon_moments(const std::vector<Vec2>& v) {
  // Shoelace sums for area, first and second moments about the origin (Green's theorem).
  double a2 = 0.0, cx = 0.0, cy = 0.0, jo = 0.0;
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& p = v[i];
    const Vec2& q = v[(i + 1) % n];
    const double c = cross(p, q);
    a2 += c;
    cx += (p.x() + q.x()) * c;
    cy += (p.y() + q.y()) * c;
    jo += c * (p.x() * p.x() + p.x() * q.x() + q.x() * q.x() + p.y() * p.y() + p.y() * q.y() + q.y() * q.y());
  }
  const double area = 0.5 * a2;
  const Vec2 centroid(cx / (3.0 * a2), cy / (3.0 * a2));
  const double j_origin = jo / 12.0;
  return {area, centroid, j_origin - area * centroid.squaredNorm()};  // parallel-axis theorem
}

Shape make_polygon(std::vector<Vec2> vertices, Vec2* centroid_out) {
  if (vertices.size() < 3) throw std::invalid_argument("a polygon needs at least 3 vertices");
  PolygonMoments m = polygon_moments(vertices);
  if (m.area < 0) {
    std::reverse(vertices.begin(), vertices.end());
    m = polygon_moments(vertices);
  }
  if (!(m.area > 0)) throw std::invalid_argument("polygon has zero area");
  Shape s;
  s.kind = ShapeKind::polygon;
  s.area = m.area;
  s.polar_moment = m.polar_moment_about_centroid;
  for (auto& p : vertices) p -= m.centroid;
  const std::size_t n = vertices.size();
  s.inner_radius = INFINITY;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = vertices[i];
    const Vec2& b = vertices[(i + 1) % n];
    const Vec2& c = vertices[(i + 2) % n];
    if (cross(b - a, c - b) <= 0) throw std::invalid_argument("polygon is not strictly convex");
    const double edge = (b - a).norm();
    s.longest_edge = std::max(s.longest_edge, edge);
    s.bounding_radius = std::max(s.bounding_radius, a.norm());
    s.inner_radius = std::min(s.inner_radius, cross(b - a, -a) / edge);  // distance of centroid to edge line
  }
  s.vertices = std::move(vertices);
  if (centroid_out) *centroid_out = m.centroid;
  return s;
}

Shape make_disc(double radius) {
  if (!(radius > 0)) throw std::invalid_argument("a disc needs a positive radius");
  Shape s;
  s.kind = ShapeKind::disc;
  s.radius = radius;
  s.area = M_PI * radius * radius;
  s.polar_moment = 0.5 * M_PI * radius * radius * radius * radius;
  s.bounding_radius = s.inner_radius = radius;
  s.longest_edge = 2.0 * radius;
  return s;
}

}  // namespace pilelab::dem
