#pragma once
// Exact areas of intersection with a circle, for volume fractions computed from the grain
// outlines and for RVE volumes clipped to the pile.
//
// Method: the area of a region bounded by oriented edges is the sum over its edges of the
// signed area swept from a fixed point; taking the circle's centre as that point, each edge
// contributes the signed area of (triangle centre-a-b) intersected with the circle, which has
// a closed form (triangle parts inside, circular sectors outside). It holds for any simple
// polygon, convex or not, and for any set of closed oriented boundaries.
#include <vector>

#include "dem/vec2.h"

namespace pilelab::coarse {

/// Signed area of (triangle c, a, b) intersected with the disc |x - c| <= r.
double circle_sector_clip_area(const dem::Vec2& c, double r, const dem::Vec2& a, const dem::Vec2& b);

/// Area of the polygon (counter-clockwise corners) inside the circle.
double circle_polygon_area(const dem::Vec2& centre, double radius, const std::vector<dem::Vec2>& polygon);

/// Area common to two discs.
double circle_circle_area(const dem::Vec2& c1, double r1, const dem::Vec2& c2, double r2);

}  // namespace pilelab::coarse
