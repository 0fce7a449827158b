#include "continuum/elastic_problem.h"

#include <cmath>
#include <limits>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include "continuum/stress_fields.h"
#include "mesh/pile_mesh.h"

namespace pilelab::continuum {

using namespace dealii;

namespace {
// The displacement gradient at output point q, from the per-component gradients DataOut gives.
Tensor<2, 2> displacement_gradient(const DataPostprocessorInputs::Vector<2>& in, unsigned q) {
  Tensor<2, 2> g;
  for (unsigned c = 0; c < 2; ++c) g[c] = in.solution_gradients[q][c];
  return g;
}
}  // namespace

ElasticProblem::ElasticProblem(const Triangulation2& tria, const ElasticSettings& settings, double density,
                               double gravity)
    : comm_(tria.get_communicator()),
      tria_(tria),
      settings_(settings),
      lambda_(settings.material.lambda_2d(settings.plane == ElasticSettings::Plane::stress)),
      mu_(settings.material.shear_modulus()),
      density_(density),
      gravity_(gravity),
      fe_(FE_SimplexP<2>(settings.degree), 2),
      dof_handler_(tria) {}

void ElasticProblem::set_manufactured(std::shared_ptr<const Function<2>> body_force,
                                      std::shared_ptr<const Function<2>> boundary_displacement) {
  body_force_ = std::move(body_force);
  boundary_displacement_ = std::move(boundary_displacement);
}

SymmetricTensor<2, 2> ElasticProblem::stress(const SymmetricTensor<2, 2>& eps) const {
  return lambda_ * trace(eps) * unit_symmetric_tensor<2>() + 2.0 * mu_ * eps;
}

const ElasticResult& ElasticProblem::run() {
  run_model_steps(*this, result_);
  return result_;
}

// Degrees of freedom, constraints (boundary conditions) and the distributed sparse matrix.
// parallel::shared numbers the dofs so that each rank owns a contiguous range.
void ElasticProblem::setup_system() {
  dof_handler_.distribute_dofs(fe_);
  owned_ = dof_handler_.locally_owned_dofs();
  relevant_ = DoFTools::extract_locally_relevant_dofs(dof_handler_);
  result_.n_dofs = dof_handler_.n_dofs();
  result_.n_cells = tria_.n_global_active_cells();

  const Mapping<2>& mapping = simplex_mapping();
  const FEValuesExtractors::Scalar ux(0), uy(1);
  constraints_.clear();
  constraints_.reinit(relevant_);
  if (boundary_displacement_) {
    for (const auto id : tria_.get_boundary_ids())
      VectorTools::interpolate_boundary_values(mapping, dof_handler_, id, *boundary_displacement_, constraints_);
  } else {
    const Functions::ZeroFunction<2> zero(2);
    if (settings_.base == ElasticSettings::Base::rough)
      VectorTools::interpolate_boundary_values(mapping, dof_handler_, mesh::BoundaryId::base, zero, constraints_);
    else
      VectorTools::interpolate_boundary_values(mapping, dof_handler_, mesh::BoundaryId::base, zero, constraints_, fe_.component_mask(uy));
    bool has_side_wall = false;
    for (const auto id : tria_.get_boundary_ids()) has_side_wall = has_side_wall || id == mesh::BoundaryId::side_wall;
    if (has_side_wall)
      VectorTools::interpolate_boundary_values(mapping, dof_handler_, mesh::BoundaryId::side_wall, zero, constraints_, fe_.component_mask(ux));
    if (settings_.base == ElasticSettings::Base::smooth && !has_side_wall) {
      // Only a horizontal translation is left free: fix u_x at the base vertex nearest the
      // axis. Every rank sees every cell, so all pick the same vertex.
      const double axis = measure_pile(tria_).apex_x_m;
      double best = std::numeric_limits<double>::infinity();
      types::global_dof_index pinned = numbers::invalid_dof_index;
      for (const auto& cell : dof_handler_.active_cell_iterators())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == mesh::BoundaryId::base)
            for (unsigned v = 0; v < 2; ++v) {
              const double d = std::abs(cell->face(f)->vertex(v)[0] - axis);
              if (d < best - 1e-12 * (1 + std::abs(axis))) {
                best = d;
                pinned = cell->face(f)->vertex_dof_index(v, 0);  // component 0 = u_x
              }
            }
      if (relevant_.is_element(pinned) && !constraints_.is_constrained(pinned)) constraints_.add_line(pinned);
    }
  }
  constraints_.close();

  reinit_linear_system(dof_handler_, constraints_, owned_, relevant_, system_matrix_, system_rhs_, solution_);
  cache_ = std::make_unique<GridTools::Cache<2>>(tria_, mapping);
}

// Cell by cell: A_ij = int lambda div(phi_i) div(phi_j) + 2 mu eps(phi_i) : eps(phi_j),
// b_i = int f . phi_i.
void ElasticProblem::local_system(const DoFHandler<2>::active_cell_iterator& cell, FEValues<2>& fe_values,
                                  FullMatrix<double>& cell_matrix, Vector<double>& cell_rhs) const {
  const unsigned n = fe_.n_dofs_per_cell(), nq = fe_values.n_quadrature_points;
  std::vector<SymmetricTensor<2, 2>> eps(n);
  std::vector<double> div(n);
  std::vector<Tensor<1, 2>> phi(n);
  Vector<double> f_value(2);
  const FEValuesExtractors::Vector u(0);
  fe_values.reinit(cell);
  cell_matrix = 0;
  cell_rhs = 0;
  for (unsigned q = 0; q < nq; ++q) {
    for (unsigned i = 0; i < n; ++i) {
      eps[i] = fe_values[u].symmetric_gradient(i, q);
      div[i] = fe_values[u].divergence(i, q);
      phi[i] = fe_values[u].value(i, q);
    }
    Tensor<1, 2> f;
    if (body_force_) {
      body_force_->vector_value(fe_values.quadrature_point(q), f_value);
      f[0] = f_value[0];
      f[1] = f_value[1];
    } else {
      f[1] = -density_ * gravity_;  // gravity along -y
    }
    const double JxW = fe_values.JxW(q);
    for (unsigned i = 0; i < n; ++i) {
      for (unsigned j = 0; j <= i; ++j)
        cell_matrix(i, j) += (lambda_ * div[i] * div[j] + 2.0 * mu_ * (eps[i] * eps[j])) * JxW;
      cell_rhs(i) += (phi[i] * f) * JxW;
    }
  }
  for (unsigned i = 0; i < n; ++i)
    for (unsigned j = i + 1; j < n; ++j) cell_matrix(i, j) = cell_matrix(j, i);
}

// Constraints are applied while copying into the global system.
void ElasticProblem::assemble_system() {
  const QGaussSimplex<2> quadrature(fe_.degree + 1);
  FEValues<2> fe_values(simplex_mapping(), fe_, quadrature,
                        update_values | update_gradients | update_quadrature_points | update_JxW_values);
  const unsigned n = fe_.n_dofs_per_cell();
  FullMatrix<double> cell_matrix(n, n);
  Vector<double> cell_rhs(n);
  std::vector<types::global_dof_index> dofs(n);
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    local_system(cell, fe_values, cell_matrix, cell_rhs);
    cell->get_dof_indices(dofs);
    constraints_.distribute_local_to_global(cell_matrix, cell_rhs, dofs, system_matrix_, system_rhs_);
  }
  system_matrix_.compress(VectorOperation::add);
  system_rhs_.compress(VectorOperation::add);
}

// The rigid-body modes of plane elasticity: the two translations and the rotation
// (-(y - y0), x - x0), evaluated at the support points of the locally owned dofs. Algebraic
// multigrid needs them to build coarse spaces that represent near-rigid motions cheaply
// (deal.II 9.4 has no DoFTools::extract_rigid_body_modes, so they are built here).
std::vector<PETScWrappers::MPI::Vector> ElasticProblem::rigid_body_modes() const {
  std::vector<PETScWrappers::MPI::Vector> modes(3);
  for (auto& m : modes) m.reinit(owned_, comm_);
  const Quadrature<2> support(fe_.get_unit_support_points());
  FEValues<2> fe_values(simplex_mapping(), fe_, support, update_quadrature_points);
  std::vector<types::global_dof_index> dofs(fe_.n_dofs_per_cell());
  const PileGeometry pile = measure_pile(tria_);
  const Point<2> centre(pile.apex_x_m, 0.5 * pile.height_m);  // keeps the rotation mode well scaled
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fe_values.reinit(cell);
    cell->get_dof_indices(dofs);
    for (unsigned i = 0; i < dofs.size(); ++i) {
      if (!owned_.is_element(dofs[i])) continue;
      const unsigned c = fe_.system_to_component_index(i).first;
      const Point<2> x = fe_values.quadrature_point(i);
      modes[c][dofs[i]] = 1.0;
      modes[2][dofs[i]] = c == 0 ? -(x[1] - centre[1]) : (x[0] - centre[0]);
    }
  }
  for (auto& m : modes) m.compress(VectorOperation::insert);
  return modes;
}

void ElasticProblem::solve() {
  PETScWrappers::MPI::Vector x(owned_, comm_);
  result_.solver = solve_spd(system_matrix_, x, system_rhs_, rigid_body_modes(), 2, settings_.solver, "elastic_");
  constraints_.distribute(x);
  solution_ = x;  // ghosted copy for evaluation and output
}

// The vertical force the base carries: int_base p_yy dx with p = -sigma (compressive).
// Global balance says it equals the weight rho g |Omega| (the flanks carry no traction).
void ElasticProblem::compute_base_force() {
  const QGaussSimplex<1> face_quadrature(fe_.degree + 1);
  FEFaceValues<2> fe_face(simplex_mapping(), fe_, face_quadrature, update_gradients | update_JxW_values);
  const FEValuesExtractors::Vector u(0);
  std::vector<SymmetricTensor<2, 2>> eps(face_quadrature.size());
  double fy = 0, fx = 0, area = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    area += cell->measure();
    for (const auto f : cell->face_indices()) {
      if (!cell->face(f)->at_boundary() || cell->face(f)->boundary_id() != mesh::BoundaryId::base) continue;
      fe_face.reinit(cell, f);
      fe_face[u].get_function_symmetric_gradients(solution_, eps);
      for (unsigned q = 0; q < eps.size(); ++q) {
        const Stress2 p = Stress2::from_tension_positive(stress(eps[q]));
        fy += p.yy * fe_face.JxW(q);
        fx += p.xy * fe_face.JxW(q);
      }
    }
  }
  result_.base_force_N = Utilities::MPI::sum(fy, comm_);
  result_.base_shear_force = Utilities::MPI::sum(fx, comm_);
  result_.weight = density_ * gravity_ * Utilities::MPI::sum(area, comm_);

  // The consistent reaction: at a free dof the residual (A u - b)_i vanishes (to the solver's
  // tolerance); the y-translation is in A's kernel, so the residuals' y-components sum to
  // -sum_i b_i = the weight, and the base's constrained y-dofs carry all of it. Summed cell by
  // cell over the cells that own a base y-dof.
  const IndexSet base_y = DoFTools::extract_boundary_dofs(dof_handler_, fe_.component_mask(FEValuesExtractors::Scalar(1)),
                                                          {static_cast<types::boundary_id>(mesh::BoundaryId::base)});
  const QGaussSimplex<2> quadrature(fe_.degree + 1);
  FEValues<2> fe_values(simplex_mapping(), fe_, quadrature,
                        update_values | update_gradients | update_quadrature_points | update_JxW_values);
  const unsigned n = fe_.n_dofs_per_cell();
  FullMatrix<double> cell_matrix(n, n);
  Vector<double> cell_rhs(n), cell_u(n), cell_residual(n);
  std::vector<types::global_dof_index> dofs(n);
  double reaction = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    cell->get_dof_indices(dofs);
    bool touches_base = false;
    for (const auto d : dofs) touches_base = touches_base || (base_y.is_element(d) && constraints_.is_constrained(d));
    if (!touches_base) continue;
    local_system(cell, fe_values, cell_matrix, cell_rhs);
    for (unsigned i = 0; i < n; ++i) cell_u(i) = solution_[dofs[i]];
    cell_matrix.vmult(cell_residual, cell_u);
    for (unsigned i = 0; i < n; ++i)
      if (base_y.is_element(dofs[i]) && constraints_.is_constrained(dofs[i])) reaction += cell_residual(i) - cell_rhs(i);
  }
  result_.base_reaction_N = Utilities::MPI::sum(reaction, comm_);
}

ElasticProblem::Errors ElasticProblem::compute_errors(const Function<2>& exact) const {
  const QGaussSimplex<2> quadrature(fe_.degree + 2);
  FEValues<2> fe_values(simplex_mapping(), fe_, quadrature,
                        update_values | update_gradients | update_quadrature_points | update_JxW_values);
  const FEValuesExtractors::Vector u(0);
  const unsigned nq = quadrature.size();
  std::vector<Tensor<1, 2>> uh(nq);
  std::vector<Tensor<2, 2>> guh(nq);
  double l2 = 0, energy = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fe_values.reinit(cell);
    fe_values[u].get_function_values(solution_, uh);
    fe_values[u].get_function_gradients(solution_, guh);
    for (unsigned q = 0; q < nq; ++q) {
      const Point<2>& x = fe_values.quadrature_point(q);
      Tensor<1, 2> e;
      Tensor<2, 2> ge;
      for (unsigned c = 0; c < 2; ++c) {
        e[c] = uh[q][c] - exact.value(x, c);
        ge[c] = guh[q][c] - exact.gradient(x, c);
      }
      const SymmetricTensor<2, 2> eps = symmetrize(ge);
      l2 += e.norm_square() * fe_values.JxW(q);
      energy += (lambda_ * trace(eps) * trace(eps) + 2.0 * mu_ * (eps * eps)) * fe_values.JxW(q);
    }
  }
  return {std::sqrt(Utilities::MPI::sum(l2, comm_)), std::sqrt(Utilities::MPI::sum(energy, comm_))};
}

bool ElasticProblem::stress_at(const Point<2>& p, Stress2& stress_out, Tensor<1, 2>& u_out,
                               SymmetricTensor<2, 2>& strain_out) const {
  const auto found = GridTools::find_active_cell_around_point(*cache_, p);
  if (found.first.state() != IteratorState::valid || !found.first->is_locally_owned()) return false;
  const typename DoFHandler<2>::active_cell_iterator cell(&tria_, found.first->level(), found.first->index(),
                                                          &dof_handler_);
  const Quadrature<2> at_point(found.second);
  FEValues<2> fe_values(simplex_mapping(), fe_, at_point, update_values | update_gradients);
  fe_values.reinit(cell);
  const FEValuesExtractors::Vector u(0);
  std::vector<Tensor<1, 2>> value(1);
  std::vector<SymmetricTensor<2, 2>> eps(1);
  fe_values[u].get_function_values(solution_, value);
  fe_values[u].get_function_symmetric_gradients(solution_, eps);
  u_out = value[0];
  strain_out = eps[0];
  stress_out = Stress2::from_tension_positive(stress(eps[0]));
  return true;
}

std::vector<std::string> ElasticProblem::field_names() {
  return {"stress_xx",        "stress_yy",         "stress_xy",          "pressure",         "principal_stress_major",
          "principal_stress_minor", "stress_anisotropy", "stress_orientation_deg", "displacement_x", "displacement_y",
          "strain_xx",        "strain_yy",         "strain_xy",          "stress_change_xx", "stress_change_yy",
          "stress_change_xy"};
}

std::vector<std::string> ElasticProblem::field_units() {
  return {"N/m", "N/m", "N/m", "N/m", "N/m", "N/m", "1", "degree", "m", "m", "1", "1", "1", "N/m", "N/m", "N/m"};
}

PointEvaluator ElasticProblem::field_evaluator(double rho_g_h) const {
  const double change = settings_.gravity_change;
  return [this, rho_g_h, change](const Point<2>& p, std::vector<double>& v) {
    Stress2 s;
    Tensor<1, 2> u;
    SymmetricTensor<2, 2> eps;
    if (!stress_at(p, s, u, eps)) return false;
    const Principal pr = principal_stress(s, 1e-9 * rho_g_h);
    v = {-s.xx,        -s.yy,          -s.xy,           0.5 * (s.xx + s.yy), pr.major,           pr.minor,
         pr.anisotropy, pr.orientation_deg, change * u[0], change * u[1],      change * eps[0][0], change * eps[1][1],
         change * eps[0][1], -change * s.xx, -change * s.yy, -change * s.xy};
    return true;
  };
}

std::string ElasticProblem::output_results(const std::string& out_dir, double rho_g_h) const {
  DataOut<2> data_out;
  data_out.set_cell_selection([](const typename Triangulation<2>::cell_iterator& cell) {
    return cell->is_active() && cell->is_locally_owned();
  });
  data_out.attach_dof_handler(dof_handler_);
  const std::vector<DataComponentInterpretation::DataComponentInterpretation> vector2(
      2, DataComponentInterpretation::component_is_part_of_vector);
  data_out.add_data_vector(solution_, std::vector<std::string>(2, "displacement"), DataOut<2>::type_dof_data, vector2);

  // The gravity change is a load rho g * change: by linearity its displacement is change * u.
  PETScWrappers::MPI::Vector change(owned_, comm_);
  change = solution_;
  change *= settings_.gravity_change;
  PETScWrappers::MPI::Vector change_ghosted(owned_, relevant_, comm_);
  change_ghosted = change;
  data_out.add_data_vector(change_ghosted, std::vector<std::string>(2, "displacement_gravity_change"),
                           DataOut<2>::type_dof_data, vector2);

  const StressPostprocessor stresses(
      [this](const DataPostprocessorInputs::Vector<2>& in, unsigned q) {
        return Stress2::from_tension_positive(stress(symmetrize(displacement_gradient(in, q))));
      },
      update_gradients, rho_g_h);
  data_out.add_data_vector(solution_, stresses);

  // Strain (extension positive) and stress increment (N/m, tension positive) of the gravity
  // change, named as coarse/ names the DEM's (snapshot to strain_to).
  class ChangeFields : public DataPostprocessor<2> {
   public:
    ChangeFields(const ElasticProblem& p, double c) : p_(p), c_(c) {}
    void evaluate_vector_field(const DataPostprocessorInputs::Vector<2>& in,
                               std::vector<Vector<double>>& out) const override {
      for (unsigned q = 0; q < out.size(); ++q) {
        const SymmetricTensor<2, 2> eps = symmetrize(displacement_gradient(in, q));
        const SymmetricTensor<2, 2> sigma = p_.stress(eps);
        out[q][0] = c_ * eps[0][0];
        out[q][1] = c_ * eps[1][1];
        out[q][2] = c_ * eps[0][1];
        out[q][3] = c_ * sigma[0][0];
        out[q][4] = c_ * sigma[1][1];
        out[q][5] = c_ * sigma[0][1];
      }
    }
    std::vector<std::string> get_names() const override {
      return {"strain_xx", "strain_yy", "strain_xy", "stress_change_xx", "stress_change_yy", "stress_change_xy"};
    }
    UpdateFlags get_needed_update_flags() const override { return update_gradients; }

   private:
    const ElasticProblem& p_;
    double c_;
  } strain(*this, settings_.gravity_change);
  data_out.add_data_vector(solution_, strain);

  Vector<float> rank(tria_.n_active_cells());
  for (const auto& cell : tria_.active_cell_iterators()) rank(cell->active_cell_index()) = cell->subdomain_id();
  data_out.add_data_vector(rank, "mpi_rank");
  data_out.build_patches(simplex_mapping(), fe_.degree);
  return write_vtu(data_out, out_dir, "elastic", comm_);
}

}  // namespace pilelab::continuum
