#include "continuum/pile_domain.h"

#include <algorithm>
#include <cmath>

#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include "common/error.h"
#include "mesh/pile_mesh.h"

namespace pilelab::continuum {

using namespace dealii;

std::unique_ptr<Triangulation2> make_triangulation(MPI_Comm comm) {
  return std::make_unique<Triangulation2>(comm, Triangulation<2>::none, /*allow_artificial_cells=*/false,
                                          Triangulation2::partition_metis);
}

const Mapping<2>& simplex_mapping() {
  static const MappingFE<2> mapping(FE_SimplexP<2>(1));
  return mapping;
}

void check_has_base(const Triangulation<2>& tria, const std::string& what) {
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == mesh::BoundaryId::base) return;
  throw InputError(what + ": the mesh has no base: expected boundary edges in the physical group "
                          "\"BoundaryID:1\" (the line y = 0 the pile rests on)");
}

void read_pile_mesh(const std::string& msh_path, Triangulation2& tria) {
  // Missing, unreadable, empty and inverted meshes are refused here, with the file's name.
  const mesh::TriangleMesh m = mesh::read_triangle_mesh(msh_path);

  std::vector<Point<2>> vertices;
  vertices.reserve(m.nodes.size());
  for (const auto& p : m.nodes) vertices.emplace_back(p.x(), p.y());
  std::vector<CellData<2>> cells(m.triangles.size(), CellData<2>(3));
  for (std::size_t c = 0; c < m.triangles.size(); ++c) {
    for (unsigned v = 0; v < 3; ++v) cells[c].vertices[v] = m.triangles[c][v];
    cells[c].material_id = 0;
  }
  SubCellData boundary;
  for (std::size_t e = 0; e < m.boundary_edges.size(); ++e) {
    CellData<1> line(2);
    line.vertices[0] = m.boundary_edges[e][0];
    line.vertices[1] = m.boundary_edges[e][1];
    line.boundary_id = static_cast<types::boundary_id>(m.boundary_edge_ids[e]);
    boundary.boundary_lines.push_back(line);
  }
  // gmsh files may contain nodes no triangle uses (e.g. geometry points); deal.II refuses them.
  GridTools::delete_unused_vertices(vertices, cells, boundary);
  try {
    tria.create_triangulation(vertices, cells, boundary);
  } catch (const std::exception& e) {
    throw InputError(msh_path + ": deal.II cannot build a triangulation from this mesh: " + e.what());
  }
  check_has_base(tria, msh_path);
}

PileGeometry measure_pile(const Triangulation<2>& tria) {
  PileGeometry g;
  const auto& vertices = tria.get_vertices();
  const auto& used = tria.get_used_vertices();
  double ymax = -1e300, xmin = 1e300, xmax = -1e300;
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (used[i]) {
      ymax = std::max(ymax, vertices[i][1]);
      xmin = std::min(xmin, vertices[i][0]);
      xmax = std::max(xmax, vertices[i][0]);
    }
  g.height_m = ymax;
  const double tol = 1e-9 * std::max(1.0, xmax - xmin);
  double sum = 0;
  int count = 0;
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (used[i] && vertices[i][1] >= ymax - tol) {
      sum += vertices[i][0];
      ++count;
    }
  g.apex_x_m = sum / count;
  for (const auto& cell : tria.active_cell_iterators()) {
    g.area_m2 += cell->measure();
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == mesh::BoundaryId::base) g.base_length_m += cell->face(f)->measure();
  }
  return g;
}

}  // namespace pilelab::continuum
