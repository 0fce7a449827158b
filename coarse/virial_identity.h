#pragma once
// The virial identity of a packing: summed over all grains, eq. 12 telescopes. Internal
// contacts cancel (equal and opposite forces at one point), leaving
//   sum_p sum_c F^c (x) (x^c - r_p) = sum_walls F (x) x_c + sum_p m_p g (x) r_p - sum_p R_p (x) r_p,
// with R_p the residual (unbalanced) force of grain p: exact for any packing, and in a settled
// pile the residual term is the small remainder of the settling.
#include "coarse/rve_average.h"

namespace pilelab::coarse {

struct VirialIdentity {
  Tensor grain_sum = Tensor::Zero();  ///< sum over grains of V^p sigma^p [N m]
  Tensor wall = Tensor::Zero();       ///< sum over wall contacts F (x) x_c
  Tensor gravity = Tensor::Zero();    ///< sum_p m_p g (x) r_p
  Tensor residual = Tensor::Zero();   ///< sum_p R_p (x) r_p
  double scale = 0.0;                 ///< sum_p m_p |g| |r_p|: the virial's natural size
  /// |grain_sum - wall - gravity| / scale: what the settling left.
  double relative_mismatch() const { return (grain_sum - wall - gravity).norm() / scale; }
  /// The same with the residual term: round-off only.
  double relative_mismatch_with_residual() const { return (grain_sum - wall - gravity + residual).norm() / scale; }
};

VirialIdentity virial_identity(const Packing& packing);

}  // namespace pilelab::coarse
