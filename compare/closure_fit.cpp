#include "compare/closure_fit.h"

#include <cmath>

namespace pilelab::compare {

nlohmann::json osl_closure_fit(const Triangulation& mesh, const PointFields& dem, double apex_x, double repose_deg) {
  const double nan = NAN;
  nlohmann::json out = {{"eta", nan}, {"mu", nan}, {"r_squared", nan}, {"relative_misfit", nan}, {"area_m2", 0.0}};
  if (!dem.has("stress_xx") || !dem.has("stress_yy") || !dem.has("stress_xy")) return out;
  const auto &xx = dem.at("stress_xx"), &yy = dem.at("stress_yy"), &xy = dem.at("stress_xy");
  const auto &ok_xx = dem.valid.at("stress_xx"), &ok_yy = dem.valid.at("stress_yy"), &ok_xy = dem.valid.at("stress_xy");
  // The normal equations of the fit, the vertex rule on each triangle (a / 3 per node), the
  // side of the axis the triangle's centroid's.
  double a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0, c = 0, s_xx = 0, area = 0;
  int used = 0;
  struct Sample {
    double w, xx, yy, sxy;
  };
  std::vector<Sample> samples;
  for (const auto& t : mesh.triangles) {
    bool ok = true;
    for (int k : t) ok = ok && ok_xx[k] && ok_yy[k] && ok_xy[k];
    if (!ok) continue;
    const Vec2 centroid = (mesh.nodes[t[0]] + mesh.nodes[t[1]] + mesh.nodes[t[2]]) / 3.0;
    const Vec2 e1 = mesh.nodes[t[1]] - mesh.nodes[t[0]], e2 = mesh.nodes[t[2]] - mesh.nodes[t[0]];
    const double a = 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
    const double side = centroid.x() < apex_x ? -1.0 : 1.0;
    for (int k : t) {
      const double w = a / 3.0, u = yy[k], v = side * xy[k], f = xx[k];
      a11 += w * u * u, a12 += w * u * v, a22 += w * v * v, b1 += w * u * f, b2 += w * v * f, c += w * f * f;
      s_xx += w * f;
      samples.push_back({w, f, u, v});
    }
    area += a;
    ++used;
  }
  out["area_m2"] = area;
  const double det = a11 * a22 - a12 * a12;
  if (used < 3 || !(std::abs(det) > 1e-14 * a11 * a22)) return out;
  const double eta = (b1 * a22 - a12 * b2) / det, mu = (a11 * b2 - a12 * b1) / det;
  const auto misfit = [&](double e, double m) {
    double r2 = 0;
    for (const Sample& s : samples) r2 += s.w * (s.xx - e * s.yy - m * s.sxy) * (s.xx - e * s.yy - m * s.sxy);
    return r2;
  };
  const double mean_xx = s_xx / area, variance = c - area * mean_xx * mean_xx, fitted = misfit(eta, mu);
  out["eta"] = eta;
  out["mu"] = mu;
  out["r_squared"] = variance > 0 ? 1.0 - fitted / variance : nan;
  out["relative_misfit"] = c > 0 ? std::sqrt(fitted / c) : nan;
  if (repose_deg > 0 && repose_deg < 45) {
    const double mu_fpa = 2.0 * std::tan(repose_deg * M_PI / 180.0);
    out["fpa_mu"] = mu_fpa;
    out["fpa_relative_misfit"] = c > 0 ? std::sqrt(misfit(1.0, mu_fpa) / c) : nan;
  }
  return out;
}

}  // namespace pilelab::compare
