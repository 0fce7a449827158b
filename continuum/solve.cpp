// `pilelab solve`: read the scene, find or make the mesh, solve each model the scene lists, and
// write the fields, the profiles and the report section. Every rank runs this; rank 0 alone
// writes the shared files (report.json, profiles.csv, models.h5, pile.msh, the .pvtu record).
#include "continuum/solve.h"

#include "common/atomic_file.h"

#include <filesystem>
#include <iostream>
#include <sstream>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include "common/error.h"
#include "common/report.h"
#include "common/scene_reader.h"
#include "continuum/elastic_problem.h"
#include "continuum/fpa_problem.h"
#include "continuum/pile_domain.h"
#include "continuum/settings.h"
#include "mesh/mesh_run.h"

namespace pilelab::continuum {

using namespace dealii;
namespace fs = std::filesystem;

namespace {

// Runs fn on rank 0 and rethrows its InputError (or other failure) on every rank, so that an
// error there cannot leave the other ranks waiting.
void on_rank0(MPI_Comm comm, const std::function<void()>& fn) {
  std::string error;
  int kind = 0;  // 0 ok, 1 InputError, 2 other
  if (Utilities::MPI::this_mpi_process(comm) == 0) {
    try {
      fn();
    } catch (const InputError& e) {
      error = e.what();
      kind = 1;
    } catch (const std::exception& e) {
      error = e.what();
      kind = 2;
    }
  }
  kind = Utilities::MPI::broadcast(comm, kind, 0);
  error = Utilities::MPI::broadcast(comm, error, 0);
  if (kind == 1) throw InputError(error);
  if (kind == 2) throw std::runtime_error(error);
}

// What the earlier stages measured, where the scene leaves the key open; true if the FPA takes
// the measured angles (the scene sets none, or asks for the DEM's).
bool apply_measured_pile(const MeasuredPile& m, const SceneReader& reader, ContinuumSettings& s) {
  if (m.density_kg_per_m2 && !reader.has("continuum.density_kg_per_m2")) s.density_kg_per_m2 = *m.density_kg_per_m2;
  if (m.gravity_m_per_s2 && !reader.has("continuum.gravity_m_per_s2")) s.gravity_m_per_s2 = *m.gravity_m_per_s2;
  if (!m.left_repose_angle_deg || !m.right_repose_angle_deg) return false;
  const double l = *m.left_repose_angle_deg, r = *m.right_repose_angle_deg;
  const bool scene_sets_angles = reader.has("continuum.fpa.repose_angle_deg") ||
                                 reader.has("continuum.fpa.left_repose_angle_deg") ||
                                 reader.has("continuum.fpa.right_repose_angle_deg");
  if ((scene_sets_angles && !s.fpa_model.angles_from_dem) || !(l > 0 && l < 45 && r > 0 && r < 45)) return false;
  s.fpa_model.left_repose_angle_deg = l;
  s.fpa_model.right_repose_angle_deg = r;
  s.fpa_model.angles_from_dem = true;  // reported as repose_angle_source = "dem"
  return true;
}

// The mesh: continuum.mesh_file if given, else OUT/pile.msh if a mesh stage made it, else one
// generated now from the scene's [mesh] table (the `pilelab mesh` stage, run on rank 0).
std::string find_or_make_mesh(const ContinuumSettings& s, const SolveOptions& o, MPI_Comm comm,
                              ConditionalOStream& pcout) {
  if (!s.mesh_file.empty()) {
    if (!fs::exists(s.mesh_file))
      throw InputError(o.scene_path + ": continuum.mesh_file: " + s.mesh_file +
                       " does not exist (expected a gmsh .msh file)");
    return s.mesh_file;
  }
  const std::string pile = (fs::path(o.out_dir) / "pile.msh").string();
  if (fs::exists(pile)) return pile;
  if (!s.has_mesh_table)
    throw InputError(o.scene_path + ": no mesh: expected continuum.mesh_file, an existing " + pile +
                     " (from `pilelab mesh`), or a [mesh] table to generate one from");
  pcout << "continuum: no " << pile << ", generating it from the scene's [mesh] table\n";
  on_rank0(comm, [&] { mesh::run_mesh({o.scene_path, o.out_dir, std::nullopt, {}, std::nullopt}); });
  return pile;
}

nlohmann::json solver_json(const SolverSettings& s, const SolveStats& st) {
  return {{"solver", s.kind == SolverSettings::Kind::direct ? "direct (MUMPS Cholesky)" : "CG + GAMG"},
          {"tolerance", s.relative_tolerance},
          {"iterations", st.iterations},
          {"relative_residual", st.relative_residual}};
}

// What the models share on the way out, and what they add to it.
struct Outputs {
  const std::string& out_dir;
  const Triangulation2& tria;
  const PileGeometry& pile;
  const ContinuumSettings& settings;
  double rho_g_h;
  std::vector<Point<2>> points;          ///< where models.h5 has the fields
  std::vector<ModelFields> fields;       ///< per model, for models.h5
  std::vector<ProfileValue> profile_rows;
  MPI_Comm comm;
  ConditionalOStream& pcout;
};

// One model, the same way for each: solve (run() is setup, assembly, solve), write its VTU, sample
// its profiles and its fields at the output points, and report what every model reports.
template <class Problem>
nlohmann::json solve_model(Problem& problem, const std::string& name, const SolverSettings& solver, Outputs& out) {
  Timer timer;
  const auto& r = problem.run();
  const std::string file = problem.output_results(out.out_dir, out.rho_g_h);
  const auto names = Problem::field_names();
  const PointEvaluator fields = problem.field_evaluator(out.rho_g_h);
  const auto rows = sample_profiles(out.tria, out.pile, out.settings.profile_heights, out.settings.profile_points,
                                    name, names, fields, out.rho_g_h, out.comm);
  out.profile_rows.insert(out.profile_rows.end(), rows.begin(), rows.end());
  out.fields.push_back({name, names, Problem::field_units(), evaluate_at_points(out.points, names.size(), fields, out.comm), {}});
  const double wall = timer.wall_time();
  out.pcout << name << ": " << r.n_dofs << " dofs, " << r.solver.iterations << " iterations, base force / weight = "
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
          {"file", fs::path(file).filename().string()}};
}

// Isotropic elasticity under gravity, and the gravity change its displacements are for.
nlohmann::json solve_elastic(const ContinuumSettings& s, const Triangulation2& tria, const PileGeometry&, Outputs& outputs) {
  const ElasticSettings& e = s.elastic_model;
  ElasticProblem problem(tria, e, s.density_kg_per_m2, s.gravity_m_per_s2);
  nlohmann::json j = solve_model(problem, "elastic", e.solver, outputs);
  j["degree"] = e.degree;
  j["plane"] = e.plane == ElasticSettings::Plane::strain ? "strain" : "stress";
  j["base"] = e.base == ElasticSettings::Base::rough ? "rough" : "smooth";
  j["base_reaction_over_weight"] = problem.result().base_reaction_N / problem.result().weight;
  j["youngs_modulus_N_per_m"] = e.youngs_modulus_N_per_m;
  j["poisson_ratio"] = e.poisson_ratio;
  j["gravity_change"] = e.gravity_change;
  // Its displacement and strain are those of this change of g: compare scales them to the DEM's.
  outputs.fields.back().attributes["gravity_change"] = e.gravity_change;
  return j;
}

// The FPA closure with the pile's repose angles, and how well its stress balances gravity.
nlohmann::json solve_fpa(const ContinuumSettings& s, const Triangulation2& tria, const PileGeometry& pile, Outputs& outputs) {
  const FpaSettings& f = s.fpa_model;
  FpaProblem problem(tria, f, s.density_kg_per_m2, s.gravity_m_per_s2, pile.apex_x_m);
  nlohmann::json j = solve_model(problem, "fpa", f.solver, outputs);
  j["degree"] = f.degree;
  j["left_repose_angle_deg"] = f.left_repose_angle_deg;
  j["right_repose_angle_deg"] = f.right_repose_angle_deg;
  j["repose_angle_source"] = f.angles_from_dem ? "dem" : "scene";
  j["surface"] = f.surface == FpaSettings::Surface::strong ? "strong" : "weak";
  j["minor_axis_fixed_area_fraction"] = problem.result().minor_axis_fixed_area_fraction;
  j["outflow_surface_length_fraction"] = problem.result().outflow_surface_length_fraction;
  // With the free surface imposed strongly, least squares makes 1 - base force / weight equal
  // to the square of this exactly (docs/CONTINUUM.md): any misfit shows as missing weight.
  const double e = problem.result().residual_norm * std::sqrt(pile.area_m2) / problem.result().weight;
  j["equilibrium_residual_over_weight"] = e;
  const double carried = problem.result().base_force_N / problem.result().weight;
  if (!(carried >= 0.99)) {  // NaN included
    std::ostringstream w;
    w << "the FPA's base carries " << carried << " of the weight ("
      << (f.surface == FpaSettings::Surface::strong ? "1 - e^2, " : "") << "e = " << e << "); "
      << 100 * problem.result().outflow_surface_length_fraction
      << " % of the free surface is steeper than a characteristic. A smoother outline (mesh.outline_smoothing_grains), a "
         "finer mesh or degree 2 carries more";
    j["warning"] = w.str();
    if (Utilities::MPI::this_mpi_process(outputs.comm) == 0) std::cerr << "warning: " << w.str() << "\n";
  }
  return j;
}

// The models `pilelab solve` knows, in the order it solves them: the scene's switch for each
// (continuum.models) and its solve, which adds its own settings and figures to what every model
// reports (solve_model). A third model is its problem class, its table in settings.cpp and one
// line here.
struct ModelEntry {
  const char* name;
  bool ContinuumSettings::*wanted;
  nlohmann::json (*solve)(const ContinuumSettings&, const Triangulation2&, const PileGeometry&, Outputs&);
};
const ModelEntry model_registry[] = {
    {"elastic", &ContinuumSettings::elastic, solve_elastic},
    {"fpa", &ContinuumSettings::fpa, solve_fpa},
};

// The models of the settings on their mesh, and every file they write, on the ranks of comm.
nlohmann::json solve_models(const ContinuumSettings& s, const SolveOptions& o, MPI_Comm comm) {
  const bool root = Utilities::MPI::this_mpi_process(comm) == 0;
  ConditionalOStream pcout(std::cout, root && !o.quiet);
  Timer total;
  on_rank0(comm, [&] { fs::create_directories(o.out_dir); });

  const std::string msh = find_or_make_mesh(s, o, comm, pcout);
  auto tria = make_triangulation(comm);
  read_pile_mesh(msh, *tria);
  const PileGeometry pile = measure_pile(*tria);
  const double rho_g = s.density_kg_per_m2 * s.gravity_m_per_s2, rho_g_h = rho_g * pile.height_m;
  pcout << "continuum: " << msh << ": " << tria->n_global_active_cells() << " triangles, height " << pile.height_m
        << " m, apex at x = " << pile.apex_x_m << " m, " << Utilities::MPI::n_mpi_processes(comm) << " MPI rank(s)\n";

  nlohmann::json report = {{"mesh_file", msh},
                           {"mpi_ranks", Utilities::MPI::n_mpi_processes(comm)},
                           {"cells", tria->n_global_active_cells()},
                           {"pile_height_m", pile.height_m},
                           {"apex_x_m", pile.apex_x_m},
                           {"area_m2", pile.area_m2},
                           {"density_kg_per_m2", s.density_kg_per_m2},
                           {"gravity_m_per_s2", s.gravity_m_per_s2},
                           {"rho_g_h_N_per_m", rho_g_h},
                           {"stress_sign", "stress_* tension positive; pressure, principal stresses and profile sigma_* compressive positive"}};
  Outputs outputs{o.out_dir, *tria, pile, s, rho_g_h, model_output_points(*tria), {}, {}, comm, pcout};
  for (const ModelEntry& model : model_registry)
    if (s.*model.wanted) report[model.name] = model.solve(s, *tria, pile, outputs);
  report["wall_time_s"] = total.wall_time();
  on_rank0(comm, [&] {
    write_profile_values((fs::path(o.out_dir) / "profiles.csv").string(), outputs.profile_rows);
    write_models_h5((fs::path(o.out_dir) / "models.h5").string(), *tria, outputs.points, outputs.fields, rho_g_h,
                    pile.height_m);
    write_report_section((fs::path(o.out_dir) / "report.json").string(), "continuum", report);
  });
  return report;
}

}  // namespace

nlohmann::json run_solve(const SolveOptions& o) {
  // A folder that cannot be written is found before anything is computed, as the other stages
  // find it (every rank probes with a file of its own).
  prepare_output_directory(o.out_dir);
  SceneReader reader = SceneReader::from_file(o.scene_path);
  const std::string scene_dir = fs::path(o.scene_path).parent_path().string();
  ContinuumSettings s = read_continuum_scene(reader, scene_dir.empty() ? "." : scene_dir);
  // The FPA's angles: the scene's; or the DEM's, handed over by `pilelab run` (one pile or an
  // ensemble's mean) or, for `pilelab solve` with repose_angle_source = "dem", read from the
  // DEM's report section.
  const bool angles_handed_over = apply_measured_pile(o.measured, reader, s);
  if (s.fpa && s.fpa_model.angles_from_dem && !angles_handed_over)
    apply_dem_repose_angles(s.fpa_model, (fs::path(o.out_dir) / "report.json").string());
  return solve_models(s, o, MPI_COMM_WORLD);
}

nlohmann::json solve_gravity_change(const GravityChangeProblem& p, const std::string& out_dir) {
  ContinuumSettings s;
  s.fpa = false;
  s.mesh_file = p.mesh_file;
  s.density_kg_per_m2 = p.density_kg_per_m2;
  s.gravity_m_per_s2 = p.gravity_m_per_s2;
  ElasticSettings& e = s.elastic_model;
  const double lambda = p.lame_lambda_N_per_m, mu = p.shear_modulus_N_per_m;
  e.poisson_ratio = lambda / (2.0 * (lambda + mu));
  e.youngs_modulus_N_per_m = mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu);
  e.gravity_change = p.gravity_change;
  SolveOptions o;
  o.scene_path = "(the closed loop of the fit)";
  o.out_dir = out_dir;
  o.quiet = true;
  return solve_models(s, o, MPI_COMM_SELF);
}

struct ParallelContext::Impl {
  int argc = 1;
  char name[8] = "pilelab";
  char* args[2] = {name, nullptr};
  char** argv = args;
  Utilities::MPI::MPI_InitFinalize mpi{argc, argv, 1};
};

ParallelContext::ParallelContext() : impl_(std::make_unique<Impl>()) {}
ParallelContext::~ParallelContext() = default;

void run_solve_command(const SolveOptions& options) {
  // MPI (and PETSc) for this subcommand only; one thread per rank, the ranks do the work.
  int argc = 1;
  char name[] = "pilelab";
  char* args[] = {name, nullptr};
  char** argv = args;
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  run_solve(options);
}

}  // namespace pilelab::continuum
