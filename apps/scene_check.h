#pragma once
// Every table of a scene read by the reader of the stage that owns it, without running
// anything: `pilelab check`, and `pilelab run` before its first stage, so that a typo or an
// out-of-range value in [compare] is found before a day of pouring, not after.
#include <string>
#include <vector>

namespace pilelab::app {

/// The tables the scene has, in pipeline order. Throws InputError naming the file, the key and
/// what was expected at the first bad key or value.
std::vector<std::string> check_scene(const std::string& scene_path);

}  // namespace pilelab::app
