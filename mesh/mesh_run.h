#pragma once
// `pilelab mesh`: the pile triangulation OUT/pile.msh from the scene's [mesh] table, and the
// "mesh" section of OUT/report.json.
#include <array>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "mesh/pile_mesh.h"

namespace pilelab::mesh {

struct MeshRunOptions {
  std::string scene_path;
  std::string out_dir;
  /// The pile the DEM poured (an ensemble's mean): a wedge mesh takes from it the height, flank
  /// angles and apex the scene's [mesh] table leaves out.
  std::optional<Wedge> measured_pile;
  /// An ensemble's members: a dem_outline mesh without mesh.dem_file meshes their mean outline.
  std::vector<std::string> member_dem_files;
  /// The angles of repose the DEM measured (left, right) [degree], one pile's or the members'
  /// mean: a dem_outline mesh embeds the FPA's rays at these unless the scene gives
  /// mesh.left_angle_deg and mesh.right_angle_deg (the FPA takes the same by default).
  std::optional<std::array<double, 2>> measured_repose_angles_deg;
};

/// Returns the report section it wrote. A dem_outline mesh without mesh.dem_file reads
/// OUT/dem.h5.
nlohmann::json run_mesh(const MeshRunOptions& options);

}  // namespace pilelab::mesh
