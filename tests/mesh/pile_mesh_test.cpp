// The pile triangulation: exact areas and boundary lengths of the ideal shapes, the boundary
// convention deal.II relies on, and clear errors for bad mesh files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "common/error.h"
#include "mesh/pile_mesh.h"

using namespace pilelab::mesh;
namespace dem = pilelab::dem;

namespace {
// This process's scratch directory, removed when the process ends.
struct ScratchDirectory {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("pilelab_mesh_test_" + std::to_string(::getpid()));
  ~ScratchDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
};

std::string temp_path(const std::string& name) {
  static const ScratchDirectory scratch;
  std::filesystem::create_directories(scratch.dir);
  return (scratch.dir / name).string();
}

std::map<int, double> boundary_lengths(const TriangleMesh& m) {
  std::map<int, double> len;
  for (std::size_t e = 0; e < m.boundary_edges.size(); ++e)
    len[m.boundary_edge_ids[e]] += (m.nodes[m.boundary_edges[e][1]] - m.nodes[m.boundary_edges[e][0]]).norm();
  return len;
}
}  // namespace

// A polygonal domain is meshed exactly: the triangles tile it, so their areas sum to the
// wedge's area and the tagged edges to its side lengths, up to round-off.
TEST(PileMesh, AsymmetricWedgeIsTiledExactlyWithTaggedBoundaries) {
  MeshSpec spec;
  spec.wedge = {0.33, 28.0, 22.0, 0.05};
  spec.element_size_m = 0.02;
  spec.axis_element_size_m = 0.01;
  const std::string path = temp_path("wedge.msh");
  write_mesh(spec, path);
  const TriangleMesh m = read_triangle_mesh(path);
  const double h = 0.33, tl = std::tan(28.0 * M_PI / 180), tr = std::tan(22.0 * M_PI / 180);
  EXPECT_NEAR(mesh_area(m), 0.5 * h * h * (1 / tl + 1 / tr), 1e-12);
  const auto len = boundary_lengths(m);
  EXPECT_NEAR(len.at(BoundaryId::base), h / tl + h / tr, 1e-12);
  EXPECT_NEAR(len.at(BoundaryId::left_flank), h / std::sin(28.0 * M_PI / 180), 1e-12);
  EXPECT_NEAR(len.at(BoundaryId::right_flank), h / std::sin(22.0 * M_PI / 180), 1e-12);
  // The axis is embedded: nodes lie on x = apex_x all the way down.
  int on_axis = 0;
  for (const auto& p : m.nodes) on_axis += std::abs(p.x() - 0.05) < 1e-12;
  EXPECT_GE(on_axis, static_cast<int>(h / 0.01));
}

// With the FPA rays embedded, element edges run along both characteristics from the apex,
// at psi = 45 - phi/2 degrees from the vertical, down to the base.
TEST(PileMesh, FpaRaysAreMeshEdges) {
  MeshSpec spec;
  spec.wedge = {0.33, 28.0, 22.0, 0.0};
  spec.element_size_m = 0.02;
  spec.embed_rays = true;
  const std::string path = temp_path("rays.msh");
  write_mesh(spec, path);
  const TriangleMesh m = read_triangle_mesh(path);
  const double h = 0.33, tl = std::tan(28.0 * M_PI / 180), tr = std::tan(22.0 * M_PI / 180);
  EXPECT_NEAR(mesh_area(m), 0.5 * h * h * (1 / tl + 1 / tr), 1e-12);
  for (double phi : {28.0, 22.0}) {
    const double t = std::tan((45.0 - phi / 2) * M_PI / 180), side = phi == 28.0 ? -1.0 : 1.0;
    int on_ray = 0;
    for (const auto& p : m.nodes) on_ray += std::abs(p.x() - side * (h - p.y()) * t) < 1e-12 && p.y() < h - 1e-9;
    EXPECT_GE(on_ray, static_cast<int>(h / 0.02)) << phi;
  }
}

namespace {
// A 26 / 24 degree pile whose flanks are stairs of grain-sized steps (treads and risers of
// about 1 cm), as a DEM outline is before smoothing; apex at (0, h), feet at y = 0.
Outline stepped_pile(double h) {
  Outline o;
  const double step = 0.01;
  for (const auto& [phi, sign] : {std::pair{26.0, -1.0}, std::pair{24.0, 1.0}}) {
    std::vector<dem::Vec2> side;
    const double run = h / std::tan(phi * M_PI / 180);
    const int n = static_cast<int>(run / step);
    for (int k = n; k >= 1; --k) {  // from the foot up: riser, then tread
      const double x = sign * run * k / n, y = h * (n - k) / n;
      side.emplace_back(x, y);
      side.emplace_back(x, y + h / n);
    }
    if (sign < 0) {
      for (const auto& p : side) o.surface.push_back(p);
      o.apex_index = static_cast<int>(o.surface.size());
      o.surface.emplace_back(0.0, h);
    } else {
      const std::vector<dem::Vec2> right(side.rbegin(), side.rend());
      for (const auto& p : right) o.surface.push_back(p);
    }
  }
  return o;
}

int nodes_on_ray(const TriangleMesh& m, double h, double phi, double sign) {
  const double t = std::tan((45.0 - phi / 2) * M_PI / 180);
  int on_ray = 0;
  for (const auto& p : m.nodes) on_ray += std::abs(p.x() - sign * (h - p.y()) * t) < 1e-12 && p.y() < h - 1e-9;
  return on_ray;
}
}  // namespace

// The characteristics run from the apex at psi = 45 - phi/2 from the vertical and meet the base
// at x = x_apex -+ h tan(psi).
TEST(FpaRayFeet, LieWhereTheCharacteristicsMeetTheBase) {
  const double h = 0.3;
  std::string why;
  const auto feet = fpa_ray_feet(stepped_pile(h), 26.0, 24.0, why);
  ASSERT_TRUE(feet) << why;
  EXPECT_NEAR(feet->left_x, -h * std::tan(32.0 * M_PI / 180), 1e-15);
  EXPECT_NEAR(feet->right_x, h * std::tan(33.0 * M_PI / 180), 1e-15);
}

// On a DEM-like outline the rays are mesh edges as on a wedge, and the mesh still tiles the
// region exactly.
TEST(PileMesh, FpaRaysAreMeshEdgesOnARaggedOutline) {
  const double h = 0.3;
  const Outline outline = stepped_pile(h);
  MeshSpec spec;
  spec.kind = MeshSpec::Kind::dem_outline;
  spec.element_size_m = 0.02;
  spec.embed_rays = true;
  spec.ray_left_angle_deg = 26.0;
  spec.ray_right_angle_deg = 24.0;
  const std::string path = temp_path("ragged_rays.msh");
  const MeshOutcome outcome = write_outline_mesh(outline, spec, path);
  ASSERT_TRUE(outcome.rays_embedded) << outcome.rays_note;
  const TriangleMesh m = read_triangle_mesh(path);
  double twice = 0;  // the outline's area (shoelace; the base closes it at y = 0)
  for (std::size_t i = 0; i + 1 < outline.surface.size(); ++i)
    twice += outline.surface[i].x() * outline.surface[i + 1].y() - outline.surface[i + 1].x() * outline.surface[i].y();
  EXPECT_NEAR(mesh_area(m), std::abs(twice) / 2, 1e-12);
  EXPECT_GE(nodes_on_ray(m, h, 26.0, -1.0), static_cast<int>(h / 0.02));
  EXPECT_GE(nodes_on_ray(m, h, 24.0, 1.0), static_cast<int>(h / 0.02));
}

// Where a ray would leave the pile the mesh follows the axis only, and says which ray and where.
TEST(PileMesh, ARayThatLeavesThePileIsNotEmbeddedAndTheOutcomeSaysWhy) {
  const double h = 0.3;
  MeshSpec spec;
  spec.kind = MeshSpec::Kind::dem_outline;
  spec.element_size_m = 0.02;
  spec.embed_rays = true;
  spec.ray_left_angle_deg = spec.ray_right_angle_deg = 25.0;
  {
    // A notch in the left flank, 0.1 m from the axis, reaching down below the left ray.
    Outline notched = stepped_pile(h);
    std::vector<dem::Vec2>& s = notched.surface;
    const auto at = std::find_if(s.begin(), s.end(), [](const dem::Vec2& p) { return p.x() > -0.1; });
    const double below_ray = h - 0.1 / std::tan(32.5 * M_PI / 180) - 0.01;  // the ray is at y = 0.143 m there
    s.insert(at, {dem::Vec2(-0.1, below_ray), dem::Vec2(-0.095, below_ray)});
    notched.apex_index += 2;
    const MeshOutcome outcome = write_outline_mesh(notched, spec, temp_path("notched.msh"));
    EXPECT_FALSE(outcome.rays_embedded);
    EXPECT_NE(outcome.rays_note.find("left ray"), std::string::npos) << outcome.rays_note;
    EXPECT_NE(outcome.rays_note.find("crosses the surface"), std::string::npos) << outcome.rays_note;
    EXPECT_GT(read_triangle_mesh(temp_path("notched.msh")).triangles.size(), 0u);
  }
  {
    // A top whose right side drops more steeply than the right ray (a grain standing on the apex).
    Outline spire = stepped_pile(h);
    spire.surface.insert(spire.surface.begin() + spire.apex_index + 1, dem::Vec2(0.001, h - 0.01));
    const MeshOutcome outcome = write_outline_mesh(spire, spec, temp_path("spire.msh"));
    EXPECT_FALSE(outcome.rays_embedded);
    EXPECT_NE(outcome.rays_note.find("right ray"), std::string::npos) << outcome.rays_note;
    EXPECT_NE(outcome.rays_note.find("at the apex"), std::string::npos) << outcome.rays_note;
  }
  {
    // No angles known: nothing to embed.
    MeshSpec no_angles = spec;
    no_angles.ray_left_angle_deg = no_angles.ray_right_angle_deg = 0.0;
    const MeshOutcome outcome = write_outline_mesh(stepped_pile(h), no_angles, temp_path("no_angles.msh"));
    EXPECT_FALSE(outcome.rays_embedded);
    EXPECT_NE(outcome.rays_note.find("no angles"), std::string::npos) << outcome.rays_note;
  }
}

TEST(PileMesh, BlockHasBaseSideWallsAndTop) {
  MeshSpec spec;
  spec.kind = MeshSpec::Kind::block;
  spec.block = {2.0, 1.0};
  spec.element_size_m = 0.1;
  const std::string path = temp_path("block.msh");
  write_mesh(spec, path);
  const TriangleMesh m = read_triangle_mesh(path);
  EXPECT_NEAR(mesh_area(m), 2.0, 1e-12);
  const auto len = boundary_lengths(m);
  EXPECT_NEAR(len.at(BoundaryId::base), 2.0, 1e-12);
  EXPECT_NEAR(len.at(BoundaryId::side_wall), 2.0, 1e-12);
  EXPECT_NEAR(len.at(BoundaryId::top), 2.0, 1e-12);
}

TEST(PileMesh, MissingFileIsNamed) {
  try {
    read_triangle_mesh("/nonexistent/pile.msh");
    FAIL();
  } catch (const pilelab::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/pile.msh"), std::string::npos);
  }
}

TEST(PileMesh, CorruptFileIsAnError) {
  const std::string path = temp_path("corrupt.msh");
  std::ofstream(path) << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n2 1 0 3\n1\n";
  EXPECT_THROW(read_triangle_mesh(path), pilelab::InputError);
}

TEST(PileMesh, InvertedTriangleIsRefused) {
  // One clockwise triangle in MSH 2.2 ASCII.
  const std::string path = temp_path("inverted.msh");
  std::ofstream(path) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 0 1 0\n3 1 0 0\n$EndNodes\n"
                         "$Elements\n1\n1 2 2 100 1 1 2 3\n$EndElements\n";
  try {
    read_triangle_mesh(path);
    FAIL();
  } catch (const pilelab::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("inverted"), std::string::npos) << e.what();
  }
}

// A triangle copied over another (the same corners under a new element number) would count the
// grains under it twice in every coarse-grained field: refused, naming both triangles.
TEST(PileMesh, OverlappingTrianglesAreRefused) {
  const std::string square = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n";
  const std::string good = temp_path("two_triangles.msh");
  std::ofstream(good) << square << "$Elements\n2\n1 2 2 100 1 1 2 3\n2 2 2 100 1 1 3 4\n$EndElements\n";
  EXPECT_NEAR(mesh_area(read_triangle_mesh(good)), 1.0, 1e-15);  // the square, as a control
  const std::string copied = temp_path("copied_triangle.msh");
  std::ofstream(copied) << square << "$Elements\n3\n1 2 2 100 1 1 2 3\n2 2 2 100 1 1 3 4\n3 2 2 100 1 2 3 1\n$EndElements\n";
  try {
    read_triangle_mesh(copied);
    FAIL() << "a triangle lying over another was accepted";
  } catch (const pilelab::InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(copied), std::string::npos) << message;
    EXPECT_NE(message.find("triangles 1 and 3 overlap"), std::string::npos) << message;
  }
}

TEST(PileMesh, AbsurdElementCountIsRefused) {
  MeshSpec spec;
  spec.element_size_m = 1e-5;
  EXPECT_THROW(write_mesh(spec, temp_path("huge.msh")), pilelab::InputError);
}

// A fine axis size grades the whole mesh around the axis: the estimate the guard uses follows
// gmsh's count (within a factor 1.5 either way; an estimate blind to the axis size is off by
// s / a), and an absurd axis size is refused even with a modest element size.
TEST(PileMesh, AxisElementSizeCountsInTheElementEstimate) {
  for (bool axis : {true, false})
    for (double a : {0.02, 0.004, 0.001}) {
      MeshSpec spec;
      spec.wedge = {0.2, 30.0, 25.0, 0.0};
      spec.element_size_m = 0.02;
      spec.axis_element_size_m = a;
      spec.embed_axis = axis;
      write_mesh(spec, temp_path("graded.msh"));
      const TriangleMesh m = read_triangle_mesh(temp_path("graded.msh"));
      const double ratio = m.triangles.size() / estimated_triangle_count(mesh_area(m), spec);
      EXPECT_GT(ratio, 1 / 1.5) << axis << " " << a;
      EXPECT_LT(ratio, 1.5) << axis << " " << a;
    }
  MeshSpec spec;
  spec.element_size_m = 0.02;
  spec.axis_element_size_m = 1e-7;
  try {
    write_mesh(spec, temp_path("fine_axis.msh"));
    FAIL() << "no error for a 0.1 micron axis size";
  } catch (const pilelab::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.axis_element_size_m"), std::string::npos) << e.what();
  }
}

// The .geo templates in meshes/ give gmsh the same geometry and boundary tags as the API.
TEST(PileMesh, GeoTemplatesMeshWithGmsh) {
  struct Case {
    std::string geo, args;
    double area;
  };
  const double h = 0.33, t28 = std::tan(28.0 * M_PI / 180), t30 = std::tan(30.0 * M_PI / 180);
  const std::vector<Case> cases = {
      {"wedge.geo", "-setnumber left_angle_deg 30", 0.5 * h * h * (1 / t30 + 1 / t28)},
      {"symmetric_wedge.geo", "-setnumber repose_angle_deg 30", h * h / t30},
      {"block.geo", "-setnumber width_m 2 -setnumber height_m 0.5", 1.0}};
  for (const Case& c : cases) {
    const std::string out = temp_path(c.geo + ".msh");
    const std::string cmd = "gmsh -2 " + std::string(PILELAB_SOURCE_DIR) + "/meshes/" + c.geo + " " + c.args +
                            " -o " + out + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const TriangleMesh m = read_triangle_mesh(out);
    EXPECT_NEAR(mesh_area(m), c.area, 1e-12) << c.geo;
    EXPECT_GT(boundary_lengths(m).at(BoundaryId::base), 0.0) << c.geo;
  }
}
