// The OSL closure fit (compare/closure_fit.h): exact on stress fields that obey the closure,
// the FPA's misfit zero where the fields obey the FPA, and a misfit that grows with a
// perturbation the closure cannot absorb.
#include <cmath>

#include <gtest/gtest.h>

#include "compare/closure_fit.h"

using namespace pilelab::compare;

namespace {

// A wedge-shaped patch of a regular grid, apex at x = 0.1: triangles of the n x n grid on
// [-1, 1.2] x [0, 1], with stresses built from arbitrary smooth sigma_yy and sigma_xy and
// sigma_xx from the closure (plus `extra` times an independent field).
struct Patch {
  Triangulation mesh;
  PointFields fields;
};
Patch patch(double eta, double mu, double extra) {
  Patch p;
  const int n = 24;
  const double apex = 0.1;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) p.mesh.nodes.emplace_back(-1.0 + 2.2 * i / n, 1.0 * j / n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      p.mesh.triangles.push_back({a, b, d});
      p.mesh.triangles.push_back({a, d, c});
    }
  std::vector<double> xx, yy, xy;
  for (const auto& q : p.mesh.nodes) {
    const double syy = -(1.0 - q.y()) * (2.0 + std::cos(3 * q.x()));
    const double sxy = 0.4 * std::sin(2 * (q.x() - apex)) * (1.2 - q.y());
    yy.push_back(syy);
    xy.push_back(sxy);
    xx.push_back(0.0);
  }
  // sigma_xx from the closure, the side decided per node (the fit decides per triangle; on the
  // axis, where they can disagree, sigma_xy = 0).
  for (std::size_t k = 0; k < xx.size(); ++k) {
    const double s = p.mesh.nodes[k].x() < apex ? -1.0 : 1.0;
    xx[k] = eta * yy[k] + mu * s * xy[k] + extra * std::cos(5 * p.mesh.nodes[k].y()) * p.mesh.nodes[k].x();
  }
  const std::vector<char> ok(xx.size(), 1);
  p.fields.points = p.mesh.nodes;
  p.fields.set("stress_xx", xx, ok);
  p.fields.set("stress_yy", yy, ok);
  p.fields.set("stress_xy", xy, ok);
  return p;
}

}  // namespace

// Fields that obey the closure are fitted exactly: the normal equations have the true
// constants as their solution, R^2 = 1 and no misfit, to round-off. The axis x = 0.1 is a grid
// line, so every triangle lies on one side, and sigma_xy vanishes on it, so the nodes on the
// axis obey the closure on both sides.
TEST(OslClosureFit, ExactOnFieldsThatObeyTheClosure) {
  for (const auto& [eta, mu] : {std::pair{0.8, 1.0}, std::pair{1.3, 0.2}}) {
    Patch p = patch(eta, mu, 0.0);
    const nlohmann::json fit = osl_closure_fit(p.mesh, p.fields, 0.1, 0.0);
    EXPECT_NEAR(fit["eta"].get<double>(), eta, 1e-12) << fit.dump();
    EXPECT_NEAR(fit["mu"].get<double>(), mu, 1e-12) << fit.dump();
    EXPECT_NEAR(fit["r_squared"].get<double>(), 1.0, 1e-12);
    EXPECT_LT(fit["relative_misfit"].get<double>(), 1e-12);
    EXPECT_NEAR(fit["area_m2"].get<double>(), 2.2, 1e-12);
    EXPECT_FALSE(fit.contains("fpa_mu"));  // no angle, no FPA
  }
}

// Fields that obey the FPA at 28 degrees give the FPA no misfit, and the fit finds its members'
// constants eta = 1, mu = 2 tan(28 deg).
TEST(OslClosureFit, FpaFieldsGiveTheFpaNoMisfit) {
  const double mu = 2 * std::tan(28 * M_PI / 180);
  Patch p = patch(1.0, mu, 0.0);
  const nlohmann::json fit = osl_closure_fit(p.mesh, p.fields, 0.1, 28.0);
  EXPECT_NEAR(fit["fpa_mu"].get<double>(), mu, 1e-15);
  EXPECT_LT(fit["fpa_relative_misfit"].get<double>(), 1e-12);
  EXPECT_NEAR(fit["eta"].get<double>(), 1.0, 1e-12);
}

// A part of sigma_xx the closure cannot absorb leaves a misfit that grows with it, and the
// FPA's misfit at the wrong angle exceeds the fit's (the fit minimises the same functional).
TEST(OslClosureFit, MisfitGrowsWithWhatTheClosureCannotAbsorb) {
  double previous = 0;
  for (double extra : {0.05, 0.2, 0.8}) {
    Patch p = patch(0.8, 1.0, extra);
    const nlohmann::json fit = osl_closure_fit(p.mesh, p.fields, 0.1, 30.0);
    const double misfit = fit["relative_misfit"].get<double>();
    EXPECT_GT(misfit, previous);
    EXPECT_LT(fit["r_squared"].get<double>(), 1.0);
    EXPECT_GE(fit["fpa_relative_misfit"].get<double>(), misfit);
    previous = misfit;
  }
}

// Without stresses, or with too few triangles, the constants are NaN (null in the report).
TEST(OslClosureFit, NothingToFitGivesNaN) {
  Patch p = patch(0.8, 1.0, 0.0);
  std::vector<char> none(p.fields.points.size(), 0);
  p.fields.set("stress_yy", p.fields.at("stress_yy"), none);
  const nlohmann::json fit = osl_closure_fit(p.mesh, p.fields, 0.1, 28.0);
  EXPECT_TRUE(std::isnan(fit["eta"].get<double>()));
  EXPECT_EQ(fit["area_m2"].get<double>(), 0.0);
}
