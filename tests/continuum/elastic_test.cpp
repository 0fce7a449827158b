// Verification of the elasticity solver: a manufactured solution with the optimal convergence
// rates of P1 and P2 (L2 and energy norm), and the gravity-loaded block on a smooth base between
// smooth walls, whose exact stress the P2 space contains (so it must come out exact up to the
// solver tolerance), also as nu approaches 1/2.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include <deal.II/grid/grid_generator.h>

#include "continuum/elastic_problem.h"
#include "continuum/fpa_exact.h"
#include "mpi_environment.h"

using namespace pilelab::continuum;
using dealii::Point;
using dealii::Tensor;

namespace {

// u = A (sin(a x) sin(b y), cos(a x) cos(b y)) with a != b, so that div u != 0 and lambda counts.
// Then -div sigma = f = -mu Lap u - (lambda + mu) grad div u:
//   f_x = A sin(ax) sin(by) [mu (a^2 + b^2) + (lambda + mu)(a - b) a]
//   f_y = A cos(ax) cos(by) [mu (a^2 + b^2) - (lambda + mu)(a - b) b]
constexpr double A = 1e-3, a = M_PI, b = 2 * M_PI;

class ManufacturedU : public dealii::Function<2> {
 public:
  ManufacturedU() : dealii::Function<2>(2) {}
  double value(const Point<2>& p, unsigned c) const override {
    return c == 0 ? A * std::sin(a * p[0]) * std::sin(b * p[1]) : A * std::cos(a * p[0]) * std::cos(b * p[1]);
  }
  Tensor<1, 2> gradient(const Point<2>& p, unsigned c) const override {
    const double x = p[0], y = p[1];
    if (c == 0) return Tensor<1, 2>({A * a * std::cos(a * x) * std::sin(b * y), A * b * std::sin(a * x) * std::cos(b * y)});
    return Tensor<1, 2>({-A * a * std::sin(a * x) * std::cos(b * y), -A * b * std::cos(a * x) * std::sin(b * y)});
  }
};

class ManufacturedF : public dealii::Function<2> {
 public:
  ManufacturedF(double lambda, double mu) : dealii::Function<2>(2), lambda_(lambda), mu_(mu) {}
  double value(const Point<2>& p, unsigned c) const override {
    const double x = p[0], y = p[1];
    if (c == 0) return A * std::sin(a * x) * std::sin(b * y) * (mu_ * (a * a + b * b) + (lambda_ + mu_) * (a - b) * a);
    return A * std::cos(a * x) * std::cos(b * y) * (mu_ * (a * a + b * b) - (lambda_ + mu_) * (a - b) * b);
  }
  void vector_value(const Point<2>& p, dealii::Vector<double>& v) const override {
    v[0] = value(p, 0);
    v[1] = value(p, 1);
  }

 private:
  double lambda_, mu_;
};

ElasticProblem::Errors manufactured_errors(int degree, unsigned n, double nu, ElasticResult* result = nullptr) {
  auto tria = make_triangulation(MPI_COMM_WORLD);
  dealii::GridGenerator::subdivided_hyper_rectangle_with_simplices(*tria, {n, n}, Point<2>(0, 0), Point<2>(1, 1));
  ElasticSettings s;
  s.degree = degree;
  s.material.poisson_ratio = nu;
  s.solver.kind = SolverSettings::Kind::direct;
  ElasticProblem problem(*tria, s, 1.0, 1.0);
  problem.set_manufactured(std::make_shared<ManufacturedF>(s.material.lambda_2d(s.plane == ElasticSettings::Plane::stress), s.material.shear_modulus()), std::make_shared<ManufacturedU>());
  const ElasticResult& r = problem.run();
  if (result) *result = r;
  return problem.compute_errors(ManufacturedU());
}

// The block [-w/2, w/2] x [0, h] with the boundary ids of mesh/pile_mesh.h: base 1, walls 4, top 5.
std::unique_ptr<Triangulation2> block(unsigned nx, unsigned ny, double w, double h) {
  auto tria = make_triangulation(MPI_COMM_WORLD);
  dealii::GridGenerator::subdivided_hyper_rectangle_with_simplices(*tria, {nx, ny}, Point<2>(-w / 2, 0),
                                                                    Point<2>(w / 2, h));
  for (const auto& cell : tria->active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary()) {
        const Point<2> c = cell->face(f)->center();
        cell->face(f)->set_boundary_id(std::abs(c[1]) < 1e-12 ? 1 : std::abs(c[1] - h) < 1e-12 ? 5 : 4);
      }
  return tria;
}

}  // namespace

// Optimal rates: ||u - u_h||_L2 ~ h^(p+1), energy norm ~ h^p, for smooth u. Measured between the
// two finest of four meshes (h = 1/4 ... 1/32); the margin 0.15 allows for the pre-asymptotic
// remainder of the next term in the error expansion.
TEST(ElasticManufactured, OptimalRatesP1AndP2) {
  for (int p : {1, 2}) {
    std::vector<double> l2, en;
    for (unsigned n : {4u, 8u, 16u, 32u}) {
      const auto e = manufactured_errors(p, n, 0.3);
      l2.push_back(e.l2);
      en.push_back(e.energy);
    }
    for (std::size_t i = 1; i < l2.size(); ++i)
      std::printf("P%d h=1/%d: L2 %.3e (rate %.3f), energy %.3e (rate %.3f)\n", p, 4 << i, l2[i],
                  std::log2(l2[i - 1] / l2[i]), en[i], std::log2(en[i - 1] / en[i]));
    const double rate_l2 = std::log2(l2[2] / l2[3]), rate_en = std::log2(en[2] / en[3]);
    EXPECT_GT(rate_l2, p + 1 - 0.15) << "P" << p << " L2 rate";
    EXPECT_GT(rate_en, p - 0.15) << "P" << p << " energy rate";
    EXPECT_LT(rate_l2, p + 1 + 0.5) << "P" << p << ": faster than theory means the error measure is broken";
  }
}

// Near-incompressibility: on a fixed mesh the P1 energy error grows like (lambda/mu) ^ (1/2) at
// worst (volumetric locking); P2 on triangles locks too, less. The test prints the table and
// checks that the solver still converges and the P2 error stays below the P1 error.
TEST(ElasticManufactured, ReportErrorAsNuApproachesOneHalf) {
  for (double nu : {0.3, 0.45, 0.49, 0.499, 0.4999}) {
    const auto e1 = manufactured_errors(1, 16, nu);
    const auto e2 = manufactured_errors(2, 16, nu);
    const double scale = std::sqrt(ElasticSettings{}.material.youngs_modulus_N_per_m);  // energy of u ~ sqrt(E) A
    std::printf("nu=%.4f  P1: L2 %.3e energy/sqrt(E) %.3e   P2: L2 %.3e energy/sqrt(E) %.3e\n", nu, e1.l2,
                e1.energy / scale, e2.l2, e2.energy / scale);
    EXPECT_TRUE(std::isfinite(e1.l2) && std::isfinite(e2.l2));
    EXPECT_LT(e2.l2, e1.l2);
  }
}

// The block on a smooth base (u_y = 0) between smooth walls (u_x = 0), loaded by gravity:
// u_x = 0, u_y quadratic in y, so sigma_yy = -rho g (h - y), sigma_xy = 0 and, with eps_xx = 0,
// sigma_xx = lambda/(lambda + 2 mu) sigma_yy: nu/(1-nu) sigma_yy in plane strain, and with the
// plane-stress lambda* = E nu/(1 - nu^2), nu sigma_yy in plane stress. P2 contains the displacement, so Galerkin
// orthogonality makes the discrete solution exact up to the solver's tolerance (1e-12 here).
TEST(ElasticBlock, ExactStressOnSmoothBaseBetweenSmoothWalls) {
  const double rho = 4100, g = 9.81, h = 0.5, w = 0.4;
  for (auto plane : {ElasticSettings::Plane::strain, ElasticSettings::Plane::stress})
    for (double nu : {0.0, 0.3, 0.45, 0.49, 0.499}) {
      auto tria = block(6, 7, w, h);
      ElasticSettings s;
      s.degree = 2;
      s.material.poisson_ratio = nu;
      s.plane = plane;
      s.base = ElasticSettings::Base::smooth;
      s.solver.kind = SolverSettings::Kind::direct;
      ElasticProblem problem(*tria, s, rho, g);
      const ElasticResult& r = problem.run();
      const double ratio = plane == ElasticSettings::Plane::strain ? nu / (1 - nu) : nu;
      double worst = 0;
      for (double x : {-0.17, -0.05, 0.0, 0.11, 0.19})
        for (double y : {0.0, 0.013, 0.2, 0.37, 0.49}) {
          Stress2 p;
          Tensor<1, 2> u;
          dealii::SymmetricTensor<2, 2> eps;
          ASSERT_TRUE(problem.stress_at(Point<2>(x, y), p, u, eps));
          const double pyy = rho * g * (h - y);  // compressive positive
          worst = std::max({worst, std::abs(p.yy - pyy), std::abs(p.xx - ratio * pyy), std::abs(p.xy)});
        }
      const double error = worst / (rho * g * h);
      std::printf("block P2 plane %s nu=%.3f: max stress error / rho g h = %.2e, base force / weight - 1 = %.2e\n",
                  plane == ElasticSettings::Plane::strain ? "strain" : "stress", nu, error,
                  r.base_force_N / r.weight - 1);
      // Round-off grows with the condition number ~ lambda / mu = 2 nu / (1 - 2 nu).
      const double kappa = 1 + 2 * nu / (1 - 2 * nu);
      EXPECT_LT(error, 1e-9 * kappa);
      EXPECT_NEAR(r.base_force_N / r.weight, 1.0, 1e-9 * kappa);
    }
}

// P1 cannot represent the quadratic u_y: its stresses are constant per triangle. The balance of
// forces still holds exactly for the consistent discrete problem only in the limit; here we check
// the first-order convergence of the base force to the weight (error ~ h, halving per refinement).
TEST(ElasticBlock, P1BaseForceConvergesToWeight) {
  const double rho = 4100, g = 9.81, h = 0.5, w = 0.4;
  std::vector<double> err;
  for (unsigned n : {4u, 8u, 16u}) {
    auto tria = block(n, n, w, h);
    ElasticSettings s;
    s.degree = 1;
    s.base = ElasticSettings::Base::smooth;
    ElasticProblem problem(*tria, s, rho, g);
    const ElasticResult& r = problem.run();
    err.push_back(std::abs(r.base_force_N / r.weight - 1));
    std::printf("block P1 n=%u: |base force / weight - 1| = %.3e (%u CG iterations)\n", n, err.back(),
                r.solver.iterations);
  }
  EXPECT_GT(std::log2(err[1] / err[2]), 1 - 0.15);
}

// A 28 degree wedge 0.33 m high of two triangles, refined globally; base, left and right flank tagged.
std::unique_ptr<Triangulation2> wedge_28_degrees(unsigned refinements) {
  auto tria = make_triangulation(MPI_COMM_WORLD);
  const double h = 0.33, L = h / std::tan(28 * M_PI / 180);
  std::vector<Point<2>> v = {{-L, 0}, {0, 0}, {L, 0}, {0, h}};
  std::vector<dealii::CellData<2>> cells(2, dealii::CellData<2>(3));
  cells[0].vertices = {0, 1, 3};
  cells[1].vertices = {1, 2, 3};
  tria->create_triangulation(v, cells, {});
  for (const auto& cell : tria->active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary())
        cell->face(f)->set_boundary_id(std::abs(cell->face(f)->center()[1]) < 1e-12 ? 1 : cell->face(f)->center()[0] < 0 ? 2 : 3);
  tria->refine_global(refinements);
  return tria;
}

// The consistent reaction (the residual A u - b at the base's constrained dofs) is the weight on
// any mesh, P1 included: the y-translation lies in A's kernel and every free dof's residual is
// zero to the solver's tolerance (relative 1e-10 of |b|), while the integral of P1's constant
// cell stresses along the base misses the weight by O(h). Coarse blocks and a coarse wedge,
// both bases.
TEST(ElasticReaction, IsTheWeightOnCoarseP1Meshes) {
  const double rho = 4100, g = 9.81;
  for (auto base : {ElasticSettings::Base::rough, ElasticSettings::Base::smooth}) {
    auto tria = block(4, 4, 0.4, 0.5);
    ElasticSettings s;
    s.degree = 1;
    s.base = base;
    ElasticProblem problem(*tria, s, rho, g);
    const ElasticResult& r = problem.run();
    std::printf("block P1 n=4 %s: reaction / weight - 1 = %.2e, cell-stress base force / weight - 1 = %.2e\n",
                base == ElasticSettings::Base::rough ? "rough" : "smooth", r.base_reaction_N / r.weight - 1,
                r.base_force_N / r.weight - 1);
    EXPECT_NEAR(r.base_reaction_N / r.weight, 1.0, 1e-8);
    EXPECT_GT(std::abs(r.base_force_N / r.weight - 1), 1e-3);  // the trace is what the reaction improves on
  }
  auto tria = wedge_28_degrees(2);
  ElasticSettings s;
  s.degree = 1;
  ElasticProblem problem(*tria, s, rho, g);
  const ElasticResult& r = problem.run();
  EXPECT_NEAR(r.base_reaction_N / r.weight, 1.0, 1e-8);
}

// The rough (clamped) and smooth bases both carry the weight of a wedge.
TEST(ElasticWedge, BaseCarriesTheWeight) {
  auto tria = wedge_28_degrees(5);
  for (auto base : {ElasticSettings::Base::rough, ElasticSettings::Base::smooth}) {
    ElasticSettings s;
    s.base = base;
    ElasticProblem problem(*tria, s, 4100, 9.81);
    const ElasticResult& r = problem.run();
    std::printf("wedge P2 %s base: base force / weight = %.6f, %u CG iterations\n",
                base == ElasticSettings::Base::rough ? "rough" : "smooth", r.base_force_N / r.weight,
                r.solver.iterations);
    // Stresses of P2 are linear per cell: the integrated base reaction converges like h^2 to the
    // weight except near the two feet, where the clamped base has a stress singularity.
    EXPECT_NEAR(r.base_force_N / r.weight, 1.0, 5e-3);
    EXPECT_NEAR(r.base_shear_force / r.weight, 0.0, 5e-3);
  }
}
