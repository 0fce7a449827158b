#pragma once
// Wedge meshes for the closures' verification: fans of triangles around the apex whose edges
// can follow the exact solutions' kinks.
#include <cmath>
#include <memory>
#include <vector>

#include "continuum/pile_domain.h"

namespace pilelab::testing {

using continuum::make_triangulation;
using continuum::Triangulation2;
using dealii::Point;

// Boundary ids from position: base y = 0 -> 1, flanks left / right of the apex -> 2 / 3.
inline void set_wedge_ids(Triangulation2& tria, double apex_x) {
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary()) {
        const Point<2> c = cell->face(f)->center();
        cell->face(f)->set_boundary_id(std::abs(c[1]) < 1e-12 ? 1 : c[0] < apex_x ? 2 : 3);
      }
}

// A wedge from a coarse fan of triangles around the apex, refined `levels` times (red
// refinement: every edge of the coarse mesh stays a line of edges). base_x: the base points
// between the feet, each joined to the apex.
inline std::unique_ptr<Triangulation2> fan_wedge(double h, double phi_left, double phi_right, std::vector<double> base_x,
                                                 unsigned levels) {
  constexpr double deg = M_PI / 180;
  auto tria = make_triangulation(MPI_COMM_WORLD);
  std::vector<Point<2>> v;
  v.emplace_back(-h / std::tan(phi_left * deg), 0);
  for (double x : base_x) v.emplace_back(x, 0);
  v.emplace_back(h / std::tan(phi_right * deg), 0);
  const unsigned apex = v.size();
  v.emplace_back(0, h);
  std::vector<dealii::CellData<2>> cells;
  for (unsigned i = 0; i + 1 < apex; ++i) {
    dealii::CellData<2> c(3);
    c.vertices = {i, i + 1, apex};
    cells.push_back(c);
  }
  tria->create_triangulation(v, cells, {});
  set_wedge_ids(*tria, 0.0);
  tria->refine_global(levels);
  return tria;
}

}  // namespace pilelab::testing
