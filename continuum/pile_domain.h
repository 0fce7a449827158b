#pragma once
// The pile as deal.II sees it: a triangulation shared by all MPI ranks (p4est is for
// quadrilaterals only; parallel::shared partitions triangles with METIS), the linear simplex
// mapping every FEValues needs, and the few geometric numbers the models are scaled with.
#include <memory>
#include <string>

#include <deal.II/distributed/shared_tria.h>
#include <deal.II/fe/mapping_fe.h>

namespace pilelab::continuum {

using Triangulation2 = dealii::parallel::shared::Triangulation<2>;

/// An empty triangulation on comm, partitioned with METIS across its ranks.
std::unique_ptr<Triangulation2> make_triangulation(MPI_Comm comm);

/// Reads a gmsh mesh (named groups "BoundaryID:n", see mesh/pile_mesh.h) into tria through
/// mesh::read_triangle_mesh, the reader coarse/ uses too, so both stages see the same mesh.
/// Throws InputError naming the file for a missing, unreadable, empty or inverted mesh and for
/// a mesh without a base (boundary id 1).
void read_pile_mesh(const std::string& msh_path, Triangulation2& tria);

/// Throws InputError (naming `what`) unless tria has boundary faces with id 1 (the base).
void check_has_base(const dealii::Triangulation<2>& tria, const std::string& what);

/// The linear simplex mapping: deal.II's default mapping is for quadrilaterals.
const dealii::Mapping<2>& simplex_mapping();

struct PileGeometry {
  double height_m = 0;      ///< highest vertex above y = 0
  double apex_x_m = 0;      ///< x of the highest vertex (mean x if the top is flat)
  double area_m2 = 0;       ///< area of the domain (pile weight = rho g area)
  double base_length_m = 0;
};

PileGeometry measure_pile(const dealii::Triangulation<2>& tria);

}  // namespace pilelab::continuum
