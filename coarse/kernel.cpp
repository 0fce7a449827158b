#include "coarse/kernel.h"

#include <cmath>
#include <stdexcept>

namespace pilelab::coarse {

Kernel::Kernel(const KernelShape& shape, double width)
    : shape_(&shape),
      width_(width),
      support_(shape.support * width),
      scale_(1.0 / (2.0 * M_PI * width * width * shape.radial_mass(shape.support))) {}

double Kernel::mass_within_over_r2(double r) const {
  if (r >= support_) return scale_ * width_ * width_ * shape_->radial_mass(shape_->support) / (r * r);
  if (r == 0.0) return 0.5 * scale_ * shape_->profile(0.0);
  const double s = r / width_;
  return scale_ * shape_->radial_mass(s) / (s * s);
}

double Kernel::total_mass_over_2pi() const { return 1.0 / (2.0 * M_PI); }

std::vector<std::string> kernel_names() {
  std::vector<std::string> names;
  for (const KernelShape* k : kernel_shapes()) names.emplace_back(k->name);
  return names;
}

const KernelShape& kernel_shape(const std::string& name) {
  for (const KernelShape* k : kernel_shapes())
    if (name == k->name) return *k;
  std::string known;
  for (const std::string& n : kernel_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("no coarse-graining kernel '" + name + "' (known: " + known + ")");
}

}  // namespace pilelab::coarse
