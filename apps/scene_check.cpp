#include "apps/scene_check.h"

#include <filesystem>

#include "coarse/coarse_scene.h"
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

std::vector<std::string> check_scene(const std::string& path) {
  SceneReader reader = SceneReader::from_file(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  const std::string out = "OUT";  // defaults of file keys only; nothing is opened
  std::vector<std::string> found;
  reader.get_string("scene.name", "");
  reader.get_string("scene.description", "");
  if (reader.has("scene")) found.push_back("scene");
  if (reader.has("ensemble")) read_ensemble_scene(reader), found.push_back("ensemble");
  if (reader.has("dem")) {
    const dem::DemScene scene = dem::read_dem_scene(reader);
    // An explicit step is tested against the stability limit of the scene's own grains, which
    // only drawing them gives (about 2 s for a paper pile): the refusal `pilelab dem` gives.
    if (scene.time_step > 0.0) dem::PileProtocol(scene, path);
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
  if (reader.has("coarse")) {
    const coarse::CoarseSettings c = coarse::read_coarse_scene(reader, dir, out);
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
    must_exist("continuum.mesh_file", continuum::read_continuum_scene(reader, dir).mesh_file);
    found.push_back("continuum");
  }
#endif
  reader.reject_unknown({"scene", "ensemble", "dem", "mesh", "coarse", "compare"}, scene_tables());
  return found;
}

}  // namespace pilelab::app
