#include "coarse/kernel_average.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <tuple>

namespace pilelab::coarse {

namespace {
// The signed kernel mass in the triangle (point, a, b): in polar coordinates about the point,
// int dtheta Phi(rho(theta)), or along the edge q(t) = a + t (b - a) - point,
//   int_0^1 Phi(|q|) / |q|^2 cross(q(0), b - a) dt.
// Where |q| exceeds the support Phi is constant and the piece is Phi_total times its angle; the
// rest is split where the edge crosses the support's circle, at the edge's point nearest to the
// point, and into pieces shorter than the kernel width, on which the integrand is smooth, and
// summed by an 8-point Gauss-Legendre rule.
double triangle_mass(const Kernel& kernel, const Vec2& point, const Vec2& a, const Vec2& b) {
  static const double gx[8] = {0.019855071751231856, 0.10166676129318664, 0.2372337950418355,
                               0.4082826787521751,  0.5917173212478249,  0.7627662049581645,
                               0.8983332387068134,  0.9801449282487681};
  static const double gw[8] = {0.050614268145188129, 0.11119051722668724, 0.15685332293894364,
                               0.18134189168918099,  0.18134189168918099, 0.15685332293894364,
                               0.11119051722668724,  0.050614268145188129};
  const Vec2 p = a - point, d = b - a;
  const double c = p.x() * d.y() - p.y() * d.x();  // cross(p, d): twice the triangle's signed area
  const double dd = d.squaredNorm();
  if (dd == 0.0 || c == 0.0) return 0.0;
  const double w = kernel.width(), support = kernel.support(), phi_total = kernel.total_mass_over_2pi();
  const auto angle = [&](double t0, double t1) {  // signed angle swept from q(t0) to q(t1)
    const Vec2 q0 = p + t0 * d, q1 = p + t1 * d;
    return std::atan2(q0.x() * q1.y() - q0.y() * q1.x(), q0.dot(q1));
  };
  // The edge's parameters where |q(t)| = support, clamped to [0, 1].
  const double t_foot = -p.dot(d) / dd;
  const double h2 = (p + t_foot * d).squaredNorm();
  double lo = 0.0, hi = 0.0;  // the inside piece [lo, hi]
  if (h2 < support * support) {
    const double half = std::sqrt((support * support - h2) / dd);
    lo = std::clamp(t_foot - half, 0.0, 1.0);
    hi = std::clamp(t_foot + half, 0.0, 1.0);
  }
  double mass = 0.0;
  if (lo > 0.0) mass += phi_total * angle(0.0, lo);
  if (hi < 1.0) mass += phi_total * angle(std::max(hi, lo), 1.0);
  // The inside piece, split at the edge's point nearest to the point as well: there |q| =
  // sqrt(h^2 + |d|^2 (t - t_foot)^2) turns, and Lucy's Phi / r^2 holds |q|^3, smooth on
  // either side of that point but not across it.
  const auto gauss = [&](double t0, double t1) {
    const int pieces = std::max(1, static_cast<int>(std::ceil((t1 - t0) * std::sqrt(dd) / w)));
    const double step = (t1 - t0) / pieces;
    double sum = 0.0;
    for (int k = 0; k < pieces; ++k)
      for (int i = 0; i < 8; ++i) {
        const Vec2 q = p + (t0 + (k + gx[i]) * step) * d;
        sum += gw[i] * step * kernel.mass_within_over_r2(q.norm());
      }
    return sum * c;
  };
  if (hi > lo) {
    if (t_foot > lo && t_foot < hi)
      mass += gauss(lo, t_foot) + gauss(t_foot, hi);
    else
      mass += gauss(lo, hi);
  }
  return mass;
}
}  // namespace

double kernel_mass_fraction_in(const Domain& domain, const Kernel& kernel, const Vec2& point) {
  if (domain.empty()) return 1.0;
  const double support = kernel.support();
  // Wholly inside: no edge comes within the support (and the point is inside).
  bool near_edge = false;
  for (const auto& [a, b] : domain.edges) {
    const Vec2 d = b - a;
    const double t = d.squaredNorm() > 0 ? std::clamp((point - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    if ((a + t * d - point).squaredNorm() < support * support) {
      near_edge = true;
      break;
    }
  }
  if (!near_edge) return domain.contains(point) ? 1.0 : 0.0;
  double mass = 0.0;
  for (const auto& [a, b] : domain.edges) mass += triangle_mass(kernel, point, a, b);
  return std::clamp(mass / (2 * M_PI * kernel.total_mass_over_2pi()), 0.0, 1.0);
}

KernelAverager::KernelAverager(const Packing& packing, const Kernel& kernel, Domain domain, bool clip_volume)
    : packing_(packing),
      kernel_(kernel),
      support_(kernel.support()),
      domain_(std::move(domain)),
      clip_volume_(clip_volume) {
  const std::size_t n = packing.grains.size();
  contacts_of_.assign(n, {});
  fabric_.assign(n, Tensor::Zero());
  contact_count_.assign(n, 0);
  std::vector<Vec2> centres(n);
  for (std::size_t p = 0; p < n; ++p) {
    centres[p] = packing.grains[p].centre;
    const dem::Shape* shape = packing.grains[p].shape;
    max_bounding_radius_ = std::max(max_bounding_radius_, shape ? shape->bounding_radius : 0.0);
  }
  for (std::size_t c = 0; c < packing.contacts.size(); ++c) {
    const Contact& k = packing.contacts[c];
    contacts_of_[k.a].push_back(static_cast<int>(c));
    for (int p : {k.a, k.b}) {
      if (p < 0) continue;
      const Vec2 x = k.point - packing.grains[p].centre;
      if (x.norm() > 0) fabric_[p] += x.normalized() * x.normalized().transpose();
      ++contact_count_[p];
    }
  }
  grid_ = GrainGrid(centres, std::max(support_, 1e-9));
}

void KernelAverager::set_displacements(const Packing& later) {
  grain_displacements(packing_, later, displacement_, has_displacement_);
}

double KernelAverager::normalisation(const Vec2& point) const {
  return clip_volume_ ? kernel_mass_fraction_in(domain_, kernel_, point) : 1.0;
}

double KernelAverager::density(const Vec2& point) const {
  double rho = 0;
  grid_.for_each_near(point, support_, [&](int p) { rho += packing_.grains[p].mass * phi(point - packing_.grains[p].centre); });
  const double f = normalisation(point);
  return f > 0 ? rho / f : rho;  // f = 0: a point whose kernel holds no material; as average()
}

RveSample KernelAverager::average(const Vec2& point) const {
  // Five-point Gauss-Legendre rule on [0, 1] for the line integral along each branch: the
  // kernel is smooth on the scale of a branch (w >= a grain diameter).
  static const double gx[5] = {0.04691007703066800, 0.23076534494715845, 0.5, 0.76923465505284155,
                               0.95308992296933200};
  static const double gw[5] = {0.11846344252809454, 0.23931433524968324, 0.28444444444444444,
                               0.23931433524968324, 0.11846344252809454};
  RveSample s;
  double weight_sum = 0, contacts = 0;
  Tensor A = Tensor::Zero(), B = Tensor::Zero();
  std::vector<std::tuple<double, Vec2, Vec2>> fit;  // weight, branch, relative displacement
  double moved_weight = 0;
  const double reach = support_ + 2 * max_bounding_radius_;  // branches start within reach
  grid_.for_each_near(point, reach, [&](int p) {
    const Grain& g = packing_.grains[p];
    const double w = phi(point - g.centre);
    if ((g.centre - point).norm() < support_) ++s.grain_count;
    weight_sum += w;
    s.fabric += w * g.area * fabric_[p];
    s.volume_fraction += w * g.area;
    contacts += w * contact_count_[p];
    if (!displacement_.empty() && has_displacement_[p]) s.displacement += w * displacement_[p], moved_weight += w;
    for (int c : contacts_of_[p]) {
      const Contact& k = packing_.contacts[c];
      const Vec2 branch = k.b >= 0 ? Vec2(packing_.grains[k.b].centre - g.centre) : Vec2(k.point - g.centre);
      double line = 0;
      for (int i = 0; i < 5; ++i) line += gw[i] * phi(point - g.centre - gx[i] * branch);
      s.stress += line * k.force_on_a * branch.transpose();
      if (k.b >= 0 && !displacement_.empty() && has_displacement_[p] && has_displacement_[k.b]) {
        const double wc = phi(point - g.centre - 0.5 * branch);
        const Vec2 du = displacement_[k.b] - displacement_[p];
        A += wc * branch * branch.transpose();
        B += wc * branch * du.transpose();
        fit.emplace_back(wc, branch, du);
        ++s.strain_contacts;
      }
    }
  });
  s.volume = 0;
  if (weight_sum <= 0) {
    s.grain_count = 0;
    s.stress.setZero();
    return s;
  }
  // The densities count only the material inside: divided by the kernel's mass there.
  const double f = normalisation(point);
  if (f > 0 && f != 1.0) {
    s.stress /= f;
    s.fabric /= f;
    s.volume_fraction /= f;
  }
  s.coordination = contacts / weight_sum;
  if (moved_weight > 0) s.displacement /= moved_weight;
  const double trace = A.trace();
  if (s.strain_contacts >= 2 && A.determinant() > 1e-10 * trace * trace) {
    s.displacement_gradient = (A.inverse() * B).transpose();
    s.has_strain = true;
    double residual = 0, total = 0;  // the weighted relative residual of the fit
    for (const auto& [w, l, du] : fit) {
      residual += w * (du - s.displacement_gradient * l).squaredNorm();
      total += w * du.squaredNorm();
    }
    s.strain_fit_residual = total > 0 ? std::sqrt(residual / total) : 0.0;
  }
  return s;
}

}  // namespace pilelab::coarse
