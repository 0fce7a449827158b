#include "apps/scene_check.h"

#include <cstdio>
#include <filesystem>

#include "coarse/coarse_scene.h"
#include "common/duration_text.h"
#include "common/ensemble.h"
#include "common/error.h"
#include "common/scene_reader.h"
#include "common/scene_tables.h"
#include "compare/compare_run.h"
#include "dem/dem_scene.h"
#include "dem/pile_protocol.h"
#include "mesh/pile_mesh.h"
#ifdef PILELAB_WITH_CONTINUUM
#include "continuum/settings.h"
#endif

namespace pilelab::app {

SceneCheck check_scene(const std::string& path, bool estimate_cost) {
  SceneReader reader = SceneReader::from_file(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  const std::string out = "OUT";  // defaults of file keys only; nothing is opened
  SceneCheck check;
  std::vector<std::string>& found = check.tables;
  reader.get_string("scene.name", "");
  reader.get_string("scene.description", "");
  if (reader.has("scene")) found.push_back("scene");
  if (reader.has("ensemble")) read_ensemble_scene(reader), found.push_back("ensemble");
  if (reader.has("dem")) {
    const dem::DemScene scene = dem::read_dem_scene(reader);
    // An explicit step is tested against the stability limit of the scene's own grains, which
    // only drawing them gives (about 2 s for a paper pile): the refusal `pilelab dem` gives.
    if (scene.time_step > 0.0 || estimate_cost) {
      const dem::PileProtocol protocol(scene, path);
      if (estimate_cost) check.pour_cost = dem::run_cost(scene, protocol.world().settings().time_step);
    }
    check.grain_count = scene.grain_count;
    found.push_back("dem");
  }
  // A file a stage reads that no stage of this scene makes must exist now, not be found missing
  // after the pour.
  const auto must_exist = [&](const std::string& key, const std::string& file) {
    if (!file.empty() && !std::filesystem::exists(file))
      throw InputError(path + ": " + key + " = " + file +
                       ": no such file (a stage reads it and no stage of this scene makes it)");
  };
  const auto made_in_out = [&](const std::string& file) { return file.rfind(out + "/", 0) == 0; };
  if (reader.has("mesh")) mesh::read_mesh_scene(reader, dir), found.push_back("mesh");
  std::string coarse_mesh;  // the mesh each stage works on, when the scene has the stage
  if (reader.has("coarse")) {
    const coarse::CoarseSettings c = coarse::read_coarse_scene(reader, dir, out);
    coarse_mesh = c.mesh_file;
    for (const std::string& f : c.dem_files)
      if (!made_in_out(f)) must_exist("coarse.dem_files", f);
    if (!made_in_out(c.mesh_file))
      must_exist("coarse.mesh_file", c.mesh_file);
    else if (!reader.has("mesh"))
      throw InputError(path + ": [coarse] samples its fields on OUT/pile.msh, which only the mesh stage makes: add a "
                              "[mesh] table, or name a mesh in coarse.mesh_file");
    found.push_back("coarse");
  }
  if (reader.has("compare")) compare::read_compare_scene(reader, dir, out), found.push_back("compare");
#ifdef PILELAB_WITH_CONTINUUM
  if (reader.has("continuum")) {
    const std::string mesh_file = continuum::read_continuum_scene(reader, dir).mesh_file;
    must_exist("continuum.mesh_file", mesh_file);
    // compare matches the models' points to the fields' points: both must come from one mesh.
    const std::string solve_mesh = mesh_file.empty() ? out + "/pile.msh" : mesh_file;
    const auto same = [](const std::string& a, const std::string& b) {
      return std::filesystem::path(a).lexically_normal() == std::filesystem::path(b).lexically_normal();
    };
    if (reader.has("compare") && !coarse_mesh.empty() && !same(coarse_mesh, solve_mesh))
      throw InputError(path + ": the fields are coarse-grained on " + coarse_mesh + " (coarse.mesh_file) and the models solved on " +
                       solve_mesh + " (continuum.mesh_file): compare needs both on one mesh; name the same file in both keys");
    found.push_back("continuum");
  }
#endif
  reader.reject_unknown({"scene", "ensemble", "dem", "mesh", "coarse", "compare"}, scene_tables());
  return check;
}

std::string cost_text(const SceneCheck& check) {
  if (!check.pour_cost) return "";
  const dem::RunCost& c = *check.pour_cost;
  const auto core_time = [&](double grain_steps) { return duration_text(grain_steps / dem::reference_grain_steps_per_core_s); };
  char text[512];
  std::snprintf(text, sizeof text,
                "the pour: %d grains at dt = %.3g s, %.3g to %.3g s simulated (settling at its minimum or its limit): "
                "%.3g to %.3g steps, %.3g to %.3g grain-steps, about %s to %s on one core at %.0e grain-steps/s",
                check.grain_count, c.time_step, c.simulated.shortest, c.simulated.longest, c.steps_shortest, c.steps_longest,
                c.grain_steps_shortest, c.grain_steps_longest, core_time(c.grain_steps_shortest).c_str(),
                core_time(c.grain_steps_longest).c_str(), dem::reference_grain_steps_per_core_s);
  return text;
}

}  // namespace pilelab::app
