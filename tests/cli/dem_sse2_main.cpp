// `pilelab dem SCENE -o OUT -q` with the DEM's SSE2 code alone (pilelab_dem_sse2): the other
// half of Reproducibility.SameFilesWhateverTheInstructionSet.
#include <cstdio>
#include <exception>

#include "dem/pile_run.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s SCENE OUT\n", argv[0]);
    return 2;
  }
  try {
    pilelab::dem::DemRunOptions options;
    options.scene_path = argv[1];
    options.out_dir = argv[2];
    options.quiet = true;
    pilelab::dem::run_dem(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
