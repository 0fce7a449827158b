// Verification of the OSL closure (continuum/models/osl.h): its exact wedge solution, derived in
// docs/CONTINUUM.md, is recovered to round-off on meshes that follow its kinks, and the FPA is
// its member eta = 1, mu = 2 tan(phi), in the closed form and in the solver.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "../mpi_environment.h"
#include "../wedge_meshes.h"
#include "continuum/fpa_exact.h"
#include "continuum/models/fpa.h"
#include "continuum/models/osl.h"

using namespace pilelab::continuum;
using dealii::Point;
using pilelab::testing::fan_wedge;

namespace {

constexpr double rho = 4100, g = 9.81, h = 0.33, phi = 28.0;

OslSettings osl(double eta, double mu, int degree) {
  OslSettings s;
  s.eta = eta;
  s.mu = mu;
  s.degree = degree;
  return s;
}

double relative_error(const ClosureProblem& problem, const std::function<Stress2(const Point<2>&)>& exact) {
  const double area = h * h / std::tan(phi * M_PI / 180);
  return problem.stress_error(exact) / (rho * g * h * std::sqrt(area));
}

}  // namespace

// At eta = 1 and mu = 2 tan(phi) the OSL is the FPA: the closed forms agree at every point to
// round-off (inner coefficient a = sin(phi)), and the two solvers build the same closure, so
// their solutions agree to round-off too.
TEST(OslWedge, FpaIsItsMember) {
  const double mu = 2 * std::tan(phi * M_PI / 180);
  for (double x : {-0.6, -0.3, -0.1, 0.0, 0.05, 0.2, 0.5})
    for (double y : {0.0, 0.1, 0.25}) {
      const Stress2 a = osl_symmetric_wedge_stress(1.0, mu, phi, h, 0, rho * g, x, y);
      const Stress2 b = fpa_symmetric_wedge_stress(phi, h, 0, rho * g, x, y);
      EXPECT_NEAR(a.xx, b.xx, 1e-12 * rho * g * h) << x << " " << y;
      EXPECT_NEAR(a.yy, b.yy, 1e-12 * rho * g * h) << x << " " << y;
      EXPECT_NEAR(a.xy, b.xy, 1e-12 * rho * g * h) << x << " " << y;
    }
  auto tria = fan_wedge(h, phi, phi, {0.0}, 3);  // not aligned: the solution is not exact
  OslProblem o(*tria, osl(1.0, mu, 1), rho, g, 0.0);
  FpaSettings f;
  f.left_repose_angle_deg = f.right_repose_angle_deg = phi;
  FpaProblem p(*tria, f, rho, g, 0.0);
  o.run();
  p.run();
  Stress2 so, sp;
  for (double x : {-0.4, -0.1, 0.02, 0.3})
    if (o.stress_at(Point<2>(x, 0.05), so) && p.stress_at(Point<2>(x, 0.05), sp)) {
      EXPECT_NEAR(so.yy, sp.yy, 1e-10 * rho * g * h);
      EXPECT_NEAR(so.xy, sp.xy, 1e-10 * rho * g * h);
    }
}

// The exact stress is linear in each of the four sectors between the flanks, the two rays
// X = tau Z from the apex and the axis. On a fan mesh with those lines as edges it lies in the P1
// and P2 spaces, the least-squares functional vanishes there, and the unique minimiser is the
// exact stress: the error is round-off, and the base carries the weight. Constants on both
// sides of the FPA's (eta below and above 1, mu small and large), each checked to admit the
// wedge solution.
TEST(OslWedge, ExactOnMeshAlignedWithTheCharacteristics) {
  for (const auto& [eta, mu] : {std::pair{0.8, 1.0}, std::pair{1.2, 0.5}, std::pair{1.0, 0.3}, std::pair{0.6, 1.6}}) {
    ASSERT_TRUE(osl_wedge_solution_exists(eta, mu, phi)) << eta << " " << mu;
    const double ray = h * osl_apex_ray_slope(eta, mu);
    for (int p : {1, 2}) {
      auto tria = fan_wedge(h, phi, phi, {-ray, 0.0, ray}, 3);
      OslProblem problem(*tria, osl(eta, mu, p), rho, g, 0.0);
      const ClosureResult& r = problem.run();
      const double error = relative_error(problem, [&](const Point<2>& x) {
        return osl_symmetric_wedge_stress(eta, mu, phi, h, 0, rho * g, x[0], x[1]);
      });
      std::printf("OSL eta=%.2f mu=%.2f, P%d: relative L2 stress error %.2e, base force / weight - 1 = %.2e\n", eta, mu,
                  p, error, r.base_force_N / r.weight - 1);
      EXPECT_LT(error, 1e-10);
      EXPECT_NEAR(r.base_force_N / r.weight, 1.0, 1e-10);
    }
  }
}

// A mesh that does not follow the rays must miss the kinks: the error is then well above
// round-off, which shows the aligned test above could fail; and it falls with refinement
// (least squares bounds it by the best approximation of a kinked field, O(h^(1/2)) at least).
TEST(OslWedge, ConvergesOnMeshNotAlignedWithTheRays) {
  const double eta = 0.8, mu = 1.0;
  std::vector<double> errors;
  for (unsigned levels : {3u, 4u, 5u}) {
    auto tria = fan_wedge(h, phi, phi, {0.0}, levels);
    OslProblem problem(*tria, osl(eta, mu, 1), rho, g, 0.0);
    problem.run();
    errors.push_back(relative_error(problem, [&](const Point<2>& x) {
      return osl_symmetric_wedge_stress(eta, mu, phi, h, 0, rho * g, x[0], x[1]);
    }));
    std::printf("OSL axis-only mesh, %u levels: relative L2 stress error %.3e\n", levels, errors.back());
  }
  EXPECT_GT(errors[0], 1e-4);
  EXPECT_GT(std::log2(errors[0] / errors[1]), 0.5 - 0.1);
  EXPECT_GT(std::log2(errors[1] / errors[2]), 0.5 - 0.1);
}
