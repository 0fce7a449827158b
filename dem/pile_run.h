#pragma once
// `pilelab dem`: runs the pile protocol of a scene to the end, writing VTK frames, checkpoints,
// progress lines, and finally OUT/dem.h5 and the "dem" section of OUT/report.json.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace pilelab::dem {

struct DemRunOptions {
  std::string scene_path;
  std::string out_dir;
  bool restart = false;          ///< continue from OUT/checkpoint.h5
  bool quiet = false;            ///< no progress lines
  int threads = 0;               ///< OpenMP threads; 0: the default
  std::int64_t stop_after_steps = 0;  ///< > 0: write a checkpoint and stop there (restart tests)
};

/// Returns the report's "dem" section. Throws InputError for bad scenes and files.
nlohmann::json run_dem(const DemRunOptions& options);

}  // namespace pilelab::dem
