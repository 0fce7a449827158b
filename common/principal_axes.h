#pragma once
// Principal values and major axis of a symmetric 2D tensor: one definition of the major axis's
// orientation and of the anisotropy for every module (coarse fields, continuum models and their
// comparison), so that fields of the same name mean the same thing wherever they come from.

namespace pilelab {

struct PrincipalAxes {
  double major = 0.0;            ///< the larger principal value
  double minor = 0.0;            ///< the smaller one
  double mean = 0.0;             ///< (major + minor) / 2
  double anisotropy = 0.0;       ///< (major - minor) / (|major| + |minor|), in [0, 1]; 0 for a zero tensor
  double orientation_deg = 0.0;  ///< the major axis from the horizontal, counter-clockwise, in [0, 180);
                                 ///< 90 for an isotropic tensor, which has none
};

/// The principal axes of [[xx, xy], [xy, yy]] in closed form (Mohr's circle). Pass a stress
/// with compression positive to make the most compressive value the major one. |major| +
/// |minor| at or below zero_scale counts as a zero tensor (anisotropy 0, not 0/0).
PrincipalAxes principal_axes(double xx, double yy, double xy, double zero_scale = 0.0);

}  // namespace pilelab
