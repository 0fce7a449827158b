#pragma once
// Rebuilds a World from a snapshot of a dem.h5 file: walls where they were, grains with their
// shapes, masses and state. The spring history is not stored in dem.h5; each contact's spring
// starts at its recorded tangential force (exact for contacts at rest, which is what a settled
// snapshot holds). For benchmarks, and for continuing experiments from a finished pile.
#include <string>

#include "dem/dem_file.h"
#include "dem/world.h"

namespace pilelab::dem {

World world_from_snapshot(const DemFile& file, const std::string& snapshot, const WorldSettings& settings);

}  // namespace pilelab::dem
