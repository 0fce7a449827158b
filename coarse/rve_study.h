#pragma once
// The RVE-size study (paper section 4, Figs. 5-6): at chosen points, every quantity against the
// number of grains in the RVE, for radii growing geometrically; and the smallest converged size.
//
// Convergence: size i is converged when every larger size of the study stays within
// `tolerance` of it, measured against the largest size's magnitude (a tensor's components share
// one scale: its largest component there). The study's choice is the largest converged grain
// count over the points.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "coarse/rve_average.h"

namespace pilelab::coarse {

struct RveStudySettings {
  double first_radius_m = 0.0;     ///< smallest RVE
  double growth = 1.12;            ///< radius ratio of consecutive sizes
  double max_grain_count = 600.0;  ///< stop once an RVE holds this many grains
  double max_radius_m = 1.0;       ///< or once it is this large
  double tolerance = 0.05;
};

struct RveStudy {
  std::string csv;                 ///< rve_study.csv: point,x_m,y_m,radius_m,grain_count,quantity,value
  nlohmann::json points = nlohmann::json::array();  ///< per point: converged count and radius
  double chosen_grain_count = 0.0;
};

/// Throws std::invalid_argument unless first_radius_m and max_radius_m are finite and > 0 and
/// growth is finite and > 1 (otherwise the radius loop would never end).
RveStudy rve_size_study(const RveAverager& rve, const std::vector<Vec2>& points, const RveStudySettings& settings);

}  // namespace pilelab::coarse
