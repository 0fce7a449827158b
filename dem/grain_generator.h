#pragma once
// Random grains as in the paper: convex polygons whose corners lie on an ellipse with
// independently drawn axes (section 2), or on a circle of drawn diameter ("round particles",
// section 5), or discs.
#include <vector>

#include "common/rng.h"
#include "dem/shape.h"

namespace pilelab::dem {

/// The curve a polygon's corners are placed on.
enum class GrainOutline {
  ellipse,  ///< two axes drawn independently: elongated grains (paper section 2)
  circle,   ///< one diameter drawn: round grains of many sizes (paper section 5)
};

/// How a polygon's corners are placed on its outline.
enum class CornerPlacement {
  jittered,  ///< corner k at 2 pi (k + xi_k) / n, xi_k uniform in [-corner_jitter, corner_jitter]
  random,    ///< n independent uniform angles, sorted, conditioned on no gap below corner_min_gap
};

struct GrainSpec {
  ShapeKind kind = ShapeKind::polygon;
  GrainOutline outline = GrainOutline::ellipse;
  int corners_min = 6;            ///< paper: 6
  int corners_max = 8;            ///< paper: 8
  double mean_diameter = 6.8e-3;  ///< mean ellipse axis (disc diameter) [m]
  /// Largest relative deviation of a size from the mean: each axis (the circle's or disc's
  /// diameter) is drawn uniformly from mean * [1 - p, 1 + p], so ellipses reach an aspect ratio
  /// (1 + p) / (1 - p).
  /// Paper: 0.3 ("a degree of poly-dispersity of about 30 %"). 0 gives a monodisperse mixture
  /// (polygons then still differ in their corner positions).
  double polydispersity = 0.3;
  /// Corners sit at angles 2 pi (k + xi_k) / n on the ellipse, xi_k uniform in
  /// [-corner_jitter, corner_jitter]; below 0.5 neighbouring corners cannot swap.
  double corner_jitter = 0.25;
  CornerPlacement corner_placement = CornerPlacement::jittered;
  /// For random placement: the smallest angular gap between neighbouring corners, as a fraction
  /// of the mean gap 2 pi / n (so that no edge is degenerate); below 1.
  double corner_min_gap = 0.25;

  double smallest_diameter() const { return mean_diameter * (1.0 - polydispersity); }
  double largest_diameter() const { return mean_diameter * (1.0 + polydispersity); }
};

/// The angles [rad] of a polygon's n corners, increasing over less than a turn: jittered
/// regular placement, or random placement with no gap below min_gap_fraction of 2 pi / n.
std::vector<double> jittered_corner_angles(int n, double jitter, Rng& rng);
std::vector<double> random_corner_angles(int n, double min_gap_fraction, Rng& rng);

/// Draws one grain shape (body frame, centroid at origin). Orientation is chosen at insertion.
Shape random_grain(const GrainSpec& spec, Rng& rng);

}  // namespace pilelab::dem
