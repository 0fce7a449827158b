#pragma once
// Smooth coarse-graining with a kernel of width w (after Goldhirsch 2010 and Weinhart et al.
// 2012), the scene's alternative to the paper's RVE discs. With phi a normalised 2D kernel:
//
//   density          rho(r)   = sum_p m_p phi(r - r_p)
//   stress (static)  sigma(r) = sum_c f_c (x) b_c  int_0^1 phi(r - r_p - s b_c) ds
//
// where for a grain-grain contact f_c is the force on p and b_c = r_q - r_p (the branch
// between the centres), and for a wall contact b_c = x_c - r_p. Because d/ds of the kernel
// along the branch is its divergence, div sigma = sum_p phi(r - r_p) (sum of contact forces
// on p) minus the wall forces spread at their contact points: in equilibrium
// div sigma + rho g = -sum_walls f_c phi(r - x_c), exact up to the quadrature of the branch
// integral: the momentum balance the RVE average only approaches.
// Fabric, coordination and volume fraction are kernel-weighted grain sums; the strain is
// Cambou's fit with each contact weighted by the kernel at its branch midpoint.
//
// Near a boundary part of the kernel lies outside the material (below the plate, above the
// free surface) and would dilute every density: at the plate by half. With a domain and
// clip_volume (the RVE's rule, coarse.rve_volume = "clipped"), volume fraction, fabric and
// stress are divided by the fraction of the kernel's mass inside the domain,
//   f(r) = int_domain phi(r - y) dy / int_plane phi,
// as the RVE divides by the part of its disc inside the pile. f = 1 wherever the kernel's
// support lies inside, so there the fields and the momentum balance above are unchanged.
#include "coarse/kernel.h"
#include "coarse/rve_average.h"

namespace pilelab::coarse {

/// The fraction of the kernel's mass about point that lies inside the domain (1 for an empty
/// domain, the whole plane). Exact up to a Gauss-Legendre rule on smooth pieces: it agrees
/// with direct two-dimensional quadrature to that quadrature's error (3e-8).
double kernel_mass_fraction_in(const Domain& domain, const Kernel& kernel, const Vec2& point);

class KernelAverager {
 public:
  /// With a domain and clip_volume, the densities are divided by the kernel's mass fraction
  /// inside the domain (see above); without, they are the plain kernel sums.
  KernelAverager(const Packing& packing, const Kernel& kernel, Domain domain = {}, bool clip_volume = true);
  void set_displacements(const Packing& later);
  /// The fields at a point, in the RveSample layout (volume is 0: the kernel has no edge;
  /// grain_count counts the grains within the kernel's support).
  RveSample average(const Vec2& point) const;
  double density(const Vec2& point) const;
  const Kernel& kernel() const { return kernel_; }

 private:
  double phi(const Vec2& d) const { return kernel_.value(d.norm()); }
  /// What the densities at point are divided by: the kernel's mass fraction in the domain, or 1.
  double normalisation(const Vec2& point) const;
  const Packing& packing_;
  Kernel kernel_;
  double support_;
  Domain domain_;
  bool clip_volume_ = true;
  double max_bounding_radius_ = 0.0;
  GrainGrid grid_;
  std::vector<std::vector<int>> contacts_of_;  ///< per grain: contacts where it is grain a
  std::vector<Tensor> fabric_;
  std::vector<int> contact_count_;
  std::vector<Vec2> displacement_;
  std::vector<char> has_displacement_;
};

}  // namespace pilelab::coarse
