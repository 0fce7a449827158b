#include "dem/pile_shape.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/portable_math.h"

namespace pilelab::dem {

namespace {
// The least-squares line y = a + b x through the surface points: its slope b and the slope's
// standard error sqrt(s^2 / Sxx), s^2 = sum of squared residuals / (n - 2), the usual estimate
// when the points scatter independently about the line (needs n >= 3).
struct LineFit {
  double slope, slope_standard_error;
};

LineFit fit_line(const std::vector<Vec2>& pts) {
  double sx = 0, sy = 0;
  for (const Vec2& p : pts) {
    sx += p.x();
    sy += p.y();
  }
  const double mx = sx / pts.size(), my = sy / pts.size();
  double sxx = 0, sxy = 0;
  for (const Vec2& p : pts) {
    sxx += (p.x() - mx) * (p.x() - mx);
    sxy += (p.x() - mx) * (p.y() - my);
  }
  const double slope = sxy / sxx;
  double squared_residuals = 0;
  for (const Vec2& p : pts) {
    const double r = p.y() - my - slope * (p.x() - mx);
    squared_residuals += r * r;
  }
  return {slope, std::sqrt(squared_residuals / (pts.size() - 2) / sxx)};
}

// The flank's angle atan(|b|) and its standard error by the delta method,
// d(atan b)/db = 1 / (1 + b^2), both in degrees; NaN for fewer than 3 points.
void flank_angle(const std::vector<Vec2>& pts, double& angle_deg, double& standard_error_deg) {
  if (pts.size() < 3) {
    angle_deg = standard_error_deg = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  const LineFit fit = fit_line(pts);
  angle_deg = portable_atan(std::abs(fit.slope)) * 180.0 / M_PI;
  standard_error_deg = fit.slope_standard_error / (1.0 + fit.slope * fit.slope) * 180.0 / M_PI;
}
}  // namespace

PileShape measure_pile(const World& world, const Snapshot& snapshot, double bin_width) {
  PileShape shape;
  const std::size_t n = snapshot.grain_count();
  if (n == 0) {
    flank_angle({}, shape.repose_left_deg, shape.repose_left_se_deg);
    flank_angle({}, shape.repose_right_deg, shape.repose_right_se_deg);
    return shape;
  }
  double xmin = INFINITY, xmax = -INFINITY;
  for (std::size_t g = 0; g < n; ++g) {
    xmin = std::min(xmin, snapshot.position[2 * g]);
    xmax = std::max(xmax, snapshot.position[2 * g]);
  }
  const int bins = static_cast<int>((xmax - xmin) / bin_width) + 1;
  std::vector<double> top(bins, -INFINITY);
  for (std::size_t g = 0; g < n; ++g) {
    const Vec2 p(snapshot.position[2 * g], snapshot.position[2 * g + 1]);
    const Shape& s = world.shape(static_cast<int>(snapshot.body[g]));
    double sn, c;
    rotation_sincos(snapshot.angle[g], sn, c);
    double y = p.y() + s.radius;
    for (const Vec2& v : s.vertices) y = std::max(y, p.y() + rotate(v, c, sn).y());
    const int b = static_cast<int>((p.x() - xmin) / bin_width);
    top[b] = std::max(top[b], y);
  }
  int apex = 0;
  for (int b = 0; b < bins; ++b) {
    if (top[b] == -INFINITY) continue;
    shape.surface.emplace_back(xmin + (b + 0.5) * bin_width, top[b]);
    if (top[b] > top[apex]) apex = b;
  }
  shape.height = top[apex];
  shape.apex_x = xmin + (apex + 0.5) * bin_width;
  std::vector<Vec2> left, right;
  for (const Vec2& s : shape.surface) {
    if (s.y() < 0.2 * shape.height || s.y() > 0.8 * shape.height) continue;
    (s.x() < shape.apex_x ? left : right).push_back(s);
  }
  shape.left_points = static_cast<int>(left.size());
  shape.right_points = static_cast<int>(right.size());
  flank_angle(left, shape.repose_left_deg, shape.repose_left_se_deg);
  flank_angle(right, shape.repose_right_deg, shape.repose_right_se_deg);
  return shape;
}

}  // namespace pilelab::dem
