#include "coarse/rve_study.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

#include "coarse/quantities.h"

namespace pilelab::coarse {

namespace {
// The study's quantities; consecutive entries of one tensor share a scale (group, size).
struct StudyQuantity {
  const char* name;
  int group, size;
};
const StudyQuantity study_quantities[] = {
    {"stress_xx", 0, 3}, {"stress_yy", 0, 3}, {"stress_xy", 0, 3},     {"fabric_xx", 3, 3},
    {"fabric_yy", 3, 3}, {"fabric_xy", 3, 3}, {"coordination", 6, 1},  {"volume_fraction", 7, 1},
    {"strain_xx", 8, 3}, {"strain_yy", 8, 3}, {"strain_xy", 8, 3}};
constexpr std::size_t study_count = sizeof(study_quantities) / sizeof(study_quantities[0]);
}  // namespace

RveStudy rve_size_study(const RveAverager& rve, const std::vector<Vec2>& points, const RveStudySettings& settings) {
  // The radius loop ends on a grain count or a radius; a NaN or zero start reaches neither.
  auto positive = [](double x) { return std::isfinite(x) && x > 0; };
  if (!positive(settings.first_radius_m) || !positive(settings.max_radius_m) || !(settings.growth > 1) ||
      !std::isfinite(settings.growth))
    throw std::invalid_argument("rve_size_study: first_radius_m = " + std::to_string(settings.first_radius_m) +
                                ", max_radius_m = " + std::to_string(settings.max_radius_m) +
                                " and growth = " + std::to_string(settings.growth) +
                                " must be finite, the radii > 0 and the growth > 1");
  RveStudy study;
  std::ostringstream csv;
  csv << std::setprecision(10) << "point,x_m,y_m,radius_m,grain_count,quantity,value\n";
  const auto& table = quantities();
  std::vector<const Quantity*> quantity(study_count);
  for (std::size_t q = 0; q < study_count; ++q)
    quantity[q] = &*std::find_if(table.begin(), table.end(),
                                 [&](const Quantity& x) { return x.name == study_quantities[q].name; });
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vec2 p = points[k];
    std::vector<double> counts, radii;
    std::vector<std::vector<double>> values(study_count);
    for (double r = settings.first_radius_m;; r *= settings.growth) {
      const RveSample s = rve.average(p, r);
      counts.push_back(s.grain_count);
      radii.push_back(r);
      for (std::size_t q = 0; q < study_count; ++q) {
        const auto v = quantity[q]->value(s);
        values[q].push_back(v ? *v : NAN);
        if (v) csv << k << ',' << p.x() << ',' << p.y() << ',' << r << ',' << s.grain_count << ',' << quantity[q]->name << ',' << *v << '\n';
      }
      if (s.grain_count >= settings.max_grain_count || r > settings.max_radius_m) break;
    }
    const std::size_t last = counts.size() - 1;
    std::size_t converged = last;
    for (std::size_t i = 0; i <= last; ++i) {
      bool ok = counts[i] >= 2;
      for (std::size_t q = 0; q < study_count && ok; ++q) {
        if (std::isnan(values[q][last])) continue;
        double scale = 0;
        const auto& sq = study_quantities[q];
        for (int g = sq.group; g < sq.group + sq.size; ++g)
          if (!std::isnan(values[g][last])) scale = std::max(scale, std::abs(values[g][last]));
        for (std::size_t j = i; j <= last && ok; ++j)
          ok = !std::isnan(values[q][j]) && std::abs(values[q][j] - values[q][i]) <= settings.tolerance * scale;
      }
      if (ok) {
        converged = i;
        break;
      }
    }
    study.chosen_grain_count = std::max(study.chosen_grain_count, counts[converged]);
    study.points.push_back({{"x_m", p.x()}, {"y_m", p.y()}, {"converged_grain_count", counts[converged]},
                            {"converged_radius_m", radii[converged]}, {"largest_grain_count", counts[last]}});
  }
  study.csv = csv.str();
  return study;
}

}  // namespace pilelab::coarse
