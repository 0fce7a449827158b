#pragma once
// The two ways the continuum models solve their symmetric positive-definite systems:
// conjugate gradients preconditioned with PETSc's algebraic multigrid (GAMG, smoothed
// aggregation, given the near-null space of the operator when there is one), or MUMPS's
// parallel sparse Cholesky for small problems.
#include <string>
#include <vector>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include "continuum/settings.h"

namespace pilelab::continuum {

struct SolveStats {
  unsigned iterations = 0;       ///< CG iterations; 1 for the direct solver
  double relative_residual = 0;  ///< |b - A x| / |b| on return
};

/// Sizes the distributed system of dof_handler: the sparsity pattern (constraints eliminated)
/// from the locally relevant dofs, exchanged between ranks; rhs on the owned dofs; solution
/// ghosted (owned plus relevant), for evaluation and output.
void reinit_linear_system(const dealii::DoFHandler<2>& dof_handler, const dealii::AffineConstraints<double>& constraints,
                          const dealii::IndexSet& owned, const dealii::IndexSet& relevant,
                          dealii::PETScWrappers::MPI::SparseMatrix& matrix, dealii::PETScWrappers::MPI::Vector& rhs,
                          dealii::PETScWrappers::MPI::Vector& solution);

/// Solves A x = b. near_null_space: vectors spanning the kernel of the unconstrained operator
/// (for elasticity the rigid-body modes), handed to GAMG so that its coarse spaces represent
/// them; may be empty. block_size: unknowns per support point, numbered consecutively.
/// options_prefix: PETSc options with this prefix (e.g. from PETSC_OPTIONS) override the
/// defaults. Throws std::runtime_error if the iteration does not converge.
SolveStats solve_spd(const dealii::PETScWrappers::MPI::SparseMatrix& A, dealii::PETScWrappers::MPI::Vector& x,
                     const dealii::PETScWrappers::MPI::Vector& b,
                     std::vector<dealii::PETScWrappers::MPI::Vector> near_null_space, unsigned block_size,
                     const SolverSettings& settings, const std::string& options_prefix);

}  // namespace pilelab::continuum
