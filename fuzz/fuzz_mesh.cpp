// Mesh files: a gmsh .msh through the mesh reader the coarse and compare stages use.
#include "fuzz/fuzz_target.h"
#include "mesh/pile_mesh.h"

using namespace pilelab;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fuzz::InputFile file(data, size, ".msh");
  fuzz::expect_clean_refusal("mesh", [&] { mesh::read_triangle_mesh(file.path()); });
  return 0;
}
