#pragma once
// The load of a pile on its plate, measured as a load-cell experiment measures it: the vertical
// force of every grain-plate contact, binned along x. Its integral is the weight the plate
// carries; its shape is the base pressure whose dip under the apex the paper looks for.
#include <vector>

#include "dem/snapshot.h"
#include "dem/world.h"

namespace pilelab::dem {

struct PlateLoad {
  double bin_width = 0.0;       ///< [m]
  std::vector<double> x;        ///< bin centres [m], the bins tiling the plate from its left end
  std::vector<double> load;     ///< vertical force on the plate per unit length of plate in each bin [N/m]
  double total_force = 0.0;     ///< the sum of the contacts' vertical forces on the plate [N]
  double weight = 0.0;          ///< sum of m g over the snapshot's grains [N]
};

/// The load at a snapshot of the bodies the pile stands on (`base`, ascending: the plate, and a
/// base of fixed grains if there is one), with the weight under the snapshot's gravity;
/// `plate_left` and `plate_width` [m] say where the bins lie.
PlateLoad plate_load(const World& world, const Snapshot& snapshot, const std::vector<int>& base, double plate_left,
                     double plate_width, double bin_width);

/// The dip statistic used everywhere (the tables, the figures, the report): the mean load over
/// the centre |x'| < centre_window over its mean over the ring ring_inner < |x'| < ring_outer,
/// minus 1, with x' = (x - apex_x) / half_width. Below 0: a dip under the apex; 0: a flat top; a
/// load proportional to the height above the plate, (1 - |x'|), gives 0.95 / 0.75 - 1 = +0.27.
/// NaN where a window holds no bin or the ring carries nothing.
struct DipWindows {
  double centre = 0.1, ring_inner = 0.15, ring_outer = 0.35;
};
double centre_over_ring(const std::vector<double>& x, const std::vector<double>& load, double apex_x, double half_width,
                        const DipWindows& windows = {});

}  // namespace pilelab::dem
