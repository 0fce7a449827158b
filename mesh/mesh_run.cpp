#include "mesh/mesh_run.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/report.h"
#include "common/scene_reader.h"
#include "common/scene_tables.h"
#include "mesh/pile_mesh.h"

namespace pilelab::mesh {

nlohmann::json run_mesh(const MeshRunOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  SceneReader reader = SceneReader::from_file(opt.scene_path);
  MeshSpec spec = read_mesh_scene(reader, std::filesystem::path(opt.scene_path).parent_path().string());
  reader.reject_unknown({"mesh"}, scene_tables());
  if (opt.measured_pile && spec.kind == MeshSpec::Kind::wedge) {
    if (!reader.has("mesh.height_m")) spec.wedge.height_m = opt.measured_pile->height_m;
    if (!reader.has("mesh.left_angle_deg")) spec.wedge.left_angle_deg = opt.measured_pile->left_angle_deg;
    if (!reader.has("mesh.right_angle_deg")) spec.wedge.right_angle_deg = opt.measured_pile->right_angle_deg;
    if (!reader.has("mesh.apex_x_m")) spec.wedge.apex_x_m = opt.measured_pile->apex_x_m;
  }
  if (spec.kind == MeshSpec::Kind::dem_outline && spec.dem_file.empty()) {
    if (opt.member_dem_files.empty())
      spec.dem_file = (std::filesystem::path(opt.out_dir) / "dem.h5").string();
    else
      spec.dem_files = opt.member_dem_files;
  }

  if (spec.kind == MeshSpec::Kind::dem_outline && opt.measured_repose_angles_deg) {
    if (!reader.has("mesh.left_angle_deg")) spec.ray_left_angle_deg = (*opt.measured_repose_angles_deg)[0];
    if (!reader.has("mesh.right_angle_deg")) spec.ray_right_angle_deg = (*opt.measured_repose_angles_deg)[1];
  }

  prepare_output_directory(opt.out_dir);
  const std::string msh = (std::filesystem::path(opt.out_dir) / "pile.msh").string();
  const MeshOutcome outcome = write_mesh(spec, msh);
  if (spec.embed_rays && !outcome.rays_embedded)
    std::fprintf(stderr, "pilelab mesh: the FPA's rays are not mesh edges: %s; the FPA smears its kinks over several cells there "
                 "(docs/CONTINUUM.md, Limitations)\n", outcome.rays_note.c_str());
  const TriangleMesh mesh = read_triangle_mesh(msh);

  const double area = mesh_area(mesh);
  double height = 0;
  for (const auto& p : mesh.nodes) height = std::max(height, p.y());
  const char* kinds[] = {"wedge", "block", "dem_outline"};
  nlohmann::json section = {
      {"file", "pile.msh"},
      {"kind", kinds[static_cast<int>(spec.kind)]},
      {"nodes", mesh.nodes.size()},
      {"triangles", mesh.triangles.size()},
      {"element_size_m", spec.element_size_m},
      {"area_m2", area},
      {"height_m", height},
      {"wall_time_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()}};
  if (spec.kind == MeshSpec::Kind::dem_outline) {
    if (spec.dem_files.empty())
      section["dem_file"] = spec.dem_file;
    else
      section["mean_outline_of"] = spec.dem_files.size();  // members, listed in the coarse section
  }
  if (spec.embed_rays) {
    section["fpa_rays_embedded"] = outcome.rays_embedded;
    if (outcome.rays_embedded)
      section["fpa_rays_angles_deg"] = {outcome.ray_left_angle_deg, outcome.ray_right_angle_deg};
    else
      section["fpa_rays_not_embedded_because"] = outcome.rays_note;
  }
  if (spec.kind == MeshSpec::Kind::wedge)
    section["wedge"] = {{"height_m", spec.wedge.height_m},
                        {"left_angle_deg", spec.wedge.left_angle_deg},
                        {"right_angle_deg", spec.wedge.right_angle_deg},
                        {"apex_x_m", spec.wedge.apex_x_m},
                        {"from_dem", opt.measured_pile.has_value()}};
  write_report_section((std::filesystem::path(opt.out_dir) / "report.json").string(), "mesh", section);
  return section;
}

}  // namespace pilelab::mesh
