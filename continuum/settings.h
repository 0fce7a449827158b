#pragma once
// Settings of the continuum stage: the scene's [continuum] table as plain structs with units
// in the names, defaults and ranges (docs/SCENES.md lists every key); each model's own table
// is read by the model (continuum/model.h). No deal.II here, so the command-line front end
// compiles without it.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/scene_reader.h"
#include "continuum/model.h"

namespace pilelab::continuum {

/// How a linear system is solved. Both report their iteration count (1 for direct).
struct SolverSettings {
  enum class Kind { iterative, direct } kind = Kind::iterative;
  double relative_tolerance = 1e-10;  ///< |r| <= tol |b| for the iterative solvers
  int max_iterations = 5000;
};

/// The stage's own keys, and the settings of every registered model (each model's table is
/// read, so that a misspelt key is refused whether or not the model is listed).
struct ContinuumSettings {
  std::vector<std::string> models = {"elastic", "fpa"};  ///< continuum.models, in the registry's order
  std::string mesh_file;  ///< empty: OUT/pile.msh if it exists, else generated from [mesh]
  bool has_mesh_table = false;
  double density_kg_per_m2 = 4100.0;   ///< bulk areal density (grains 5000 kg/m^2 at packing 0.82)
  double gravity_m_per_s2 = 9.81;
  std::vector<double> profile_heights = {0.0, 0.1, 0.2, 0.3, 0.5, 0.7};  ///< y / h, as [coarse]
  int profile_points = 61;             ///< points per horizontal cut, flank to flank, as [coarse]
  std::map<std::string, std::shared_ptr<const ModelSettings>> model_settings;  ///< by model name

  bool wants(const std::string& model) const;
  /// The settings of a registered model, as its own type (std::bad_cast for the wrong one).
  template <class Settings>
  const Settings& settings_of(const std::string& model) const {
    return dynamic_cast<const Settings&>(*model_settings.at(model));
  }
};

/// Reads [continuum] (and checks that it holds no unknown keys). Relative file names are taken
/// relative to scene_dir. Throws InputError naming the file and the key.
ContinuumSettings read_continuum_scene(SceneReader& reader, const std::string& scene_dir);

/// Reads the solver keys of a model's table (solver, solver_tolerance, solver_max_iterations)
/// over the defaults in s.
SolverSettings read_solver(ModelTable& table, SolverSettings s);

}  // namespace pilelab::continuum
