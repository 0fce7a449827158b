#pragma once
// `pilelab solve`: the continuum models of the scene's [continuum] table on the pile
// triangulation. This header is deal.II-free so that the command-line front end compiles fast.
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

namespace pilelab::continuum {

struct SolveOptions {
  std::string scene_path;
  std::string out_dir;
  bool quiet = false;
};

/// Solves the models the scene lists and writes OUT/elastic.vtu, OUT/fpa.vtu (.pvtu and pieces
/// under MPI), OUT/profiles.csv and the "continuum" section of OUT/report.json (rank 0 only).
/// Must run inside an MPI context (see run_solve_command). Returns the report section.
nlohmann::json run_solve(const SolveOptions& options);

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
