#pragma once
// Representative-volume-element averages of a static packing at a point (paper section 3-4).
//
// The RVE is the disc of radius R around the point. A grain belongs to it when its centre lies
// inside (the paper's rule) and, with a domain, inside the domain too. V is the RVE's area, by default clipped to the pile domain (the
// part of the disc below the plate or above the free surface holds no material and no grain
// centres; counting it would dilute every average near a boundary). Sign convention: tension
// positive, as in continuum mechanics; the profiles flip it to compression positive.
//
//  stress     eq. 12   sigma_ij = (1/V) sum_p sum_c F_i^c x_j^c   (x^c: centre -> contact point,
//                      F^c: force on p; wall contacts included)                    [N/m]
//  fabric     eq. 18   F_ij = (1/V) sum_p V^p sum_c n_i^c n_j^c   (n^c: unit x^c)     [1]
//  coordination eq. 19 C = (1/N) sum_p c^p  (contacts of every kind, walls included)   [1]
//  volume fraction     (area of every grain outline inside the disc) / V            [1]
//  strain     eq. 13-14 Cambou's best-fit translation gradient from the grain-centre
//                      displacements between a reference packing and a later one, over the
//                      grain-grain contacts of the reference with at least one grain inside:
//                      minimises sum_c |du_q - du_p - H l^c|^2 with l^c = r_q - r_p.
#include <Eigen/Core>
#include <vector>

#include "common/principal_axes.h"

#include "coarse/grain_grid.h"
#include "coarse/packing.h"

namespace pilelab::coarse {

using Tensor = Eigen::Matrix2d;

/// The region holding material, as closed boundaries of oriented edges (counter-clockwise
/// around the material): e.g. the boundary of the mesh. Empty means the whole plane.
struct Domain {
  std::vector<std::pair<Vec2, Vec2>> edges;
  bool empty() const { return edges.empty(); }
  /// Area of the disc (centre, radius) inside the domain.
  double area_in_disc(const Vec2& centre, double radius) const;
  /// Whether a point lies inside (crossing number of a ray to +x).
  bool contains(const Vec2& point) const;
};

struct RveSample {
  int grain_count = 0;          ///< grains whose centre lies in the RVE
  double volume = 0.0;          ///< V [m^2]
  Tensor stress = Tensor::Zero();
  Tensor fabric = Tensor::Zero();
  double coordination = 0.0;
  double volume_fraction = 0.0;
  // Strain (only with displacements; has_strain is false for too few or collinear contacts).
  bool has_strain = false;
  int strain_contacts = 0;
  dem::Vec2 displacement{0, 0};  ///< mean grain-centre displacement of the grains inside [m]
  // Incremental stress (later snapshot minus this one, same window), for stress-strain fits.
  bool has_stress_change = false;
  Tensor stress_change = Tensor::Zero();
  Tensor displacement_gradient = Tensor::Zero();  ///< H_ij = du_i/dx_j
  double strain_fit_residual = 0.0;  ///< sqrt(sum |du - H l|^2 / sum |du|^2): 0 = affine
  bool has_data() const { return grain_count > 0; }
  Tensor strain() const { return 0.5 * (displacement_gradient + displacement_gradient.transpose()); }
  /// Rigid rotation of the fit, (H_yx - H_xy)/2 [rad], counter-clockwise positive.
  double rotation() const { return 0.5 * (displacement_gradient(1, 0) - displacement_gradient(0, 1)); }
};

class RveAverager {
 public:
  /// With a domain, grains whose centre lies outside it are left out; clip_volume makes V the
  /// part of the disc inside the domain (otherwise the whole disc, as in the paper).
  explicit RveAverager(const Packing& packing, Domain domain = {}, bool clip_volume = true);

  /// Grain-centre displacements from this packing to later (grains matched by body; grains
  /// missing from later get no displacement and their contacts are left out of the fit).
  void set_displacements(const Packing& later);

  RveSample average(const Vec2& point, double radius) const;

  const Packing& packing() const { return packing_; }
  double mean_grain_area() const { return mean_area_; }
  double max_bounding_radius() const { return max_bounding_radius_; }
  /// Grains whose centre lies outside the domain: left out of every average (the domain
  /// does not cover the whole pile).
  int grains_outside_domain() const { return outside_count_; }
  /// Whether grain p's centre lies in the domain (grains outside are left out of every average).
  bool grain_in_domain(std::size_t p) const { return in_domain_[p] != 0; }

 private:
  const Packing& packing_;
  Domain domain_;
  bool clip_volume_ = true;
  GrainGrid grid_;
  std::vector<Tensor> moment_;        ///< per grain: sum_c F^c (x) x^c  [N m]
  std::vector<Tensor> fabric_;        ///< per grain: sum_c n^c (x) n^c
  std::vector<int> contacts_;         ///< per grain: contact count
  std::vector<std::vector<int>> partners_;  ///< per grain: grain-grain contact partners
  std::vector<double> bounding_radius_;
  std::vector<char> in_domain_;
  int outside_count_ = 0;
  std::vector<Vec2> displacement_;
  std::vector<char> has_displacement_;
  double mean_area_ = 0.0, max_bounding_radius_ = 0.0;
};

/// Principal values, anisotropy and major-axis orientation of a 2D tensor (its symmetric
/// part), as defined once for every module in common/principal_axes.h.
using TensorSummary = PrincipalAxes;
/// The major value is the largest one of sign * tensor: sign = -1 makes the most compressive
/// stress the major one (compression positive); for strain, pass the tensor and
/// by_magnitude = true to take the eigenvalue of largest magnitude.
TensorSummary summarise(const Tensor& tensor, double sign = 1.0, bool by_magnitude = false);

}  // namespace pilelab::coarse
