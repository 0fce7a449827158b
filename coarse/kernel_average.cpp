#include "coarse/kernel_average.h"

#include <Eigen/LU>
#include <cmath>
#include <tuple>

namespace pilelab::coarse {

double kernel_value(Kernel kernel, double r, double w) {
  if (kernel == Kernel::gaussian) return r < 3 * w ? std::exp(-r * r / (w * w)) / (M_PI * w * w) : 0.0;
  if (r >= w) return 0.0;
  const double s = r / w;
  return 5.0 / (M_PI * w * w) * (1 + 3 * s) * (1 - s) * (1 - s) * (1 - s);
}

double kernel_support(Kernel kernel, double w) { return kernel == Kernel::gaussian ? 3 * w : w; }

KernelAverager::KernelAverager(const Packing& packing, Kernel kernel, double width)
    : packing_(packing), kernel_(kernel), width_(width), support_(kernel_support(kernel, width)) {
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

double KernelAverager::density(const Vec2& point) const {
  double rho = 0;
  grid_.for_each_near(point, support_, [&](int p) { rho += packing_.grains[p].mass * phi(point - packing_.grains[p].centre); });
  return rho;
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
