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
#include "continuum/model_context.h"
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

// What the earlier stages measured, where the scene leaves the key open (the models take
// their own, such as the FPA's angles, from the context).
void apply_measured_pile(const MeasuredPile& m, const SceneReader& reader, ContinuumSettings& s) {
  if (m.density_kg_per_m2 && !reader.has("continuum.density_kg_per_m2")) s.density_kg_per_m2 = *m.density_kg_per_m2;
  if (m.gravity_m_per_s2 && !reader.has("continuum.gravity_m_per_s2")) s.gravity_m_per_s2 = *m.gravity_m_per_s2;
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

}  // namespace

nlohmann::json solver_json(const SolverSettings& s, const SolveStats& st) {
  return {{"solver", s.kind == SolverSettings::Kind::direct ? "direct (MUMPS Cholesky)" : "CG + GAMG"},
          {"tolerance", s.relative_tolerance},
          {"iterations", st.iterations},
          {"relative_residual", st.relative_residual}};
}

void warn(ModelContext& c, nlohmann::json& section, const std::string& warning) {
  section["warning"] = warning;
  if (Utilities::MPI::this_mpi_process(c.comm) == 0) std::cerr << "warning: " << warning << "\n";
}

namespace {

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
  ModelContext context{o.out_dir, *tria, pile, s, o.measured, rho_g_h, model_output_points(*tria), {}, {}, comm, pcout};
  for (const std::string& name : s.models)
    report[name] = find_model(name)->solve(*s.model_settings.at(name), context);
  report["wall_time_s"] = total.wall_time();
  on_rank0(comm, [&] {
    write_profile_values((fs::path(o.out_dir) / "profiles.csv").string(), context.profile_rows);
    write_models_h5((fs::path(o.out_dir) / "models.h5").string(), *tria, context.points, context.fields, rho_g_h,
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
  apply_measured_pile(o.measured, reader, s);
  return solve_models(s, o, MPI_COMM_WORLD);
}

nlohmann::json solve_scene_text(const std::string& text, const std::string& source, const std::string& out_dir) {
  SceneReader reader(text, source);
  const ContinuumSettings s = read_continuum_scene(reader, ".");
  SolveOptions o;
  o.scene_path = source;
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
