// Scene files: TOML text through the scene reader and every stage's table reader that has no
// deal.II in it (the continuum's is fuzzed through the same SceneReader calls).
#include "coarse/coarse_scene.h"
#include "common/ensemble.h"
#include "common/scene_reader.h"
#include "compare/compare_run.h"
#include "dem/dem_scene.h"
#include "fuzz/fuzz_target.h"
#include "mesh/pile_mesh.h"

using namespace pilelab;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::expect_clean_refusal("scene", [&] {
    SceneReader reader(text, "fuzz.toml");
    // Each table on its own, so that a refusal of one does not hide the others from the fuzzer.
    fuzz::expect_clean_refusal("scene", [&] { dem::read_dem_scene(reader); });
    fuzz::expect_clean_refusal("scene", [&] { mesh::read_mesh_scene(reader, "/tmp"); });
    fuzz::expect_clean_refusal("scene", [&] { coarse::read_coarse_scene(reader, "/tmp", "/tmp"); });
    fuzz::expect_clean_refusal("scene", [&] { compare::read_compare_scene(reader, "/tmp", "/tmp"); });
    fuzz::expect_clean_refusal("scene", [&] { read_ensemble_scene(reader); });
  });
  return 0;
}
