#pragma once
// Spatial hashing of grain centres on a uniform grid, so that an RVE query visits only the
// grains near it: O(grains in the RVE), not O(all grains).
#include <vector>

#include "dem/vec2.h"

namespace pilelab::coarse {

class GrainGrid {
 public:
  GrainGrid() = default;
  GrainGrid(const std::vector<dem::Vec2>& centres, double cell_size);

  /// Calls visit(i) for every point i whose cell meets the square around the circle (centre,
  /// radius): a superset of the points within radius; the caller tests the distance.
  template <class Visit>
  void for_each_near(const dem::Vec2& centre, double radius, Visit&& visit) const {
    if (points_ == 0) return;
    const int i0 = cell_x(centre.x() - radius), i1 = cell_x(centre.x() + radius);
    const int j0 = cell_y(centre.y() - radius), j1 = cell_y(centre.y() + radius);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const int cell = j * nx_ + i;
        for (int k = start_[cell]; k < start_[cell + 1]; ++k) visit(index_[k]);
      }
  }

 private:
  int cell_x(double x) const;
  int cell_y(double y) const;
  dem::Vec2 origin_{0, 0};
  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::size_t points_ = 0;
  std::vector<int> start_;  ///< cell -> first entry in index_ (CSR layout)
  std::vector<int> index_;
};

}  // namespace pilelab::coarse
