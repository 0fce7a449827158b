#pragma once
// `pilelab compare` and `pilelab fit`: the DEM's fields against the continuum models on the
// common triangulation, and stress-strain relations fitted to the DEM. Writes the "compare"
// and "fit" sections of OUT/report.json, OUT/compare.vtu, and adds the DEM's axis
// misalignment profiles to OUT/profiles.csv (docs/FORMAT.md).
#include <string>

#include <nlohmann/json.hpp>

namespace pilelab::compare {

struct CompareRunOptions {
  std::string scene_path;
  std::string out_dir;
};

struct FitOptions {
  std::string fields_path;       ///< a fields.h5 (from coarse/, or the user's own)
  std::string out_dir;
  int resamples = 200;           ///< bootstrap resamples
  int folds = 5;                 ///< cross-validation folds
  unsigned seed = 1;
  double sample_spacing_m = 0.0; ///< thin the points to about this spacing; 0: the RVE radius
};

nlohmann::json run_compare(const CompareRunOptions& options);

/// One model of a models.h5 against the DEM fields: relative L2 differences of the
/// displacement (both components) and of the strain components (the closed loop of a fit).
nlohmann::json compare_displacements(const std::string& fields_path, const std::string& models_path,
                                     const std::string& model);

/// The fit section alone, from any fields.h5 with stress_change_*, strain_*, fabric_* and
/// pressure fields.
nlohmann::json run_fit(const FitOptions& options);

}  // namespace pilelab::compare
