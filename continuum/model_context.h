#pragma once
// What a model's solve is handed (continuum/model.h): the pile's mesh and geometry, the stage's
// settings, what the earlier stages measured, and the outputs every model adds to (its fields
// at the points of models.h5, its profiles). solve_model() is the part every model shares:
// run the problem, write its VTU, sample it, and report what every model reports.
#include <string>
#include <vector>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <nlohmann/json.hpp>

#include "continuum/field_output.h"
#include "continuum/linear_solvers.h"
#include "continuum/pile_domain.h"
#include "continuum/settings.h"
#include "continuum/solve.h"

namespace pilelab::continuum {

struct ModelContext {
  const std::string& out_dir;
  const Triangulation2& tria;
  const PileGeometry& pile;
  const ContinuumSettings& settings;
  const MeasuredPile& measured;  ///< for the keys a scene leaves open (solve.h)
  double rho_g_h;
  std::vector<dealii::Point<2>> points;  ///< where models.h5 has the fields
  std::vector<ModelFields> fields;       ///< per model, for models.h5
  std::vector<ProfileValue> profile_rows;
  MPI_Comm comm;
  dealii::ConditionalOStream& pcout;
};

/// The solver's settings and its figures, as every model reports them.
nlohmann::json solver_json(const SolverSettings& s, const SolveStats& st);

/// One model, the same way for each: solve (run() is setup, assembly, solve), write its VTU,
/// sample its profiles and its fields at the output points, and report what every model
/// reports. Problem has run(), output_results(), field_names(), field_units() and
/// field_evaluator() (continuum/model_problem.h).
template <class Problem>
nlohmann::json solve_model(Problem& problem, const std::string& name, const SolverSettings& solver, ModelContext& c) {
  dealii::Timer timer;
  const auto& r = problem.run();
  const std::string file = problem.output_results(c.out_dir, c.rho_g_h);
  const auto names = problem.field_names();
  const PointEvaluator fields = problem.field_evaluator(c.rho_g_h);
  const auto rows = sample_profiles(c.tria, c.pile, c.settings.profile_heights, c.settings.profile_points, name, names,
                                    fields, c.rho_g_h, c.comm);
  c.profile_rows.insert(c.profile_rows.end(), rows.begin(), rows.end());
  c.fields.push_back({name, names, problem.field_units(), evaluate_at_points(c.points, names.size(), fields, c.comm), {}});
  const double wall = timer.wall_time();
  c.pcout << name << ": " << r.n_dofs << " dofs, " << r.solver.iterations << " iterations, base force / weight = "
          << r.base_force_N / r.weight << ", " << wall << " s -> " << file << "\n";
  return {{"dofs", r.n_dofs},
          {"linear_solver", solver_json(solver, r.solver)},
          {"iterations", r.solver.iterations},
          {"setup_s", r.setup_s},
          {"assemble_s", r.assemble_s},
          {"solve_s", r.solve_s},
          {"wall_time_s", wall},
          {"weight_N", r.weight},
          {"base_force_N", r.base_force_N},
          {"base_force_over_weight", r.base_force_N / r.weight},
          {"base_shear_over_weight", r.base_shear_force / r.weight},
          {"file", file.substr(file.find_last_of('/') + 1)}};
}

/// Prints a model's warning on rank 0 and puts it in its report section.
void warn(ModelContext& c, nlohmann::json& section, const std::string& warning);

}  // namespace pilelab::continuum
