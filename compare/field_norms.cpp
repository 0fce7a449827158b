#include "compare/field_norms.h"

#include <cmath>

namespace pilelab::compare {

namespace {
double triangle_area(const Triangulation& m, const std::array<int, 3>& t) {
  return 0.5 * dem::cross(m.nodes[t[1]] - m.nodes[t[0]], m.nodes[t[2]] - m.nodes[t[0]]);
}
// int_T f g for linear f, g with nodal values.
double product_integral(double area, const double f[3], const double g[3]) {
  return area / 12.0 * (f[0] * g[0] + f[1] * g[1] + f[2] * g[2] + (f[0] + f[1] + f[2]) * (g[0] + g[1] + g[2]));
}
}  // namespace

L2Difference l2_difference(const Triangulation& mesh, const std::vector<double>& a, const std::vector<char>& a_ok,
                           const std::vector<double>& b, const std::vector<char>& b_ok, const Region& region) {
  L2Difference out;
  double diff2 = 0, ref2 = 0;
  for (const auto& t : mesh.triangles) {
    bool ok = true;
    for (int k : t) ok = ok && a_ok[k] && b_ok[k];
    if (!ok) continue;
    const Vec2 centroid = (mesh.nodes[t[0]] + mesh.nodes[t[1]] + mesh.nodes[t[2]]) / 3.0;
    if (region && !region(centroid)) continue;
    const double area = triangle_area(mesh, t);
    const double d[3] = {a[t[0]] - b[t[0]], a[t[1]] - b[t[1]], a[t[2]] - b[t[2]]};
    const double r[3] = {b[t[0]], b[t[1]], b[t[2]]};
    diff2 += product_integral(area, d, d);
    ref2 += product_integral(area, r, r);
    out.area += area;
  }
  out.difference = std::sqrt(std::max(diff2, 0.0));
  out.reference = std::sqrt(std::max(ref2, 0.0));
  // No common triangle: no comparison (NaN, written as null), never a perfect match.
  out.relative = out.area == 0 ? NAN : out.reference > 0 ? out.difference / out.reference : 0.0;
  return out;
}

double area_mean(const Triangulation& mesh, const std::vector<double>& f, const std::vector<char>& ok,
                 const Region& region) {
  double integral = 0, area = 0;
  for (const auto& t : mesh.triangles) {
    if (!(ok[t[0]] && ok[t[1]] && ok[t[2]])) continue;
    const Vec2 centroid = (mesh.nodes[t[0]] + mesh.nodes[t[1]] + mesh.nodes[t[2]]) / 3.0;
    if (region && !region(centroid)) continue;
    const double a = triangle_area(mesh, t);
    integral += a * (f[t[0]] + f[t[1]] + f[t[2]]) / 3.0;
    area += a;
  }
  // No triangle with data: no mean (NaN, written as null), as for l2_difference.
  return area > 0 ? integral / area : NAN;
}

double axis_angle_deg(double a, double b) {
  double d = std::fmod(std::abs(a - b), 180.0);
  return d > 90.0 ? 180.0 - d : d;
}

}  // namespace pilelab::compare
