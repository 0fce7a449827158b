#pragma once
// An ensemble: the same scene poured with several seeds (the paper averages 14 symmetric and 7
// asymmetric piles). The scene's [ensemble] table lists the seeds; every member is a complete DEM
// run of its own in OUT/members/<seed>/, and the later stages work on all of them.
#include <cstdint>
#include <string>
#include <vector>

#include "common/scene_reader.h"

namespace pilelab {

struct EnsembleSpec {
  std::vector<std::int64_t> seeds;  ///< in the order given; empty: the scene is one pile
  bool empty() const { return seeds.empty(); }
};

/// [ensemble]: `seeds = [...]`, or `count = N` with `first_seed` (default 1) for the seeds
/// first_seed .. first_seed + N - 1. Refuses both forms at once, repeated seeds and empty lists.
EnsembleSpec read_ensemble_scene(SceneReader& reader);

/// OUT/members/<seed>: where a member's DEM output lives.
std::string member_directory(const std::string& out_dir, std::int64_t seed);

/// The member's own scene: the [scene] and [dem] tables of the ensemble's scene with dem.seed
/// set to the member's seed, as TOML text (the DEM reads nothing else). Written beside the
/// member's output, it reproduces the member alone: `pilelab dem members/<seed>/scene.toml`.
std::string member_scene_text(const std::string& scene_path, std::int64_t seed);

/// Mean, sample standard deviation and standard error of the mean of finite values (the
/// others are counted apart): what the ensemble reports of every quantity.
struct SampleStatistics {
  double mean = 0.0, standard_deviation = 0.0, standard_error = 0.0;
  int count = 0;      ///< finite values
  int missing = 0;    ///< non-finite values left out (a flank without a measured angle)
};
SampleStatistics sample_statistics(const std::vector<double>& values);

}  // namespace pilelab
