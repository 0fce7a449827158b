#pragma once
// `pilelab compare` and `pilelab fit`: the DEM's fields against the continuum models on the
// common triangulation, and stress-strain relations fitted to the DEM. Writes the "compare"
// and "fit" sections of OUT/report.json, OUT/compare.vtu, and adds the DEM's axis
// misalignment profiles to OUT/profiles.csv (docs/FORMAT.md).
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "common/scene_reader.h"

namespace pilelab::compare {

/// Solves the continuum models of a [continuum] table given as scene text (the closed loops:
/// a model with the constants fitted to the DEM, on the fields' mesh, whose fields are then set
/// against the DEM's) into OUT_DIR/models.h5; `source` names the text in errors. The caller
/// supplies it (continuum::solve_scene_text), so that compare/ needs no finite elements; it is
/// called on this process alone.
using ModelSolver = std::function<void(const std::string& scene_text, const std::string& source, const std::string& out_dir)>;

struct CompareRunOptions {
  std::string scene_path;
  std::string out_dir;
  /// The repose angle the DEM measured (one pile's flank mean, or an ensemble's mean): the FPA
  /// angle psi = 45 - phi/2 uses it unless compare.repose_angle_deg is given. Without it, the
  /// "dem" section of OUT/report.json is read (a standalone `pilelab compare`).
  std::optional<double> measured_repose_angle_deg;
  /// Without it, the fits have no closed loop.
  ModelSolver solve_models;
};

/// The [compare] table, read and checked in one place.
struct CompareSettings {
  std::string fields_path;        ///< default OUT/fields.h5
  std::string models_path;        ///< default OUT/models.h5 (optional file)
  int fit_resamples = 200;
  int fit_folds = 5;
  unsigned fit_seed = 1;
  double fit_sample_spacing_m = 0;  ///< 0: fit_sample_spacing() of the fields file
  double repose_angle_deg = 0;      ///< 0: the DEM's
};
CompareSettings read_compare_scene(SceneReader& reader, const std::string& scene_dir, const std::string& out_dir);

/// The spacing of the fit's sample points: the one asked for, else the RVE radius the fields
/// were averaged with, else a twentieth of the pile height (fields without an RVE).
double fit_sample_spacing(const std::string& fields_path, double requested_m);

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
