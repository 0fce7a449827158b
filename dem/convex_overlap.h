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
#include <cstdint>

#include "dem/vec2.h"

namespace pilelab::dem {

struct Overlap {
  double area = 0.0;   ///< overlap area [m^2]; 0: not touching
  double chord = 0.0;  ///< contact-line length [m]
  Vec2 point{0, 0};    ///< force point: midpoint of the chord (overlap centroid if the boundaries
                       ///< do not cross exactly twice: nested or degenerate overlaps) [m]
  Vec2 normal{0, 1};   ///< unit normal pointing from a to b
  /// Where the overlap's centroid projects onto the contact line, from the force point along the
  /// tangent perp(normal) [m]. The contact law may act there instead (ForcePoint::area_centroid):
  /// a force proportional to the area is conservative only through that line (docs/DEM.md).
  double centroid_shift = 0.0;
  int crossings = 0;   ///< number of boundary crossing points found
  /// Not touching: a lower bound on the distance between the shapes [m], their separation
  /// along the axis that showed them apart (a separating edge's outward normal, or the line of
  /// centres); 0 where none did (the clip's answer). Along that axis, held where it was found,
  /// the separation shrinks by at most how far the shapes' points move (and the distance, which
  /// it bounds, likewise), which lets the World skip a pair until its grains have moved that far.
  double gap = 0.0;
  bool touching() const { return area > 0.0; }
};

/// What the narrow phase keeps of a polygon pair from one step to the next, so that a pair that
/// has barely moved is answered in a few cross products: the edges at which the boundaries
/// crossed (a contact), or an edge that separated the shapes (no contact). Only a hint: the
/// overlap is the same whatever it holds (stale, wrong or empty), so it need not be saved in a
/// checkpoint, and a pair seen for the first time starts from the default.
struct OverlapHint {
  enum Kind : std::uint8_t { none = 0, crossing = 1, separated_by_a = 2, separated_by_b = 3, separated_along_centres = 4 };
  std::uint8_t kind = none;
  /// crossing: a's edge where a's boundary enters b, b's edge there, a's edge where it leaves
  /// b, b's edge there; separated_by_a or _b: the separating edge in [0] (edge e joins corners
  /// e and e+1); separated_along_centres: the line of centres separated the shapes.
  std::uint8_t edge[4] = {0, 0, 0, 0};
};

/// Two convex polygons in world coordinates, vertices counter-clockwise (at most 64 each).
/// centroid_a and centroid_b, points inside each polygon (their centroids), orient the normal
/// when the chord is degenerate (nested or identical polygons).
Overlap overlap_polygons(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                         const Vec2& centroid_b);

/// The same, given the longest edge of either polygon [m] (which sets the tolerance below which
/// a point counts as on a line, 1e-12 of it): the World passes it from the shapes rather than
/// measure the edges anew for every pair.
Overlap overlap_polygons(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                         const Vec2& centroid_b, double longest_edge);

/// The same, starting from what the pair was at the last step and updating it. Shallow
/// overlaps, where the boundaries cross exactly twice, take a fast path (the chord joins the
/// two crossings, the overlap is the polygon of the corners between them); everything else
/// (deep or degenerate overlaps, nested shapes) is clipped.
inline Overlap overlap_polygons(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                                const Vec2& centroid_b, double longest_edge, OverlapHint& hint);

/// Two polygons farther apart than this fraction of the longer of their longest edges never
/// touch in overlap_polygons, whatever the hint: its tolerances (the clear margin of the fast
/// path, 1e-9 of the edge; the clip's on-the-line tolerance, 1e-12) are a thousand times
/// smaller and more. A caller that proves a pair this far apart may skip it and get the same
/// answer, zero, bit for bit.
constexpr double certain_separation = 1e-6;



/// Two discs: the lens of two circles.
Overlap overlap_discs(const Vec2& ca, double ra, const Vec2& cb, double rb);

/// A disc (centre c, radius r) and a convex polygon (CCW, world coordinates). The normal
/// points from the disc to the polygon.
Overlap overlap_disc_polygon(const Vec2& c, double r, const Vec2* b, int nb, const Vec2& centroid_b);

/// Maximum number of polygon corners supported by overlap_polygons.
constexpr int max_polygon_corners = 64;

}  // namespace pilelab::dem

// The hinted overload, inline (the DEM's innermost loop).
#include "dem/two_crossing_overlap.h"
