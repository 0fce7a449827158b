#pragma once
// The rigid shape of a grain or wall in its own frame: a convex polygon (vertices counter-
// clockwise, centroid at the origin) or a disc. Mass properties per unit areal density.
#include <vector>

#include "dem/vec2.h"

namespace pilelab::dem {

enum class ShapeKind { polygon = 0, disc = 1 };

struct Shape {
  ShapeKind kind = ShapeKind::polygon;
  std::vector<Vec2> vertices;  ///< body frame, counter-clockwise, centroid at origin (polygons) [m]
  double radius = 0.0;         ///< disc radius [m]; 0 for polygons
  double area = 0.0;           ///< [m^2]
  double polar_moment = 0.0;   ///< integral of |r|^2 over the shape about its centroid [m^4]
  double bounding_radius = 0.0;  ///< largest distance from centroid to boundary [m]
  double inner_radius = 0.0;     ///< smallest distance from centroid to boundary [m]
  double longest_edge = 0.0;     ///< [m]; 2*radius for a disc
};

/// Builds a polygon shape from vertices in any frame and order (at least 3, convex). The
/// vertices are reordered counter-clockwise and shifted so the centroid is the origin; the
/// shift is returned in centroid_out if given, so a caller can place the body where the
/// vertices were. Throws std::invalid_argument for degenerate or non-convex input.
Shape make_polygon(std::vector<Vec2> vertices, Vec2* centroid_out = nullptr);
Shape make_disc(double radius);

/// Area, centroid and polar second moment about the centroid of a simple polygon (CCW).
struct PolygonMoments {
  double area;
  Vec2 centroid;
  double polar_moment_about_centroid;
};
PolygonMoments polygon_moments(const std::vector<Vec2>& ccw_vertices);

}  // namespace pilelab::dem
