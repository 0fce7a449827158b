#include "dem/plate_force.h"

#include <algorithm>
#include <cmath>

namespace pilelab::dem {

PlateLoad plate_load(const World& world, const Snapshot& snapshot, const std::vector<int>& base, double plate_left,
                     double plate_width, double bin_width) {
  PlateLoad p;
  p.bin_width = bin_width;
  const int bins = std::max(1, static_cast<int>(std::ceil(plate_width / bin_width)));
  p.load.assign(bins, 0.0);
  for (int i = 0; i < bins; ++i) p.x.push_back(plate_left + (i + 0.5) * bin_width);
  // A contact's force on b is `force`; a base body is a wall, the lower body of its pairs (walls
  // come first), so the grain presses it down with the grain's upward force.
  for (std::size_t c = 0; c < snapshot.contact_count_total(); ++c) {
    if (!std::binary_search(base.begin(), base.end(), static_cast<int>(snapshot.pair[2 * c]))) continue;
    const double down = snapshot.force[2 * c + 1];
    p.total_force += down;
    const int bin = static_cast<int>(std::floor((snapshot.point[2 * c] - plate_left) / bin_width));
    if (bin >= 0 && bin < bins) p.load[bin] += down / bin_width;
  }
  for (std::int64_t body : snapshot.body) p.weight += world.mass(static_cast<int>(body)) * snapshot.gravity;
  return p;
}

double centre_over_ring(const std::vector<double>& x, const std::vector<double>& load, double apex_x, double half_width,
                        const DipWindows& windows) {
  double centre = 0.0, ring = 0.0;
  int centre_bins = 0, ring_bins = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double u = std::abs(x[i] - apex_x) / half_width;
    if (u < windows.centre) {
      centre += load[i];
      ++centre_bins;
    } else if (u > windows.ring_inner && u < windows.ring_outer) {
      ring += load[i];
      ++ring_bins;
    }
  }
  if (centre_bins == 0 || ring_bins == 0 || !(ring > 0.0)) return NAN;
  return (centre / centre_bins) / (ring / ring_bins) - 1.0;
}

}  // namespace pilelab::dem
