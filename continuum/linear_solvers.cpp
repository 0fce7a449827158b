#include "continuum/linear_solvers.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <petscksp.h>
#include <petscmat.h>

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

// MUMPS's sparse Cholesky (LL^T without pivoting: the matrices are symmetric positive definite)
// with METIS's nested-dissection ordering, which suits 2D meshes.
void configure_direct(KSP ksp, PC pc, Mat mat) {
  check(MatSetOption(mat, MAT_SPD, PETSC_TRUE), "MatSetOption");
  check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
  check(PCSetType(pc, PCCHOLESKY), "PCSetType");
  check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  check(PCFactorSetUpMatSolverType(pc), "PCFactorSetUpMatSolverType");
  Mat factor;
  check(PCFactorGetMatrix(pc, &factor), "PCFactorGetMatrix");
  check(MatMumpsSetIcntl(factor, 7, 5), "MatMumpsSetIcntl");  // ICNTL(7) = 5: METIS
}

// CG on the unpreconditioned residual, so that the tolerance means |b - A x| <= tol |b| whatever
// the preconditioner and on any number of ranks; GAMG (smoothed aggregation, Chebyshev/Jacobi
// smoothing) as the preconditioner, with the near-null space if there is one.
MatNullSpace configure_cg_gamg(KSP ksp, PC pc, Mat mat, std::vector<PETScWrappers::MPI::Vector>& near_null_space,
                               unsigned block_size, const SolverSettings& settings, MPI_Comm comm) {
  check(KSPSetType(ksp, KSPCG), "KSPSetType");
  check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  check(KSPSetTolerances(ksp, settings.relative_tolerance, 0.0, PETSC_DEFAULT, settings.max_iterations),
        "KSPSetTolerances");
  // The unknowns of a support point are consecutive (FESystem numbers them together and
  // parallel::shared keeps that order), so the matrix is made of block_size x block_size
  // blocks: GAMG aggregates nodes instead of single dofs and keeps its coarse levels sparse.
  if (block_size > 1) check(MatSetBlockSize(mat, block_size), "MatSetBlockSize");
  check(PCSetType(pc, PCGAMG), "PCSetType");
  PetscReal threshold[1] = {0.02};  // drop weak couplings: coarsen along the strong ones
  check(PCGAMGSetThreshold(pc, threshold, 1), "PCGAMGSetThreshold");
  if (near_null_space.empty()) return nullptr;
  orthonormalise(near_null_space);
  std::vector<Vec> vecs;
  for (auto& v : near_null_space) vecs.push_back(v);
  MatNullSpace null_space;
  check(MatNullSpaceCreate(comm, PETSC_FALSE, static_cast<PetscInt>(vecs.size()), vecs.data(), &null_space),
        "MatNullSpaceCreate");
  check(MatSetNearNullSpace(mat, null_space), "MatSetNearNullSpace");
  return null_space;
}

}  // namespace

void reinit_linear_system(const DoFHandler<2>& dof_handler, const AffineConstraints<double>& constraints,
                          const IndexSet& owned, const IndexSet& relevant, PETScWrappers::MPI::SparseMatrix& matrix,
                          PETScWrappers::MPI::Vector& rhs, PETScWrappers::MPI::Vector& solution) {
  const MPI_Comm comm = dof_handler.get_triangulation().get_communicator();
  DynamicSparsityPattern dsp(relevant);
  DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, false);
  SparsityTools::distribute_sparsity_pattern(dsp, owned, comm, relevant);
  matrix.reinit(owned, owned, dsp, comm);
  rhs.reinit(owned, comm);
  solution.reinit(owned, relevant, comm);
}

SolveStats solve_spd(const PETScWrappers::MPI::SparseMatrix& A, PETScWrappers::MPI::Vector& x,
                     const PETScWrappers::MPI::Vector& b, std::vector<PETScWrappers::MPI::Vector> near_null_space,
                     unsigned block_size, const SolverSettings& settings, const std::string& options_prefix) {
  const MPI_Comm comm = A.get_mpi_communicator();
  const bool direct = settings.kind == SolverSettings::Kind::direct;
  Mat mat = A;
  KSP ksp;
  PC pc;
  check(KSPCreate(comm, &ksp), "KSPCreate");
  check(KSPSetOperators(ksp, mat, mat), "KSPSetOperators");
  check(KSPGetPC(ksp, &pc), "KSPGetPC");
  MatNullSpace null_space = nullptr;
  if (direct) configure_direct(ksp, pc, mat);
  else null_space = configure_cg_gamg(ksp, pc, mat, near_null_space, block_size, settings, comm);
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

  SolveStats stats;
  stats.iterations = direct ? 1 : static_cast<unsigned>(its);
  stats.relative_residual = relative_residual(A, x, b);
  if (direct && !(stats.relative_residual < 1e-6))
    throw std::runtime_error("the direct solver (MUMPS Cholesky) failed: relative residual " +
                             std::to_string(stats.relative_residual) + " (is the problem singular?)");
  if (reason < 0 || !std::isfinite(stats.relative_residual))
    throw std::runtime_error("CG with algebraic multigrid did not converge (PETSc reason " + std::to_string(reason) +
                             ", " + std::to_string(its) + " iterations, relative residual " +
                             std::to_string(stats.relative_residual) +
                             "); try solver = \"direct\" or a larger solver_max_iterations");
  return stats;
}

}  // namespace pilelab::continuum
