#pragma once
// Random grains as in the paper: convex polygons whose corners lie on an ellipse with
// independently drawn axes (section 2), or on a circle of drawn diameter ("round particles",
// section 5), or discs.
#include "common/rng.h"
#include "dem/shape.h"

namespace pilelab::dem {

/// The curve a polygon's corners are placed on.
enum class GrainOutline {
  ellipse,  ///< two axes drawn independently: elongated grains (paper section 2)
  circle,   ///< one diameter drawn: round grains of many sizes (paper section 5)
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

  double smallest_diameter() const { return mean_diameter * (1.0 - polydispersity); }
  double largest_diameter() const { return mean_diameter * (1.0 + polydispersity); }
};

/// Draws one grain shape (body frame, centroid at origin). Orientation is chosen at insertion.
Shape random_grain(const GrainSpec& spec, Rng& rng);

}  // namespace pilelab::dem
