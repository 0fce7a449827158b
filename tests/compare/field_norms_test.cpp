// Integrals of nodal fields are exact for linear fields; identical fields differ by zero.
#include <gtest/gtest.h>

#include <cmath>

#include "compare/field_norms.h"

using namespace pilelab::compare;

namespace {
// The unit square cut into 2 n^2 triangles.
Triangulation square(int n) {
  Triangulation m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.nodes.emplace_back(double(i) / n, double(j) / n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  return m;
}
}  // namespace

TEST(FieldNorms, LinearFieldsAreIntegratedExactly) {
  const Triangulation m = square(8);
  std::vector<double> x(m.nodes.size()), zero(m.nodes.size(), 0.0);
  std::vector<char> ok(m.nodes.size(), 1);
  for (std::size_t k = 0; k < m.nodes.size(); ++k) x[k] = 2 * m.nodes[k].x() + m.nodes[k].y();
  // || 2x + y ||^2 over the unit square = 4/3 + 1/3 + 2*2/4 = 8/3.
  const L2Difference d = l2_difference(m, x, ok, zero, ok);
  EXPECT_NEAR(d.difference * d.difference, 8.0 / 3.0, 1e-13);
  EXPECT_NEAR(d.area, 1.0, 1e-14);
  EXPECT_NEAR(area_mean(m, x, ok), 1.5, 1e-14);
  // Lower half only: || 2x + y ||^2 over y < 1/2 is 2/3 + 1/24 + 1/4 = 23/24.
  const L2Difference h = l2_difference(m, x, ok, zero, ok, [](const Vec2& c) { return c.y() < 0.5; });
  EXPECT_NEAR(h.area, 0.5, 1e-14);  // rows of triangles end exactly at y = 1/2
  EXPECT_NEAR(h.difference * h.difference, 23.0 / 24.0, 1e-13);
}

TEST(FieldNorms, IdenticalFieldsDifferByZeroAndMissingDataIsLeftOut) {
  const Triangulation m = square(4);
  std::vector<double> f(m.nodes.size());
  std::vector<char> ok(m.nodes.size(), 1), some(m.nodes.size(), 1);
  for (std::size_t k = 0; k < f.size(); ++k) f[k] = std::sin(3 * m.nodes[k].x()) + m.nodes[k].y();
  EXPECT_EQ(l2_difference(m, f, ok, f, ok).relative, 0.0);
  some[0] = 0;  // a corner node without data drops its triangles
  EXPECT_LT(l2_difference(m, f, some, f, ok).area, 1.0);
}

// No triangle with data (or none in the region): no mean, NaN (null in JSON), never 0, which
// would read as perfectly aligned axes.
TEST(FieldNorms, MeanWithoutDataIsNaN) {
  const Triangulation m = square(4);
  std::vector<double> f(m.nodes.size(), 7.0);
  std::vector<char> none(m.nodes.size(), 0), ok(m.nodes.size(), 1);
  EXPECT_TRUE(std::isnan(area_mean(m, f, none)));
  EXPECT_TRUE(std::isnan(area_mean(m, f, ok, [](const Vec2& c) { return c.y() > 2.0; })));
  EXPECT_NEAR(area_mean(m, f, ok), 7.0, 1e-14);
}

TEST(FieldNorms, AxisAngles) {
  EXPECT_DOUBLE_EQ(axis_angle_deg(10, 170), 20.0);
  EXPECT_DOUBLE_EQ(axis_angle_deg(60, 120), 60.0);
  EXPECT_DOUBLE_EQ(axis_angle_deg(0, 90), 90.0);
  EXPECT_DOUBLE_EQ(axis_angle_deg(45, 45), 0.0);
}

TEST(PointFields, PointsAreMatchedByPosition) {
  const std::vector<Vec2> a = {{0, 0}, {1, 0}, {0, 1}}, b = {{0, 1}, {2, 2}, {1, 1e-13}};
  const auto idx = match_points(a, b, 1e-9);
  EXPECT_EQ(idx, (std::vector<int>{2, -1, 1}));
}
