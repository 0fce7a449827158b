#pragma once
// `pilelab coarse`: DEM snapshots -> continuum fields on the pile triangulation.
// Writes OUT/fields.h5, OUT/fields.vtu, OUT/profiles.csv, OUT/rve_study.csv and the "coarse"
// section of OUT/report.json (docs/FORMAT.md).
#include <string>

#include <nlohmann/json.hpp>

namespace pilelab::coarse {

struct CoarseRunOptions {
  std::string scene_path;
  std::string out_dir;
};

nlohmann::json run_coarse(const CoarseRunOptions& options);

}  // namespace pilelab::coarse
