#pragma once
// Every table of a scene read by the reader of the stage that owns it, without running
// anything: `pilelab check`, and `pilelab run` before its first stage, so that a typo or an
// out-of-range value in [compare] is found before a day of pouring, not after.
#include <optional>
#include <string>
#include <vector>

#include "dem/pile_protocol.h"

namespace pilelab::app {

/// What checking a scene found: its tables in pipeline order and, when asked for, what its pour
/// costs (at the time step the scene gives or its grains' stability bound sets).
struct SceneCheck {
  std::vector<std::string> tables;
  std::optional<dem::RunCost> pour_cost;
  int grain_count = 0;
};

/// Every table of the scene read by its stage's reader. Throws InputError naming the file, the
/// key and what was expected at the first bad key or value. With estimate_cost, the scene's
/// grains are drawn for their time step (about 2 s for a paper pile) and the pour's cost given.
SceneCheck check_scene(const std::string& scene_path, bool estimate_cost = false);

/// The cost as one line: simulated time, steps, grain-steps and core-hours at the reference rate.
std::string cost_text(const SceneCheck& check);

}  // namespace pilelab::app
