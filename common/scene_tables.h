#pragma once
// The top-level tables a scene file may hold, one per pipeline stage. Each stage checks
// every key of its own table (SceneReader::reject_unknown) and only the names of the others.
#include <string>
#include <vector>

namespace pilelab {

inline const std::vector<std::string>& scene_tables() {
  static const std::vector<std::string> tables = {"scene",   "dem", "mesh",     "coarse",  "continuum",
                                                  "compare", "fit", "pipeline", "ensemble"};
  return tables;
}

}  // namespace pilelab
