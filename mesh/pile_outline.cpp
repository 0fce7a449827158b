#include "mesh/pile_outline.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/portable_math.h"

namespace pilelab::mesh {

namespace {
// Distance from p to the segment a-b.
double distance_to_segment(const dem::Vec2& p, const dem::Vec2& a, const dem::Vec2& b) {
  const dem::Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

void simplify_range(const std::vector<dem::Vec2>& pts, std::size_t first, std::size_t last,
                    double tolerance, std::vector<bool>& keep) {
  if (last <= first + 1) return;
  double worst = -1;
  std::size_t worst_index = first;
  for (std::size_t i = first + 1; i < last; ++i) {
    const double d = distance_to_segment(pts[i], pts[first], pts[last]);
    if (d > worst) worst = d, worst_index = i;
  }
  if (worst <= tolerance) return;
  keep[worst_index] = true;
  simplify_range(pts, first, worst_index, tolerance, keep);
  simplify_range(pts, worst_index, last, tolerance, keep);
}
}  // namespace

std::vector<dem::Vec2> simplify_polyline(const std::vector<dem::Vec2>& points, double tolerance) {
  if (points.size() <= 2) return points;
  std::vector<bool> keep(points.size(), false);
  keep.front() = keep.back() = true;
  simplify_range(points, 0, points.size() - 1, tolerance, keep);
  std::vector<dem::Vec2> out;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (keep[i]) out.push_back(points[i]);
  return out;
}

namespace {
// h(x) of a surface polyline (x non-decreasing), zero outside its feet.
double height_at(const std::vector<dem::Vec2>& surface, double x) {
  if (surface.empty() || x <= surface.front().x() || x >= surface.back().x()) return 0.0;
  const auto right = std::upper_bound(surface.begin(), surface.end(), x,
                                      [](double value, const dem::Vec2& p) { return value < p.x(); });
  const dem::Vec2& b = *right;
  const dem::Vec2& a = *(right - 1);
  const double dx = b.x() - a.x();
  return dx > 0 ? a.y() + (x - a.x()) / dx * (b.y() - a.y()) : std::max(a.y(), b.y());
}
}  // namespace

Outline mean_outline(const std::vector<Outline>& outlines, double spacing) {
  if (outlines.empty()) throw InputError("mean outline: no outlines to average");
  double left = INFINITY, right = -INFINITY;
  for (const Outline& o : outlines) {
    left = std::min(left, o.surface.front().x());
    right = std::max(right, o.surface.back().x());
  }
  const int intervals = std::max(2, static_cast<int>(std::ceil((right - left) / spacing)));
  Outline mean;
  mean.surface.reserve(intervals + 1);
  for (int i = 0; i <= intervals; ++i) {
    const double x = i == intervals ? right : left + (right - left) * i / intervals;
    double sum = 0;
    for (const Outline& o : outlines) sum += height_at(o.surface, x);
    mean.surface.emplace_back(x, sum / outlines.size());
  }
  for (int i = 1; i < intervals; ++i)
    if (mean.surface[i].y() > mean.surface[mean.apex_index].y()) mean.apex_index = i;
  return mean;
}

Outline smoothed_outline(const Outline& outline, double width) {
  const std::vector<dem::Vec2>& h = outline.surface;
  if (!(width > 0) || h.size() < 3) return outline;
  // The integral H(x) of h from the left foot, exact at the polyline's corners (h is linear
  // between them); the window's mean is (H(x + w/2) - H(x - w/2)) / w.
  std::vector<double> integral(h.size(), 0.0);
  for (std::size_t i = 1; i < h.size(); ++i)
    integral[i] = integral[i - 1] + 0.5 * (h[i].y() + h[i - 1].y()) * (h[i].x() - h[i - 1].x());
  const auto H = [&](double x) {
    if (x <= h.front().x()) return 0.0;
    if (x >= h.back().x()) return integral.back();
    const auto right = std::upper_bound(h.begin(), h.end(), x, [](double v, const dem::Vec2& p) { return v < p.x(); });
    const std::size_t i = static_cast<std::size_t>(right - h.begin()) - 1;
    const double y = height_at(h, x);
    return integral[i] + 0.5 * (h[i].y() + y) * (x - h[i].x());
  };
  const double left = h.front().x() - 0.5 * width, right = h.back().x() + 0.5 * width;
  const int intervals = std::max(2, static_cast<int>(std::ceil((right - left) / (width / 16))));
  Outline smooth;
  for (int i = 0; i <= intervals; ++i) {
    const double x = i == intervals ? right : left + (right - left) * i / intervals;
    const double y = i == 0 || i == intervals ? 0.0 : (H(x + 0.5 * width) - H(x - 0.5 * width)) / width;
    smooth.surface.emplace_back(x, std::max(y, 0.0));
    if (y > smooth.surface[smooth.apex_index].y()) smooth.apex_index = i;
  }
  return smooth;
}

double mean_grain_diameter(const dem::DemFile& file, const dem::Snapshot& snapshot) {
  double sum = 0;
  const std::size_t n = snapshot.grain_count();
  for (std::size_t g = 0; g < n; ++g)
    sum += 2.0 * std::sqrt(file.shapes.at(static_cast<std::size_t>(snapshot.body[g])).area / M_PI);
  return n ? sum / n : 0.0;
}

Outline outline_of_pile(const dem::DemFile& file, const dem::Snapshot& snapshot, double strip_width,
                        double tolerance) {
  const std::size_t n = snapshot.grain_count();
  if (n < 3)
    throw InputError(file.path + ": snapshot '" + snapshot.name + "' has " + std::to_string(n) +
                     " grains; a pile outline needs at least 3");
  // Every grain's boundary points in the world frame: polygon corners, or a disc's extreme
  // points (left, right, top).
  double xmin = INFINITY, xmax = -INFINITY;
  std::vector<double> top_of_grain(n), left_of_grain(n), right_of_grain(n);
  for (std::size_t g = 0; g < n; ++g) {
    const dem::Vec2 c(snapshot.position[2 * g], snapshot.position[2 * g + 1]);
    const dem::Shape& s = file.shapes.at(static_cast<std::size_t>(snapshot.body[g]));
    double top = c.y() + s.radius, left = c.x() - s.radius, right = c.x() + s.radius;
    double sn, cs;
    rotation_sincos(snapshot.angle[g], sn, cs);
    for (const dem::Vec2& v : s.vertices) {
      const dem::Vec2 w = c + dem::rotate(v, cs, sn);
      top = std::max(top, w.y());
      left = std::min(left, w.x());
      right = std::max(right, w.x());
    }
    top_of_grain[g] = top;
    left_of_grain[g] = left;
    right_of_grain[g] = right;
    xmin = std::min(xmin, left);
    xmax = std::max(xmax, right);
  }
  const int strips = std::max(1, static_cast<int>(std::ceil((xmax - xmin) / strip_width)));
  const double width = (xmax - xmin) / strips;
  std::vector<double> top(strips, -INFINITY);
  for (std::size_t g = 0; g < n; ++g) {
    const int b = std::clamp(static_cast<int>((snapshot.position[2 * g] - xmin) / width), 0, strips - 1);
    top[b] = std::max(top[b], top_of_grain[g]);
  }
  std::vector<dem::Vec2> surface;
  surface.emplace_back(xmin, 0.0);
  for (int b = 0; b < strips; ++b)
    if (top[b] > 0) surface.emplace_back(xmin + (b + 0.5) * width, top[b]);
  surface.emplace_back(xmax, 0.0);
  surface = simplify_polyline(surface, tolerance);

  Outline outline;
  outline.surface = surface;
  outline.apex_index = 0;
  for (int i = 1; i + 1 < static_cast<int>(surface.size()); ++i)
    if (surface[i].y() > surface[outline.apex_index].y()) outline.apex_index = i;
  if (outline.apex_index == 0)
    throw InputError(file.path + ": snapshot '" + snapshot.name + "' has no pile above the plate");
  return outline;
}

}  // namespace pilelab::mesh
