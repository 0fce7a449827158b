// fields.h5: the coarse-grained fields through the comparison's reader.
#include "compare/point_fields.h"
#include "fuzz/fuzz_target.h"

using namespace pilelab;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fuzz::InputFile file(data, size, ".h5");
  fuzz::expect_clean_refusal("fields", [&] {
    compare::Triangulation mesh;
    bool on_nodes = true;
    compare::read_dem_fields(file.path(), &mesh, &on_nodes);
  });
  return 0;
}
