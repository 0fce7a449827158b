#pragma once
// What every continuum model shares: the figures each solve reports, and the run() that reads
// like the method (set up, assemble, solve, then the base force), timed step by step. A model
// is a class with setup_system(), assemble_system(), solve(), compute_base_force() and a
// result() deriving from ModelResult; solve.cpp's registry says how the scene selects it and
// what its report adds.
#include <cstddef>

#include <deal.II/base/timer.h>

#include "continuum/linear_solvers.h"

namespace pilelab::continuum {

struct ModelResult {
  std::size_t n_dofs = 0;
  std::size_t n_cells = 0;
  SolveStats solver;
  double setup_s = 0, assemble_s = 0, solve_s = 0;
  double base_force_N = 0;      ///< int_base p_yy dx, compressive positive (N: a 2D force)
  double base_shear_force = 0;  ///< int_base p_xy dx (p = -sigma): 0 for a pile in balance
  double weight = 0;            ///< rho g |Omega|
};

/// The steps of a model's solve, each timed into its result.
template <class Problem, class Result>
void run_model_steps(Problem& problem, Result& result) {
  dealii::Timer timer;
  problem.setup_system();
  result.setup_s = timer.wall_time();
  timer.restart();
  problem.assemble_system();
  result.assemble_s = timer.wall_time();
  timer.restart();
  problem.solve();
  result.solve_s = timer.wall_time();
  problem.compute_base_force();
}

}  // namespace pilelab::continuum
