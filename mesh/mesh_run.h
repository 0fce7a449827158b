#pragma once
// `pilelab mesh`: the pile triangulation OUT/pile.msh from the scene's [mesh] table, and the
// "mesh" section of OUT/report.json.
#include <string>

#include <nlohmann/json.hpp>

namespace pilelab::mesh {

struct MeshRunOptions {
  std::string scene_path;
  std::string out_dir;
};

/// Returns the report section it wrote. A dem_outline mesh without mesh.dem_file reads
/// OUT/dem.h5.
nlohmann::json run_mesh(const MeshRunOptions& options);

}  // namespace pilelab::mesh
