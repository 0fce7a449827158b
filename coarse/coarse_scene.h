#pragma once
// The [coarse] table of a scene: which piles, which snapshots, where to sample, how to average.
// Every key, its unit and range: docs/SCENES.md.
#include <string>
#include <vector>

#include "common/scene_reader.h"

namespace pilelab::coarse {

struct CoarseSettings {
  std::vector<std::string> dem_files;       ///< one pile, or an ensemble averaged point by point
  std::string snapshot = "settled";         ///< the state whose stress, fabric, density are averaged
  std::string strain_to = "relaxed";        ///< strain: displacements from snapshot to this one
  std::string mesh_file;                    ///< the triangulation the fields live on
  enum class Location { nodes, cells } location = Location::nodes;
  /// The paper's RVE discs, or a registered kernel (coarse/kernel_registry.cpp) named kernel.
  enum class Method { rve, kernel } method = Method::rve;
  std::string kernel;                       ///< the kernel's name, with Method::kernel
  double rve_radius_m = 0.0;                ///< > 0: this radius; 0: from rve_grain_count
  double rve_grain_count = 150.0;           ///< grains per RVE (paper: 100-200); 0: the study's choice
  bool clip_volume = true;                  ///< V = the part of the disc inside the pile
  double kernel_width_m = 0.0;              ///< 0: the RVE radius
  std::vector<double> profile_heights = {0.0, 0.1, 0.2, 0.3, 0.5, 0.7};  ///< y / h
  int profile_points = 61;
  std::vector<double> study_x_m;            ///< RVE-size study points (empty: three defaults)
  std::vector<double> study_y_over_h;
  double study_tolerance = 0.05;            ///< relative change that counts as converged
  double study_max_grain_count = 600.0;
};

/// Reads [coarse]; relative paths are taken relative to the scene's directory; dem_files and
/// mesh_file default to OUT/dem.h5 and OUT/pile.msh.
CoarseSettings read_coarse_scene(SceneReader& reader, const std::string& scene_dir, const std::string& out_dir);

}  // namespace pilelab::coarse
