#pragma once
// Stress-only closures of a pile (FPA, OSL, ...), solved by a least-squares finite element
// method (docs/CONTINUUM.md has the derivation and the reasons).
//
// The stress alone is unknown. Equilibrium under gravity (tension positive, b = (0, -g)),
//   d_x s_xx + d_y s_xy = 0,   d_x s_xy + d_y s_yy = rho g,
// is closed by a linear relation between the stresses on each side of the vertical axis
// through the apex,
//   s_yy = c_xx s_xx + c_xy s_xy,
// whose two constants per side the model gives (LinearClosure): the fixed principal axes of
// Wittmer, Cates and Claudin (models/fpa.h), the oriented stress linearity of Wittmer, Claudin,
// Cates and Bouchaud (models/osl.h). We keep s_xx and s_xy as the unknowns, continuous P1 or
// P2: they are the traction on a vertical line, which equilibrium makes continuous across the
// axis, while s_yy may jump there (it does for an asymmetric pile). The problem is hyperbolic
// with depth as time where c_xy^2 + 4 c_xx > 0: its characteristics have the slopes
// dy/dx = m with m^2 - c_xy m - c_xx = 0, the free surface carries the data, and the base
// receives whatever arrives (no base condition). We minimise
//   J(s) = || d_x s_xx + d_y s_xy ||^2 + || d_x s_xy + d_y (c_xx s_xx + c_xy s_xy) - rho g ||^2
//          [+ sum_F gamma / h_F || sigma n ||^2_F over free-surface faces F, when weak],
// whose normal equations are symmetric positive definite (De Sterck, Manteuffel, McCormick and
// Olson, SIAM J. Sci. Comput. 26, 2004): no upwinding, no stabilisation parameter, and CG with
// algebraic multigrid or a Cholesky factorisation solve them. By default the traction-free
// surface is imposed exactly: traction-free plus the closure force sigma = 0 on a free surface
// that is not a characteristic.
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

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

/// The numerical settings every closure shares ([continuum.<model>] keys degree, surface,
/// surface_weight and the solver's).
struct ClosureSettings : ModelSettings {
  int degree = 1;
  /// Traction-free flanks: "strong" imposes sigma = 0 there (what traction-free plus the
  /// closure imply, see docs/CONTINUUM.md), "weak" adds surface_weight/h_F * |sigma n|^2 on
  /// the flanks to the least-squares functional.
  enum class Surface { strong, weak } surface = Surface::strong;
  double surface_weight = 10.0;
  /// Direct by default: the least-squares matrix of a hyperbolic operator is strongly
  /// anisotropic along the characteristics, which algebraic multigrid handles poorly
  /// (docs/CONTINUUM.md has the iteration counts); MUMPS's Cholesky factorisation does not care.
  SolverSettings solver{SolverSettings::Kind::direct};
};

/// Reads the keys of ClosureSettings from a closure model's table.
void read_closure_settings(ModelTable& table, ClosureSettings& s);

/// s_yy = xx s_xx + xy s_xy (tension positive) on each side of the apex.
struct LinearClosure {
  struct Side {
    double xx = 1.0, xy = 0.0;
    /// The slopes dy/dx of the two characteristics, roots of m^2 - xy m - xx = 0; NaN if the
    /// side is not hyperbolic (xy^2 + 4 xx <= 0).
    std::array<double, 2> characteristic_slopes() const;
  };
  Side left, right;
};

struct ClosureResult : ModelResult {
  double residual_norm = 0;       ///< J(s_h)^(1/2): how far the discrete stress is from equilibrium
  /// Fraction of the area (at quadrature points) where p_xy has the sign of the side (p_xy > 0
  /// right of the apex), the opposite of what a pile's weight leaning outwards gives. For the
  /// FPA this is where the closure's fixed direction is the MINOR principal axis: the linear
  /// closure fixes the axes, not which is major (near the axis on the shallower side of an
  /// asymmetric pile; docs/CONTINUUM.md).
  double reversed_shear_area_fraction = 0;
  /// Fraction of the free surface's length through which a characteristic (followed
  /// downwards) leaves the pile: a step of the outline steeper than the characteristic. The
  /// stress jumps across the characteristic that re-enters below such a step, which continuous
  /// elements cannot represent (docs/CONTINUUM.md).
  double outflow_surface_length_fraction = 0;
};

struct ClosureResult;
struct ModelContext;
/// What every closure model adds to its report section: its degree and surface condition, the
/// outflow fraction, the equilibrium residual, and a warning where its base carries less than
/// 0.99 of the weight. `label` names the model in the warning ("FPA", "OSL").
void report_closure(const ClosureSettings& s, const ClosureResult& r, const std::string& label, ModelContext& c,
                    nlohmann::json& section);

class ClosureProblem {
 public:
  /// name: the model's (its VTU file); apex_x_m: the axis where the closure changes side.
  ClosureProblem(std::string name, const Triangulation2& tria, const ClosureSettings& settings,
                 const LinearClosure& closure, double density_kg_per_m2, double gravity_m_per_s2, double apex_x_m);

  const ClosureResult& run();

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

  const ClosureResult& result() const { return result_; }

 private:
  template <class Problem, class Result>
  friend void run_model_steps(Problem&, Result&);
  void setup_system();
  void assemble_system();
  void solve();
  void compute_base_force();

  /// The closure of the side of the axis the cell lies on (decided by its centre).
  bool right_of_axis(const dealii::TriaAccessor<2, 2, 2>& cell) const { return cell.center()[0] > apex_x_; }
  const LinearClosure::Side& closure_of(const dealii::TriaAccessor<2, 2, 2>& cell) const {
    return right_of_axis(cell) ? closure_.right : closure_.left;
  }
  /// The compressive stress from the unknowns (s_xx, s_xy) with the closure of this cell.
  static Stress2 stress_from(double sxx, double sxy, const LinearClosure::Side& c) {
    return {-sxx, -(c.xx * sxx + c.xy * sxy), -sxy};
  }

  std::string name_;
  MPI_Comm comm_;
  const Triangulation2& tria_;
  ClosureSettings settings_;
  LinearClosure closure_;
  double density_, gravity_, apex_x_;
  dealii::FESystem<2> fe_;
  dealii::DoFHandler<2> dof_handler_;
  dealii::IndexSet owned_, relevant_;
  dealii::AffineConstraints<double> constraints_;
  dealii::PETScWrappers::MPI::SparseMatrix system_matrix_;
  dealii::PETScWrappers::MPI::Vector system_rhs_;
  dealii::PETScWrappers::MPI::Vector solution_;
  std::unique_ptr<dealii::GridTools::Cache<2>> cache_;
  ClosureResult result_;
};

}  // namespace pilelab::continuum
