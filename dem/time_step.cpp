#include "dem/time_step.h"

#include <algorithm>
#include <cmath>

namespace pilelab::dem {

namespace {

// The weight of a chord of length c whose force acts at moment arm a.
struct ChordWeight {
  double inv_mass, inv_inertia;
  double operator()(double c, double a) const { return c * (inv_mass + a * a * inv_inertia); }
};

// Chords along one edge, whose ends run from s_p to s_q along it (measured from the foot of the
// centroid): a chord with midpoint s is at most 2 min(s - s_p, s_q - s) long and acts at arm |s|.
// On each half the weight is a cubic in s; its maximum is at the middle or where the
// derivative, 2/m + (6 s^2 - 4 s_end s)/I (up to sign), vanishes.
void heaviest_chord_along_edge(double s_p, double s_q, const ChordWeight& weight, HeaviestChord& best) {
  auto consider = [&](double s) {
    const double c = 2.0 * std::min(s - s_p, s_q - s);
    const double w = weight(c, s);
    if (c > 0.0 && w > best.weight) best = {c, std::abs(s), w};
  };
  const double mid = 0.5 * (s_p + s_q);
  consider(mid);
  for (double end : {s_p, s_q}) {
    // 6 s^2 - 4 end s + 2 I/m = 0
    const double disc = 16.0 * end * end - 48.0 * weight.inv_mass / weight.inv_inertia;
    if (disc < 0.0) continue;
    for (double sign : {-1.0, 1.0}) {
      const double s = (4.0 * end + sign * std::sqrt(disc)) / 12.0;
      if (s > std::min(end, mid) && s < std::max(end, mid)) consider(s);
    }
  }
}

// Chords from P on edge i (parameter u) to Q on edge j (parameter w), which cut off corners
// i+1 .. j. Returns the weight, or -1 if the cut-off part is deeper than max_depth.
struct CornerChords {
  const std::vector<Vec2>& v;
  int i, j;  // j may exceed n: indices are taken mod n
  double max_depth;
  ChordWeight weight;
  double lever_cap;  // 0: levers not counted; otherwise the inner radius
  double evaluate(double u, double w, HeaviestChord* out = nullptr) const {
    const int n = static_cast<int>(v.size());
    const Vec2 p = v[i % n] + u * (v[(i + 1) % n] - v[i % n]);
    const Vec2 q = v[j % n] + w * (v[(j + 1) % n] - v[j % n]);
    const Vec2 d = q - p;
    const double c = d.norm();
    if (!(c > 0.0)) return -1.0;
    const Vec2 t = d / c;
    // The cut-off corners lie right of p -> q (the polygon is counter-clockwise).
    for (int k = i + 1; k <= j; ++k)
      if (cross(v[k % n] - p, t) > max_depth) return -1.0;
    const Vec2 mid = 0.5 * (p + q);
    const double arm = std::abs(t.dot(mid));
    // A chord across corners may pass closer to the centroid than any edge: its lever, and so
    // l, is then shorter than the inner radius (only when the search counts levers).
    const double lever = lever_cap > 0.0 ? std::clamp(mid.norm(), 0.5 * lever_cap, lever_cap) : 0.0;
    const double result = weight(c, arm) * (lever_cap > 0.0 ? lever_cap / lever : 1.0);
    if (out) *out = {c, arm, result, lever};
    return result;
  }
};

}  // namespace

// The largest omega_t dt at which the tangential spring of A.2 stays stable, with
// omega_t^2 = k_t / m_t and the viscous coefficient sqrt(k_t m_t) (damping ratio 1/2). Per step
// the spring grows by k_t v dt, v the velocity the forces see (integrator.h).
//  - Leapfrog: v dt is the exact displacement, so the spring is a damped oscillator:
//    2 (sqrt(1 + 1/4) - 1/2). With the viscous term stored too (TangentialHistory::total) it is
//    an undamped spring k_t + sqrt(k_t m_t)/dt: x^2 + x <= 4 with x = omega_t dt.
//  - Verlet: its v + a dt overshoots the displacement; the characteristic polynomial has a root
//    at -1 when x^2 + 2 x = 2 (spring), or x^2 + x = 2 (total).
//  - Gear 5: measured on the model problem (the one tests/dem/time_step_test.cpp integrates):
//    0.152 and 0.2595, taken as 0.15 and 0.25.
double tangential_limit_omega_dt(Scheme scheme, TangentialHistory history) {
  const bool total = history == TangentialHistory::total;
  switch (scheme) {
    case Scheme::leapfrog: return total ? 0.5 * (std::sqrt(17.0) - 1.0) : 2.0 * (std::sqrt(1.25) - 0.5);
    case Scheme::verlet: return total ? 1.0 : std::sqrt(3.0) - 1.0;
    case Scheme::gear5: return total ? 0.25 : 0.15;
  }
  return 0.0;
}

HeaviestChord heaviest_chord(const Shape& polygon, double mass, double inertia, double max_depth, bool count_levers) {
  const std::vector<Vec2>& v = polygon.vertices;
  const int n = static_cast<int>(v.size());
  const ChordWeight weight{1.0 / mass, 1.0 / inertia};
  HeaviestChord best;
  for (int e = 0; e < n; ++e) {
    const Vec2 p = v[e], q = v[(e + 1) % n];
    const Vec2 t = (q - p).normalized();
    heaviest_chord_along_edge(t.dot(p), t.dot(q), weight, best);
  }
  // Chords along an edge lie at least the inner radius from the centroid: lever factor 1.
  if (count_levers) best.lever = polygon.inner_radius;
  if (max_depth <= 0.0) return best;
  // Across corners: a grid over (u, w), then three rounds of a finer grid around its best point.
  constexpr int coarse = 16, fine = 4, rounds = 3;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < i + n; ++j) {
      const CornerChords chords{v, i, j, max_depth, weight, count_levers ? polygon.inner_radius : 0.0};
      double best_here = -1.0, u_best = 0.0, w_best = 0.0;
      for (int a = 0; a <= coarse; ++a)
        for (int b = 0; b <= coarse; ++b) {
          const double u = double(a) / coarse, w = double(b) / coarse;
          const double value = chords.evaluate(u, w);
          if (value > best_here) best_here = value, u_best = u, w_best = w;
        }
      // The part cut off only grows as Q moves on round the boundary (it stays convex and keeps
      // what it had), so the search stops at the first edge with no admissible chord on the grid.
      if (best_here < 0.0) break;
      double spacing = 1.0 / coarse;
      for (int r = 0; r < rounds; ++r) {
        const double u0 = u_best, w0 = w_best;
        spacing /= fine;  // the finer grid spans one spacing of the last on either side
        for (int a = -fine; a <= fine; ++a)
          for (int b = -fine; b <= fine; ++b) {
            const double u = std::clamp(u0 + a * spacing, 0.0, 1.0), w = std::clamp(w0 + b * spacing, 0.0, 1.0);
            const double value = chords.evaluate(u, w);
            if (value > best_here) best_here = value, u_best = u, w_best = w;
          }
      }
      if (best_here > best.weight) chords.evaluate(u_best, w_best, &best);
    }
  return best;
}

namespace {
// A disc cut f r deep: chord 2 r sqrt(2 f - f^2) through the centre's line (arm 0), lever
// r (1 - f), floored at r/2 as the contact law floors it; the chord through the centre beyond.
double disc_weight_at_depth(double r, double m, double f) {
  const double depth = std::min(f, 1.0);
  const double chord = 2.0 * r * std::sqrt(depth * (2.0 - depth));
  const double lever = std::max(1.0 - depth, 0.5) * r;
  return chord / m * r / lever;
}
}  // namespace

// The default bound is the lever-counted bound at the deepest overlap it admits: a chord that
// cuts a quarter of the inner radius off an elongated grain can pass at 0.77 of the inner radius
// from the centroid, and counting it at the inner radius (as this bound did until 2026-11-23)
// left the default step above that contact's limit.
TimeStepBound stable_time_step(const std::vector<Shape>& grains, double areal_density,
                               const ContactParameters& contact, Scheme scheme) {
  return stable_time_step_at_depth(grains, areal_density, contact, scheme, max_overlap_depth_fraction);
}

// The bound over all grains for chords cutting up to depth_fraction of the inner radius, each
// chord at its own lever (the distance of its midpoint from the centroid, at most the inner
// radius).
TimeStepBound stable_time_step_at_depth(const std::vector<Shape>& grains, double areal_density,
                                        const ContactParameters& contact, Scheme scheme, double depth_fraction) {
  TimeStepBound b;
  for (std::size_t i = 0; i < grains.size(); ++i) {
    const Shape& s = grains[i];
    const double m = areal_density * s.area, inertia = areal_density * s.polar_moment;
    // Keeps the smallest limit over all modes, with the mode that sets it.
    auto record = [&](double limit, double omega, double zeta) {
      if (b.stiffest_grain < 0 || limit < b.stable_limit) {
        b.stable_limit = limit;
        b.omega_max = omega;
        b.period_min = 2.0 * M_PI / omega;
        b.damping_ratio = zeta;
        b.stiffest_grain = static_cast<int>(i);
      }
    };
    // Normal mode: the heaviest chord, with l at its smallest.
    // l is proportional to the lever for twins (both contact lengths are harmonic means), so a
    // chord with a shorter lever counts as a heavier one: w r_in / lever, with l at r_in.
    const double l = contact_length(contact, s.inner_radius, s.inner_radius);
    const double w = s.kind == ShapeKind::disc
                         ? disc_weight_at_depth(s.radius, m, depth_fraction)
                         : heaviest_chord(s, m, inertia, depth_fraction * s.inner_radius, true).weight;
    const double omega = std::sqrt(2.0 * contact.youngs_modulus * w / l);
    const double zeta = 0.5 * contact.damping_gamma * std::sqrt(w * m / l);
    record(stability_limit_omega_dt(scheme, zeta) / omega, omega, zeta);
    // Tangential mode: force at the bounding radius.
    if (contact.friction_mu > 0.0) {
      const double k_t = contact.tangential_stiffness_ratio * contact.youngs_modulus;
      const double r = s.bounding_radius;
      const double omega_t = std::sqrt(2.0 * k_t * (1.0 / m + r * r / inertia));
      record(tangential_limit_omega_dt(scheme, contact.tangential_history) / omega_t, omega_t, 0.5);
    }
  }
  return b;
}

}  // namespace pilelab::dem
