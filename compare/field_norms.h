#pragma once
// Integrals over the pile of fields given at the nodes of its triangulation, with linear
// interpolation on each triangle (exact for the products of two such fields):
//   int_T f g = |T|/12 (sum_i f_i g_i + (sum_i f_i)(sum_i g_i)).
// Only triangles whose three nodes have data in every field involved count.
#include <functional>
#include <vector>

#include "compare/point_fields.h"

namespace pilelab::compare {

/// Which triangles take part (by centroid), e.g. the lower half of the pile.
using Region = std::function<bool(const Vec2& centroid)>;

struct L2Difference {
  double difference = 0.0;   ///< || a - b ||
  double reference = 0.0;    ///< || b ||
  double relative = 0.0;     ///< difference / reference (0 if the reference vanishes, NaN if no triangle counts)
  double area = 0.0;         ///< area integrated over [m^2]
};

/// || a - b ||_L2 over the triangles in region where both have data.
L2Difference l2_difference(const Triangulation& mesh, const std::vector<double>& a, const std::vector<char>& a_ok,
                           const std::vector<double>& b, const std::vector<char>& b_ok, const Region& region = {});

/// Area-weighted mean of a nodal field over the triangles (in region) where it has data; NaN
/// (written to JSON as null) if there is none.
double area_mean(const Triangulation& mesh, const std::vector<double>& f, const std::vector<char>& ok,
                 const Region& region = {});

/// Angle between two axes given as orientations in degrees (mod 180): in [0, 90].
double axis_angle_deg(double a_deg, double b_deg);

}  // namespace pilelab::compare
