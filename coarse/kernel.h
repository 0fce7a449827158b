#pragma once
// Coarse-graining kernels, apart from the fields they average and the points they are
// evaluated at (MercuryCG's split). A kernel is a radial profile of s = r / w with a compact
// support, defined in a file of its own under coarse/kernels/ and registered by one line in
// kernel_registry.cpp; this file normalises it at a width and gives what the averagers need:
// its value, its support and its mass within a radius (from which kernel_average.cpp gets the
// share of its mass inside the pile).
#include <string>
#include <vector>

namespace pilelab::coarse {

/// A kernel's definition: its profile phi(s) up to a constant factor on 0 <= s < support (0
/// beyond), and the radial integral int_0^s phi(t) t dt, exact to round-off also for small s
/// (the domain clipping divides it by s^2).
struct KernelShape {
  const char* name;
  const char* description;
  double support;  ///< in widths
  double (*profile)(double s);
  double (*radial_mass)(double s);
};

/// The registered kernels, in the registry's order.
const std::vector<const KernelShape*>& kernel_shapes();
/// The names of the registered kernels.
std::vector<std::string> kernel_names();
/// The kernel of that name; std::invalid_argument naming the known ones if there is none.
const KernelShape& kernel_shape(const std::string& name);

/// A registered kernel at a width w [m], normalised so that its integral over the plane is 1.
class Kernel {
 public:
  Kernel(const KernelShape& shape, double width);
  /// phi(r) [1/m^2]: the normalised kernel at distance r.
  double value(double r) const { return r < support_ ? scale_ * shape_->profile(r / width_) : 0.0; }
  double support() const { return support_; }  ///< [m]
  double width() const { return width_; }      ///< [m]
  /// Phi(r) / r^2 with Phi(r) = int_0^r phi(t) t dt (so 2 pi Phi(r) is the mass within r):
  /// phi(0) / 2 at r = 0, Phi's total over r^2 beyond the support.
  double mass_within_over_r2(double r) const;
  /// Phi's total, 1 / (2 pi).
  double total_mass_over_2pi() const;
  const KernelShape& shape() const { return *shape_; }
  const char* name() const { return shape_->name; }

 private:
  const KernelShape* shape_;
  double width_, support_, scale_;  // scale_ = 1 / (2 pi w^2 radial_mass(support))
};

}  // namespace pilelab::coarse
