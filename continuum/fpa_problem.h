#pragma once
// The fixed-principal-axes (FPA) model of Wittmer, Cates and Claudin for a pile, solved by a
// least-squares finite element method (docs/CONTINUUM.md has the derivation and the reasons).
//
// The stress alone is unknown. Equilibrium under gravity (tension positive, b = (0, -g)),
//   d_x s_xx + d_y s_xy = 0,   d_x s_xy + d_y s_yy = rho g,
// is closed by fixing the principal axes at +-psi = +-(pi/4 - phi/2) from the vertical on the
// two sides of the vertical axis through the apex. With t = tan(phi) = cot(2 psi) and
// s = +1 right of the axis, -1 left of it, the closure is linear on each side:
//   s_yy = s_xx - 2 s t s_xy.
// We keep s_xx and s_xy as the unknowns, continuous P1 or P2: they are the traction on a
// vertical line, which equilibrium makes continuous across the axis, while s_yy may jump there
// (it does for an asymmetric pile). The problem is hyperbolic with depth as time: the
// characteristics are the principal directions, the free surface carries the data, and the base
// receives whatever arrives (no base condition). We minimise
//   J(s) = || d_x s_xx + d_y s_xy ||^2 + || d_x s_xy + d_y (s_xx - 2 s t s_xy) - rho g ||^2
//          [+ sum_F gamma / h_F || sigma n ||^2_F over free-surface faces F, when weak],
// whose normal equations are symmetric positive definite (De Sterck, Manteuffel, McCormick and
// Olson, SIAM J. Sci. Comput. 26, 2004): no upwinding, no stabilisation parameter, and CG with
// algebraic multigrid or a Cholesky factorisation solve them. By default the traction-free
// surface is imposed exactly: traction-free plus the closure force sigma = 0 on a free surface
// whose slope is not a principal direction (true for 0 < phi < 45 degrees).
#include <memory>
#include <string>
#include <vector>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_tools_cache.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include "continuum/field_output.h"
#include "continuum/linear_solvers.h"
#include "continuum/model_problem.h"
#include "continuum/pile_domain.h"
#include "continuum/settings.h"
#include "continuum/stress_fields.h"

namespace pilelab::continuum {

struct FpaResult : ModelResult {
  double residual_norm = 0;       ///< J(s_h)^(1/2): how far the discrete stress is from equilibrium
  /// Fraction of the area (at quadrature points) where the closure's fixed direction is the
  /// MINOR principal axis: the linear closure fixes the axes, not which is major, and where
  /// p_xy has the other side's sign the most compressive axis is perpendicular to the intended
  /// one (near the axis on the shallower side of an asymmetric pile; docs/CONTINUUM.md).
  double minor_axis_fixed_area_fraction = 0;
  /// Fraction of the free surface's length through which a characteristic (a principal
  /// direction, followed downwards) leaves the pile: a step of the outline steeper than the
  /// characteristic. The stress jumps across the characteristic that re-enters below such a
  /// step, which continuous elements cannot represent (docs/CONTINUUM.md).
  double outflow_surface_length_fraction = 0;
};

class FpaProblem {
 public:
  /// apex_x_m: the axis where the closure changes side.
  FpaProblem(const Triangulation2& tria, const FpaSettings& settings, double density_kg_per_m2,
             double gravity_m_per_s2, double apex_x_m);

  const FpaResult& run();

  /// Compressive-positive stress at p if this rank owns p's cell.
  bool stress_at(const dealii::Point<2>& p, Stress2& stress) const;

  /// L2 error of p_yy along the base (boundary id 1) against exact(x): (int_base (p_yy - exact)^2 dx)^(1/2).
  double base_pressure_error(const std::function<double(double x)>& exact_p_yy) const;
  /// L2 error of the whole stress tensor (xx, yy, xy) over the domain.
  double stress_error(const std::function<Stress2(const dealii::Point<2>&)>& exact) const;

  /// Fields for OUT/models.h5 at a point (names, units: docs/FORMAT.md), in the units and signs
  /// of coarse/'s fields.h5 so that compare/ can put them beside the DEM's.
  static std::vector<std::string> field_names();
  static std::vector<std::string> field_units();
  PointEvaluator field_evaluator(double rho_g_h) const;
  std::string output_results(const std::string& out_dir, double rho_g_h) const;

  const FpaResult& result() const { return result_; }

 private:
  template <class Problem, class Result>
  friend void run_model_steps(Problem&, Result&);
  void setup_system();
  void assemble_system();
  void solve();
  void compute_base_force();

  /// 2 s tan(phi_s) for the side of the axis the cell lies on (decided by its centre).
  double closure_coefficient(const dealii::TriaAccessor<2, 2, 2>& cell) const;
  /// The compressive stress from the unknowns (s_xx, s_xy) with the closure of this cell.
  static Stress2 stress_from(double sxx, double sxy, double k) { return {-sxx, -(sxx - k * sxy), -sxy}; }

  MPI_Comm comm_;
  const Triangulation2& tria_;
  FpaSettings settings_;
  double density_, gravity_, apex_x_;
  dealii::FESystem<2> fe_;
  dealii::DoFHandler<2> dof_handler_;
  dealii::IndexSet owned_, relevant_;
  dealii::AffineConstraints<double> constraints_;
  dealii::PETScWrappers::MPI::SparseMatrix system_matrix_;
  dealii::PETScWrappers::MPI::Vector system_rhs_;
  dealii::PETScWrappers::MPI::Vector solution_;
  std::unique_ptr<dealii::GridTools::Cache<2>> cache_;
  FpaResult result_;
};

}  // namespace pilelab::continuum
