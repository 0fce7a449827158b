#pragma once
// The narrow phase's fast path (convex_overlap.h), inline: the overlap of a polygon pair from
// what it was at the last step, which the DEM's pair loop evaluates for every touching pair of
// every step, compiled into that loop. Included by convex_overlap.h; not a header of its own.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "dem/convex_overlap.h"
#include "dem/four_lanes.h"
#include "dem/vec2.h"

namespace pilelab::dem {

namespace two_crossing {

// --- The two-crossing fast path -----------------------------------------------------------
//
// In a pile almost every overlap is shallow: the boundaries cross exactly twice, at X1 where
// a's boundary enters b (a's edge i crossing b's edge k) and at X2 where it leaves (a's edge
// j crossing b's edge l). The overlap is then the polygon
//     X1, a[i+1], ..., a[j], X2, b[l+1], ..., b[k]
// (a's corners inside b, then b's corners inside a), the contact line is X1 X2, and
// n * chord = (S_a - S_b) / 2 = outward(X2 - X1), since the outward-normal integral of a path
// depends only on its ends. Given the four edges this costs a few cross products, and a pair
// that barely moved since the last step crosses at the same edges.
//
// The edges are accepted only if they prove the configuration: each crossing is a proper one
// (every corner involved lies clearly, by more than a margin, on its side of the other edge's
// line) and every corner listed as inside the other shape lies clearly inside it. Then the
// closed path above lies in the boundary of the intersection and runs once around it, so it is
// the whole boundary: the boundaries cross nowhere else. A configuration that passes therefore
// has one answer whichever way its edges were found, so the hint never changes the result;
// anything closer to degenerate than the margin goes to the clip.

// The margin, as a fraction of the longest edge: far above round-off (1e-16), far below any
// contact that matters (a corner 1e-9 of an edge deep is picometres for sand grains).
inline constexpr double clear_margin = 1e-9;

inline int next_index(int i, int n) { return i + 1 == n ? 0 : i + 1; }

// |d| times the signed distance of p from the line through e0 along d (> 0: left, the inside
// of a counter-clockwise polygon).
inline double side_of(const Vec2& d, const Vec2& e0, const Vec2& p) { return cross(d, p - e0); }
inline bool clearly_left(double side, double d2, double margin2) { return side > 0.0 && side * side > margin2 * d2; }
inline bool clearly_right(double side, double d2, double margin2) { return side < 0.0 && side * side > margin2 * d2; }

// The fast path is written in plain doubles: Eigen's packed 2-vectors cost a shuffle in every
// cross product, and this is the innermost loop of the DEM. The operations are the ones the
// vector forms would perform, in the same order.
struct Point {
  double x, y;
};
inline Point point_at(const Vec2* p, int i) { return {p[i].x(), p[i].y()}; }
// |d| times the signed distance of p from the line through e0 along d = (dx, dy).
inline double side_of(double dx, double dy, const Point& e0, const Point& p) {
  return dx * (p.y - e0.y) - dy * (p.x - e0.x);
}

// p lies inside the convex polygon (CCW), farther than the margin from every edge's line.
inline bool clearly_inside(const Point& p, const Vec2* poly, int n, double margin2) {
  Point e0 = point_at(poly, n - 1);
  for (int k = 0; k < n; ++k) {
    const Point e1 = point_at(poly, k);
    const double dx = e1.x - e0.x, dy = e1.y - e0.y;
    const double side = side_of(dx, dy, e0, p);
    if (!(side > 0.0 && side * side > margin2 * (dx * dx + dy * dy))) return false;
    e0 = e1;
  }
  return true;
}

// Where a's edge i properly crosses b's edge k, a passing from one side of b's edge to the
// other (entering: from the right, outside, to the left), or false: every corner involved lies
// clearly on its side of the other edge's line. The point lies on a's edge, at the parameter
// the clip computes.
template <bool entering>
[[gnu::always_inline]] inline bool proper_crossing(const Vec2* a, int na, int i, const Vec2* b, int nb, int k, double margin2, Point& x) {
  const Point a0 = point_at(a, i), a1 = point_at(a, next_index(i, na));
  const Point b0 = point_at(b, k), b1 = point_at(b, next_index(k, nb));
  const double dax = a1.x - a0.x, day = a1.y - a0.y, dbx = b1.x - b0.x, dby = b1.y - b0.y;
  const double s0 = side_of(dbx, dby, b0, a0), s1 = side_of(dbx, dby, b0, a1);  // a's corners against b's edge
  const double t0 = side_of(dax, day, a0, b0), t1 = side_of(dax, day, a0, b1);  // b's corners against a's edge
  // Entering b, a goes from outside to inside b's edge, and b's edge from inside a to outside.
  const bool signs = entering ? (s0 < 0.0 && s1 > 0.0 && t0 > 0.0 && t1 < 0.0)
                              : (s0 > 0.0 && s1 < 0.0 && t0 < 0.0 && t1 > 0.0);
  if (!signs) return false;
  const double ma = margin2 * (dax * dax + day * day), mb = margin2 * (dbx * dbx + dby * dby);
  if (!(s0 * s0 > mb && s1 * s1 > mb && t0 * t0 > ma && t1 * t1 > ma)) return false;
  const double t = s0 / (s0 - s1);
  x = {a0.x + t * dax, a0.y + t * day};
  return true;
}

// A triangle (counter-clockwise) with its edges, to test points against it.
struct Triangle {
  Point corner[3];
  double dx[3], dy[3], length2[3];
  [[gnu::always_inline]] Triangle(const Point& p0, const Point& p1, const Point& p2) : corner{p0, p1, p2} {
    for (int m = 0; m < 3; ++m) {
      const Point& next = corner[m == 2 ? 0 : m + 1];
      dx[m] = next.x - corner[m].x;
      dy[m] = next.y - corner[m].y;
      length2[m] = dx[m] * dx[m] + dy[m] * dy[m];
    }
  }
  [[gnu::always_inline]] bool clearly_contains(const Point& p, double margin2) const {
    for (int m = 0; m < 3; ++m) {
      const double side = side_of(dx[m], dy[m], corner[m], p);
      if (!(side > 0.0 && side * side > margin2 * length2[m])) return false;
    }
    return true;
  }
};

// p lies left of the line e0 -> e1, farther than the margin from it. (Inlined by force: as a
// lambda GCC kept it a call, three of them for every contact.)
[[gnu::always_inline]] inline bool clearly_left_of_edge(const Point& e0, const Point& e1, const Point& p, double margin2) {
  const double dx = e1.x - e0.x, dy = e1.y - e0.y;
  const double side = side_of(dx, dy, e0, p);
  return side > 0.0 && side * side > margin2 * (dx * dx + dy * dy);
}

// p lies in the triangle p0 p1 p2 (counter-clockwise), farther than the margin from each edge's
// line: Triangle::clearly_contains for a single point, each edge formed only when the one
// before has passed (the same operations, so the same answer).
[[gnu::always_inline]] inline bool clearly_in_triangle(const Point& p0, const Point& p1, const Point& p2, const Point& p,
                                                       double margin2) {
  return clearly_left_of_edge(p0, p1, p, margin2) && clearly_left_of_edge(p1, p2, p, margin2) &&
         clearly_left_of_edge(p2, p0, p, margin2);
}

// The overlap of a two-crossing configuration from its crossings X1 (a enters b) and X2, twice
// its area and its centroid.
[[gnu::always_inline]] inline bool two_crossing_result(const Point& x1, const Point& x2, double a2, const Point& centroid,
                                                       double margin, Overlap& o) {
  const double area = 0.5 * a2;
  if (!(area > 0.0)) return false;
  const double lx = x2.x - x1.x, ly = x2.y - x1.y;
  const double chord = std::sqrt(lx * lx + ly * ly);
  if (!(chord > margin)) return false;
  o.area = area;
  o.chord = chord;
  o.normal = Vec2(ly / chord, -lx / chord);  // outward(X2 - X1) / chord
  const double mid_x = 0.5 * (x1.x + x2.x), mid_y = 0.5 * (x1.y + x2.y);
  o.point = Vec2(mid_x, mid_y);
  o.centroid_shift = ((centroid.x - mid_x) * lx + (centroid.y - mid_y) * ly) / chord;  // along t = (X2 - X1) / chord
  o.crossings = 2;
  return true;
}

// The contact of a pile, spelt out: one corner c of polygon p lies in an edge e0 -> e1 of
// polygon q (corners q_corners[0..q_count)), p's edges into and out of it (p0 -> c, c -> p2)
// crossing that edge at X_in and X_out; the overlap is the triangle X_in, c, X_out. The same
// tests and operations as the general case below, on the six sides it needs instead of eight
// (two are shared), without its loops. Returns false where the general case would.
[[gnu::always_inline]] inline bool corner_in_edge(const Point& p0, const Point& c, const Point& p2, const Point& e0, const Point& e1,
                    const Point& q_centroid, const Vec2* q_corners, int q_count, double margin2, Point& x_in, Point& x_out,
                    double& a2, Point& centroid) {
  const double d0x = c.x - p0.x, d0y = c.y - p0.y, d2x = p2.x - c.x, d2y = p2.y - c.y;
  const double dex = e1.x - e0.x, dey = e1.y - e0.y;
  const double s0 = side_of(dex, dey, e0, p0), s1 = side_of(dex, dey, e0, c), s2 = side_of(dex, dey, e0, p2);
  if (!(s0 < 0.0 && s1 > 0.0 && s2 < 0.0)) return false;
  const double t0 = side_of(d0x, d0y, p0, e0), t1 = side_of(d0x, d0y, p0, e1);  // q's edge against p0 -> c
  const double u0 = side_of(d2x, d2y, c, e0), u1 = side_of(d2x, d2y, c, e1);    // and against c -> p2
  if (!(t0 > 0.0 && t1 < 0.0 && u0 < 0.0 && u1 > 0.0)) return false;
  const double me = margin2 * (dex * dex + dey * dey), m0 = margin2 * (d0x * d0x + d0y * d0y),
               m2 = margin2 * (d2x * d2x + d2y * d2y);
  if (!(s0 * s0 > me && s1 * s1 > me && t0 * t0 > m0 && t1 * t1 > m0)) return false;
  if (!(s1 * s1 > me && s2 * s2 > me && u0 * u0 > m2 && u1 * u1 > m2)) return false;
  const double r_in = s0 / (s0 - s1), r_out = s1 / (s1 - s2);
  x_in = {p0.x + r_in * d0x, p0.y + r_in * d0y};
  x_out = {c.x + r_out * d2x, c.y + r_out * d2y};
  // The corner must lie in q: in the triangle of the chord and q's centroid (three sides), or
  // else inside every edge (an oblique push near the end of a long edge).
  if (!clearly_in_triangle(x_out, x_in, q_centroid, c, margin2) && !clearly_inside(c, q_corners, q_count, margin2))
    return false;
  const double qx = c.x - x_in.x, qy = c.y - x_in.y, rx = x_out.x - x_in.x, ry = x_out.y - x_in.y;
  a2 = (0.0 * qy - 0.0 * qx) + (qx * ry - qy * rx);  // the shoelace about X_in, as the general case sums it
  centroid = {(x_in.x + c.x + x_out.x) / 3.0, (x_in.y + c.y + x_out.y) / 3.0};
  return true;
}

// The general two-crossing configuration (any chains of corners between the crossings).
[[gnu::noinline]] inline bool general_two_crossing(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                                            const Vec2& centroid_b, int i, int k, int j, int l, double margin,
                                            Overlap& o) {
  const double margin2 = margin * margin;
  Point x1, x2;
  if (!proper_crossing<true>(a, na, i, b, nb, k, margin2, x1)) return false;
  if (!proper_crossing<false>(a, na, j, b, nb, l, margin2, x2)) return false;
  const double lx = x2.x - x1.x, ly = x2.y - x1.y;  // the chord, X1 to X2
  // The chains of corners between the crossings: a's from i+1 to j, b's from l+1 to k.
  const int a_chain = j >= i ? j - i : j - i + na, b_chain = k >= l ? k - l : k - l + nb;
  if (a_chain == 0 && b_chain == 0) return false;  // two segments cannot cross twice
  // On one edge both crossings lie on it in the order the path takes.
  if (a_chain == 0) {
    const Point a0 = point_at(a, i), a1 = point_at(a, next_index(i, na));
    if (lx * (a1.x - a0.x) + ly * (a1.y - a0.y) <= 0.0) return false;
  }
  if (b_chain == 0) {
    const Point b0 = point_at(b, k), b1 = point_at(b, next_index(k, nb));
    if (-lx * (b1.x - b0.x) - ly * (b1.y - b0.y) <= 0.0) return false;
  }
  // Each chain must lie inside the other shape. The triangle of the chord and the other
  // shape's centroid lies inside that shape (it is convex), and holds the corners of a shallow
  // contact: three cross products prove what testing every edge would.
  if (a_chain > 0) {
    const Triangle in_b(x2, x1, {centroid_b.x(), centroid_b.y()});
    for (int m = 1, v = next_index(i, na); m <= a_chain; ++m, v = next_index(v, na)) {
      const Point p = point_at(a, v);
      if (!in_b.clearly_contains(p, margin2) && !clearly_inside(p, b, nb, margin2)) return false;
    }
  }
  if (b_chain > 0) {
    const Triangle in_a(x1, x2, {centroid_a.x(), centroid_a.y()});
    for (int m = 1, v = next_index(l, nb); m <= b_chain; ++m, v = next_index(v, nb)) {
      const Point p = point_at(b, v);
      if (!in_a.clearly_contains(p, margin2) && !clearly_inside(p, a, na, margin2)) return false;
    }
  }
  // Shoelace about X1, so that the round-off scales with the overlap, not with |X1|. The
  // closing edge back to X1 contributes nothing.
  // mx, my: three times the area's first moment about X1, for its centroid.
  double a2 = 0.0, mx = 0.0, my = 0.0, px = 0.0, py = 0.0;  // px, py: the last corner, relative to X1
  const auto add = [&](const Point& p) {
    const double qx = p.x - x1.x, qy = p.y - x1.y;
    const double c = px * qy - py * qx;
    a2 += c;
    mx += (px + qx) * c;
    my += (py + qy) * c;
    px = qx;
    py = qy;
  };
  for (int m = 1, v = next_index(i, na); m <= a_chain; ++m, v = next_index(v, na)) add(point_at(a, v));
  add(x2);
  for (int m = 1, v = next_index(l, nb); m <= b_chain; ++m, v = next_index(v, nb)) add(point_at(b, v));
  return two_crossing_result(x1, x2, a2, {x1.x + mx / (3.0 * a2), x1.y + my / (3.0 * a2)}, margin, o);
}

// One corner of each polygon inside the other, the usual shape of a flat face pressed on a flat
// face: a's corner j = i + 1 in b, b's corner k = l + 1 in a, and the overlap the quadrilateral
// X1, a[j], X2, b[k]. general_two_crossing's tests and operations for chains of one corner
// each, in its order, without its loops; returns false where it would.
[[gnu::always_inline]] inline bool corner_each(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                                               const Vec2& centroid_b, int i, int k, int j, int l, double margin2,
                                               Point& x1, Point& x2, double& a2, Point& centroid) {
  if (!proper_crossing<true>(a, na, i, b, nb, k, margin2, x1)) return false;
  if (!proper_crossing<false>(a, na, j, b, nb, l, margin2, x2)) return false;
  const Point in_b = point_at(a, j), in_a = point_at(b, k);
  if (!clearly_in_triangle(x2, x1, {centroid_b.x(), centroid_b.y()}, in_b, margin2) &&
      !clearly_inside(in_b, b, nb, margin2))
    return false;
  if (!clearly_in_triangle(x1, x2, {centroid_a.x(), centroid_a.y()}, in_a, margin2) &&
      !clearly_inside(in_a, a, na, margin2))
    return false;
  // The shoelace about X1 over a[j], X2, b[k], term by term as the general case sums it.
  double px = 0.0, py = 0.0, mx = 0.0, my = 0.0;
  a2 = 0.0;
  for (const Point& p : {in_b, x2, in_a}) {
    const double qx = p.x - x1.x, qy = p.y - x1.y;
    const double c = px * qy - py * qx;
    a2 += c;
    mx += (px + qx) * c;
    my += (py + qy) * c;
    px = qx;
    py = qy;
  }
  centroid = {x1.x + mx / (3.0 * a2), x1.y + my / (3.0 * a2)};
  return true;
}

// The overlap from the four crossing edges, if they prove a two-crossing configuration.
// centroid_a and centroid_b must lie inside their polygons. The two shapes of a shallow
// contact, a corner of a in an edge of b or of b in an edge of a, and a corner of each in the
// other are spelt out; the hot path of the DEM is this function with those three branches.
[[gnu::always_inline]] inline bool two_crossing_overlap(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b,
                                                        int nb, const Vec2& centroid_b, const std::uint8_t edge[4],
                                                        double margin, Overlap& o) {
  const int i = edge[0], k = edge[1], j = edge[2], l = edge[3];
  if (i >= na || j >= na || k >= nb || l >= nb) return false;
  const double margin2 = margin * margin;
  Point x1, x2, centroid;
  double a2 = 0.0;
  if (k == l && j == next_index(i, na)) {
    if (corner_in_edge(point_at(a, i), point_at(a, j), point_at(a, next_index(j, na)), point_at(b, k),
                       point_at(b, next_index(k, nb)), {centroid_b.x(), centroid_b.y()}, b, nb, margin2, x1, x2, a2, centroid))
      return two_crossing_result(x1, x2, a2, centroid, margin, o);
  } else if (i == j && k == next_index(l, nb)) {
    // b's corner k in a's edge i: b's edges l -> k and k -> k+1 cross it at X2 and X1.
    if (corner_in_edge(point_at(b, l), point_at(b, k), point_at(b, next_index(k, nb)), point_at(a, i),
                       point_at(a, next_index(i, na)), {centroid_a.x(), centroid_a.y()}, a, na, margin2, x2, x1, a2, centroid))
      return two_crossing_result(x1, x2, a2, centroid, margin, o);
  } else if (j == next_index(i, na) && k == next_index(l, nb)) {
    if (corner_each(a, na, centroid_a, b, nb, centroid_b, i, k, j, l, margin2, x1, x2, a2, centroid))
      return two_crossing_result(x1, x2, a2, centroid, margin, o);
    return false;
  }
  return general_two_crossing(a, na, centroid_a, b, nb, centroid_b, i, k, j, l, margin, o);
}

// If q's corners all lie clearly outside the line of p's edge e, the edge separates the two
// shapes: then how far q lies beyond the line [m] (positive), else 0.
inline double separation_beyond_edge(const Vec2* p, int np, int e, const Vec2* q, int nq, double margin2) {
  if (e >= np) return 0.0;
  const Vec2 d = p[next_index(e, np)] - p[e];
  const double d2 = d.squaredNorm();
  double nearest = INFINITY;  // |d| times the nearest corner's distance beyond the line
  for (int m = 0; m < nq; ++m) {
    const double side = side_of(d, p[e], q[m]);
    if (!clearly_right(side, d2, margin2)) return 0.0;
    nearest = std::min(nearest, -side);
  }
  return nearest / std::sqrt(d2);
}

// If the projections of the two shapes on the line of centres do not meet, how far apart they
// lie [m] (positive), else 0.
inline double separation_along_centres(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                                       const Vec2& centroid_b) {
  const double ax = centroid_b.x() - centroid_a.x(), ay = centroid_b.y() - centroid_a.y();
  double max_a = -INFINITY, min_b = INFINITY;
  for (int i = 0; i < na; ++i) max_a = std::max(max_a, ax * a[i].x() + ay * a[i].y());
  for (int k = 0; k < nb; ++k) min_b = std::min(min_b, ax * b[k].x() + ay * b[k].y());
  if (!(max_a < min_b)) return 0.0;
  return (min_b - max_a) / std::sqrt(ax * ax + ay * ay);
}

// Everything but the hint's answer: the line of centres, a search for the crossing edges or a
// separating edge, and the clip (convex_overlap.cpp).
[[gnu::noinline]] Overlap search_overlap(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                                         const Vec2& centroid_b, double longest_edge, OverlapHint& hint);

}  // namespace two_crossing

[[gnu::always_inline]] inline Overlap overlap_polygons(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                         const Vec2& centroid_b, double longest_edge, OverlapHint& hint) {
  const double margin = two_crossing::clear_margin * longest_edge;
  // What the pair was last step, if it still holds.
  Overlap o;
  switch (hint.kind) {
    case OverlapHint::crossing:
      if (two_crossing::two_crossing_overlap(a, na, centroid_a, b, nb, centroid_b, hint.edge, margin, o)) return o;
      break;
    case OverlapHint::separated_by_a:
      o.gap = two_crossing::separation_beyond_edge(a, na, hint.edge[0], b, nb, margin * margin);
      if (o.gap > 0.0) return o;
      break;
    case OverlapHint::separated_by_b:
      o.gap = two_crossing::separation_beyond_edge(b, nb, hint.edge[0], a, na, margin * margin);
      if (o.gap > 0.0) return o;
      break;
    case OverlapHint::separated_along_centres:
      o.gap = two_crossing::separation_along_centres(a, na, centroid_a, b, nb, centroid_b);
      if (o.gap > 0.0) return o;
      break;
    default: break;
  }
  return two_crossing::search_overlap(a, na, centroid_a, b, nb, centroid_b, longest_edge, hint);
}

}  // namespace pilelab::dem

namespace pilelab::dem::two_crossing {

// The shape of a hint of a corner of one polygon in an edge of the other, from the hint alone: a
// crossing whose boundary enters and leaves through one edge of exactly one of the polygons.
// The pair loop sorts its pairs by it before it reads their grains.
inline bool corner_in_edge_shape(const OverlapHint& hint) {
  return hint.kind == OverlapHint::crossing && ((hint.edge[1] == hint.edge[3]) != (hint.edge[0] == hint.edge[2]));
}

// A hint of a corner of one polygon in an edge of the other, with edges that exist: the first
// two shapes of two_crossing_overlap, which corner_in_edge_x4 answers.
inline bool corner_in_edge_hint(const OverlapHint& hint, int na, int nb) {
  if (!corner_in_edge_shape(hint)) return false;
  const int i = hint.edge[0], k = hint.edge[1], j = hint.edge[2], l = hint.edge[3];
  if (i >= na || j >= na || k >= nb || l >= nb) return false;
  return (k == l && j == next_index(i, na)) || (i == j && k == next_index(l, nb));
}

// Four corner-in-edge contacts at once, in the lanes of 256-bit vectors (four_lanes.h): for each lane the operations of corner_in_edge and two_crossing_result in
// the same order, so the same bits, and ok false wherever either would return false (then the
// caller answers that pair the scalar way). A lane is a corner c of one polygon, its neighbours
// p0 and p2 (counter-clockwise p0, c, p2), the other polygon's edge e0 -> e1 and that polygon's
// centroid; the chord runs from where p0 -> c crosses the edge to where c -> p2 does.
struct CornerInEdgeBatch {
  Double4 p0x, p0y, cx, cy, p2x, p2y, e0x, e0y, e1x, e1y, qx, qy, margin;
  Mask4 chord_reversed;  ///< the chord from where c -> p2 crosses to where p0 -> c does (b's corner in a)
};
struct CornerInEdgeOverlaps {
  Double4 area, chord, point_x, point_y, normal_x, normal_y, centroid_shift;
  Mask4 ok;
  /// Every test passed but the corner's in the triangle of the chord and the centroid: the lane
  /// is corner_in_edge's overlap if the corner lies clearly inside every edge of the edge's
  /// polygon (clearly_inside, for the caller, which has the polygon).
  Mask4 needs_polygon_test;
};
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
[[gnu::always_inline]] inline Double4 side_of(Double4 dx, Double4 dy, Double4 e0x, Double4 e0y, Double4 px, Double4 py) {
  return dx * (py - e0y) - dy * (px - e0x);
}
[[gnu::always_inline]] inline Mask4 clearly_left_of_edge(Double4 e0x, Double4 e0y, Double4 e1x, Double4 e1y, Double4 px, Double4 py,
                                  Double4 margin2) {
  const Double4 dx = e1x - e0x, dy = e1y - e0y;
  const Double4 side = side_of(dx, dy, e0x, e0y, px, py);
  return (side > 0.0) & (side * side > margin2 * (dx * dx + dy * dy));
}
/// The four lanes' overlaps, inlined into a caller compiled for its own instruction set (the
/// DEM's pair loop, cloned for AVX2).
[[gnu::always_inline]] inline void corner_in_edge_lanes(const CornerInEdgeBatch& in, CornerInEdgeOverlaps& out) {
  const Double4 margin2 = in.margin * in.margin;
  const Double4 d0x = in.cx - in.p0x, d0y = in.cy - in.p0y, d2x = in.p2x - in.cx, d2y = in.p2y - in.cy;
  const Double4 dex = in.e1x - in.e0x, dey = in.e1y - in.e0y;
  const Double4 s0 = side_of(dex, dey, in.e0x, in.e0y, in.p0x, in.p0y);
  const Double4 s1 = side_of(dex, dey, in.e0x, in.e0y, in.cx, in.cy);
  const Double4 s2 = side_of(dex, dey, in.e0x, in.e0y, in.p2x, in.p2y);
  const Double4 t0 = side_of(d0x, d0y, in.p0x, in.p0y, in.e0x, in.e0y), t1 = side_of(d0x, d0y, in.p0x, in.p0y, in.e1x, in.e1y);
  const Double4 u0 = side_of(d2x, d2y, in.cx, in.cy, in.e0x, in.e0y), u1 = side_of(d2x, d2y, in.cx, in.cy, in.e1x, in.e1y);
  const Double4 me = margin2 * (dex * dex + dey * dey), m0 = margin2 * (d0x * d0x + d0y * d0y),
                m2 = margin2 * (d2x * d2x + d2y * d2y);
  Mask4 ok = (s0 < 0.0) & (s1 > 0.0) & (s2 < 0.0) & (t0 > 0.0) & (t1 < 0.0) & (u0 < 0.0) & (u1 > 0.0);
  ok &= (s0 * s0 > me) & (s1 * s1 > me) & (t0 * t0 > m0) & (t1 * t1 > m0);
  ok &= (s2 * s2 > me) & (u0 * u0 > m2) & (u1 * u1 > m2);
  const Double4 r_in = s0 / (s0 - s1), r_out = s1 / (s1 - s2);
  const Double4 inx = in.p0x + r_in * d0x, iny = in.p0y + r_in * d0y;
  const Double4 outx = in.cx + r_out * d2x, outy = in.cy + r_out * d2y;
  const Mask4 in_triangle = clearly_left_of_edge(outx, outy, inx, iny, in.cx, in.cy, margin2) &
                           clearly_left_of_edge(inx, iny, in.qx, in.qy, in.cx, in.cy, margin2) &
                           clearly_left_of_edge(in.qx, in.qy, outx, outy, in.cx, in.cy, margin2);
  const Double4 qx = in.cx - inx, qy = in.cy - iny, rx = outx - inx, ry = outy - iny;
  const Double4 a2 = (0.0 * qy - 0.0 * qx) + (qx * ry - qy * rx);
  const Double4 area = 0.5 * a2;
  ok &= area > 0.0;
  // The chord, formed as two_crossing_result forms it: reversed, it is in - out itself, not
  // -(out - in), which differs where the two are equal (+0 against -0).
  const Double4 lx = in.chord_reversed ? inx - outx : outx - inx, ly = in.chord_reversed ? iny - outy : outy - iny;
  const Double4 chord2 = lx * lx + ly * ly;
  const Double4 chord = lane_sqrt(chord2);
  ok &= chord > in.margin;
  out.ok = ok & in_triangle;
  out.needs_polygon_test = ok & ~in_triangle;
  out.area = area;
  out.chord = chord;
  out.normal_x = ly / chord;
  out.normal_y = -lx / chord;
  const Double4 mid_x = 0.5 * (inx + outx), mid_y = 0.5 * (iny + outy);
  out.point_x = mid_x;
  out.point_y = mid_y;
  const Double4 centroid_x = (inx + in.cx + outx) / 3.0, centroid_y = (iny + in.cy + outy) / 3.0;
  out.centroid_shift = ((centroid_x - mid_x) * lx + (centroid_y - mid_y) * ly) / chord;
}
#pragma GCC diagnostic pop

/// corner_in_edge_lanes as a function of its own, cloned for AVX2 and SSE2 (four_lanes.h): the
/// entry point of the test that compares it with the scalar path. The pair loop inlines
/// corner_in_edge_lanes instead.
void corner_in_edge_x4(const CornerInEdgeBatch& in, CornerInEdgeOverlaps& out);

}  // namespace pilelab::dem::two_crossing
