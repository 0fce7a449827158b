#pragma once
// Named presets a scene can ask for with `[scene] preset = "NAME"`: TOML that fills in the keys
// the scene leaves out, in the tables the scene has (a preset never adds a stage). The values
// come from the speed-accuracy study (docs/studies/speed_accuracy.md), which says what each
// costs and buys.
#include <string>
#include <utility>
#include <vector>

namespace pilelab {

/// (name, TOML text) of every preset.
inline const std::vector<std::pair<std::string, std::string>>& scene_presets() {
  static const std::vector<std::pair<std::string, std::string>> presets = {
      {"fast",
       "# The cheapest settings, each measured alone: leapfrog near its limit (within an\n"
       "# ensemble's noise), a loose settling threshold (0.2 % on the core's fabric), P1.\n"
       "[dem.integrator]\nscheme = \"leapfrog\"\ntime_step_fraction = 0.95\n"
       "[dem.settle]\nkinetic_energy_per_grain_J = 1e-6\n"
       "[continuum.elastic]\ndegree = 1\n"
       "[continuum.fpa]\ndegree = 1\n"},
      {"accurate",
       "# The study's reference: Verlet at 0.18 of its limit (the paper's 2e-6 s on the paper's\n"
       "# grains, about 8 times the default step's cost), a strict settling threshold, P2 models.\n"
       "[dem.integrator]\nscheme = \"verlet\"\ntime_step_fraction = 0.18\n"
       "[dem.settle]\nkinetic_energy_per_grain_J = 1e-8\n"
       "[continuum.elastic]\ndegree = 2\n"
       "[continuum.fpa]\ndegree = 2\n"},
  };
  return presets;
}

}  // namespace pilelab
