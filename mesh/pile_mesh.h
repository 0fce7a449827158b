#pragma once
// The pile triangulation shared by coarse/ and continuum/. Meshes are made with gmsh's C++
// API and written as MSH 4.1 (ASCII), which gmsh, meshio and deal.II's GridIn all read.
//
// Boundary convention (named physical curves "BoundaryID:n", because deal.II's gmsh reader
// ignores unnamed groups): see BoundaryId. All cells form one physical surface "MaterialID:0".
// The pile stands on y = 0; lengths are in metres; angles in degrees from the horizontal.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "common/scene_reader.h"
#include "dem/vec2.h"

namespace pilelab::mesh {

enum BoundaryId : int {
  base = 1,         ///< y = 0, where the pile rests on the plate
  left_flank = 2,   ///< free surface left of the apex
  right_flank = 3,  ///< free surface right of the apex
  side_wall = 4,    ///< vertical walls of a block
  top = 5,          ///< free top of a block
};

/// An ideal triangular pile: apex at (apex_x_m, height_m), flanks at the repose angles.
struct Wedge {
  double height_m = 0.33;
  double left_angle_deg = 28.0;
  double right_angle_deg = 28.0;
  double apex_x_m = 0.0;
};

/// A rectangle [-width/2, width/2] x [0, height]: the test geometry with closed-form stresses.
struct Block {
  double width_m = 1.0;
  double height_m = 1.0;
};

/// The free surface of a DEM pile: points from the left foot (y = 0) over the apex to the
/// right foot (y = 0), x increasing. The base closes the outline along y = 0.
struct Outline {
  std::vector<dem::Vec2> surface;
  int apex_index = 0;  ///< the highest point; left of it is the left flank, right the right flank
};

struct MeshSpec {
  enum class Kind { wedge, block, dem_outline } kind = Kind::wedge;
  Wedge wedge;
  Block block;
  std::string dem_file;                 ///< kind == dem_outline: the dem.h5 whose pile is meshed
  std::vector<std::string> dem_files;   ///< kind == dem_outline, an ensemble: the mean outline of these
  std::string dem_snapshot = "settled";
  /// kind == dem_outline: the surface's height averaged over this many mean grain diameters
  /// (smoothed_outline); 0 keeps the grains' own steps.
  double outline_smoothing_grains = 3.0;
  double element_size_m = 0.02;         ///< target edge length
  double axis_element_size_m = 0.0;     ///< near the vertical axis through the apex (0: same)
  bool embed_axis = true;               ///< element edges follow the axis (the FPA kink)
  /// Also the FPA's two characteristics from the apex, at psi = 45 - phi/2 from the vertical
  /// (kinks of its stress), where they run inside the pile (the scene's default: on wherever
  /// the axis is). A wedge takes phi from its flanks; a DEM outline from ray_angles_deg.
  bool embed_rays = false;
  /// kind == dem_outline: the FPA's angles of repose (left, right) [degree] whose rays are
  /// embedded; 0 when none is known (then no ray is embedded, and the outcome says so).
  double ray_left_angle_deg = 0.0, ray_right_angle_deg = 0.0;
};

/// What write_mesh made beyond the spec: whether the FPA's rays are edges of the mesh, and if
/// not, why (a ray that leaves a ragged outline, an outline without an apex between its feet,
/// no angles known).
struct MeshOutcome {
  bool rays_embedded = false;
  double ray_left_angle_deg = 0.0, ray_right_angle_deg = 0.0;  ///< the phi of the embedded rays
  std::string rays_note;  ///< empty when embedded or not asked for
};

/// Where the FPA's characteristics from the apex of an outline meet the base, if both run
/// inside the pile: each ray from the apex at psi = 45 - phi/2 degrees from the vertical must
/// reach the base between the feet without crossing the outline (on a ragged surface a notch
/// near the apex can cut it). Otherwise why_not names the side and the crossing.
struct RayFeet {
  double left_x = 0.0, right_x = 0.0;  ///< [m]
};
std::optional<RayFeet> fpa_ray_feet(const Outline& outline, double left_angle_deg, double right_angle_deg,
                                    std::string& why_not);

/// Reads the [mesh] table; relative file names are taken relative to scene_dir.
MeshSpec read_mesh_scene(SceneReader& reader, const std::string& scene_dir);

/// The outline of an ideal wedge (surface points left foot, apex, right foot).
Outline wedge_outline(const Wedge& wedge);

/// About how many triangles gmsh makes of a region of this area with these sizes (the smaller
/// axis size counts, since gmsh grades the size linearly away from the axis). write_mesh
/// refuses a spec whose estimate exceeds 4e6.
double estimated_triangle_count(double area, const MeshSpec& spec);

/// Meshes spec and writes msh_path atomically. Throws InputError on degenerate geometry.
MeshOutcome write_mesh(const MeshSpec& spec, const std::string& msh_path);

/// Meshes the region between an outline and the base with spec's sizes and embedded lines
/// (spec.kind only decides where the rays' angles come from), and writes msh_path atomically.
MeshOutcome write_outline_mesh(const Outline& outline, const MeshSpec& spec, const std::string& msh_path);

/// A triangulation as plain arrays (what coarse/ needs; deal.II reads the file itself).
struct TriangleMesh {
  std::vector<dem::Vec2> nodes;
  std::vector<std::array<int, 3>> triangles;   ///< node indices, counter-clockwise
  std::vector<std::array<int, 2>> boundary_edges;
  std::vector<int> boundary_edge_ids;          ///< a BoundaryId per boundary edge
};

/// Total area of the triangles [m^2].
double mesh_area(const TriangleMesh& mesh);

/// Reads a 2D linear-triangle mesh from an MSH file. Throws InputError naming the file when
/// it is missing, unreadable, holds no triangles, or holds inverted (clockwise) triangles.
TriangleMesh read_triangle_mesh(const std::string& msh_path);

}  // namespace pilelab::mesh
