#pragma once
// `pilelab coarse`: DEM snapshots -> continuum fields on the pile triangulation.
// Writes OUT/fields.h5, OUT/fields.vtu, OUT/profiles.csv, OUT/rve_study.csv and the "coarse"
// section of OUT/report.json (docs/FORMAT.md).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pilelab::coarse {

struct CoarseRunOptions {
  std::string scene_path;
  std::string out_dir;
  /// The piles to average (an ensemble's members) where the scene's [coarse] table lists none.
  std::vector<std::string> dem_files;
};

nlohmann::json run_coarse(const CoarseRunOptions& options);

}  // namespace pilelab::coarse
