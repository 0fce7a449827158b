#include "coarse/rve_average.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "coarse/circle_overlap.h"

namespace pilelab::coarse {

double Domain::area_in_disc(const Vec2& centre, double radius) const {
  if (edges.empty()) return M_PI * radius * radius;
  double area = 0;
  for (const auto& [a, b] : edges) area += circle_sector_clip_area(centre, radius, a, b);
  return std::max(area, 0.0);
}

bool Domain::contains(const Vec2& x) const {
  if (edges.empty()) return true;
  bool inside = false;
  for (const auto& [a, b] : edges)
    if ((a.y() > x.y()) != (b.y() > x.y()) && x.x() < a.x() + (x.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x()))
      inside = !inside;
  return inside;
}

RveAverager::RveAverager(const Packing& packing, Domain domain, bool clip_volume)
    : packing_(packing), domain_(std::move(domain)), clip_volume_(clip_volume) {
  const std::size_t n = packing.grains.size();
  moment_.assign(n, Tensor::Zero());
  fabric_.assign(n, Tensor::Zero());
  contacts_.assign(n, 0);
  partners_.assign(n, {});
  bounding_radius_.assign(n, 0.0);
  std::vector<Vec2> centres(n);
  double area_sum = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const Grain& g = packing.grains[p];
    centres[p] = g.centre;
    area_sum += g.area;
    bounding_radius_[p] = g.shape ? g.shape->bounding_radius : 0.0;
    max_bounding_radius_ = std::max(max_bounding_radius_, bounding_radius_[p]);
  }
  mean_area_ = n ? area_sum / n : 0.0;
  in_domain_.assign(n, 1);
  if (!domain_.empty())
    for (std::size_t p = 0; p < n; ++p)
      if (!domain_.contains(centres[p])) in_domain_[p] = 0, ++outside_count_;
  // Each contact adds x (x) F to the grain(s) it touches (eq. 10 times V^p) and n (x) n to
  // their fabric (eq. 15).
  auto add = [&](int p, const Vec2& point, const Vec2& force) {
    const Vec2 x = point - packing.grains[p].centre;
    moment_[p] += force * x.transpose();
    const double len = x.norm();
    if (len > 0) fabric_[p] += (x / len) * (x / len).transpose();
    ++contacts_[p];
  };
  for (const Contact& c : packing.contacts) {
    add(c.a, c.point, c.force_on_a);
    if (c.b >= 0) {
      add(c.b, c.point, -c.force_on_a);
      partners_[c.a].push_back(c.b);
      partners_[c.b].push_back(c.a);
    }
  }
  // Cells of two grain sizes, but never more cells than about one per grain (point grains).
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (const Vec2& c : centres) x0 = std::min(x0, c.x()), x1 = std::max(x1, c.x()), y0 = std::min(y0, c.y()), y1 = std::max(y1, c.y());
  const double spread = n ? std::sqrt(std::max((x1 - x0) * (y1 - y0), (x1 - x0 + y1 - y0) * (x1 - x0 + y1 - y0) * 1e-6) / n) : 1.0;
  const double cell = std::max({2.0 * max_bounding_radius_, spread, 1e-9});
  grid_ = GrainGrid(centres, cell);
}

void RveAverager::set_displacements(const Packing& later) {
  grain_displacements(packing_, later, displacement_, has_displacement_);
}

RveSample RveAverager::average(const Vec2& point, double radius) const {
  RveSample s;
  s.volume = clip_volume_ ? domain_.area_in_disc(point, radius) : M_PI * radius * radius;
  const double r2 = radius * radius;
  std::vector<int> inside;
  double grain_area_inside = 0;
  grid_.for_each_near(point, radius + max_bounding_radius_, [&](int p) {
    const Grain& g = packing_.grains[p];
    const double d = (g.centre - point).norm();
    const double rb = bounding_radius_[p];
    if ((g.centre - point).squaredNorm() <= r2 && in_domain_[p]) inside.push_back(p);
    // Volume fraction from the outlines: whole grains, cut grains, or nothing.
    if (d + rb <= radius) {
      grain_area_inside += g.area;
    } else if (d - rb < radius) {
      if (g.shape && g.shape->kind == dem::ShapeKind::disc)
        grain_area_inside += circle_circle_area(point, radius, g.centre, g.shape->radius);
      else if (g.shape)
        grain_area_inside += circle_polygon_area(point, radius, world_outline(g));
    }
  });
  s.grain_count = static_cast<int>(inside.size());
  if (s.volume <= 0 || inside.empty()) return s;
  std::sort(inside.begin(), inside.end());  // a fixed summation order: reproducible sums
  int contact_sum = 0;
  for (int p : inside) {
    s.stress += moment_[p];
    s.fabric += packing_.grains[p].area * fabric_[p];
    contact_sum += contacts_[p];
  }
  s.stress /= s.volume;
  s.fabric /= s.volume;
  s.coordination = static_cast<double>(contact_sum) / s.grain_count;
  s.volume_fraction = grain_area_inside / s.volume;

  if (displacement_.empty()) return s;
  int moved = 0;
  for (int p : inside)
    if (has_displacement_[p]) s.displacement += displacement_[p], ++moved;
  if (moved) s.displacement /= moved;
  // Cambou's best fit (eq. 13-14): A = sum l l^T, B = sum l du^T, H^T = A^{-1} B. Each
  // grain-grain contact with at least one grain inside counts once.
  Tensor A = Tensor::Zero(), B = Tensor::Zero();
  std::vector<std::pair<int, int>> pairs;
  auto inside_rve = [&](int q) { return std::binary_search(inside.begin(), inside.end(), q); };
  for (int p : inside)
    for (int q : partners_[p]) {
      if (inside_rve(q) && q < p) continue;  // counted from q's side
      if (!has_displacement_[p] || !has_displacement_[q]) continue;
      const Vec2 l = packing_.grains[q].centre - packing_.grains[p].centre;
      const Vec2 du = displacement_[q] - displacement_[p];
      A += l * l.transpose();
      B += l * du.transpose();
      pairs.emplace_back(p, q);
    }
  s.strain_contacts = static_cast<int>(pairs.size());
  const double trace = A.trace();
  if (pairs.size() < 2 || !(A.determinant() > 1e-10 * trace * trace)) return s;  // singular fit
  s.displacement_gradient = (A.inverse() * B).transpose();
  double residual = 0, total = 0;
  for (const auto& [p, q] : pairs) {
    const Vec2 l = packing_.grains[q].centre - packing_.grains[p].centre;
    const Vec2 du = displacement_[q] - displacement_[p];
    residual += (du - s.displacement_gradient * l).squaredNorm();
    total += du.squaredNorm();
  }
  s.strain_fit_residual = total > 0 ? std::sqrt(residual / total) : 0.0;
  s.has_strain = true;
  return s;
}

TensorSummary summarise(const Tensor& t, double sign, bool by_magnitude) {
  TensorSummary s = principal_axes(sign * t(0, 0), sign * t(1, 1), sign * 0.5 * (t(0, 1) + t(1, 0)));
  if (by_magnitude && std::abs(s.minor) > std::abs(s.major)) {
    // The value of largest magnitude is the smaller one: it becomes the major value, and its
    // axis is perpendicular to the larger one's. The anisotropy does not change.
    std::swap(s.major, s.minor);
    s.orientation_deg += s.orientation_deg < 90.0 ? 90.0 : -90.0;
  }
  return s;
}

}  // namespace pilelab::coarse
