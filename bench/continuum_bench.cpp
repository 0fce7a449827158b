// Throughput of the continuum solvers on a wedge with about a million unknowns:
// elasticity (P2, assemble + solve with CG + GAMG) and the FPA (least squares, same mesh and
// degree) on as many MPI ranks as it is started with. A whole-run benchmark, so a plain MPI
// program rather than a Google Benchmark kernel:
//
//   mpirun -np 2 build/bench/continuum_bench [element_size_m=0.00138] [degree=2] [elastic|fpa|both]
//
// Prints dofs, times and dofs per second (unknowns / (assembly + solve) wall time) per model.
#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <deal.II/base/mpi.h>

#include "continuum/elastic_problem.h"
#include "continuum/models/fpa.h"
#include "continuum/pile_domain.h"
#include "mesh/pile_mesh.h"

using namespace pilelab;

int main(int argc, char** argv) {
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm comm = MPI_COMM_WORLD;
  const bool root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  const double h = argc > 1 ? std::atof(argv[1]) : 0.00138;
  const int degree = argc > 2 ? std::atoi(argv[2]) : 2;
  const std::string which = argc > 3 ? argv[3] : "both";  // elastic, fpa or both

  // The paper's wedge (0.33 m, 28 degrees), meshed once by rank 0.
  const std::string msh = (std::filesystem::temp_directory_path() /
                           ("pilelab_continuum_bench_" + std::to_string(h) + ".msh")).string();
  if (root && !std::filesystem::exists(msh)) {
    mesh::MeshSpec spec;
    spec.kind = mesh::MeshSpec::Kind::wedge;
    spec.element_size_m = h;
    mesh::write_mesh(spec, msh);
  }
  MPI_Barrier(comm);
  auto tria = continuum::make_triangulation(comm);
  continuum::read_pile_mesh(msh, *tria);
  const auto pile = continuum::measure_pile(*tria);
  const int ranks = static_cast<int>(dealii::Utilities::MPI::n_mpi_processes(comm));

  // Solves one model and prints its throughput: unknowns per second of assembly + solve.
  auto time_model = [&](auto& problem, const char* name) {
    const std::clock_t cpu = std::clock();
    const auto& r = problem.run();
    const double cpu_s = double(std::clock() - cpu) / CLOCKS_PER_SEC;
    const double t = r.assemble_s + r.solve_s;
    if (root)
      std::printf("%s P%d: %zu dofs, %zu cells, %d ranks: setup %.2f s, assemble %.2f s, solve %.2f s "
                  "(%u iterations; 1: direct); assemble+solve %.2f s = %.3g dofs/s; base force/weight %.6f; "
                  "CPU time of rank 0 for setup+assemble+solve %.2f s\n",
                  name, degree, r.n_dofs, r.n_cells, ranks, r.setup_s, r.assemble_s, r.solve_s, r.solver.iterations, t,
                  r.n_dofs / t, r.base_force_N / r.weight, cpu_s);
  };
  if (which != "fpa") {
    continuum::ElasticSettings elastic;
    elastic.degree = degree;
    continuum::ElasticProblem problem(*tria, elastic, 4100.0, 9.81);
    time_model(problem, "elastic");
  }
  if (which != "elastic") {
    continuum::FpaSettings fpa;
    fpa.degree = degree;
    continuum::FpaProblem problem(*tria, fpa, 4100.0, 9.81, pile.apex_x_m);
    time_model(problem, "fpa");
  }
  return 0;
}
