#pragma once
// Narrow phase: the overlap of two convex shapes placed in the world, as the contact law of
// the paper (Appendix A.1) needs it: the overlap area A, the contact line (chord) joining the
// two points where the boundaries cross, the force point at the chord's midpoint, and the unit
// normal perpendicular to the chord.
//
// The normal and chord length are computed in a form that stays defined in degenerate cases:
// n * chord = (S_a - S_b) / 2, where S_a is the integral of a's outward normal over the part of
// a's boundary inside b (likewise S_b). For two crossing points S_a equals the chord turned by
// 90 degrees (the boundary pieces and the chord enclose the same region), so this is exactly
// the paper's chord; it is also the gradient of A with respect to a translation of b, which makes
// dA/dt = chord * (approach speed at the force point) exact for rigid motions.
#include "dem/vec2.h"

namespace pilelab::dem {

struct Overlap {
  double area = 0.0;   ///< overlap area [m^2]; 0: not touching
  double chord = 0.0;  ///< contact-line length [m]
  Vec2 point{0, 0};    ///< force point: midpoint of the chord (overlap centroid if the boundaries
                       ///< do not cross exactly twice: nested or degenerate overlaps) [m]
  Vec2 normal{0, 1};   ///< unit normal pointing from a to b
  int crossings = 0;   ///< number of boundary crossing points found
  bool touching() const { return area > 0.0; }
};

/// Two convex polygons in world coordinates, vertices counter-clockwise (at most 64 each).
/// centroid_a and centroid_b orient the normal when the chord is degenerate (nested or
/// identical polygons).
Overlap overlap_polygons(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                         const Vec2& centroid_b);

/// The same, given the longest edge of either polygon [m] (which sets the tolerance below which
/// a point counts as on a line, 1e-12 of it): the World passes it from the shapes rather than
/// measure the edges anew for every pair.
Overlap overlap_polygons(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                         const Vec2& centroid_b, double longest_edge);

/// Two discs: the lens of two circles.
Overlap overlap_discs(const Vec2& ca, double ra, const Vec2& cb, double rb);

/// A disc (centre c, radius r) and a convex polygon (CCW, world coordinates). The normal
/// points from the disc to the polygon.
Overlap overlap_disc_polygon(const Vec2& c, double r, const Vec2* b, int nb, const Vec2& centroid_b);

/// Maximum number of polygon corners supported by overlap_polygons.
constexpr int max_polygon_corners = 64;

}  // namespace pilelab::dem
