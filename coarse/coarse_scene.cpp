#include "coarse/coarse_scene.h"

#include <filesystem>

#include "coarse/kernel.h"
#include "common/error.h"

namespace pilelab::coarse {

namespace {
std::string resolve(const std::string& path, const std::string& dir) {
  if (path.empty() || std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(dir) / path).string();
}
}  // namespace

CoarseSettings read_coarse_scene(SceneReader& r, const std::string& scene_dir, const std::string& out_dir) {
  CoarseSettings s;
  for (const std::string& f : r.get_string_list("coarse.dem_files", {})) s.dem_files.push_back(resolve(f, scene_dir));
  if (s.dem_files.empty()) s.dem_files.push_back((std::filesystem::path(out_dir) / "dem.h5").string());
  s.snapshot = r.get_string("coarse.snapshot", s.snapshot);
  s.strain_to = r.get_string("coarse.strain_to", s.strain_to);
  s.mesh_file = resolve(r.get_string("coarse.mesh_file", ""), scene_dir);
  if (s.mesh_file.empty()) s.mesh_file = (std::filesystem::path(out_dir) / "pile.msh").string();
  s.location = r.get_choice("coarse.location", "nodes", {"nodes", "cells"}) == "nodes" ? CoarseSettings::Location::nodes
                                                                                      : CoarseSettings::Location::cells;
  std::vector<std::string> methods = {"rve"};
  for (const std::string& k : kernel_names()) methods.push_back(k);
  const std::string method = r.get_choice("coarse.method", "rve", methods);
  s.method = method == "rve" ? CoarseSettings::Method::rve : CoarseSettings::Method::kernel;
  if (s.method == CoarseSettings::Method::kernel) s.kernel = method;
  s.rve_radius_m = r.get_double("coarse.rve_radius_m", 0.0, Range::at_least(0.0));
  s.rve_grain_count = r.get_double("coarse.rve_grain_count", s.rve_grain_count, Range::closed(0.0, 1e5));
  s.clip_volume = r.get_choice("coarse.rve_volume", "clipped", {"clipped", "full"}) == "clipped";
  s.kernel_width_m = r.get_double("coarse.kernel_width_m", 0.0, Range::at_least(0.0));
  s.profile_heights = r.get_double_list("coarse.profile_heights", s.profile_heights, Range::closed(0.0, 1.0));
  s.profile_points = static_cast<int>(r.get_int("coarse.profile_points", s.profile_points, 2, 100000));
  s.study_x_m = r.get_double_list("coarse.rve_study.points_x_m", {}, Range{});
  s.study_y_over_h = r.get_double_list("coarse.rve_study.points_y_over_h", {}, Range::closed(0.0, 1.0));
  if (s.study_x_m.size() != s.study_y_over_h.size())
    throw InputError(r.source() + ": coarse.rve_study.points_x_m and points_y_over_h must have the same length");
  s.study_tolerance = r.get_double("coarse.rve_study.tolerance", s.study_tolerance, {0.0, 1.0, true});
  s.study_max_grain_count = r.get_double("coarse.rve_study.max_grain_count", s.study_max_grain_count, Range::closed(10, 1e5));
  return s;
}

}  // namespace pilelab::coarse
