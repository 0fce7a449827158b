#pragma once
// Isotropic linear elasticity of the pile under its own weight, in the manner of deal.II's
// step-8 (the equations) and step-40 (the parallel layout).
//
// Find u in V with  a(u, v) = (f, v)  for all v in V, where
//   a(u, v) = int lambda div u div v + 2 mu eps(u) : eps(v) dx,    f = (0, -rho g),
// rho the areal density (kg/m^2), so that in 2D the stresses sigma = lambda tr(eps) I + 2 mu eps
// are forces per unit length (N/m) and lambda, mu are in N/m. Plane strain uses Lame's lambda;
// plane stress the reduced lambda* = 2 lambda mu / (lambda + 2 mu) (IsotropicMaterial::lambda_2d).
// Boundary conditions (ids of mesh/pile_mesh.h): base (1) rough, u = 0, or smooth, u_y = 0;
// side walls (4) smooth, u_x = 0; flanks and top traction-free (natural). A smooth base with no
// side wall leaves a horizontal rigid translation free: it is removed by fixing u_x at the base
// vertex nearest the pile axis (for a symmetric pile that is where u_x = 0 anyway).
#include <memory>
#include <string>
#include <vector>

#include <deal.II/base/function.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_tools_cache.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include "common/isotropic_material.h"
#include "continuum/field_output.h"
#include "continuum/linear_solvers.h"
#include "continuum/model_problem.h"
#include "continuum/pile_domain.h"
#include "continuum/settings.h"
#include "continuum/stress_fields.h"

namespace pilelab::continuum {

/// Isotropic linear elasticity, two-dimensional. Moduli are per unit depth (N/m), like the
/// DEM's contact stiffness; stresses come out in N/m.
struct ElasticSettings : ModelSettings {
  IsotropicMaterial material;  ///< E 1e7 N/m, nu 0.3 by default
  enum class Plane { strain, stress } plane = Plane::strain;
  enum class Base { rough, smooth } base = Base::rough;  ///< rough: u = 0; smooth: u_y = 0
  int degree = 2;                                        ///< FE_SimplexP degree, 1 or 2
  double gravity_change = -0.1;                          ///< relative change of g (DEM relaxation)
  SolverSettings solver;
};

struct ElasticResult : ModelResult {
  /// The vertical force the base's constraints exert, from the residual A u - b at the base's
  /// constrained dofs (the consistent reaction): the weight up to the solver's tolerance on any
  /// mesh, unlike base_force_N, the integral of the cells' stresses along the base (O(h^p)).
  double base_reaction_N = 0;
};

class ElasticProblem {
 public:
  ElasticProblem(const Triangulation2& tria, const ElasticSettings& settings, double density_kg_per_m2,
                 double gravity_m_per_s2);

  /// For verification: replace gravity by a body force (N/m^2, two components) and the
  /// boundary conditions by u = g on the whole boundary. Call before run().
  void set_manufactured(std::shared_ptr<const dealii::Function<2>> body_force,
                        std::shared_ptr<const dealii::Function<2>> boundary_displacement);

  /// setup_system, assemble_system, solve; then the base force.
  const ElasticResult& run();

  struct Errors {
    double l2 = 0;      ///< ||u - u_h||_L2
    double energy = 0;  ///< a(u - u_h, u - u_h)^(1/2)
  };
  /// exact must provide value() and gradient() for both components.
  Errors compute_errors(const dealii::Function<2>& exact) const;

  /// Compressive-positive stress, displacement (full gravity) at p, if this rank owns p's cell.
  bool stress_at(const dealii::Point<2>& p, Stress2& stress, dealii::Tensor<1, 2>& u,
                 dealii::SymmetricTensor<2, 2>& strain) const;

  /// Fields for OUT/models.h5 at a point (names, units: docs/FORMAT.md), in the units and signs
  /// of coarse/'s fields.h5 so that compare/ can put them beside the DEM's.
  static std::vector<std::string> field_names();
  static std::vector<std::string> field_units();
  PointEvaluator field_evaluator(double rho_g_h) const;

  /// OUT/elastic.vtu (or .pvtu): displacement, gravity-change displacement and strain, stresses.
  std::string output_results(const std::string& out_dir, double rho_g_h) const;

  const ElasticResult& result() const { return result_; }
  const dealii::DoFHandler<2>& dof_handler() const { return dof_handler_; }

 private:
  template <class Problem, class Result>
  friend void run_model_steps(Problem&, Result&);
  void setup_system();
  void assemble_system();
  void solve();
  void compute_base_force();
  /// The cell's stiffness matrix and load vector, before constraints.
  void local_system(const dealii::DoFHandler<2>::active_cell_iterator& cell, dealii::FEValues<2>& fe_values,
                    dealii::FullMatrix<double>& cell_matrix, dealii::Vector<double>& cell_rhs) const;
  std::vector<dealii::PETScWrappers::MPI::Vector> rigid_body_modes() const;
  dealii::SymmetricTensor<2, 2> stress(const dealii::SymmetricTensor<2, 2>& strain) const;

  MPI_Comm comm_;
  const Triangulation2& tria_;
  ElasticSettings settings_;
  double lambda_, mu_, density_, gravity_;
  std::shared_ptr<const dealii::Function<2>> body_force_, boundary_displacement_;

  dealii::FESystem<2> fe_;
  dealii::DoFHandler<2> dof_handler_;
  dealii::IndexSet owned_, relevant_;
  dealii::AffineConstraints<double> constraints_;
  dealii::PETScWrappers::MPI::SparseMatrix system_matrix_;
  dealii::PETScWrappers::MPI::Vector system_rhs_;
  dealii::PETScWrappers::MPI::Vector solution_;  ///< ghosted: locally relevant entries
  std::unique_ptr<dealii::GridTools::Cache<2>> cache_;
  ElasticResult result_;
};

}  // namespace pilelab::continuum
