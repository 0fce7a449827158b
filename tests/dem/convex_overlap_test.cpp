// The narrow phase (dem/convex_overlap) against independent oracles. CGAL's exact-constructions
// kernel gives the true overlap polygon, its area and the points where the boundaries cross,
// for the very double coordinates handed to the code under test; MPFR evaluates the textbook
// disc formulas with 256-bit numbers. Every tolerance is therefore a bound on the double
// round-off of the code under test, written as eps times the lengths that round-off scales with:
//   R    the magnitude of the world coordinates (each stored coordinate is uncertain by eps R),
//   D    the size of the pair (differences and cross products of corners),
//   sine the sine of the angle at which two edges cross (a crossing point moves along an edge
//        by (perturbation) / sine, so that is how ill-conditioned the crossing itself is).
#include "dem/convex_overlap.h"

#include <gtest/gtest.h>
#include <mpfr.h>

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <list>
#include <random>
#include <vector>

#include "common/rng.h"

namespace pilelab::dem {
namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Exact = Kernel::FT;
using ExactPoint = Kernel::Point_2;
using ExactVector = Kernel::Vector_2;
using ExactPolygon = CGAL::Polygon_2<Kernel>;
using ExactPolygonWithHoles = CGAL::Polygon_with_holes_2<Kernel>;

constexpr double eps = std::numeric_limits<double>::epsilon();

using Polygon = std::vector<Vec2>;  // convex, counter-clockwise, world coordinates

// ---------------------------------------------------------------------------------------------
// Exact geometry (CGAL)

double to_double(const Exact& x) { return CGAL::to_double(CGAL::exact(x)); }
Vec2 to_vec(const ExactPoint& p) { return {to_double(p.x()), to_double(p.y())}; }
ExactPoint to_exact(const Vec2& p) { return {p.x(), p.y()}; }

ExactPolygon to_exact(const Polygon& polygon) {
  ExactPolygon exact;
  for (const Vec2& p : polygon) exact.push_back(to_exact(p));
  return exact;
}

// Translated without rounding: the probes of the area gradient see exactly the step asked for.
ExactPolygon translated(const ExactPolygon& polygon, const ExactVector& step) {
  ExactPolygon moved;
  for (auto v = polygon.vertices_begin(); v != polygon.vertices_end(); ++v) moved.push_back(*v + step);
  return moved;
}

// The regularised intersection (empty when only the boundaries meet); one piece for convex input.
ExactPolygon exact_intersection(const ExactPolygon& a, const ExactPolygon& b) {
  std::list<ExactPolygonWithHoles> pieces;
  CGAL::intersection(a, b, std::back_inserter(pieces));
  EXPECT_LE(pieces.size(), 1u);
  return pieces.empty() ? ExactPolygon() : pieces.front().outer_boundary();
}

Exact exact_area(const ExactPolygon& p) { return p.is_empty() ? Exact(0) : p.area(); }

// The centroid of a polygon of positive area, from exact first moments, rounded once.
Vec2 exact_centroid(const ExactPolygon& p) {
  Exact a2 = 0, mx = 0, my = 0;
  for (auto e = p.edges_begin(); e != p.edges_end(); ++e) {
    const auto &u = e->source(), &v = e->target();
    const Exact c = u.x() * v.y() - v.x() * u.y();
    a2 += c;
    mx += (u.x() + v.x()) * c;
    my += (u.y() + v.y()) * c;
  }
  return {to_double(mx / (3 * a2)), to_double(my / (3 * a2))};
}

double perimeter(const ExactPolygon& p) {  // rounded edge lengths: only a tolerance scale
  double sum = 0.0;
  for (auto e = p.edges_begin(); e != p.edges_end(); ++e) sum += std::sqrt(to_double(e->squared_length()));
  return sum;
}

double diameter(const Polygon& corners) {
  double d = 0.0;
  for (const Vec2& p : corners)
    for (const Vec2& q : corners) d = std::max(d, (p - q).norm());
  return d;
}

double perimeter(const Polygon& p) {
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) sum += (p[(i + 1) % p.size()] - p[i]).norm();
  return sum;
}

// Distance from p to the polygon (0 inside or on it).
double distance_to(const ExactPolygon& polygon, const Vec2& p) {
  const ExactPoint q = to_exact(p);
  if (polygon.bounded_side(q) != CGAL::ON_UNBOUNDED_SIDE) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (auto e = polygon.edges_begin(); e != polygon.edges_end(); ++e)
    best = std::min(best, std::sqrt(to_double(CGAL::squared_distance(q, *e))));
  return best;
}

struct Crossing {
  ExactPoint point;
  double sine;  // of the angle between the two crossing edges
};

struct BoundaryCrossings {
  std::vector<Crossing> points;
  bool collinear = false;  // some edges share a segment: the crossing set is not a point set
};

// Where the two boundaries meet, from every edge pair: independent of any clipping order.
BoundaryCrossings boundary_crossings(const ExactPolygon& a, const ExactPolygon& b) {
  BoundaryCrossings result;
  for (auto ea = a.edges_begin(); ea != a.edges_end(); ++ea) {
    for (auto eb = b.edges_begin(); eb != b.edges_end(); ++eb) {
      if (!CGAL::do_intersect(*ea, *eb)) continue;
      const auto meet = CGAL::intersection(*ea, *eb);
      const ExactPoint* point = boost::get<ExactPoint>(&*meet);
      if (!point) {
        result.collinear = true;
        continue;
      }
      const bool seen = std::any_of(result.points.begin(), result.points.end(),
                                    [&](const Crossing& c) { return c.point == *point; });
      if (seen) continue;
      const Vec2 da = to_vec(ea->target()) - to_vec(ea->source());
      const Vec2 db = to_vec(eb->target()) - to_vec(eb->source());
      result.points.push_back({*point, std::abs(cross(da, db)) / (da.norm() * db.norm())});
    }
  }
  return result;
}

// ---------------------------------------------------------------------------------------------
// High-precision reals (MPFR), for the disc formulas, which involve acos and sqrt

class Big {
 public:
  Big(double x = 0.0) {  // NOLINT: implicit, so formulas read like formulas
    mpfr_init2(v_, bits);
    mpfr_set_d(v_, x, MPFR_RNDN);
  }
  Big(const Big& o) {
    mpfr_init2(v_, bits);
    mpfr_set(v_, o.v_, MPFR_RNDN);
  }
  Big& operator=(const Big& o) {
    mpfr_set(v_, o.v_, MPFR_RNDN);
    return *this;
  }
  ~Big() { mpfr_clear(v_); }
  double to_double() const { return mpfr_get_d(v_, MPFR_RNDN); }

  friend Big operator+(const Big& a, const Big& b) { return apply(mpfr_add, a, b); }
  friend Big operator-(const Big& a, const Big& b) { return apply(mpfr_sub, a, b); }
  friend Big operator*(const Big& a, const Big& b) { return apply(mpfr_mul, a, b); }
  friend Big operator/(const Big& a, const Big& b) { return apply(mpfr_div, a, b); }
  friend bool operator<(const Big& a, const Big& b) { return mpfr_less_p(a.v_, b.v_) != 0; }
  friend Big sqrt(const Big& a) { return apply(mpfr_sqrt, a); }
  friend Big acos(const Big& a) { return apply(mpfr_acos, a); }
  friend Big abs(const Big& a) { return apply(mpfr_abs, a); }
  static Big pi() {
    Big r;
    mpfr_const_pi(r.v_, MPFR_RNDN);
    return r;
  }

 private:
  // 256 bits: the cancellations in these formulas (a lens 1e-12 radii deep loses about 80
  // bits) leave far more than double precision.
  static constexpr mpfr_prec_t bits = 256;
  template <class F>
  static Big apply(F f, const Big& a, const Big& b) {
    Big r;
    f(r.v_, a.v_, b.v_, MPFR_RNDN);
    return r;
  }
  template <class F>
  static Big apply(F f, const Big& a) {
    Big r;
    f(r.v_, a.v_, MPFR_RNDN);
    return r;
  }
  mpfr_t v_;
};

/// Area of the part of a disc of radius r beyond a line at signed distance d from its centre
/// (d < 0: the centre is on that part's side), d in [-r, r].
Big circular_segment(const Big& r, const Big& d) { return r * r * acos(d / r) - d * sqrt(r * r - d * d); }

// ---------------------------------------------------------------------------------------------
// Shared checks

void expect_finite(const Overlap& o) {
  EXPECT_TRUE(std::isfinite(o.area) && std::isfinite(o.chord) && std::isfinite(o.point.x()) &&
              std::isfinite(o.point.y()) && std::isfinite(o.normal.x()) && std::isfinite(o.normal.y()))
      << "area " << o.area << " chord " << o.chord << " point " << o.point.transpose() << " normal "
      << o.normal.transpose();
}

// The normal is s / |s| or a unit fallback: unit to a few rounding steps.
void expect_unit_normal(const Overlap& o) { EXPECT_NEAR(o.normal.norm(), 1.0, 4 * eps); }

Overlap overlap(const Polygon& a, const Vec2& centroid_a, const Polygon& b, const Vec2& centroid_b) {
  return overlap_polygons(a.data(), int(a.size()), centroid_a, b.data(), int(b.size()), centroid_b);
}

Vec2 vertex_mean(const Polygon& p) {
  Vec2 sum(0, 0);
  for (const Vec2& v : p) sum += v;
  return sum / double(p.size());
}

double largest_coordinate(const Polygon& a, const Polygon& b) {
  double r = 0.0;
  for (const Vec2& p : a) r = std::max(r, p.norm());
  for (const Vec2& p : b) r = std::max(r, p.norm());
  return r;
}

Polygon joined(const Polygon& a, const Polygon& b) {
  Polygon all = a;
  all.insert(all.end(), b.begin(), b.end());
  return all;
}

// Round-off bounds for one polygon pair, from the exact overlap (see the file comment).
struct PolygonTolerances {
  double position;  // of a computed crossing point (the worst crossing)
  double gradient;  // of the vector chord * normal = -(area gradient)
  double area;
  double centroid;  // of the overlap centroid, the force point when there are no two crossings
};

PolygonTolerances polygon_tolerances(const Polygon& a, const Polygon& b, const ExactPolygon& exact_overlap,
                                     const BoundaryCrossings& crossings) {
  const double coordinate = largest_coordinate(a, b);
  const double size = diameter(joined(a, b));
  const int corners = int(a.size() + b.size());
  PolygonTolerances tol{};
  // A clipped corner is a + t (b - a) with t a ratio of cross products of corner differences:
  // error eps (R + D) across the edge and eps (R + D) / sine along it. The clip may start from
  // a corner of an earlier clip, whose error stays along its own edge; 16 covers the few
  // rounding steps of each stage.
  for (const Crossing& c : crossings.points)
    tol.position = std::max(tol.position, 16 * eps * (coordinate + size) / c.sine);
  // chord * normal = (S_a - S_b) / 2 telescopes to differences of crossing points, plus one
  // rounding per summed edge vector.
  double crossing_errors = 0.0;
  for (const Crossing& c : crossings.points) crossing_errors += 16 * eps * (coordinate + size) / c.sine;
  const double overlap_perimeter = exact_overlap.is_empty() ? 0.0 : perimeter(exact_overlap);
  tol.gradient = crossing_errors + 8 * eps * (perimeter(a) + perimeter(b));
  // Moving a corner along its edge by e changes the area by e times the neighbour's distance
  // from that edge, which is sine times an edge length: the 1 / sine cancels and each corner
  // contributes eps (R + D) times its edges. The shoelace sums about a local corner add
  // eps (overlap size) per term.
  const double overlap_size = 0.5 * overlap_perimeter;
  tol.area = 16 * eps * (coordinate + size + corners * overlap_size) * overlap_perimeter;
  const double area = to_double(exact_area(exact_overlap));
  tol.centroid = 16 * eps * (coordinate + size) + (area > 0 ? 2 * overlap_size * tol.area / area : 0.0);
  return tol;
}

// sqrt(A) of the overlap of two convex bodies is a concave function of the translation of b
// (Brunn-Minkowski). So the computed -chord * normal / (2 sqrt(A)) must be a supergradient:
// for every probe step v, sqrt(A(v)) <= sqrt(A(0)) - chord normal.v / (2 sqrt(A(0))). Probing
// v = +-h normal brackets the chord; v = +-h tangent shows the normal is not turned. Where A
// has a kink (collinear edges) any value between the one-sided slopes passes, as it should.
void expect_area_gradient(const ExactPolygon& a, const ExactPolygon& b, const Overlap& o, double h,
                          double gradient_tol) {
  const Exact area0 = exact_area(exact_intersection(a, b));
  const double root0 = std::sqrt(to_double(area0));
  ASSERT_GT(root0, 0.0);
  const Vec2 tangent = perp(o.normal);
  struct Probe {
    Vec2 direction;
    double sign;
  };
  for (const Probe& probe : {Probe{o.normal, 1.0}, Probe{o.normal, -1.0}, Probe{tangent, 1.0}, Probe{tangent, -1.0}}) {
    const ExactVector step = ExactVector(probe.direction.x(), probe.direction.y()) * Exact(probe.sign * h);
    const Exact moved = exact_area(exact_intersection(a, translated(b, step)));
    const double root = std::sqrt(to_double(moved));
    const double predicted_slope = -o.chord * probe.sign * probe.direction.dot(o.normal) / (2 * root0);
    // gradient_tol bounds the error of chord * normal; 4 eps root0 the rounding of the roots.
    const double allowance = gradient_tol / (2 * root0) * h + 4 * eps * root0;
    EXPECT_LE(root, root0 + predicted_slope * h + allowance)
        << "probe " << (probe.sign * probe.direction).transpose() << " h " << h << " chord " << o.chord;
    if (probe.sign > 0 && probe.direction == o.normal && o.chord > gradient_tol) {
      EXPECT_LT(moved, area0) << "moving b along +normal must reduce the overlap";
    }
  }
}

// What kind of pair check_polygon_pair saw, for the coverage counts of the random test.
struct PairReport {
  bool overlapping = false;
  bool tiny = false;  // overlap smaller than 1e-12 of the smaller polygon
  int crossings = 0;
};

PairReport check_polygon_pair(const Polygon& a, const Polygon& b, bool probe_gradient) {
  const Vec2 centroid_a = vertex_mean(a), centroid_b = vertex_mean(b);
  const Overlap o = overlap(a, centroid_a, b, centroid_b);
  const ExactPolygon exact_a = to_exact(a), exact_b = to_exact(b);
  EXPECT_TRUE(exact_a.is_convex() && exact_a.is_counterclockwise_oriented());
  EXPECT_TRUE(exact_b.is_convex() && exact_b.is_counterclockwise_oriented());
  const ExactPolygon exact_overlap = exact_intersection(exact_a, exact_b);
  const Exact exact = exact_area(exact_overlap);
  const double exact_value = to_double(exact);
  const BoundaryCrossings crossings = boundary_crossings(exact_a, exact_b);
  const PolygonTolerances tol = polygon_tolerances(a, b, exact_overlap, crossings);
  const double smaller_area = std::min(to_double(exact_a.area()), to_double(exact_b.area()));

  PairReport report;
  report.overlapping = exact > 0;
  report.tiny = exact_value < 1e-12 * smaller_area;
  report.crossings = int(crossings.points.size());

  expect_finite(o);
  expect_unit_normal(o);
  EXPECT_GE(o.chord, 0.0);

  // Area: within the round-off model, and within 1e-10 of the smaller grain's area.
  EXPECT_NEAR(o.area, exact_value, tol.area) << "exact " << exact_value;
  EXPECT_LE(std::abs(o.area - exact_value), 1e-10 * smaller_area);

  // Zero exactly when the interiors do not meet; touching closed sets may give a sliver no
  // larger than the round-off of the touching boundaries.
  if (exact == 0) {
    const bool touching = CGAL::do_intersect(exact_a, exact_b);
    if (touching) {
      EXPECT_LE(o.area, 16 * eps * (largest_coordinate(a, b) + diameter(joined(a, b))) *
                            std::min(perimeter(a), perimeter(b)));
    } else {
      EXPECT_EQ(o.area, 0.0);
    }
    return report;
  }
  if (exact_value > tol.area) {
    EXPECT_TRUE(o.touching());
  }
  if (!o.touching()) return report;

  // The force point lies in the overlap.
  const double point_tol = o.crossings == 2 ? tol.position : tol.centroid;
  EXPECT_LE(distance_to(exact_overlap, o.point), point_tol) << "point " << o.point.transpose();
  // The overlap's centroid projects onto the contact line at centroid_shift from the point.
  EXPECT_NEAR(o.centroid_shift, (exact_centroid(exact_overlap) - o.point).dot(perp(o.normal)), tol.centroid);

  if (crossings.collinear) return report;  // the crossing set is a segment: nothing to compare
  // Crossings that round-off cannot merge must all be found.
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < crossings.points.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      closest = std::min(closest, (to_vec(crossings.points[i].point) - to_vec(crossings.points[j].point)).norm());
  if (closest > std::max(1e-11 * diameter(joined(a, b)), 100 * tol.position)) {
    EXPECT_EQ(o.crossings, int(crossings.points.size()));
  }

  // Two crossings: the paper's contact line.
  if (o.crossings == 2 && crossings.points.size() == 2) {
    const Vec2 p1 = to_vec(crossings.points[0].point), p2 = to_vec(crossings.points[1].point);
    EXPECT_LE((o.point - 0.5 * (p1 + p2)).norm(), tol.position) << "force point is not the chord midpoint";
    EXPECT_NEAR(o.chord, (p2 - p1).norm(), tol.gradient);
    EXPECT_LE(std::abs(o.normal.dot(p2 - p1)), tol.gradient) << "normal not perpendicular to the chord";
  }

  if (probe_gradient) {
    // A step that keeps the bodies overlapping: the area shrinks at most at the rate of the
    // widest chord, the smaller diameter, so h = A / (2 D) leaves at least half of it.
    const double h = 0.5 * exact_value / std::min(diameter(a), diameter(b));
    expect_area_gradient(exact_a, exact_b, o, h, tol.gradient);
  }

  // The same pair the other way round: same area and point, opposite normal.
  const Overlap swapped = overlap(b, centroid_b, a, centroid_a);
  expect_finite(swapped);
  EXPECT_NEAR(swapped.area, o.area, 2 * tol.area);
  EXPECT_EQ(swapped.crossings, o.crossings);
  if (o.crossings == 2 && swapped.crossings == 2) {
    EXPECT_LE((swapped.point - o.point).norm(), 2 * tol.position);
    EXPECT_NEAR(swapped.chord, o.chord, 2 * tol.gradient);
    EXPECT_LE((swapped.normal + o.normal).norm(), 2 * tol.gradient / o.chord);
  }
  return report;
}

// ---------------------------------------------------------------------------------------------
// Random input

// Corners on an ellipse (semi-axes size and size / aspect, turned at random) at random angles
// whose gaps are at least a quarter of the mean gap: no corner is nearly flat, so rounding the
// coordinates cannot break convexity (the exact check in check_polygon_pair confirms it).
Polygon random_convex_polygon(Rng& rng, double size, const Vec2& centre) {
  const int n = rng.uniform_int(3, 12);
  const double aspect = std::exp(rng.uniform(0.0, std::log(4.0)));
  const double turn = rng.uniform(0.0, 2 * M_PI);
  std::vector<double> gaps(n);
  double total = 0.0;
  for (double& g : gaps) total += g = rng.uniform(0.25, 1.0);
  Polygon corners;
  double angle = rng.uniform(0.0, 2 * M_PI);
  for (int i = 0; i < n; ++i) {
    const Vec2 on_ellipse(size * std::cos(angle), size / aspect * std::sin(angle));
    corners.push_back(centre + rotate(on_ellipse, std::cos(turn), std::sin(turn)));
    angle += 2 * M_PI * gaps[i] / total;
  }
  return corners;
}

Vec2 random_direction(Rng& rng) {
  const double angle = rng.uniform(0.0, 2 * M_PI);
  return {std::cos(angle), std::sin(angle)};
}

// A corner of guest pushed through an edge of host by depth (< 0: a gap). The corner is the
// guest's extreme one against the edge's outward normal, so with depth < 0 the edge's line
// separates them, and a small depth gives a small overlap at a vertex-edge contact, the common
// case in a pile.
void push_corner_into_edge(Rng& rng, const Polygon& host, Polygon& guest, double depth) {
  const int k = rng.uniform_int(0, int(host.size()) - 1);
  const Vec2 e0 = host[k], e1 = host[(k + 1) % host.size()];
  const Vec2 outward_normal = Vec2((e1 - e0).y(), -(e1 - e0).x()).normalized();
  const Vec2 contact = e0 + rng.uniform(0.1, 0.9) * (e1 - e0);
  const Vec2 tip = *std::min_element(guest.begin(), guest.end(), [&](const Vec2& p, const Vec2& q) {
    return outward_normal.dot(p) < outward_normal.dot(q);
  });
  const Vec2 shift = contact - depth * outward_normal - tip;
  for (Vec2& p : guest) p += shift;
}

// ---------------------------------------------------------------------------------------------
// Polygon-polygon: random pairs

TEST(ConvexOverlap, RandomPairsMatchExactIntersection) {
  Rng rng(20240611);
  constexpr int pairs = 10000;
  constexpr int gradient_probe_every = 4;  // the exact probes cost four Boolean operations
  int overlapping = 0, tiny = 0, two_crossings = 0, more_crossings = 0, nested = 0;
  for (int i = 0; i < pairs && !HasFailure(); ++i) {
    SCOPED_TRACE("pair " + std::to_string(i));
    // Sizes over six decades (the tolerances must scale), up to 4x apart; the pair sits up
    // to 20 sizes from the origin, as grains in a pile do.
    const double scale = std::pow(10.0, rng.uniform(-3.0, 3.0));
    const double size_a = scale * std::exp2(rng.uniform(-1.0, 1.0));
    const double size_b = scale * std::exp2(rng.uniform(-1.0, 1.0));
    const Vec2 place = scale * std::pow(10.0, rng.uniform(-1.0, 1.3)) * random_direction(rng);
    Polygon a = random_convex_polygon(rng, size_a, place);
    Polygon b;
    if (rng.uniform() < 0.7) {
      // Depths from 1e-9 of the smaller size to all of it; one in ten a gap instead.
      const double depth = std::min(size_a, size_b) * std::pow(10.0, rng.uniform(-9.0, 0.0)) *
                           (rng.uniform() < 0.1 ? -1.0 : 1.0);
      b = random_convex_polygon(rng, size_b, Vec2(0, 0));
      if (rng.uniform() < 0.5)
        push_corner_into_edge(rng, a, b, depth);
      else
        push_corner_into_edge(rng, b, a, depth);
    } else {
      // Centres anywhere up to just beyond reach: deep, nested and missing pairs.
      const Vec2 offset = (size_a + size_b) * rng.uniform(0.0, 1.1) * random_direction(rng);
      b = random_convex_polygon(rng, size_b, place + offset);
    }
    const PairReport report = check_polygon_pair(a, b, i % gradient_probe_every == 0);
    overlapping += report.overlapping;
    tiny += report.overlapping && report.tiny;
    two_crossings += report.overlapping && report.crossings == 2;
    more_crossings += report.crossings > 2;
    nested += report.overlapping && report.crossings == 0;
  }
  if (HasFailure()) return;  // the loop stopped early: the counts below mean nothing
  // The generator covers what it claims.
  EXPECT_GT(overlapping, pairs * 7 / 10);
  EXPECT_GT(tiny, pairs / 20);
  EXPECT_GT(two_crossings, pairs / 2);
  EXPECT_GT(more_crossings, pairs / 50);
  EXPECT_GT(nested, 10);
  RecordProperty("overlapping", overlapping);
  RecordProperty("tiny", tiny);
  RecordProperty("more_than_two_crossings", more_crossings);
  RecordProperty("nested", nested);
}

// ---------------------------------------------------------------------------------------------
// Polygon-polygon: degenerate cases. Coordinates are dyadic where the geometry must be exact.

Polygon square(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

Polygon shifted(Polygon p, const Vec2& by) {
  for (Vec2& v : p) v += by;
  return p;
}

// A diamond standing on its lowest corner, which is at tip.
Polygon diamond(const Vec2& tip, double half_width) {
  return {tip, tip + Vec2(half_width, half_width), tip + Vec2(0, 2 * half_width), tip + Vec2(-half_width, half_width)};
}

TEST(ConvexOverlap, VertexTouchingEdgeHasZeroArea) {
  for (const Vec2& place : {Vec2(0, 0), Vec2(3, 5), Vec2(-96, 40)}) {
    SCOPED_TRACE("place " + std::to_string(place.x()));
    const Polygon a = shifted(square(-1, -2, 1, 0), place);
    for (double along : {0.0, 0.5, -0.75}) {  // the tip on the top edge of a
      const Polygon b = diamond(place + Vec2(along, 0), 1.0);
      for (bool swap : {false, true}) {
        const Overlap o = swap ? overlap(b, vertex_mean(b), a, vertex_mean(a)) : overlap(a, vertex_mean(a), b, vertex_mean(b));
        expect_finite(o);
        EXPECT_EQ(o.area, 0.0);
        EXPECT_FALSE(o.touching());
      }
      check_polygon_pair(a, b, false);
    }
  }
}

TEST(ConvexOverlap, VertexSlightlyPenetratingEdge) {
  // The tip of a 45-degree diamond a depth d into the top edge of a box: the overlap is the
  // triangle with corners (+-d, 0) and (0, -d): area d^2, chord 2d, point at the middle of the
  // edge piece, normal straight up (from a to b).
  for (const Vec2& place : {Vec2(0, 0), Vec2(3, 5), Vec2(-96, 40)}) {
    for (int depth_exponent : {-4, -12, -20}) {
      SCOPED_TRACE("place " + std::to_string(place.x()) + " depth 2^" + std::to_string(depth_exponent));
      const double depth = std::ldexp(1.0, depth_exponent);
      const Polygon a = shifted(square(-1, -2, 1, 0), place);
      const Polygon b = diamond(place + Vec2(0.25, -depth), 1.0);
      const Overlap o = overlap(a, vertex_mean(a), b, vertex_mean(b));
      expect_finite(o);
      const double size_round_off = 16 * eps * (place.norm() + 4);
      EXPECT_NEAR(o.area, depth * depth, size_round_off * 4 * depth);
      EXPECT_EQ(o.crossings, 2);
      EXPECT_NEAR(o.chord, 2 * depth, size_round_off);
      EXPECT_LE((o.point - (place + Vec2(0.25, 0))).norm(), size_round_off);
      EXPECT_LE((o.normal - Vec2(0, 1)).norm(), size_round_off / depth);
      check_polygon_pair(a, b, true);
    }
  }
}

TEST(ConvexOverlap, SquaresSharingAWholeEdgeHaveZeroArea) {
  for (const Vec2& place : {Vec2(0, 0), Vec2(3, 5), Vec2(-96, 40)}) {
    const Polygon a = shifted(square(0, 0, 1, 1), place);
    for (const Polygon& b : {square(1, 0, 2, 1), square(0, 1, 1, 2), square(1, 0.25, 2, 0.75), square(-1, -1, 0, 0)}) {
      const Polygon b_placed = shifted(b, place);
      for (bool swap : {false, true}) {
        const Overlap o = swap ? overlap(b_placed, vertex_mean(b_placed), a, vertex_mean(a))
                               : overlap(a, vertex_mean(a), b_placed, vertex_mean(b_placed));
        expect_finite(o);
        EXPECT_EQ(o.area, 0.0);
        EXPECT_FALSE(o.touching());
      }
    }
  }
}

TEST(ConvexOverlap, SquaresWithCollinearBottomEdges) {
  // The overlap [1/2, 1] x [0, 1]. Moving b right shrinks it at rate 1 (its height): chord 1
  // along +x. For b twice as tall, moving b up shrinks it at rate 1/2 but moving it down does
  // not change it: the area has a kink, and the outward-normal integral gives the mean slope.
  struct Case {
    Polygon b;
    Vec2 chord_normal;
  };
  for (const Vec2& place : {Vec2(0, 0), Vec2(3, 5), Vec2(-96, 40)}) {
    SCOPED_TRACE("place " + std::to_string(place.x()));
    const Polygon a = shifted(square(0, 0, 1, 1), place);
    for (const Case& c : {Case{square(0.5, 0, 1.5, 1), {1, 0}}, Case{square(0.5, 0, 1.5, 2), {1, 0.25}}}) {
      const Polygon b = shifted(c.b, place);
      const Overlap o = overlap(a, vertex_mean(a), b, vertex_mean(b));
      expect_finite(o);
      expect_unit_normal(o);
      const double round_off = 16 * eps * (place.norm() + 3);
      EXPECT_NEAR(o.area, 0.5, 4 * round_off);
      EXPECT_LE((o.chord * o.normal - c.chord_normal).norm(), 4 * round_off);
      const ExactPolygon exact_a = to_exact(a), exact_b = to_exact(b);
      EXPECT_LE(distance_to(exact_intersection(exact_a, exact_b), o.point), round_off);
      expect_area_gradient(exact_a, exact_b, o, 0.125, 4 * round_off);
      const Overlap swapped = overlap(b, vertex_mean(b), a, vertex_mean(a));
      EXPECT_NEAR(swapped.area, o.area, 8 * round_off);
      EXPECT_LE((swapped.chord * swapped.normal + o.chord * o.normal).norm(), 8 * round_off);
    }
  }
}

TEST(ConvexOverlap, IdenticalGrains) {
  Rng rng(7);
  for (int i = 0; i < 200; ++i) {
    SCOPED_TRACE("polygon " + std::to_string(i));
    const double size = std::pow(10.0, rng.uniform(-3.0, 3.0));
    const Polygon a = random_convex_polygon(rng, size, size * rng.uniform(0.0, 20.0) * random_direction(rng));
    const Overlap o = overlap(a, vertex_mean(a), a, vertex_mean(a));
    expect_finite(o);
    expect_unit_normal(o);
    const ExactPolygon exact_a = to_exact(a);
    const double area = to_double(exact_a.area());
    const double round_off = 16 * eps * (largest_coordinate(a, a) + 2 * size * int(a.size())) * perimeter(a);
    EXPECT_NEAR(o.area, area, round_off);
    EXPECT_LE(distance_to(exact_a, o.point), 16 * eps * (largest_coordinate(a, a) + size) + 2 * size * round_off / area);
  }
}

TEST(ConvexOverlap, NestedPolygons) {
  // A small polygon strictly inside a large one: the overlap is the small one, with no
  // crossings; the force point is its centroid and the normal follows the centroids.
  Rng rng(11);
  int nested = 0;
  for (int i = 0; i < 200; ++i) {
    SCOPED_TRACE("pair " + std::to_string(i));
    const double size = std::pow(10.0, rng.uniform(-3.0, 3.0));
    const Vec2 place = size * rng.uniform(0.0, 20.0) * random_direction(rng);
    const Polygon large = random_convex_polygon(rng, 4 * size, place);
    // Near large's centre; the few large polygons that do not reach around it are skipped.
    const Polygon small = random_convex_polygon(rng, 0.1 * size, place + 0.1 * size * random_direction(rng));
    const ExactPolygon exact_large = to_exact(large), exact_small = to_exact(small);
    bool inside = true;
    for (const Vec2& p : small) inside = inside && exact_large.bounded_side(to_exact(p)) == CGAL::ON_BOUNDED_SIDE;
    if (!inside) continue;
    const double round_off = 16 * eps * (largest_coordinate(large, small) + 8 * size) * perimeter(small);
    for (bool small_first : {true, false}) {
      const Polygon& a = small_first ? small : large;
      const Polygon& b = small_first ? large : small;
      const Overlap o = overlap(a, vertex_mean(a), b, vertex_mean(b));
      expect_finite(o);
      expect_unit_normal(o);
      EXPECT_NEAR(o.area, to_double(exact_small.area()), round_off);
      EXPECT_EQ(o.crossings, 0);
      EXPECT_EQ(o.chord, 0.0);
      const Vec2 line = vertex_mean(b) - vertex_mean(a);
      EXPECT_LE((o.normal - line.normalized()).norm(), 16 * eps * (largest_coordinate(a, b) / line.norm() + 1));
      // The overlap centroid: the small polygon's, from exact moments.
      Exact cx = 0, cy = 0;
      for (auto e = exact_small.edges_begin(); e != exact_small.edges_end(); ++e) {
        const Exact c = e->source().x() * e->target().y() - e->source().y() * e->target().x();
        cx += (e->source().x() + e->target().x()) * c;
        cy += (e->source().y() + e->target().y()) * c;
      }
      const Vec2 centroid(to_double(cx / (6 * exact_small.area())), to_double(cy / (6 * exact_small.area())));
      const double small_size = diameter(small);
      EXPECT_LE((o.point - centroid).norm(),
                16 * eps * (largest_coordinate(a, b) + small_size) + 2 * small_size * round_off / to_double(exact_small.area()));
    }
    ++nested;
  }
  EXPECT_GT(nested, 50);
}

TEST(ConvexOverlap, TinyOverlaps) {
  // Depth 2^-30 (about 1e-9) of grains of size 1, also away from the origin. A clipped corner
  // is uncertain by about eps (R + D), i.e. a relative area error of eps (R + D) / depth, which
  // is 1e-6 already at R + D = 4: generic coordinates cannot do better than the round-off
  // model. With dyadic coordinates every corner of these overlaps is exactly representable,
  // so there the analytic value must be met to 1e-6 wherever the pair sits.
  const double depth = std::ldexp(1.0, -30);
  for (const Vec2& place : {Vec2(0, 0), Vec2(3, 5), Vec2(-24, 40)}) {
    SCOPED_TRACE("place " + std::to_string(place.x()));
    const double relative_tol = 16 * eps * (place.norm() + 4) / depth;
    // Vertex into edge: the triangle (+-d, 0), (0, -d) under the top edge: area d^2.
    {
      const Polygon a = shifted(square(-0.5, -1, 0.5, 0), place);
      const Polygon b = diamond(place + Vec2(0.125, -depth), 0.5);
      const Overlap o = overlap(a, vertex_mean(a), b, vertex_mean(b));
      EXPECT_EQ(o.crossings, 2);
      EXPECT_NEAR(o.area, depth * depth, relative_tol * depth * depth);
      EXPECT_NEAR(o.area, depth * depth, 1e-6 * depth * depth);
      EXPECT_NEAR(o.chord, 2 * depth, relative_tol * depth);
      check_polygon_pair(a, b, true);
    }
    // Edge on edge: a sliver d thick and 3/4 long; its crossings are (1/4, 1) and (1, 1 - d).
    {
      const Polygon a = shifted(square(0, 0, 1, 1), place);
      const Polygon b = shifted(square(0.25, 1 - depth, 1.25, 2 - depth), place);
      const Overlap o = overlap(a, vertex_mean(a), b, vertex_mean(b));
      EXPECT_EQ(o.crossings, 2);
      EXPECT_NEAR(o.area, 0.75 * depth, relative_tol * 0.75 * depth);
      EXPECT_NEAR(o.area, 0.75 * depth, 1e-6 * 0.75 * depth);
      EXPECT_NEAR(o.chord, std::hypot(0.75, depth), 16 * eps * (place.norm() + 2));
      EXPECT_LE((o.point - (place + Vec2(0.625, 1 - 0.5 * depth))).norm(), 16 * eps * (place.norm() + 2));
      check_polygon_pair(a, b, true);
    }
  }
  // Turned by a generic angle the corners round, so the reference is the exact area of the
  // rounded input; the contact stays 1e-9 deep.
  Rng rng(3);
  for (int i = 0; i < 100; ++i) {
    SCOPED_TRACE("turned pair " + std::to_string(i));
    Polygon a = random_convex_polygon(rng, 1.0, Vec2(0, 0));
    Polygon b = random_convex_polygon(rng, 1.0, Vec2(0, 0));
    push_corner_into_edge(rng, a, b, 1e-9);
    const Vec2 place = rng.uniform(0.0, 4.0) * random_direction(rng);
    a = shifted(a, place);
    b = shifted(b, place);
    const PairReport report = check_polygon_pair(a, b, true);
    const Overlap o = overlap(a, vertex_mean(a), b, vertex_mean(b));
    const double exact = to_double(exact_area(exact_intersection(to_exact(a), to_exact(b))));
    const double model = 16 * eps * (largest_coordinate(a, b) + diameter(joined(a, b))) / 1e-9;
    EXPECT_TRUE(report.overlapping);
    EXPECT_EQ(o.crossings, 2);
    EXPECT_NEAR(o.area, exact, model * exact);
  }
}

TEST(ConvexOverlap, SwappingTheGrainsFlipsOnlyTheNormal) {
  // check_polygon_pair compares overlap(a, b) with overlap(b, a) on every overlapping pair;
  // here on the configurations of the degenerate tests and a batch of random ones.
  const Vec2 place(3, 5);
  const Polygon box = shifted(square(-1, -2, 1, 0), place);
  check_polygon_pair(box, diamond(place + Vec2(0.25, -std::ldexp(1.0, -12)), 1.0), false);
  check_polygon_pair(box, diamond(place + Vec2(0.25, -0.5), 1.0), false);
  check_polygon_pair(box, shifted(square(-0.25, -1.5, 0.25, -1), place), false);  // nested
  Rng rng(5);
  for (int i = 0; i < 500; ++i) {
    SCOPED_TRACE("pair " + std::to_string(i));
    const Polygon a = random_convex_polygon(rng, 1.0, Vec2(0, 0));
    Polygon b = random_convex_polygon(rng, rng.uniform(0.5, 2.0), Vec2(0, 0));
    push_corner_into_edge(rng, a, b, std::pow(10.0, rng.uniform(-9.0, 0.0)));
    check_polygon_pair(a, b, false);
  }
}

// ---------------------------------------------------------------------------------------------
// Polygon-polygon: the hint the World keeps per pair

bool same_bits(const Overlap& x, const Overlap& y) {
  return std::memcmp(&x.area, &y.area, sizeof(double)) == 0 && std::memcmp(&x.chord, &y.chord, sizeof(double)) == 0 &&
         x.point == y.point && x.normal == y.normal && x.crossings == y.crossings &&
         std::memcmp(&x.centroid_shift, &y.centroid_shift, sizeof(double)) == 0;
}

double longest_edge(const Polygon& a, const Polygon& b) {
  double longest = 0.0;
  for (const Polygon* p : {&a, &b})
    for (std::size_t i = 0; i < p->size(); ++i) longest = std::max(longest, ((*p)[(i + 1) % p->size()] - (*p)[i]).norm());
  return longest;
}

TEST(ConvexOverlap, TheHintNeverChangesTheResult) {
  // The hint only says where to look first: fresh, the pair's own from the last call, one left
  // by a slightly different placement, or garbage, the result must be the same to the bit.
  Rng rng(31);
  int shallow = 0, fast = 0, separated = 0;
  for (int i = 0; i < 3000 && !HasFailure(); ++i) {
    SCOPED_TRACE("pair " + std::to_string(i));
    const Polygon a = random_convex_polygon(rng, 1.0, Vec2(0, 0));
    Polygon b = random_convex_polygon(rng, rng.uniform(0.5, 2.0), Vec2(0, 0));
    const double depth = std::pow(10.0, rng.uniform(-6.0, -0.5)) * (rng.uniform() < 0.2 ? -1.0 : 1.0);
    push_corner_into_edge(rng, a, b, depth);
    const Polygon nudged = shifted(b, 1e-3 * random_direction(rng));
    const Vec2 ca = vertex_mean(a), cb = vertex_mean(b);
    const double edge = longest_edge(a, b);
    const auto run = [&](const Polygon& q, OverlapHint& hint) {
      return overlap_polygons(a.data(), int(a.size()), ca, q.data(), int(q.size()), vertex_mean(q), edge, hint);
    };
    OverlapHint fresh;
    const Overlap reference = run(b, fresh);
    const Overlap unhinted = overlap_polygons(a.data(), int(a.size()), ca, b.data(), int(b.size()), cb);
    EXPECT_TRUE(same_bits(reference, unhinted));
    OverlapHint own = fresh;
    EXPECT_TRUE(same_bits(run(b, own), reference)) << "with its own hint";
    OverlapHint from_nudged;
    run(nudged, from_nudged);
    EXPECT_TRUE(same_bits(run(b, from_nudged), reference)) << "with the hint of a nudged placement";
    for (int g = 0; g < 8; ++g) {
      OverlapHint garbage;
      garbage.kind = static_cast<std::uint8_t>(rng.uniform_int(0, 6));  // every kind, and two that are none
      for (auto& e : garbage.edge) e = static_cast<std::uint8_t>(rng.uniform_int(0, 15));
      EXPECT_TRUE(same_bits(run(b, garbage), reference)) << "with garbage hint " << g;
    }
    // The fast path is what a shallow contact takes: a corner of b 1e-6 to 0.3 deep into an
    // edge of a crosses the boundary twice, clear of any degeneracy.
    if (depth > 0 && reference.crossings == 2) {
      ++shallow;
      fast += fresh.kind == OverlapHint::crossing;
    }
    separated += depth < 0 && (fresh.kind == OverlapHint::separated_by_a || fresh.kind == OverlapHint::separated_by_b);
  }
  EXPECT_GT(shallow, 1500);
  EXPECT_EQ(fast, shallow) << "every shallow two-crossing contact takes the fast path";
  EXPECT_GT(separated, 200);
}

TEST(ConvexOverlap, EveryCrossingHintOfADeepOverlapGivesTheSameResult) {
  // Deep overlaps whose boundaries cross four or more times: some hints name two real
  // crossings of opposite sense with the wrong corners between them (a plus sign's arms), which
  // only the check of those corners can tell. Every hint, the same result.
  Rng rng(37);
  int many_crossings = 0;
  for (int i = 0; i < 400 && many_crossings < 40 && !HasFailure(); ++i) {
    const Polygon a = random_convex_polygon(rng, 1.0, Vec2(0, 0));
    const Polygon b = random_convex_polygon(rng, 1.0, 0.3 * rng.uniform() * random_direction(rng));
    if (a.size() > 8 || b.size() > 8) continue;
    const BoundaryCrossings crossings = boundary_crossings(to_exact(a), to_exact(b));
    if (crossings.points.size() < 4 || crossings.collinear) continue;
    ++many_crossings;
    SCOPED_TRACE("pair " + std::to_string(i));
    const Vec2 ca = vertex_mean(a), cb = vertex_mean(b);
    const double edge = longest_edge(a, b);
    const Overlap reference = overlap_polygons(a.data(), int(a.size()), ca, b.data(), int(b.size()), cb);
    const int na = int(a.size()), nb = int(b.size());
    for (int e = 0; e < na * nb * na * nb && !HasFailure(); ++e) {
      OverlapHint hint;
      hint.kind = OverlapHint::crossing;
      hint.edge[0] = static_cast<std::uint8_t>(e % na);
      hint.edge[1] = static_cast<std::uint8_t>(e / na % nb);
      hint.edge[2] = static_cast<std::uint8_t>(e / (na * nb) % na);
      hint.edge[3] = static_cast<std::uint8_t>(e / (na * nb * na));
      const Overlap o = overlap_polygons(a.data(), na, ca, b.data(), nb, cb, edge, hint);
      EXPECT_TRUE(same_bits(o, reference)) << "hint edges " << int(hint.edge[0]) << " " << int(hint.edge[1]) << " "
                                           << int(hint.edge[2]) << " " << int(hint.edge[3]);
    }
  }
  EXPECT_GE(many_crossings, 40);
}

// The distance between two disjoint polygons, in long double: the nearest of each corner to
// each edge of the other.
long double polygon_distance(const Polygon& a, const Polygon& b) {
  const auto corner_to_edges = [](const Polygon& p, const Polygon& q) {
    long double nearest = INFINITY;
    for (const Vec2& c : p)
      for (std::size_t k = 0; k < q.size(); ++k) {
        const Vec2& e0 = q[k];
        const Vec2& e1 = q[(k + 1) % q.size()];
        const long double dx = (long double)e1.x() - e0.x(), dy = (long double)e1.y() - e0.y();
        const long double cx = (long double)c.x() - e0.x(), cy = (long double)c.y() - e0.y();
        const long double t = std::clamp((cx * dx + cy * dy) / (dx * dx + dy * dy), 0.0L, 1.0L);
        nearest = std::min(nearest, std::hypot(cx - t * dx, cy - t * dy));
      }
    return nearest;
  };
  return std::min(corner_to_edges(a, b), corner_to_edges(b, a));
}

TEST(ConvexOverlap, TheGapIsALowerBoundOnTheDistance) {
  // Pairs apart by 1e-9 to 0.3 of their size, corner to edge or in any direction: whatever the
  // hint, no contact, and the gap reported (the separation along the axis that showed them
  // apart) never exceeds the true distance. The World skips a pair on that bound.
  Rng rng(43);
  int with_gap = 0, close = 0;
  for (int i = 0; i < 3000 && !HasFailure(); ++i) {
    SCOPED_TRACE("pair " + std::to_string(i));
    Polygon a = random_convex_polygon(rng, 1.0, Vec2(0, 0));
    Polygon b = random_convex_polygon(rng, rng.uniform(0.5, 2.0), Vec2(0, 0));
    const double depth = -std::pow(10.0, rng.uniform(-9.0, -0.5));
    if (i % 2) {
      push_corner_into_edge(rng, a, b, depth);
    } else {
      // Along a random direction until the projections part, then the gap beyond.
      const Vec2 u = random_direction(rng);
      double max_a = -INFINITY, min_b = INFINITY;
      for (const Vec2& p : a) max_a = std::max(max_a, u.dot(p));
      for (const Vec2& p : b) min_b = std::min(min_b, u.dot(p));
      b = shifted(b, (max_a - min_b - depth) * u);
    }
    // Away from the origin, as grains are: the World allows the gap a round-off of 1e-12 of the
    // coordinates' size (world.cpp), which this checks.
    const Vec2 place = rng.uniform(0.0, 3.0) * random_direction(rng);
    a = shifted(a, place);
    b = shifted(b, place);
    const double size = std::abs(place.x()) + std::abs(place.y()) + 4.0;
    const double edge = longest_edge(a, b);
    const long double distance = polygon_distance(a, b);
    ASSERT_GT(distance, 0.0L);
    close += distance < 1e-6 * edge;
    std::vector<OverlapHint> hints(1);
    for (int g = 0; g < 6; ++g) {
      OverlapHint garbage;
      garbage.kind = static_cast<std::uint8_t>(rng.uniform_int(0, 6));
      for (auto& e : garbage.edge) e = static_cast<std::uint8_t>(rng.uniform_int(0, 15));
      hints.push_back(garbage);
    }
    for (OverlapHint& hint : hints) {
      const Overlap o =
          overlap_polygons(a.data(), int(a.size()), vertex_mean(a), b.data(), int(b.size()), vertex_mean(b), edge, hint);
      if (distance > certain_separation * edge) {
        EXPECT_FALSE(o.touching()) << "distance " << double(distance);
      }
      if (o.touching()) continue;
      EXPECT_GE(o.gap, 0.0);
      // The projections carry round-off of a few ulp of the coordinates.
      EXPECT_LE(o.gap, distance + 1e-12L * size) << "distance " << double(distance);
      with_gap += o.gap > 0.0;
    }
  }
  EXPECT_GT(with_gap, 10000);
  EXPECT_GT(close, 300);
}

// ---------------------------------------------------------------------------------------------
// Disc-disc

struct LensReference {
  bool separated = false, contained = false;
  double area = 0.0, chord = 0.0;
  Vec2 point{0, 0}, normal{0, 1};
};

// The textbook lens (two circular segments on the chord from the law of cosines), at 256 bits.
LensReference lens_reference(const Vec2& ca, double ra, const Vec2& cb, double rb) {
  LensReference ref;
  const Big dx = Big(cb.x()) - Big(ca.x()), dy = Big(cb.y()) - Big(ca.y());
  const Big dist = sqrt(dx * dx + dy * dy);
  const Big r_a(ra), r_b(rb);
  if (!(dist < r_a + r_b)) {
    ref.separated = true;
    return ref;
  }
  if (0.0 < dist.to_double()) ref.normal = Vec2((dx / dist).to_double(), (dy / dist).to_double());
  if (!(abs(r_a - r_b) < dist)) {
    const double r = std::min(ra, rb);
    ref.contained = true;
    ref.area = (Big::pi() * Big(r) * Big(r)).to_double();
    return ref;
  }
  const Big x = (dist * dist + r_a * r_a - r_b * r_b) / (Big(2.0) * dist);  // ca to the chord
  const Big half_chord = sqrt(r_a * r_a - x * x);
  ref.area = (circular_segment(r_a, x) + circular_segment(r_b, dist - x)).to_double();
  ref.chord = (Big(2.0) * half_chord).to_double();
  ref.point = Vec2((Big(ca.x()) + x * dx / dist).to_double(), (Big(ca.y()) + x * dy / dist).to_double());
  return ref;
}

void check_disc_pair(const Vec2& ca, double ra, const Vec2& cb, double rb) {
  const Overlap o = overlap_discs(ca, ra, cb, rb);
  const LensReference ref = lens_reference(ca, ra, cb, rb);
  expect_finite(o);
  expect_unit_normal(o);
  if (ref.separated) {
    EXPECT_EQ(o.area, 0.0);
    return;
  }
  const double coordinate = std::max(ca.norm(), cb.norm());
  const double dist = (cb - ca).norm();
  // The centre distance is known to eps (R + dist); the area moves by chord per unit of it
  // (dA/d dist = -chord). Each segment is then formed to a few eps of itself.
  const double length_round_off = 32 * eps * (coordinate + dist + ra + rb);
  if (ref.contained) {
    EXPECT_NEAR(o.area, ref.area, 4 * eps * ref.area);
    EXPECT_EQ(o.crossings, 0);
    return;
  }
  EXPECT_NEAR(o.area, ref.area, 32 * eps * ref.area + ref.chord * length_round_off);
  EXPECT_EQ(o.crossings, 2);
  // The half-chord near tangency is ill-conditioned: dh = (r / h) dx.
  EXPECT_NEAR(o.chord, ref.chord, length_round_off * (1 + 2 * std::max(ra, rb) / ref.chord));
  // The point is ca + x n, and n turns by eps R / dist.
  EXPECT_LE((o.point - ref.point).norm(), length_round_off * (1 + std::max(ra, rb) / dist));
  EXPECT_LE((o.normal - ref.normal).norm(), 8 * eps * (1 + coordinate / dist));
}

TEST(DiscOverlap, LensMatchesHighPrecisionFormula) {
  Rng rng(99);
  for (int i = 0; i < 20000 && !HasFailure(); ++i) {
    SCOPED_TRACE("pair " + std::to_string(i));
    const double scale = std::pow(10.0, rng.uniform(-3.0, 3.0));
    const double ra = scale * std::pow(10.0, rng.uniform(-0.5, 0.5));
    const double rb = scale * std::pow(10.0, rng.uniform(-0.5, 0.5));
    const Vec2 ca = scale * std::pow(10.0, rng.uniform(-1.0, 1.3)) * random_direction(rng);
    // Depths from 1e-12 of the smaller radius to total containment, and some gaps.
    const double relative_depth = std::pow(10.0, rng.uniform(-12.0, 0.4));
    const double dist = std::max(0.0, ra + rb - relative_depth * 2 * std::min(ra, rb) * (rng.uniform() < 0.05 ? -1 : 1));
    check_disc_pair(ca, ra, ca + dist * random_direction(rng), rb);
  }
  // Exact limits: touching, internally tangent, concentric, and a hair from containment.
  check_disc_pair({3, 5}, 1.0, {5, 5}, 1.0);
  check_disc_pair({3, 5}, 1.0, {3.5, 5}, 0.5);
  check_disc_pair({3, 5}, 1.0, {3, 5}, 0.5);
  check_disc_pair({3, 5}, 1.0, {3, 5}, 1.0);
  check_disc_pair({3, 5}, 1.0, {3.5 + std::ldexp(1.0, -30), 5}, 0.5);
  check_disc_pair({3, 5}, 1.0, {5 - std::ldexp(1.0, -40), 5}, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Disc-polygon

Overlap overlap(const Vec2& c, double r, const Polygon& b) {
  return overlap_disc_polygon(c, r, b.data(), int(b.size()), vertex_mean(b));
}

// The code sums, per edge, the disc's share of the triangle (centre, edge): sectors of r^2 and
// triangles inside the disc, each good to a few eps r^2, with edge ends known to eps R.
double disc_polygon_area_tol(const Vec2& c, double r, const Polygon& b) {
  double reach = 0.0, coordinate = c.norm();
  for (const Vec2& p : b) {
    reach = std::max(reach, (p - c).norm());
    coordinate = std::max(coordinate, p.norm());
  }
  return 32 * eps * r * (double(b.size()) * r + coordinate + reach);
}

TEST(DiscPolygonOverlap, DiscCuttingOneEdge) {
  // A large polygon (a turned square 200 radii across, or a random one) and a disc at the
  // middle of one edge, its centre at signed distance d outside the edge's line: the overlap
  // is the circular segment r^2 acos(d/r) - d sqrt(r^2 - d^2); d < 0 gives the rest of the disc.
  Rng rng(17);
  int cases = 0;
  for (int i = 0; i < 2000 && !HasFailure(); ++i) {
    SCOPED_TRACE("case " + std::to_string(i));
    const double r = std::pow(10.0, rng.uniform(-3.0, 3.0));
    const Vec2 place = r * rng.uniform(0.0, 50.0) * random_direction(rng);
    const Polygon b = i % 2 ? random_convex_polygon(rng, 100 * r, place) : [&] {
      Polygon box;
      const double turn = rng.uniform(0.0, 2 * M_PI);
      for (const Vec2& corner : {Vec2(-1, -1), Vec2(1, -1), Vec2(1, 1), Vec2(-1, 1)})
        box.push_back(place + rotate(100 * r * corner, std::cos(turn), std::sin(turn)));
      return box;
    }();
    // The longest edge, so the disc reaches no other edge.
    int k = 0;
    for (int j = 0; j < int(b.size()); ++j)
      if ((b[(j + 1) % b.size()] - b[j]).norm() > (b[(k + 1) % b.size()] - b[k]).norm()) k = j;
    const Vec2 e0 = b[k], e1 = b[(k + 1) % b.size()];
    if ((e1 - e0).norm() < 8 * r) continue;
    const Vec2 outward_normal = Vec2((e1 - e0).y(), -(e1 - e0).x()).normalized();
    const double depth = r * std::pow(10.0, rng.uniform(-9.0, std::log10(2.0)));  // of the disc into b
    const Vec2 c = 0.5 * (e0 + e1) + (r - depth) * outward_normal;
    bool cuts_one_edge = true;  // the polygon may be narrow across: the disc must miss the rest
    for (int j = 0; j < int(b.size()); ++j)
      if (j != k) {
        const Vec2 d = b[(j + 1) % b.size()] - b[j];
        cuts_one_edge = cuts_one_edge && cross(d, c - b[j]) / d.norm() > r;
      }
    if (!cuts_one_edge) continue;
    const Overlap o = overlap(c, r, b);
    expect_finite(o);
    expect_unit_normal(o);
    // Signed distance of the centre from the edge's line, from the input as stored.
    const Big dx = Big(e1.x()) - Big(e0.x()), dy = Big(e1.y()) - Big(e0.y());
    const Big signed_distance =
        (dx * (Big(e0.y()) - Big(c.y())) - dy * (Big(e0.x()) - Big(c.x()))) / sqrt(dx * dx + dy * dy);
    const double reference = circular_segment(Big(r), signed_distance).to_double();
    const double half_chord = sqrt(Big(r) * Big(r) - signed_distance * signed_distance).to_double();
    EXPECT_NEAR(o.area, reference, disc_polygon_area_tol(c, r, b)) << "depth " << depth / r;
    EXPECT_EQ(o.crossings, 2);
    const double d = signed_distance.to_double();
    const double round_off = 32 * eps * (c.norm() + place.norm() + 200 * r);
    EXPECT_NEAR(o.chord, 2 * half_chord, round_off * (1 + r / half_chord)) << "r " << r << " depth " << depth;
    EXPECT_LE((o.point - (c - d * outward_normal)).norm(), round_off * (1 + r / half_chord));
    EXPECT_LE((o.normal + outward_normal).norm(), 8 * eps) << "normal must point from the disc into b";
    ++cases;
  }
  EXPECT_GT(cases, 1000);
}

TEST(DiscPolygonOverlap, DiscInsidePolygon) {
  Rng rng(23);
  int cases = 0;
  for (int i = 0; i < 500; ++i) {
    SCOPED_TRACE("case " + std::to_string(i));
    const double size = std::pow(10.0, rng.uniform(-3.0, 3.0));
    const Vec2 place = size * rng.uniform(0.0, 20.0) * random_direction(rng);
    const Polygon b = random_convex_polygon(rng, size, place);
    const Vec2 c = vertex_mean(b) + 0.05 * size * random_direction(rng);
    double r = 0.5 * size;  // shrink until the disc clears every edge line
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Vec2 d = b[(j + 1) % b.size()] - b[j];
      r = std::min(r, 0.9 * cross(d, c - b[j]) / d.norm());
    }
    if (!(r > 1e-3 * size)) continue;
    const Overlap o = overlap(c, r, b);
    expect_finite(o);
    expect_unit_normal(o);
    EXPECT_NEAR(o.area, M_PI * r * r, disc_polygon_area_tol(c, r, b));
    EXPECT_EQ(o.crossings, 0);
    EXPECT_EQ(o.chord, 0.0);
    EXPECT_EQ(o.point, c);
    ++cases;
  }
  EXPECT_GT(cases, 250);
}

TEST(DiscPolygonOverlap, PolygonInsideDisc) {
  Rng rng(29);
  for (int i = 0; i < 500; ++i) {
    SCOPED_TRACE("case " + std::to_string(i));
    const double size = std::pow(10.0, rng.uniform(-3.0, 3.0));
    const Vec2 place = size * rng.uniform(0.0, 20.0) * random_direction(rng);
    const Polygon b = random_convex_polygon(rng, size, place);
    const Vec2 c = place + size * rng.uniform(0.0, 2.0) * random_direction(rng);
    double reach = 0.0;
    for (const Vec2& p : b) reach = std::max(reach, (p - c).norm());
    const double r = reach * rng.uniform(1.01, 3.0);
    const Overlap o = overlap(c, r, b);
    expect_finite(o);
    expect_unit_normal(o);
    EXPECT_NEAR(o.area, to_double(to_exact(b).area()), disc_polygon_area_tol(c, r, b));
    EXPECT_EQ(o.crossings, 0);
  }
}

// Where the polygon's edges cross the circle, from the quadratic in the edge parameter at 256
// bits; half-open edges [p, q) as the boundary is walked.
struct CircleCrossing {
  Vec2 point;
  double half_chord;  // of the edge's line in the circle: the crossing's conditioning is r / this
};

std::vector<CircleCrossing> circle_crossings(const Vec2& c, double r, const Polygon& b) {
  std::vector<CircleCrossing> found;
  for (std::size_t k = 0; k < b.size(); ++k) {
    const Vec2& p = b[k];
    const Vec2& q = b[(k + 1) % b.size()];
    const Big px = Big(p.x()) - Big(c.x()), py = Big(p.y()) - Big(c.y());
    const Big dx = Big(q.x()) - Big(p.x()), dy = Big(q.y()) - Big(p.y());
    const Big a = dx * dx + dy * dy, half_b = px * dx + py * dy, rest = px * px + py * py - Big(r) * Big(r);
    const Big discriminant = half_b * half_b - a * rest;
    if (!(Big(0.0) < discriminant)) continue;
    const Big root = sqrt(discriminant);
    for (const Big& t : {(Big(0.0) - half_b - root) / a, (Big(0.0) - half_b + root) / a}) {
      if (t < Big(0.0) || !(t < Big(1.0))) continue;
      found.push_back({Vec2((Big(p.x()) + t * dx).to_double(), (Big(p.y()) + t * dy).to_double()),
                       (root / sqrt(a)).to_double()});
    }
  }
  return found;
}

// A regular n-gon about c with its corners at radius corner_radius (rounded to doubles).
ExactPolygon regular_polygon(const Vec2& c, double corner_radius, int n) {
  ExactPolygon p;
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * M_PI * i / n;
    p.push_back(to_exact(c + corner_radius * Vec2(std::cos(angle), std::sin(angle))));
  }
  return p;
}

TEST(DiscPolygonOverlap, RandomPairsLieBetweenInscribedAndCircumscribedPolygons) {
  Rng rng(31);
  constexpr int sides = 128;
  int two_crossings = 0;
  for (int i = 0; i < 600 && !HasFailure(); ++i) {
    SCOPED_TRACE("pair " + std::to_string(i));
    const double size = std::pow(10.0, rng.uniform(-3.0, 3.0));
    const Vec2 place = size * rng.uniform(0.0, 20.0) * random_direction(rng);
    const Polygon b = random_convex_polygon(rng, size, place);
    const double r = size * std::exp2(rng.uniform(-2.0, 2.0));
    const Vec2 c = place + (size + r) * rng.uniform(0.0, 1.1) * random_direction(rng);
    const Overlap o = overlap(c, r, b);
    expect_finite(o);
    expect_unit_normal(o);

    // The disc between two exact polygons: corners pulled in by the rounding of their
    // coordinates (eps (|c| + r) each) stay inside the circle; an apothem pushed out by it
    // stays outside.
    const double rounding = 8 * eps * (c.norm() + r);
    const ExactPolygon exact_b = to_exact(b);
    const ExactPolygon inscribed = regular_polygon(c, r - rounding, sides);
    const ExactPolygon circumscribed = regular_polygon(c, (r + rounding) / std::cos(M_PI / sides), sides);
    const double lower = to_double(exact_area(exact_intersection(exact_b, inscribed)));
    const double upper = to_double(exact_area(exact_intersection(exact_b, circumscribed)));
    const double tol = disc_polygon_area_tol(c, r, b);
    EXPECT_GE(o.area, lower - tol);
    EXPECT_LE(o.area, upper + tol);
    if (upper == 0.0) {
      EXPECT_EQ(o.area, 0.0);
    }
    if (!(o.area > 0)) continue;

    // The force point lies in the overlap: in b and in the disc.
    double coordinate = c.norm(), reach = 0.0;
    for (const Vec2& p : b) {
      coordinate = std::max(coordinate, p.norm());
      reach = std::max(reach, (p - c).norm());
    }
    const double length_round_off = 32 * eps * (coordinate + reach + r);
    const std::vector<CircleCrossing> crossings = circle_crossings(c, r, b);
    double conditioning = 1.0;  // r / half-chord, the worst crossing's
    for (const CircleCrossing& x : crossings) conditioning = std::max(conditioning, r / x.half_chord);
    const double point_tol = length_round_off * conditioning;
    EXPECT_LE(distance_to(exact_b, o.point), point_tol);
    EXPECT_LE((o.point - c).norm(), r + point_tol);
    EXPECT_EQ(o.crossings, int(crossings.size()));
    if (o.crossings != 2 || crossings.size() != 2) continue;
    ++two_crossings;

    // The contact line, and its side: b's corners inside the disc lie behind it (the normal
    // points from the disc into b), those outside in front.
    const Vec2 x1 = crossings[0].point, x2 = crossings[1].point;
    const double gradient_tol = 2 * point_tol + 8 * eps * perimeter(b);
    EXPECT_LE((o.point - 0.5 * (x1 + x2)).norm(), point_tol);
    EXPECT_NEAR(o.chord, (x2 - x1).norm(), gradient_tol);
    EXPECT_LE(std::abs(o.normal.dot(x2 - x1)), gradient_tol);
    // The overlap's centroid on the contact line: the inscribed polygon's overlap differs from
    // the disc's by at most upper - lower in area, which moves a centroid by at most that share
    // of the area times the overlap's reach (2 r).
    const Vec2 centroid = exact_centroid(exact_intersection(exact_b, inscribed));
    const double centroid_tol = (upper - lower + 2 * tol) / o.area * 2 * r + point_tol;
    EXPECT_NEAR(o.centroid_shift, (centroid - o.point).dot(perp(o.normal)), centroid_tol);
    for (const Vec2& p : b) {
      const Big px = Big(p.x()) - Big(c.x()), py = Big(p.y()) - Big(c.y());
      const bool inside = px * px + py * py < Big(r) * Big(r);
      const double side = o.normal.dot(p - o.point);
      const double side_tol = point_tol + gradient_tol / o.chord * (p - o.point).norm();
      if (inside) {
        EXPECT_LE(side, side_tol);
      } else {
        EXPECT_GE(side, -side_tol);
      }
    }
  }
  if (!HasFailure()) {
    EXPECT_GT(two_crossings, 100);
  }
}

}  // namespace
}  // namespace pilelab::dem

namespace pilelab::dem {
namespace {

// The kernel's four lanes, each the same contact: corner `corner` of corner_polygon (after
// corner `before`) in edge `edge` of edge_polygon, whose centroid is centre; chord_reversed for
// a corner of the pair's second polygon.
two_crossing::CornerInEdgeBatch same_contact_in_every_lane(const std::vector<Vec2>& corner_polygon, int before, int corner,
                                                           const std::vector<Vec2>& edge_polygon, int edge, const Vec2& centre,
                                                           double margin, bool chord_reversed) {
  const int nc = static_cast<int>(corner_polygon.size()), ne = static_cast<int>(edge_polygon.size());
  two_crossing::CornerInEdgeBatch in;
  for (int lane = 0; lane < 4; ++lane) {
    in.p0x[lane] = corner_polygon[before].x(), in.p0y[lane] = corner_polygon[before].y();
    in.cx[lane] = corner_polygon[corner].x(), in.cy[lane] = corner_polygon[corner].y();
    in.p2x[lane] = corner_polygon[(corner + 1) % nc].x(), in.p2y[lane] = corner_polygon[(corner + 1) % nc].y();
    in.e0x[lane] = edge_polygon[edge].x(), in.e0y[lane] = edge_polygon[edge].y();
    in.e1x[lane] = edge_polygon[(edge + 1) % ne].x(), in.e1y[lane] = edge_polygon[(edge + 1) % ne].y();
    in.qx[lane] = centre.x(), in.qy[lane] = centre.y();
    in.margin[lane] = margin;
    in.chord_reversed[lane] = chord_reversed ? -1 : 0;
  }
  return in;
}

// The batched corner-in-edge kernel gives the scalar fast path's overlap bit for bit wherever it
// accepts a lane, and accepts the shallow contacts a pile is made of: two hexagons with a
// corner of one pushed into an edge of the other (either polygon's corner, either lane order).
TEST(ConvexOverlap, BatchedCornerInEdgeMatchesTheScalarPathBitForBit) {
  std::mt19937_64 random(2010);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const auto hexagon = [](Vec2 centre, double radius, double angle) {
    std::vector<Vec2> corners;
    for (int k = 0; k < 6; ++k)
      corners.push_back(centre + radius * Vec2(std::cos(angle + k * M_PI / 3), std::sin(angle + k * M_PI / 3)));
    return corners;
  };
  int cases = 0, accepted = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double radius = 3e-3;
    const Vec2 ca(0.3 + 0.1 * uniform(random), 0.1 + 0.1 * uniform(random));
    const double angle_a = 2 * M_PI * uniform(random);
    // b's inner radius is radius cos 30 deg; a's corner at angle 0 pokes into b by depth.
    const double depth = 1e-6 + 2e-5 * uniform(random);
    const Vec2 towards(std::cos(angle_a), std::sin(angle_a));
    const Vec2 cb = ca + (radius + radius * std::cos(M_PI / 6) - depth) * towards;
    const double face = std::atan2(-towards.y(), -towards.x()) + M_PI / 6;  // a face of b towards a
    const auto a = hexagon(ca, radius, angle_a);
    const auto b = hexagon(cb, radius, face + 0.2 * (uniform(random) - 0.5));
    const bool swap = trial % 2 == 1;  // half the cases: b's corner in a's edge
    const auto& p = swap ? b : a;
    const auto& q = swap ? a : b;
    const Vec2 cp = swap ? cb : ca, cq = swap ? ca : cb;
    OverlapHint hint;
    overlap_polygons(p.data(), 6, cp, q.data(), 6, cq, radius, hint);  // finds the edges
    const Overlap scalar = overlap_polygons(p.data(), 6, cp, q.data(), 6, cq, radius, hint);
    if (hint.kind != OverlapHint::crossing) continue;
    const int i = hint.edge[0], k = hint.edge[1], j = hint.edge[2], l = hint.edge[3];
    const bool corner_of_p = k == l && j == (i + 1) % 6, corner_of_q = i == j && k == (l + 1) % 6;
    if (!corner_of_p && !corner_of_q) continue;
    ++cases;
    const auto& corner_polygon = corner_of_p ? p : q;
    const auto& edge_polygon = corner_of_p ? q : p;
    const int before = corner_of_p ? i : l, corner = corner_of_p ? j : k, edge = corner_of_p ? k : i;
    const two_crossing::CornerInEdgeBatch in = same_contact_in_every_lane(
        corner_polygon, before, corner, edge_polygon, edge, corner_of_p ? cq : cp, two_crossing::clear_margin * radius, corner_of_q);
    two_crossing::CornerInEdgeOverlaps out;
    two_crossing::corner_in_edge_x4(in, out);
    for (int lane = 0; lane < 4; ++lane) {
      if (!out.ok[lane]) continue;
      ++accepted;
      const double batch[7] = {out.area[lane], out.chord[lane], out.point_x[lane], out.point_y[lane],
                               out.normal_x[lane], out.normal_y[lane], out.centroid_shift[lane]};
      const double reference[7] = {scalar.area, scalar.chord, scalar.point.x(), scalar.point.y(), scalar.normal.x(),
                                   scalar.normal.y(), scalar.centroid_shift};
      for (int m = 0; m < 7; ++m)
        ASSERT_EQ(std::memcmp(&batch[m], &reference[m], sizeof(double)), 0)
            << "trial " << trial << " value " << m << ": " << batch[m] << " against " << reference[m];
    }
  }
  // Most generated pairs are corner-in-edge contacts, and the batch proves them all.
  EXPECT_GT(cases, 1000);
  EXPECT_EQ(accepted, 4 * cases);
}

}  // namespace
}  // namespace pilelab::dem

namespace pilelab::dem {
namespace {

// A corner pushed obliquely into a long edge near its end lies outside the triangle of the
// chord and the other polygon's centroid, the kernel's quick proof that it is inside: the
// kernel then asks its caller for the test against every edge (needs_polygon_test), and with
// that answer gives the scalar path's overlap bit for bit. An elongated hexagon (axes 3:1)
// receives a regular one's corner at a random place along its long edge, tilted by up to 30
// degrees, either polygon first.
TEST(ConvexOverlap, BatchedCornerInEdgeNearTheEndOfALongEdgeMatchesTheScalarPath) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double r = 3e-3;
  const auto hexagon = [](Vec2 centre, double ax, double ay, double angle) {
    std::vector<Vec2> corners;
    const Vec2 u(std::cos(angle), std::sin(angle)), v(-std::sin(angle), std::cos(angle));
    for (int k = 0; k < 6; ++k)
      corners.push_back(centre + ax * std::cos(k * M_PI / 3) * u + ay * std::sin(k * M_PI / 3) * v);
    return corners;
  };
  int cases = 0, by_polygon = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    // q's long top edge joins its corners 1 and 2, at y = ay sin 60 deg; a point on it from
    // 0 to 95 % of the way to its ends, and p's corner 0 pointing down into it, tilted.
    const Vec2 cq(0.2 + 0.1 * uniform(random), 0.2 + 0.1 * uniform(random));
    const double ax = 3 * r, ay = r, edge_y = ay * std::sin(M_PI / 3), half_length = ax * std::cos(M_PI / 3);
    const double along = (2 * uniform(random) - 1) * 0.95 * half_length, depth = 2e-6 + 3e-5 * uniform(random);
    const double tilt = (2 * uniform(random) - 1) * M_PI / 6;
    const Vec2 down(std::sin(tilt), -std::cos(tilt));  // p's corner 0 points along this
    const Vec2 tip = cq + Vec2(along, edge_y - depth);
    const Vec2 cp = tip - r * down;
    const auto q = hexagon(cq, ax, ay, 0.0);
    const auto p = hexagon(cp, r, r, std::atan2(down.y(), down.x()));
    const bool swap = trial % 2 == 1;  // half the cases: the corner is the second polygon's
    const auto& a = swap ? q : p;
    const auto& b = swap ? p : q;
    const Vec2 ca = swap ? cq : cp, cb = swap ? cp : cq;
    const double longest = 2 * half_length;
    OverlapHint hint;
    overlap_polygons(a.data(), 6, ca, b.data(), 6, cb, longest, hint);  // finds the edges
    const Overlap scalar = overlap_polygons(a.data(), 6, ca, b.data(), 6, cb, longest, hint);
    if (hint.kind != OverlapHint::crossing) continue;
    const int i = hint.edge[0], k = hint.edge[1], j = hint.edge[2], l = hint.edge[3];
    const bool corner_of_a = k == l && j == (i + 1) % 6, corner_of_b = i == j && k == (l + 1) % 6;
    if (!corner_of_a && !corner_of_b) continue;
    ++cases;
    const auto& corner_polygon = corner_of_a ? a : b;
    const auto& edge_polygon = corner_of_a ? b : a;
    const int before = corner_of_a ? i : l, corner = corner_of_a ? j : k, edge = corner_of_a ? k : i;
    const double margin = two_crossing::clear_margin * longest;
    const two_crossing::CornerInEdgeBatch in = same_contact_in_every_lane(corner_polygon, before, corner, edge_polygon, edge,
                                                                          corner_of_a ? cb : ca, margin, corner_of_b);
    two_crossing::CornerInEdgeOverlaps out;
    two_crossing::corner_in_edge_x4(in, out);
    const bool inside = two_crossing::clearly_inside({corner_polygon[corner].x(), corner_polygon[corner].y()},
                                                     edge_polygon.data(), 6, margin * margin);
    ASSERT_FALSE(out.ok[0] && out.needs_polygon_test[0]) << "trial " << trial;
    by_polygon += out.needs_polygon_test[0] != 0;
    ASSERT_TRUE(out.ok[0] || (out.needs_polygon_test[0] && inside)) << "trial " << trial << ": a shallow contact refused";
    const double batch[7] = {out.area[0],     out.chord[0],    out.point_x[0],        out.point_y[0],
                             out.normal_x[0], out.normal_y[0], out.centroid_shift[0]};
    const double reference[7] = {scalar.area,       scalar.chord,      scalar.point.x(),     scalar.point.y(),
                                 scalar.normal.x(), scalar.normal.y(), scalar.centroid_shift};
    for (int m = 0; m < 7; ++m)
      ASSERT_EQ(std::memcmp(&batch[m], &reference[m], sizeof(double)), 0)
          << "trial " << trial << " value " << m << ": " << batch[m] << " against " << reference[m];
  }
  // Most trials are corner-in-edge contacts, and a fair share of them needs the polygon test.
  EXPECT_GT(cases, 3000);
  EXPECT_GT(by_polygon, 200);
}

}  // namespace
}  // namespace pilelab::dem
