#pragma once
// The free surface of a DEM pile as a polyline, for meshing the pile itself.
//
// Method: the x range of the grains is cut into strips of width strip_width; the surface in a
// strip is the highest point of any grain polygon (or disc) whose centre lies in it. Empty
// strips (gaps between run-out grains) are bridged by the straight line between their
// neighbours. The polyline runs from the left foot (the leftmost grain point, y = 0) over the
// strip tops to the right foot; it is then simplified (Douglas-Peucker) so that no surface
// point moves by more than tolerance, which keeps tiny edges out of the mesh.
#include "dem/dem_file.h"
#include "mesh/pile_mesh.h"

namespace pilelab::mesh {

Outline outline_of_pile(const dem::DemFile& file, const dem::Snapshot& snapshot, double strip_width,
                        double tolerance);

/// The mean free surface of several piles (an ensemble's): each outline read as a height h_k(x),
/// linear between its points and zero beyond its feet, averaged at points spacing apart from the
/// leftmost foot to the rightmost. Exact on the grid for piecewise-linear surfaces; the caller
/// simplifies. Throws InputError when the list is empty.
Outline mean_outline(const std::vector<Outline>& outlines, double spacing);

/// The outline with its height h(x) replaced by its mean over a window of the given width
/// (a moving average; h is 0 beyond the feet, so the toes spread by half the window). The
/// steps and notches of single grains along a flank, which a mesh would have to follow and
/// which the FPA's characteristics leave the pile through (docs/CONTINUUM.md), are smoothed to
/// the window's scale; a straight flank stays straight. Sampled every width / 16.
Outline smoothed_outline(const Outline& outline, double width);

/// The grains' mean area-equivalent diameter, 2 sqrt(A / pi), in a snapshot [m].
double mean_grain_diameter(const dem::DemFile& file, const dem::Snapshot& snapshot);

/// Douglas-Peucker simplification of an open polyline; the end points are kept.
std::vector<dem::Vec2> simplify_polyline(const std::vector<dem::Vec2>& points, double tolerance);

}  // namespace pilelab::mesh
