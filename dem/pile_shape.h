#pragma once
// Height and angles of repose of a pile, from its free surface.
//
// Method: the grains' x range is cut into bins of width bin_width; the surface height in a bin
// is the highest point of any grain whose centre lies in it. The apex is the highest bin and
// the height is measured from the plate top (y = 0). On each side of the apex, the bins whose
// surface lies between 20 % and 80 % of the height (leaving out the rounded tip and the foot
// with its run-out grains) are fitted by least squares with a straight line; the angle of
// repose is atan(|slope|). A side with fewer than 3 such bins has no angle (NaN).
#include <vector>

#include "dem/snapshot.h"
#include "dem/world.h"

namespace pilelab::dem {

struct PileShape {
  double height = 0.0;          ///< [m]
  double apex_x = 0.0;          ///< [m]
  double repose_left_deg = 0.0;   ///< NaN when not measurable
  double repose_right_deg = 0.0;  ///< NaN when not measurable
  /// Standard errors of the two angles from the scatter of the surface about each fitted line
  /// [degree]: how well one pile's flank is measured, not how much flanks vary from pile to pile.
  double repose_left_se_deg = 0.0, repose_right_se_deg = 0.0;
  int left_points = 0, right_points = 0;  ///< bins used by each fit
  std::vector<Vec2> surface;    ///< (bin centre, surface height) [m]
};

/// The pile of a snapshot; the world supplies the grains' shapes.
PileShape measure_pile(const World& world, const Snapshot& snapshot, double bin_width);

}  // namespace pilelab::dem
