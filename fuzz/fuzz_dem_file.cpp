// dem.h5: the DEM's output file through the reader of the later stages.
#include "dem/dem_file.h"
#include "fuzz/fuzz_target.h"

using namespace pilelab;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fuzz::InputFile file(data, size, ".h5");
  fuzz::expect_clean_refusal("dem_file", [&] { dem::read_dem_file(file.path()); });
  return 0;
}
