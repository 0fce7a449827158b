#include "coarse/grain_grid.h"

#include <algorithm>
#include <cmath>

namespace pilelab::coarse {

GrainGrid::GrainGrid(const std::vector<dem::Vec2>& centres, double cell_size) : cell_(cell_size) {
  points_ = centres.size();
  if (centres.empty()) return;
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (const auto& c : centres) {
    x0 = std::min(x0, c.x()), y0 = std::min(y0, c.y());
    x1 = std::max(x1, c.x()), y1 = std::max(y1, c.y());
  }
  origin_ = {x0, y0};
  nx_ = static_cast<int>((x1 - x0) / cell_) + 1;
  ny_ = static_cast<int>((y1 - y0) / cell_) + 1;
  start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  std::vector<int> cell_of(centres.size());
  for (std::size_t p = 0; p < centres.size(); ++p) {
    cell_of[p] = cell_y(centres[p].y()) * nx_ + cell_x(centres[p].x());
    ++start_[cell_of[p] + 1];
  }
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  index_.resize(centres.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (std::size_t p = 0; p < centres.size(); ++p) index_[fill[cell_of[p]]++] = static_cast<int>(p);
}

int GrainGrid::cell_x(double x) const {
  return std::clamp(static_cast<int>(std::floor((x - origin_.x()) / cell_)), 0, nx_ - 1);
}
int GrainGrid::cell_y(double y) const {
  return std::clamp(static_cast<int>(std::floor((y - origin_.y()) / cell_)), 0, ny_ - 1);
}

}  // namespace pilelab::coarse
