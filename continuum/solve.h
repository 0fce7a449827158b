#pragma once
// `pilelab solve`: the continuum models of the scene's [continuum] table on the pile
// triangulation. This header is deal.II-free so that the command-line front end compiles fast.
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>


namespace pilelab::continuum {

/// What the stages before the solve measured, for the [continuum] keys the scene leaves open
/// (`pilelab run` hands them over): the pile's bulk density and gravity (coarse), and its repose
/// angles (the DEM, or an ensemble's mean), which the FPA takes where both lie in (0, 45).
struct MeasuredPile {
  std::optional<double> density_kg_per_m2, gravity_m_per_s2;
  std::optional<double> left_repose_angle_deg, right_repose_angle_deg;
  /// The DEM poured the pile but could not measure a flank's angle (too few surface bins): a
  /// model that wanted the measured angles says so instead of taking its default silently.
  bool repose_unmeasured = false;
};

struct SolveOptions {
  std::string scene_path;
  std::string out_dir;
  bool quiet = false;
  MeasuredPile measured;  ///< used only where the scene sets nothing
};

/// Solves the models the scene lists and writes OUT/elastic.vtu, OUT/fpa.vtu (.pvtu and pieces
/// under MPI), OUT/profiles.csv and the "continuum" section of OUT/report.json (rank 0 only).
/// Must run inside an MPI context (see run_solve_command). Returns the report section.
nlohmann::json run_solve(const SolveOptions& options);

/// The models of a scene's [continuum] table given as text (continuum.mesh_file naming the
/// mesh), solved on this process alone (MPI_COMM_SELF) so that one rank can call it while the
/// others wait, into out_dir, quietly: what run_solve writes. `source` names the text in errors.
/// MPI and PETSc must be running (ParallelContext, or `pilelab run`'s world). The comparison's
/// closed loops use it (compare/compare_run.h: ModelSolver).
nlohmann::json solve_scene_text(const std::string& text, const std::string& source, const std::string& out_dir);

/// run_solve inside its own MPI (and PETSc) context, for the command-line action: MPI is set
/// up here and torn down on return, so other subcommands never start it.
void run_solve_command(const SolveOptions& options);

/// MPI and PETSc for as long as the object lives, for a process that runs run_solve among other
/// work (`pilelab run`). At most one per process, and not together with run_solve_command.
class ParallelContext {
 public:
  ParallelContext();
  ~ParallelContext();
  ParallelContext(const ParallelContext&) = delete;
  ParallelContext& operator=(const ParallelContext&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pilelab::continuum
