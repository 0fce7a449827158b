#include "continuum/closure_problem.h"

#include "mesh/pile_mesh.h"  // mesh::BoundaryId

#include <sstream>

#include "continuum/model_context.h"

#include <cmath>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

namespace pilelab::continuum {

using namespace dealii;

namespace {
// Free-surface boundary ids (mesh/pile_mesh.h): left and right flank, top of a block.
bool is_free_surface(types::boundary_id id) {
  return id == mesh::BoundaryId::left_flank || id == mesh::BoundaryId::right_flank || id == mesh::BoundaryId::top;
}
}  // namespace

std::array<double, 2> LinearClosure::Side::characteristic_slopes() const {
  const double d = xy * xy + 4.0 * xx;
  if (!(d > 0)) return {NAN, NAN};
  return {0.5 * (xy + std::sqrt(d)), 0.5 * (xy - std::sqrt(d))};
}

void read_closure_settings(ModelTable& t, ClosureSettings& s) {
  SceneReader& r = t.reader();
  s.degree = static_cast<int>(r.get_int(t.key("degree"), s.degree, 1, 2));
  s.surface = r.get_choice(t.key("surface"), "strong", {"strong", "weak"}) == "weak" ? ClosureSettings::Surface::weak
                                                                                    : ClosureSettings::Surface::strong;
  s.surface_weight = r.get_double(t.key("surface_weight"), s.surface_weight, Range::positive());
  s.solver = read_solver(t, s.solver);
}

void report_closure(const ClosureSettings& s, const ClosureResult& r, const std::string& label, ModelContext& c,
                    nlohmann::json& j) {
  j["degree"] = s.degree;
  j["surface"] = s.surface == ClosureSettings::Surface::strong ? "strong" : "weak";
  j["outflow_surface_length_fraction"] = r.outflow_surface_length_fraction;
  // With the free surface imposed strongly, least squares makes 1 - base force / weight equal
  // to the square of this exactly (docs/CONTINUUM.md): any misfit shows as missing weight.
  const double e = r.residual_norm * std::sqrt(c.pile.area_m2) / r.weight;
  j["equilibrium_residual_over_weight"] = e;
  const double carried = r.base_force_N / r.weight;
  if (!(carried >= 0.99)) {  // NaN included
    std::ostringstream w;
    w << "the " << label << "'s base carries " << carried << " of the weight ("
      << (s.surface == ClosureSettings::Surface::strong ? "1 - e^2, " : "") << "e = " << e << "); "
      << 100 * r.outflow_surface_length_fraction
      << " % of the free surface is steeper than a characteristic. A smoother outline (mesh.outline_smoothing_grains), a "
         "finer mesh or degree 2 carries more";
    warn(c, j, w.str());
  }
}

ClosureProblem::ClosureProblem(std::string name, const Triangulation2& tria, const ClosureSettings& settings,
                               const LinearClosure& closure, double density, double gravity, double apex_x)
    : name_(std::move(name)),
      comm_(tria.get_communicator()),
      tria_(tria),
      settings_(settings),
      closure_(closure),
      density_(density),
      gravity_(gravity),
      apex_x_(apex_x),
      fe_(FE_SimplexP<2>(settings.degree), 2),
      dof_handler_(tria) {}

const ClosureResult& ClosureProblem::run() {
  run_model_steps(*this, result_);
  return result_;
}

void ClosureProblem::setup_system() {
  dof_handler_.distribute_dofs(fe_);
  owned_ = dof_handler_.locally_owned_dofs();
  relevant_ = DoFTools::extract_locally_relevant_dofs(dof_handler_);
  result_.n_dofs = dof_handler_.n_dofs();
  result_.n_cells = tria_.n_global_active_cells();

  // Strongly imposed free surface: s_xx = s_xy = 0 there (then s_yy = 0 too, by the closure).
  // This is the complete inflow data of the hyperbolic problem; the base gets nothing.
  constraints_.clear();
  constraints_.reinit(relevant_);
  if (settings_.surface == ClosureSettings::Surface::strong)
    for (const auto id : tria_.get_boundary_ids())
      if (is_free_surface(id))
        VectorTools::interpolate_boundary_values(simplex_mapping(), dof_handler_, id, Functions::ZeroFunction<2>(2),
                                                 constraints_);
  constraints_.close();

  reinit_linear_system(dof_handler_, constraints_, owned_, relevant_, system_matrix_, system_rhs_, solution_);
  cache_ = std::make_unique<GridTools::Cache<2>>(tria_, simplex_mapping());
}

// The normal equations of J: with the two first-order residual operators
//   L1 s = d_x s_xx + d_y s_xy,   L2 s = d_x s_xy + c_xx d_y s_xx + c_xy d_y s_xy,
// A_ij = int L1 phi_i L1 phi_j + L2 phi_i L2 phi_j,   b_i = int rho g L2 phi_i,
// plus, for the weak surface, gamma/h_F int_F (sigma(phi_i) n) . (sigma(phi_j) n).
void ClosureProblem::assemble_system() {
  const QGaussSimplex<2> quadrature(fe_.degree + 1);
  FEValues<2> fe_values(simplex_mapping(), fe_, quadrature, update_gradients | update_JxW_values);
  const QGaussSimplex<1> face_quadrature(fe_.degree + 1);
  FEFaceValues<2> fe_face(simplex_mapping(), fe_, face_quadrature,
                          update_values | update_normal_vectors | update_JxW_values);
  const unsigned n = fe_.n_dofs_per_cell(), nq = quadrature.size();
  FullMatrix<double> cell_matrix(n, n);
  Vector<double> cell_rhs(n);
  std::vector<types::global_dof_index> dofs(n);
  std::vector<double> L1(n), L2(n);
  std::vector<Tensor<1, 2>> traction(n);
  const FEValuesExtractors::Scalar sxx(0), sxy(1);
  const double rho_g = density_ * gravity_;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fe_values.reinit(cell);
    const LinearClosure::Side& c = closure_of(*cell);
    cell_matrix = 0;
    cell_rhs = 0;
    for (unsigned q = 0; q < nq; ++q) {
      for (unsigned i = 0; i < n; ++i) {
        const Tensor<1, 2> g_xx = fe_values[sxx].gradient(i, q), g_xy = fe_values[sxy].gradient(i, q);
        L1[i] = g_xx[0] + g_xy[1];
        L2[i] = g_xy[0] + c.xx * g_xx[1] + c.xy * g_xy[1];
      }
      const double JxW = fe_values.JxW(q);
      for (unsigned i = 0; i < n; ++i) {
        for (unsigned j = 0; j <= i; ++j) cell_matrix(i, j) += (L1[i] * L1[j] + L2[i] * L2[j]) * JxW;
        cell_rhs(i) += rho_g * L2[i] * JxW;
      }
    }
    if (settings_.surface == ClosureSettings::Surface::weak)
      for (const auto f : cell->face_indices()) {
        if (!cell->face(f)->at_boundary() || !is_free_surface(cell->face(f)->boundary_id())) continue;
        fe_face.reinit(cell, f);
        const double weight = settings_.surface_weight / cell->face(f)->diameter();
        for (unsigned q = 0; q < face_quadrature.size(); ++q) {
          const Tensor<1, 2> nrm = fe_face.normal_vector(q);
          for (unsigned i = 0; i < n; ++i) {
            const double a = fe_face[sxx].value(i, q), b = fe_face[sxy].value(i, q);
            // sigma n with the closure's s_yy
            traction[i][0] = a * nrm[0] + b * nrm[1];
            traction[i][1] = b * nrm[0] + (c.xx * a + c.xy * b) * nrm[1];
          }
          for (unsigned i = 0; i < n; ++i)
            for (unsigned j = 0; j <= i; ++j)
              cell_matrix(i, j) += weight * (traction[i] * traction[j]) * fe_face.JxW(q);
        }
      }
    for (unsigned i = 0; i < n; ++i)
      for (unsigned j = i + 1; j < n; ++j) cell_matrix(i, j) = cell_matrix(j, i);
    cell->get_dof_indices(dofs);
    constraints_.distribute_local_to_global(cell_matrix, cell_rhs, dofs, system_matrix_, system_rhs_);
  }
  system_matrix_.compress(VectorOperation::add);
  system_rhs_.compress(VectorOperation::add);
}

void ClosureProblem::solve() {
  PETScWrappers::MPI::Vector x(owned_, comm_);
  result_.solver = solve_spd(system_matrix_, x, system_rhs_, {}, 2, settings_.solver, name_ + "_");
  constraints_.distribute(x);
  solution_ = x;
}

// Base force (as for elasticity) and the size of the residual J(s_h)^(1/2).
void ClosureProblem::compute_base_force() {
  const QGaussSimplex<1> face_quadrature(fe_.degree + 1);
  FEFaceValues<2> fe_face(simplex_mapping(), fe_, face_quadrature, update_values | update_JxW_values);
  const QGaussSimplex<2> quadrature(fe_.degree + 1);
  FEValues<2> fe_values(simplex_mapping(), fe_, quadrature, update_values | update_gradients | update_JxW_values);
  std::vector<Vector<double>> values(face_quadrature.size(), Vector<double>(2));
  std::vector<Vector<double>> cell_values(quadrature.size(), Vector<double>(2));
  std::vector<std::vector<Tensor<1, 2>>> grads(quadrature.size(), std::vector<Tensor<1, 2>>(2));
  const double rho_g = density_ * gravity_;
  double fy = 0, fx = 0, area = 0, J = 0, reversed_area = 0, surface = 0, outflow = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    area += cell->measure();
    // Free-surface faces through which a characteristic leaves the pile: a face whose outward
    // normal has a positive component along either characteristic, followed downwards.
    for (const auto f : cell->face_indices()) {
      if (!cell->face(f)->at_boundary() || !is_free_surface(cell->face(f)->boundary_id())) continue;
      const Point<2> a = cell->face(f)->vertex(0), b = cell->face(f)->vertex(1);
      Tensor<1, 2> n;
      n[0] = b[1] - a[1];
      n[1] = a[0] - b[0];
      if (n * (cell->face(f)->center() - cell->center()) < 0) n = -n;  // outward
      const double length = n.norm();
      surface += length;
      const bool right = cell->face(f)->center()[0] > apex_x_;
      for (const double m : (right ? closure_.right : closure_.left).characteristic_slopes()) {
        const double scale = (m >= 0 ? -1.0 : 1.0) / std::sqrt(1 + m * m);  // (1, m) turned downwards
        if (scale * (n[0] + m * n[1]) > 1e-12 * length) {
          outflow += length;
          break;
        }
      }
    }
    const LinearClosure::Side& c = closure_of(*cell);
    fe_values.reinit(cell);
    fe_values.get_function_gradients(solution_, grads);
    fe_values.get_function_values(solution_, cell_values);
    for (unsigned q = 0; q < quadrature.size(); ++q) {
      const double r1 = grads[q][0][0] + grads[q][1][1];
      const double r2 = grads[q][1][0] + c.xx * grads[q][0][1] + c.xy * grads[q][1][1] - rho_g;
      J += (r1 * r1 + r2 * r2) * fe_values.JxW(q);
      // A pile's weight leaning outwards gives p_xy the sign of -side (p_xy <= 0 right of the
      // apex); for the FPA, with the other sign its closure holds with the axes swapped.
      const Stress2 p = stress_from(cell_values[q][0], cell_values[q][1], c);
      if ((right_of_axis(*cell) ? p.xy : -p.xy) > 0) reversed_area += fe_values.JxW(q);
    }
    for (const auto f : cell->face_indices()) {
      if (!cell->face(f)->at_boundary() || cell->face(f)->boundary_id() != mesh::BoundaryId::base) continue;
      fe_face.reinit(cell, f);
      fe_face.get_function_values(solution_, values);
      for (unsigned q = 0; q < values.size(); ++q) {
        const Stress2 p = stress_from(values[q][0], values[q][1], c);
        fy += p.yy * fe_face.JxW(q);
        fx += p.xy * fe_face.JxW(q);
      }
    }
  }
  result_.base_force_N = Utilities::MPI::sum(fy, comm_);
  result_.base_shear_force = Utilities::MPI::sum(fx, comm_);
  result_.weight = rho_g * Utilities::MPI::sum(area, comm_);
  result_.residual_norm = std::sqrt(Utilities::MPI::sum(J, comm_));
  result_.reversed_shear_area_fraction = Utilities::MPI::sum(reversed_area, comm_) / Utilities::MPI::sum(area, comm_);
  const double surface_length = Utilities::MPI::sum(surface, comm_);
  result_.outflow_surface_length_fraction = surface_length > 0 ? Utilities::MPI::sum(outflow, comm_) / surface_length : 0.0;
}

bool ClosureProblem::stress_at(const Point<2>& p, Stress2& stress) const {
  const auto found = GridTools::find_active_cell_around_point(*cache_, p);
  if (found.first.state() != IteratorState::valid || !found.first->is_locally_owned()) return false;
  const typename DoFHandler<2>::active_cell_iterator cell(&tria_, found.first->level(), found.first->index(),
                                                          &dof_handler_);
  FEValues<2> fe_values(simplex_mapping(), fe_, Quadrature<2>(found.second), update_values);
  fe_values.reinit(cell);
  std::vector<Vector<double>> v(1, Vector<double>(2));
  fe_values.get_function_values(solution_, v);
  stress = stress_from(v[0][0], v[0][1], closure_of(*cell));
  return true;
}

double ClosureProblem::base_pressure_error(const std::function<double(double)>& exact) const {
  const QGaussSimplex<1> face_quadrature(fe_.degree + 3);
  FEFaceValues<2> fe_face(simplex_mapping(), fe_, face_quadrature,
                          update_values | update_quadrature_points | update_JxW_values);
  std::vector<Vector<double>> values(face_quadrature.size(), Vector<double>(2));
  double e2 = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    for (const auto f : cell->face_indices()) {
      if (!cell->face(f)->at_boundary() || cell->face(f)->boundary_id() != mesh::BoundaryId::base) continue;
      fe_face.reinit(cell, f);
      fe_face.get_function_values(solution_, values);
      const LinearClosure::Side& c = closure_of(*cell);
      for (unsigned q = 0; q < values.size(); ++q) {
        const double e = stress_from(values[q][0], values[q][1], c).yy - exact(fe_face.quadrature_point(q)[0]);
        e2 += e * e * fe_face.JxW(q);
      }
    }
  }
  return std::sqrt(Utilities::MPI::sum(e2, comm_));
}

double ClosureProblem::stress_error(const std::function<Stress2(const Point<2>&)>& exact) const {
  const QGaussSimplex<2> quadrature(fe_.degree + 2);
  FEValues<2> fe_values(simplex_mapping(), fe_, quadrature, update_values | update_quadrature_points | update_JxW_values);
  std::vector<Vector<double>> values(quadrature.size(), Vector<double>(2));
  double e2 = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fe_values.reinit(cell);
    fe_values.get_function_values(solution_, values);
    const LinearClosure::Side& c = closure_of(*cell);
    for (unsigned q = 0; q < values.size(); ++q) {
      const Stress2 h = stress_from(values[q][0], values[q][1], c), x = exact(fe_values.quadrature_point(q));
      e2 += ((h.xx - x.xx) * (h.xx - x.xx) + (h.yy - x.yy) * (h.yy - x.yy) + 2 * (h.xy - x.xy) * (h.xy - x.xy)) *
            fe_values.JxW(q);
    }
  }
  return std::sqrt(Utilities::MPI::sum(e2, comm_));
}

std::vector<std::string> ClosureProblem::field_names() {
  return {"stress_xx", "stress_yy", "stress_xy", "pressure", "principal_stress_major", "principal_stress_minor",
          "stress_anisotropy", "stress_orientation_deg"};
}

std::vector<std::string> ClosureProblem::field_units() { return {"N/m", "N/m", "N/m", "N/m", "N/m", "N/m", "1", "degree"}; }

PointEvaluator ClosureProblem::field_evaluator(double rho_g_h) const {
  return [this, rho_g_h](const Point<2>& p, std::vector<double>& v) {
    Stress2 s;
    if (!stress_at(p, s)) return false;
    const Principal pr = principal_stress(s, 1e-9 * rho_g_h);
    v = {-s.xx, -s.yy, -s.xy, 0.5 * (s.xx + s.yy), pr.major, pr.minor, pr.anisotropy, pr.orientation_deg};
    return true;
  };
}

std::string ClosureProblem::output_results(const std::string& out_dir, double rho_g_h) const {
  DataOut<2> data_out;
  data_out.set_cell_selection([](const typename Triangulation<2>::cell_iterator& cell) {
    return cell->is_active() && cell->is_locally_owned();
  });
  data_out.attach_dof_handler(dof_handler_);
  const StressPostprocessor stresses(
      [this](const DataPostprocessorInputs::Vector<2>& in, unsigned q) {
        const auto cell = in.template get_cell<2>();
        return stress_from(in.solution_values[q][0], in.solution_values[q][1], closure_of(*cell));
      },
      update_values, rho_g_h);
  data_out.add_data_vector(solution_, stresses);
  Vector<float> side(tria_.n_active_cells()), rank(tria_.n_active_cells());
  for (const auto& cell : tria_.active_cell_iterators()) {
    side(cell->active_cell_index()) = right_of_axis(*cell) ? 1.f : -1.f;
    rank(cell->active_cell_index()) = cell->subdomain_id();
  }
  data_out.add_data_vector(side, "closure_side");
  data_out.add_data_vector(rank, "mpi_rank");
  data_out.build_patches(simplex_mapping(), fe_.degree);
  return write_vtu(data_out, out_dir, name_, comm_);
}

}  // namespace pilelab::continuum
