#include "continuum/linear_solvers.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/solver_control.h>
#include <petscksp.h>

namespace pilelab::continuum {

using namespace dealii;

namespace {

void check(PetscErrorCode ierr, const char* what) {
  if (ierr != 0) throw std::runtime_error(std::string("PETSc error in ") + what + " (code " + std::to_string(ierr) + ")");
}

// Gram-Schmidt: PETSc wants an orthonormal basis for a (near) null space.
void orthonormalise(std::vector<PETScWrappers::MPI::Vector>& v) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) v[i].add(-(v[i] * v[j]), v[j]);
    const double norm = v[i].l2_norm();
    if (norm > 0) v[i] /= norm;
  }
}

double relative_residual(const PETScWrappers::MPI::SparseMatrix& A, const PETScWrappers::MPI::Vector& x,
                         const PETScWrappers::MPI::Vector& b) {
  PETScWrappers::MPI::Vector r(b);
  A.vmult(r, x);
  r.sadd(-1.0, 1.0, b);  // r = b - A x
  const double bnorm = b.l2_norm();
  return bnorm > 0 ? r.l2_norm() / bnorm : r.l2_norm();
}

}  // namespace

SolveStats solve_spd(const PETScWrappers::MPI::SparseMatrix& A, PETScWrappers::MPI::Vector& x,
                     const PETScWrappers::MPI::Vector& b, std::vector<PETScWrappers::MPI::Vector> near_null_space,
                     unsigned block_size, const SolverSettings& settings, const std::string& options_prefix) {
  SolveStats stats;
  const MPI_Comm comm = A.get_mpi_communicator();
  if (settings.kind == SolverSettings::Kind::direct) {
    // MUMPS in symmetric mode: an LDL^T factorisation, exact up to round-off.
    SolverControl control(1, 0);
    PETScWrappers::SparseDirectMUMPS solver(control, comm);
    solver.set_symmetric_mode(true);
    solver.solve(A, x, b);
    stats.iterations = 1;
    stats.relative_residual = relative_residual(A, x, b);
    return stats;
  }

  // CG on the unpreconditioned residual, so that the tolerance means |b - A x| <= tol |b|
  // whatever the preconditioner, and the same on any number of ranks.
  Mat mat = A;
  KSP ksp;
  PC pc;
  check(KSPCreate(comm, &ksp), "KSPCreate");
  check(KSPSetOperators(ksp, mat, mat), "KSPSetOperators");
  check(KSPSetType(ksp, KSPCG), "KSPSetType");
  check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  check(KSPSetTolerances(ksp, settings.relative_tolerance, 0.0, PETSC_DEFAULT, settings.max_iterations),
        "KSPSetTolerances");
  check(KSPSetInitialGuessNonzero(ksp, PETSC_FALSE), "KSPSetInitialGuessNonzero");
  check(KSPGetPC(ksp, &pc), "KSPGetPC");
  // The unknowns of a support point are consecutive (FESystem numbers them together and
  // parallel::shared keeps that order), so the matrix is made of block_size x block_size
  // blocks: GAMG aggregates nodes instead of single dofs and keeps its coarse levels sparse.
  if (block_size > 1) check(MatSetBlockSize(mat, block_size), "MatSetBlockSize");
  check(PCSetType(pc, PCGAMG), "PCSetType");
  MatNullSpace null_space = nullptr;
  if (!near_null_space.empty()) {
    orthonormalise(near_null_space);
    std::vector<Vec> vecs;
    for (auto& v : near_null_space) vecs.push_back(v);
    check(MatNullSpaceCreate(comm, PETSC_FALSE, static_cast<PetscInt>(vecs.size()), vecs.data(), &null_space),
          "MatNullSpaceCreate");
    check(MatSetNearNullSpace(mat, null_space), "MatSetNearNullSpace");
  }
  // Smoothed aggregation with Chebyshev/Jacobi smoothing (GAMG's defaults for SPD problems);
  // a threshold drops weak couplings so that coarsening follows the strong ones.
  PetscReal threshold[1] = {0.02};
  check(PCGAMGSetThreshold(pc, threshold, 1), "PCGAMGSetThreshold");
  // Expert tuning from the environment, e.g. PETSC_OPTIONS="-fpa_pc_type hypre" (docs/CONTINUUM.md).
  check(KSPSetOptionsPrefix(ksp, options_prefix.c_str()), "KSPSetOptionsPrefix");
  check(KSPSetFromOptions(ksp), "KSPSetFromOptions");
  check(KSPSetUp(ksp), "KSPSetUp");
  check(KSPSolve(ksp, b, x), "KSPSolve");
  PetscInt its = 0;
  KSPConvergedReason reason;
  check(KSPGetIterationNumber(ksp, &its), "KSPGetIterationNumber");
  check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
  if (null_space) {
    MatSetNearNullSpace(mat, nullptr);
    MatNullSpaceDestroy(&null_space);
  }
  KSPDestroy(&ksp);
  stats.iterations = static_cast<unsigned>(its);
  stats.relative_residual = relative_residual(A, x, b);
  if (reason < 0 || !std::isfinite(stats.relative_residual))
    throw std::runtime_error("CG with algebraic multigrid did not converge (PETSc reason " + std::to_string(reason) +
                             ", " + std::to_string(its) + " iterations, relative residual " +
                             std::to_string(stats.relative_residual) +
                             "); try solver = \"direct\" or a larger solver_max_iterations");
  return stats;
}

}  // namespace pilelab::continuum
