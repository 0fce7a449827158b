#include "dem/convex_overlap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "common/portable_math.h"

namespace pilelab::dem {

// The two-crossing fast path's tests (two_crossing_overlap.h) serve the search and the clip's
// callers here too.
using namespace two_crossing;

namespace {

// The owner of the overlap polygon's edge that leaves a vertex: a piece of a's boundary, of
// b's boundary, or of both (collinear edges).
enum Owner : int { owner_a = 0, owner_b = 1, owner_both = 2 };

struct ClipVertex {
  Vec2 p;
  int owner;
};

constexpr int max_clip = 2 * max_polygon_corners + 4;
using ClipPolygon = std::array<ClipVertex, max_clip>;

// The outward normal of edge e of a counter-clockwise polygon, scaled by the edge length.
inline Vec2 outward(const Vec2& e) { return {e.y(), -e.x()}; }

Overlap finish(const ClipVertex* v, int n, double length_tol, const Vec2& centroid_a, const Vec2& centroid_b) {
  Overlap o;
  // Drop zero-length edges, so that a vertex of one polygon lying exactly on the other's
  // boundary does not count as two crossings.
  std::array<ClipVertex, max_clip> w;
  int m = 0;
  const double length_tol2 = length_tol * length_tol;
  for (int i = 0; i < n; ++i) {
    const ClipVertex& next = v[i + 1 == n ? 0 : i + 1];
    if ((next.p - v[i].p).squaredNorm() > length_tol2) w[m++] = v[i];
  }
  if (m < 3) return o;

  // The shoelace sums are taken about a vertex of the overlap, not the world origin. Fix: in
  // world coordinates every cross product carries a rounding error of order eps |p|^2, which for
  // grains away from the origin swamps the area of a shallow overlap (a contact 1e-9 deep at
  // |p| = 3 came out with zero area, with the boundaries crossing twice). About a local vertex
  // the error scales with the overlap's own size, so the result no longer depends on where the
  // pair sits in the world.
  const Vec2 origin = w[0].p;
  double a2 = 0.0, cx = 0.0, cy = 0.0;
  Vec2 s_a(0, 0), s_b(0, 0);
  Vec2 first_crossing(0, 0), second_crossing(0, 0);
  for (int i = 0; i < m; ++i) {
    const Vec2& p = w[i].p;
    const Vec2& q = w[i + 1 == m ? 0 : i + 1].p;
    const Vec2 p_local = p - origin, q_local = q - origin;
    const double c = cross(p_local, q_local);
    a2 += c;
    cx += (p_local.x() + q_local.x()) * c;
    cy += (p_local.y() + q_local.y()) * c;
    if (w[i].owner == owner_a) s_a += outward(q - p);
    if (w[i].owner == owner_b) s_b += outward(q - p);
    const int incoming = w[i == 0 ? m - 1 : i - 1].owner;
    if (incoming != w[i].owner) {
      if (o.crossings == 0) first_crossing = p;
      if (o.crossings == 1) second_crossing = p;
      ++o.crossings;
    }
  }
  const double area = 0.5 * a2;
  if (!(area > 0.0)) return o;
  o.area = area;
  const Vec2 centroid = origin + Vec2(cx / (3.0 * a2), cy / (3.0 * a2));
  const Vec2 s = s_a - s_b;
  const double s_norm = s.norm();
  o.chord = 0.5 * s_norm;
  if (s_norm > length_tol) {
    o.normal = s / s_norm;
  } else {
    // Nested or identical shapes: no chord; push apart along the line of centres.
    const Vec2 d = centroid_b - centroid_a;
    o.normal = d.norm() > length_tol ? Vec2(d / d.norm()) : Vec2(0.0, 1.0);
    o.chord = 0.0;
  }
  o.point = (o.crossings == 2) ? Vec2(0.5 * (first_crossing + second_crossing)) : centroid;
  o.centroid_shift = (centroid - o.point).dot(perp(o.normal));
  return o;
}

// One Sutherland-Hodgman pass: keep the part of the polygon vertex(0..n-1) left of the line
// through e0 along d. Returns false, writing nothing, when the whole polygon lies strictly on
// the inner side (the edge cuts nothing off); otherwise writes the clipped polygon to out[0..m).
// side(p) = cross(d, p - e0) = |d| * signed distance of p from the line (left: inside); a point
// within length_tol of the line counts as on it (|side| <= length_tol |d|, squared: side_tol2).
template <class VertexAt>
bool clip_by_edge(const VertexAt& vertex, int n, const Vec2& e0, const Vec2& d, double side_tol2, ClipVertex* out,
                  int& m) {
  double side[max_clip];
  bool all_inside = true;
  for (int i = 0; i < n; ++i) {
    double v = cross(d, vertex(i).p - e0);
    if (v * v <= side_tol2) v = 0.0;
    side[i] = v;
    all_inside = all_inside && v > 0.0;
  }
  if (all_inside) return false;
  m = 0;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1 == n) ? 0 : i + 1;
    const ClipVertex s_v = vertex(i);
    const double s_here = side[i], s_next = side[j];
    const bool s_in = s_here >= 0.0, e_in = s_next >= 0.0;
    if (s_in) out[m++] = {s_v.p, (s_here == 0.0 && s_next == 0.0) ? int(owner_both) : s_v.owner};
    if (s_in != e_in) {
      // The signs differ strictly on one side, so the denominator is never zero.
      const double t = s_here / (s_here - s_next);
      const Vec2 x = s_v.p + t * (vertex(j).p - s_v.p);
      out[m++] = {x, s_in ? int(owner_b) : s_v.owner};
    }
  }
  return true;
}

}  // namespace

namespace {
// The general algorithm, for any pair: Sutherland-Hodgman clipping with the degenerate cases
// (collinear edges, a corner on an edge, nested shapes, many crossings) resolved by tolerances.
Overlap clipped_overlap(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb, const Vec2& centroid_b,
                        double longest_edge) {
  // Cheap rejection first: most pairs the broad phase hands over whose bounding circles overlap
  // but shapes do not are separated along the line of centres (a separating-axis test). The
  // same loop finds b's corner nearest to a along that line.
  const Vec2 axis = centroid_b - centroid_a;
  int support = 0;
  {
    double max_a = -INFINITY, min_b = INFINITY;
    for (int i = 0; i < na; ++i) max_a = std::max(max_a, axis.dot(a[i]));
    for (int k = 0; k < nb; ++k) {
      const double p = axis.dot(b[k]);
      if (p < min_b) {
        min_b = p;
        support = k;
      }
    }
    if (max_a < min_b) return {};
  }
  const double length_tol = 1e-12 * longest_edge;
  const double length_tol2 = length_tol * length_tol;

  // Start with the edge of b that faces a (one of the two at b's corner nearest to a): for the
  // shallow overlaps of a pile it cuts a down to a sliver of three or four corners at once,
  // which makes every later pass cheap. The order of the passes does not change the result.
  int first;
  {
    const int prev = (support + nb - 1) % nb;
    const Vec2 e_prev = b[support] - b[prev], e_next = b[(support + 1) % nb] - b[support];
    // Compare the cosines between each edge's inward normal and the axis, f / |e|, without
    // square roots: f |f| / |e|^2 orders the same way.
    const double f_prev = -outward(e_prev).dot(axis), f_next = -outward(e_next).dot(axis);
    first = f_prev * std::abs(f_prev) * e_next.squaredNorm() > f_next * std::abs(f_next) * e_prev.squaredNorm()
                ? prev
                : support;
  }
  // Sutherland-Hodgman: clip a by each edge's half-plane of b in turn, recording for every
  // output vertex whose boundary its outgoing edge follows. The first pass reads a's corners.
  const auto edge = [b, nb](int k) { return Vec2(b[k + 1 == nb ? 0 : k + 1] - b[k]); };
  ClipPolygon buf[2];
  int n = 0, cur = 0;
  {
    const auto corner = [a](int i) { return ClipVertex{a[i], owner_a}; };
    const Vec2 d = edge(first);
    if (!clip_by_edge(corner, na, b[first], d, length_tol2 * d.squaredNorm(), buf[0].data(), n)) {
      for (int i = 0; i < na; ++i) buf[0][i] = corner(i);  // the first edge cut nothing off
      n = na;
    }
  }
  // After the first pass a is mostly a small sliver, which most of b's other edges leave alone.
  // A circle about the sliver tells so at the cost of one cross product: an edge whose line
  // passes farther from the centre than the radius (plus a margin far above round-off, 1e-9
  // of the longest edge, and the on-the-line tolerance) has every vertex strictly inside, so
  // skipping it gives exactly what the pass would have.
  const double margin = length_tol + 1e-9 * longest_edge;
  Vec2 centre(0, 0);
  double reach2 = 0.0;  // (radius + margin)^2
  const auto enclose = [&](const ClipVertex* v, int count) {
    centre = Vec2(0, 0);
    for (int i = 0; i < count; ++i) centre += v[i].p;
    centre /= count;
    double r2 = 0.0;
    for (int i = 0; i < count; ++i) r2 = std::max(r2, (v[i].p - centre).squaredNorm());
    reach2 = (std::sqrt(r2) + margin) * (std::sqrt(r2) + margin);
  };
  if (n > 0) enclose(buf[0].data(), n);
  for (int pass = 1, k = first; pass < nb && n > 0; ++pass) {
    k = k + 1 == nb ? 0 : k + 1;
    const Vec2 d = edge(k);
    const double d2 = d.squaredNorm();
    const double centre_side = cross(d, centre - b[k]);  // |d| times the centre's distance
    if (centre_side > 0.0 && centre_side * centre_side > reach2 * d2) continue;
    const ClipVertex* in = buf[cur].data();
    int m = 0;
    if (!clip_by_edge([in](int i) { return in[i]; }, n, b[k], d, length_tol2 * d2, buf[1 - cur].data(), m)) continue;
    n = m;
    cur = 1 - cur;
    if (n > 0) enclose(buf[cur].data(), n);
  }
  if (n < 3) return {};
  return finish(buf[cur].data(), n, length_tol, centroid_a, centroid_b);
}


enum class Search { separated, found, other };

// Finds the edges of a two-crossing configuration from scratch, or an edge of b that separates
// the shapes: the sides of a's corners against each of b's edges show where a's boundary
// crosses that edge's line, and the sides of that edge's ends against a's crossing edge show
// whether it crosses within the edge.
Search find_edges(const Vec2* a, int na, const Vec2* b, int nb, double margin2, OverlapHint& hint, double& gap) {
  int entering = 0, leaving = 0;
  double side[max_polygon_corners];
  for (int k = 0; k < nb; ++k) {
    const Vec2 &b0 = b[k], &b1 = b[next_index(k, nb)];
    const Vec2 db = b1 - b0;
    const double db2 = db.squaredNorm();
    bool all_out = true;
    for (int i = 0; i < na; ++i) {
      side[i] = side_of(db, b0, a[i]);
      all_out = all_out && clearly_right(side[i], db2, margin2);
    }
    if (all_out) {
      hint.kind = OverlapHint::separated_by_b;
      hint.edge[0] = static_cast<std::uint8_t>(k);
      double nearest = INFINITY;
      for (int i = 0; i < na; ++i) nearest = std::min(nearest, -side[i]);
      gap = nearest / std::sqrt(db2);
      return Search::separated;
    }
    for (int i = 0; i < na; ++i) {
      const double s0 = side[i], s1 = side[next_index(i, na)];
      const bool in = s0 < 0.0 && s1 >= 0.0, out = s0 >= 0.0 && s1 < 0.0;
      if (!in && !out) continue;
      // Does the line crossing fall within b's edge? b's ends on opposite sides of a's edge.
      const Vec2 da = a[next_index(i, na)] - a[i];
      const double t0 = side_of(da, a[i], b0), t1 = side_of(da, a[i], b1);
      if (in && t0 >= 0.0 && t1 < 0.0) {
        if (++entering > 1) return Search::other;
        hint.edge[0] = static_cast<std::uint8_t>(i);
        hint.edge[1] = static_cast<std::uint8_t>(k);
      } else if (out && t0 < 0.0 && t1 >= 0.0) {
        if (++leaving > 1) return Search::other;
        hint.edge[2] = static_cast<std::uint8_t>(i);
        hint.edge[3] = static_cast<std::uint8_t>(k);
      }
    }
  }
  if (entering == 1 && leaving == 1) {
    hint.kind = OverlapHint::crossing;
    return Search::found;
  }
  if (entering == 0 && leaving == 0) {
    // No crossing: disjoint (then some edge separates, and it is not one of b's) or nested.
    for (int e = 0; e < na; ++e) {
      gap = separation_beyond_edge(a, na, e, b, nb, margin2);
      if (gap > 0.0) {
        hint.kind = OverlapHint::separated_by_a;
        hint.edge[0] = static_cast<std::uint8_t>(e);
        return Search::separated;
      }
    }
  }
  return Search::other;
}

}  // namespace

Overlap overlap_polygons(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                         const Vec2& centroid_b) {
  double longest2 = 0.0;
  for (int i = 0; i < na; ++i) longest2 = std::max(longest2, (a[i + 1 == na ? 0 : i + 1] - a[i]).squaredNorm());
  for (int k = 0; k < nb; ++k) longest2 = std::max(longest2, (b[k + 1 == nb ? 0 : k + 1] - b[k]).squaredNorm());
  return overlap_polygons(a, na, centroid_a, b, nb, centroid_b, std::sqrt(longest2));
}

Overlap overlap_polygons(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                         const Vec2& centroid_b, double longest_edge) {
  OverlapHint hint;
  return overlap_polygons(a, na, centroid_a, b, nb, centroid_b, longest_edge, hint);
}

// Everything but the hint's answer: the line of centres, a search for the crossing edges or a
// separating edge, and the clip.
Overlap two_crossing::search_overlap(const Vec2* a, int na, const Vec2& centroid_a, const Vec2* b, int nb,
                                     const Vec2& centroid_b, double longest_edge, OverlapHint& hint) {
  const double margin = clear_margin * longest_edge, margin2 = margin * margin;
  Overlap o;
  // The line of centres separates most of the pairs that do not touch.
  if (hint.kind != OverlapHint::separated_along_centres) {
    o.gap = separation_along_centres(a, na, centroid_a, b, nb, centroid_b);
    if (o.gap > 0.0) {
      hint.kind = OverlapHint::separated_along_centres;
      return o;
    }
  }
  switch (find_edges(a, na, b, nb, margin2, hint, o.gap)) {
    case Search::separated: return o;
    case Search::found:
      if (two_crossing_overlap(a, na, centroid_a, b, nb, centroid_b, hint.edge, margin, o)) return o;
      break;
    case Search::other: break;
  }
  hint.kind = OverlapHint::none;
  o.gap = 0.0;
  return clipped_overlap(a, na, centroid_a, b, nb, centroid_b, longest_edge);
}


namespace {
// Area of the segment cut from a disc of radius r by a chord at signed distance x from the
// centre (x < 0: more than half the disc), given the segment's height g = r - x and the
// half-chord h, both computed by the caller without cancellation.
double circular_segment_area(double r, double x, double g, double h) {
  const double s = h / r;  // sine of the half-angle theta
  if (x > 0.0 && s < 0.5) {
    // Thin segment. The textbook r^2 theta - x h subtracts two nearly equal numbers: its
    // relative error grows like eps / theta^4. With cos theta = 1 - g / r it equals
    // r^2 (asin s - s) + h g exactly, and asin s - s is summed from its Taylor series, whose
    // terms are all positive and shrink at least fourfold each.
    const double s2 = s * s;
    double term = s, sum = 0.0;
    for (int k = 1; k < 40; ++k) {
      term *= s2 * double((2 * k - 1) * (2 * k - 1)) / double((2 * k) * (2 * k + 1));
      sum += term;
      if (term <= 1e-17 * sum) break;
    }
    return r * r * sum + h * g;
  }
  return r * r * portable_atan2(h, x) - x * h;  // theta > 30 degrees: the cancellation is mild
}
}  // namespace

Overlap overlap_discs(const Vec2& ca, double ra, const Vec2& cb, double rb) {
  Overlap o;
  const Vec2 d = cb - ca;
  const double dist = d.norm();
  if (dist >= ra + rb) return o;
  o.normal = dist > 1e-12 * (ra + rb) ? Vec2(d / dist) : Vec2(0.0, 1.0);
  const double r_small = std::min(ra, rb);
  if (dist <= std::abs(ra - rb)) {  // one disc inside the other
    o.area = M_PI * r_small * r_small;
    o.chord = 0.0;
    o.point = ra < rb ? ca : cb;
    return o;
  }
  // Fix: the lens used to be ra^2 acos(x/ra) - x h + (same for b) with x and h from the
  // law of cosines, which for a shallow overlap cancels catastrophically (area wrong by a
  // factor 66 at a depth of 1e-9 radii, off by orders of magnitude below). The segment heights
  // g = r - x follow from the overlap depth without cancellation, and each segment's area from
  // circular_segment_area.
  const double depth = (ra + rb) - dist;
  const double g_a = depth * (dist + rb - ra) / (2.0 * dist);  // ra - x, x: distance from ca to the chord
  const double g_b = depth * (dist + ra - rb) / (2.0 * dist);  // rb - (dist - x)
  // h^2 = g (2 r - g) for either disc; the thinner segment's factor 2 r - g cannot cancel.
  const double h2 = (g_a * rb <= g_b * ra) ? g_a * (2.0 * ra - g_a) : g_b * (2.0 * rb - g_b);
  const double h = std::sqrt(std::max(0.0, h2));
  const double x = ra - g_a;
  o.area = circular_segment_area(ra, x, g_a, h) + circular_segment_area(rb, rb - g_b, g_b, h);
  o.chord = 2.0 * h;
  o.point = ca + x * o.normal;
  o.crossings = 2;
  return o;
}

namespace {
// Where the line p + t d (d != 0) meets the circle of radius r about the origin: at
// t_in < t_out, or nowhere (false). Fix: the roots used to come from the textbook discriminant
// (p.d)^2 - |d|^2 (|p|^2 - r^2), whose terms are of order |p|^2 |d|^2 while their difference is
// |d|^2 h^2 (h the half-chord): for an edge much longer than the disc (a wall) that lost a
// factor (|p| / h)^2, e.g. the chord of a disc on an edge 200 radii long came out wrong in the
// tenth digit. Measured from the foot of the perpendicular from the centre only r^2 - |foot|^2
// cancels, which is the problem's own conditioning.
bool line_meets_circle(const Vec2& p, const Vec2& d, double r, double& t_in, double& t_out) {
  const double a = d.squaredNorm();
  const double t_foot = -p.dot(d) / a;
  const Vec2 foot = p + t_foot * d;
  const double h2 = r * r - foot.squaredNorm();
  if (!(h2 > 0.0)) return false;
  const double dt = std::sqrt(h2 / a);
  t_in = t_foot - dt;
  t_out = t_foot + dt;
  return true;
}

// Signed area of the intersection of the disc (centred at the origin, radius r) with the
// triangle (origin, p, q): the standard decomposition of a circle-polygon intersection into
// sectors and a triangle. Its signed first moment about the origin is added to moment.
double disc_triangle_area(Vec2 p, Vec2 q, double r, Vec2& moment) {
  const double r2 = r * r;
  const Vec2 d = q - p;
  if (d.squaredNorm() == 0.0) return 0.0;
  // A sector from direction u to v: area r^2 angle / 2; first moment (r^3 / 3) (sin b - sin a,
  // cos a - cos b) for the angles a, b of u and v.
  auto sector = [&](const Vec2& u, const Vec2& v) {
    const double u_norm = u.norm(), v_norm = v.norm();
    if (u_norm > 0.0 && v_norm > 0.0)  // a corner at the centre spans no sector
      moment += (r2 * r / 3.0) * Vec2(v.y() / v_norm - u.y() / u_norm, u.x() / u_norm - v.x() / v_norm);
    return 0.5 * r2 * portable_atan2(cross(u, v), u.dot(v));
  };
  auto triangle = [&](const Vec2& u, const Vec2& v) {
    moment += (cross(u, v) / 6.0) * (u + v);
    return 0.5 * cross(u, v);
  };
  double t_in, t_out;
  if (!line_meets_circle(p, d, r, t_in, t_out)) return sector(p, q);  // the segment's line misses the circle
  const double t0 = std::clamp(t_in, 0.0, 1.0), t1 = std::clamp(t_out, 0.0, 1.0);
  const Vec2 u = p + t0 * d, v = p + t1 * d;
  return sector(p, u) + triangle(u, v) + sector(v, q);
}
}  // namespace

Overlap overlap_disc_polygon(const Vec2& c, double r, const Vec2* b, int nb, const Vec2& centroid_b) {
  Overlap o;
  double scale = r * r;
  for (int k = 0; k < nb; ++k) scale = std::max(scale, (b[(k + 1) % nb] - b[k]).squaredNorm());
  const double length_tol = 1e-12 * std::sqrt(scale);
  // The polygon's boundary inside the disc: its outward-normal integral S_b, and the points
  // where the boundary crosses the circle.
  Vec2 s_b(0, 0), crossing_sum(0, 0);
  Vec2 crossing[2];
  int crossings = 0;
  for (int k = 0; k < nb; ++k) {
    const Vec2 p = b[k] - c, d = b[(k + 1) % nb] - b[k];
    double t_in, t_out;
    if (d.squaredNorm() == 0.0 || !line_meets_circle(p, d, r, t_in, t_out)) continue;
    const double t0 = std::max(t_in, 0.0), t1 = std::min(t_out, 1.0);
    if (t1 <= t0) continue;
    s_b += outward((t1 - t0) * d);
    for (double t : {t_in, t_out})
      if (t >= 0.0 && t < 1.0) {
        if (crossings < 2) crossing[crossings] = c + p + t * d;
        crossing_sum += c + p + t * d;
        ++crossings;
      }
  }
  if (crossings == 0) {
    // The boundaries do not cross: disjoint, disc inside the polygon, or polygon inside the
    // disc. Decide exactly rather than trust a sum of sectors that cancels to round-off.
    // Fix: the polygon-inside-disc test must come first. A disc that swallows the polygon
    // usually has its centre inside the polygon too, and was given the whole disc's area
    // (25 pi for a unit square in a disc of radius 5 about its middle). With no crossing, the
    // polygon is inside exactly when one of its corners is.
    const bool polygon_inside = (b[0] - c).squaredNorm() < r * r;
    bool centre_inside = true;
    for (int k = 0; k < nb && centre_inside; ++k) centre_inside = cross(b[(k + 1) % nb] - b[k], c - b[k]) > 0.0;
    if (polygon_inside) {
      // Shoelace about the disc's centre, so the round-off scales with r, not with the
      // distance from the world origin.
      double a2 = 0.0;
      for (int k = 0; k < nb; ++k) a2 += cross(b[k] - c, b[(k + 1) % nb] - c);
      o.area = 0.5 * a2;
    } else if (centre_inside) {
      o.area = M_PI * r * r;
    } else {
      return o;
    }
    const Vec2 d = centroid_b - c;
    o.normal = d.norm() > length_tol ? Vec2(d / d.norm()) : Vec2(0.0, 1.0);
    o.point = polygon_inside ? centroid_b : c;
    return o;
  }
  double area = 0.0;
  Vec2 moment(0, 0);  // about the disc's centre
  for (int k = 0; k < nb; ++k) area += disc_triangle_area(b[k] - c, b[(k + 1) % nb] - c, r, moment);
  if (!(area > 0.0)) return o;
  o.area = area;
  o.crossings = crossings;
  const double s_norm = s_b.norm();
  if (s_norm > length_tol) {
    // S_b points out of the polygon, towards the disc: the normal from disc to polygon is -S_b.
    o.normal = -s_b / s_norm;
    o.chord = s_norm;
  } else {
    const Vec2 d = centroid_b - c;
    o.normal = d.norm() > length_tol ? Vec2(d / d.norm()) : Vec2(0.0, 1.0);
  }
  o.point = crossings == 2 ? Vec2(0.5 * (crossing[0] + crossing[1])) : Vec2(crossing_sum / crossings);
  o.centroid_shift = (c + moment / area - o.point).dot(perp(o.normal));
  return o;
}

}  // namespace pilelab::dem

namespace pilelab::dem::two_crossing {

PILELAB_AVX2_AND_SSE2
void corner_in_edge_x4(const CornerInEdgeBatch& in, CornerInEdgeOverlaps& out) { corner_in_edge_lanes(in, out); }

}  // namespace pilelab::dem::two_crossing
