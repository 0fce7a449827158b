// The pile triangulation: exact areas and boundary lengths of the ideal shapes, the boundary
// convention deal.II relies on, and clear errors for bad mesh files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "common/error.h"
#include "mesh/pile_mesh.h"

using namespace pilelab::mesh;

namespace {
std::string temp_path(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("pilelab_mesh_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
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
