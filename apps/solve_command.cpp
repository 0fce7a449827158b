// `pilelab solve`: the continuum models (elasticity, FPA) on the pile triangulation
// (continuum/solve.h). The MPI context is created inside the action, so only this subcommand
// starts MPI; `mpirun -np N pilelab solve ...` runs it in parallel.
#include <memory>

#include <optional>

#include "apps/commands.h"
#include "apps/parallel.h"
#include "common/output_lock.h"
#include "continuum/solve.h"

namespace pilelab::app {

void add_solve_command(CLI::App& app) {
  auto opt = std::make_shared<continuum::SolveOptions>();
  CLI::App* solve = app.add_subcommand(
      "solve", "Solve the continuum models of the scene's [continuum] table (isotropic elasticity under\n"
               "gravity, the FPA closure) on OUT/pile.msh, the scene's mesh_file, or a mesh generated from\n"
               "its [mesh] table. Writes OUT/elastic.vtu, OUT/fpa.vtu (.pvtu + pieces under MPI),\n"
               "OUT/profiles.csv and the \"continuum\" section of OUT/report.json (see docs/FORMAT.md).\n"
               "Runs in parallel under mpirun -np N with the same results.");
  solve->add_option("scene", opt->scene_path, "Scene file (TOML); see docs/SCENES.md")->required()->check(CLI::ExistingFile);
  solve->add_option("-o,--out", opt->out_dir, "Output directory (created if missing)")->required();
  solve->add_flag("-q,--quiet", opt->quiet, "No progress lines");
  solve->final_callback([opt] {
    // Under mpirun every rank runs this: the ranks are one writer, so none takes the lock
    // (each would be refused by the first); a single process takes it.
    std::optional<OutputLock> lock;
    if (!launched_by_mpi()) lock.emplace(opt->out_dir, "pilelab solve " + opt->scene_path);
    continuum::run_solve_command(*opt);
  });
}

}  // namespace pilelab::app
