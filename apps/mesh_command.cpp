// `pilelab mesh`: the pile triangulation (mesh/mesh_run.h).
#include <memory>

#include "apps/commands.h"
#include "common/output_lock.h"
#include "mesh/mesh_run.h"

namespace pilelab::app {

void add_mesh_command(CLI::App& app) {
  auto opt = std::make_shared<mesh::MeshRunOptions>();
  CLI::App* cmd = app.add_subcommand(
      "mesh", "Triangulate the pile from the scene's [mesh] table: an ideal wedge, a block, or the outline\n"
              "of a DEM pile. Writes OUT/pile.msh (gmsh MSH 4.1) and the \"mesh\" section of OUT/report.json.");
  cmd->add_option("scene", opt->scene_path, "Scene file (TOML); see docs/SCENES.md")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", opt->out_dir, "Output directory (created if missing)")->required();
  cmd->final_callback([opt] {
    const OutputLock lock(opt->out_dir, "pilelab mesh " + opt->scene_path);
    mesh::run_mesh(*opt);
  });
}

}  // namespace pilelab::app
