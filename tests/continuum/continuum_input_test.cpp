// Bad input to the continuum stage: each case is an InputError that names the file, the field
// and what was expected (never a crash, a hang or a NaN further down).
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/error.h"
#include "continuum/pile_domain.h"
#include "continuum/elastic_problem.h"
#include "continuum/models/fpa.h"
#include "continuum/models/osl.h"
#include "continuum/settings.h"
#include "mpi_environment.h"

using namespace pilelab;
using namespace pilelab::continuum;

namespace {

std::string error_of(const std::string& toml) {
  try {
    SceneReader r(toml, "scene.toml");
    read_continuum_scene(r, ".");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string temp_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("pilelab_continuum_input_" + name);
  std::ofstream(path) << text;
  return path.string();
}

std::string mesh_error(const std::string& path) {
  try {
    auto tria = make_triangulation(MPI_COMM_WORLD);
    read_pile_mesh(path, *tria);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A one-triangle mesh in MSH 2.2 (ASCII), the triangle's nodes in the given order and its
// edge 1-2 in the physical group "BoundaryID:<id>".
std::string one_triangle_msh(const std::string& nodes, int boundary_id) {
  const std::string id = std::to_string(boundary_id);
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 " + id + " \"BoundaryID:" + id +
         "\"\n2 100 \"MaterialID:0\"\n$EndPhysicalNames\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
         "$Elements\n2\n1 1 2 " + id + " 1 1 2\n2 2 2 100 1 " + nodes + "\n$EndElements\n";
}

}  // namespace

TEST(ContinuumInput, DefaultsAreValid) {
  SceneReader r("[continuum]\n", "scene.toml");
  const ContinuumSettings s = read_continuum_scene(r, ".");
  EXPECT_TRUE(s.wants("elastic") && s.wants("fpa") && !s.wants("osl"));
  EXPECT_DOUBLE_EQ(s.settings_of<FpaSettings>("fpa").left_repose_angle_deg, 28.0);
  EXPECT_EQ(s.settings_of<ElasticSettings>("elastic").degree, 2);
}

TEST(ContinuumInput, PoissonRatioAtOrAboveOneHalfIsRefused) {
  for (const char* nu : {"0.5", "0.6"}) {
    const std::string e = error_of(std::string("[continuum.elastic]\npoisson_ratio = ") + nu + "\n");
    EXPECT_NE(e.find("scene.toml"), std::string::npos) << e;
    EXPECT_NE(e.find("continuum.elastic.poisson_ratio"), std::string::npos) << e;
    EXPECT_NE(e.find("nu < 0.5"), std::string::npos) << e;
  }
  EXPECT_EQ(error_of("[continuum.elastic]\npoisson_ratio = 0.499\n"), "");
}

TEST(ContinuumInput, ReposeAngleOutsideZeroToFortyFiveIsRefused) {
  for (const char* line : {"repose_angle_deg = 45.0", "repose_angle_deg = 0", "repose_angle_deg = -10",
                           "left_repose_angle_deg = 50", "right_repose_angle_deg = 0.0"}) {
    const std::string e = error_of(std::string("[continuum.fpa]\n") + line + "\n");
    EXPECT_NE(e.find("continuum.fpa."), std::string::npos) << line << ": " << e;
    EXPECT_NE(e.find("0 < angle of repose < 45"), std::string::npos) << e;
  }
  EXPECT_EQ(error_of("[continuum.fpa]\nleft_repose_angle_deg = 28\nright_repose_angle_deg = 21\n"), "");
}

TEST(ContinuumInput, ReposeAnglesFromTheDemReport) {
  SceneReader r("[continuum.fpa]\nrepose_angle_source = \"dem\"\n", "scene.toml");
  FpaSettings fpa = read_continuum_scene(r, ".").settings_of<FpaSettings>("fpa");
  ASSERT_TRUE(fpa.angles_from_dem);
  const std::string good = temp_file("report.json", R"({"dem": {"repose_angle_left_deg": 25.5, "repose_angle_right_deg": 21.0}})");
  apply_dem_repose_angles(fpa, good);
  EXPECT_DOUBLE_EQ(fpa.left_repose_angle_deg, 25.5);
  EXPECT_DOUBLE_EQ(fpa.right_repose_angle_deg, 21.0);
  const std::string bad = temp_file("bad_report.json", R"({"dem": {"repose_angle_left_deg": null, "repose_angle_right_deg": 21.0}})");
  try {
    apply_dem_repose_angles(fpa, bad);
    FAIL() << "a null angle was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dem.repose_angle_left_deg"), std::string::npos) << e.what();
  }
  // The measured angles replace the scene's.
  SceneReader r2("[continuum.fpa]\nrepose_angle_source = \"dem\"\nrepose_angle_deg = 30\n", "scene.toml");
  FpaSettings fpa2 = read_continuum_scene(r2, ".").settings_of<FpaSettings>("fpa");
  apply_dem_repose_angles(fpa2, good);
  EXPECT_DOUBLE_EQ(fpa2.left_repose_angle_deg, 25.5);
  std::filesystem::remove(good);
  std::filesystem::remove(bad);
}

TEST(ContinuumInput, UnknownKeysAndBadModelsAreRefused) {
  EXPECT_NE(error_of("[continuum]\ndensity = 3\n").find("continuum.density"), std::string::npos);
  EXPECT_NE(error_of("[continuum.elastic]\nyoung = 3\n").find("continuum.elastic.young"), std::string::npos);
  EXPECT_NE(error_of("[continuum.plastic]\nx = 1\n").find("continuum.plastic"), std::string::npos);
  EXPECT_NE(error_of("[continuum]\nmodels = [\"elastic\", \"mohr\"]\n").find("continuum.models"), std::string::npos);
  EXPECT_NE(error_of("[continuum.elastic]\nplane = \"axisymmetric\"\n").find("continuum.elastic.plane"),
            std::string::npos);
  EXPECT_NE(error_of("[continuum.elastic]\ndegree = 3\n").find("continuum.elastic.degree"), std::string::npos);
}

// The OSL's two constants are the model: listed without them it is refused, naming the key;
// eta must be positive (the closure is hyperbolic only then), and unlisted its table is still
// checked.
TEST(ContinuumInput, OslNeedsItsConstants) {
  EXPECT_NE(error_of("[continuum]\nmodels = [\"osl\"]\n").find("continuum.osl.eta"), std::string::npos);
  EXPECT_NE(error_of("[continuum]\nmodels = [\"osl\"]\n[continuum.osl]\neta = 1.0\n").find("continuum.osl.mu"),
            std::string::npos);
  EXPECT_NE(error_of("[continuum]\nmodels = [\"osl\"]\n[continuum.osl]\neta = 0\nmu = 1\n").find("continuum.osl.eta"),
            std::string::npos);
  EXPECT_NE(error_of("[continuum.osl]\nnu = 1\n").find("continuum.osl.nu"), std::string::npos);
  SceneReader r("[continuum]\nmodels = [\"osl\", \"elastic\"]\n[continuum.osl]\neta = 0.8\nmu = 1.1\n", "scene.toml");
  const ContinuumSettings s = read_continuum_scene(r, ".");
  EXPECT_EQ(s.models, (std::vector<std::string>{"elastic", "osl"}));  // the registry's order
  EXPECT_DOUBLE_EQ(s.settings_of<OslSettings>("osl").eta, 0.8);
  EXPECT_DOUBLE_EQ(s.settings_of<OslSettings>("osl").mu, 1.1);
}

TEST(ContinuumInput, MissingMeshNamesTheFile) {
  const std::string e = mesh_error("/nonexistent/pile.msh");
  EXPECT_NE(e.find("/nonexistent/pile.msh"), std::string::npos) << e;
}

TEST(ContinuumInput, CorruptMeshNamesTheFile) {
  const std::string path = temp_file("corrupt.msh", "$MeshFormat\nthis is not a mesh\n");
  const std::string e = mesh_error(path);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  std::filesystem::remove(path);
}

TEST(ContinuumInput, InvertedMeshIsRefused) {
  const std::string good = temp_file("good.msh", one_triangle_msh("1 2 3", 1));
  EXPECT_EQ(mesh_error(good), "");
  const std::string inverted = temp_file("inverted.msh", one_triangle_msh("1 3 2", 1));
  const std::string e = mesh_error(inverted);
  EXPECT_NE(e.find(inverted), std::string::npos) << e;
  EXPECT_NE(e.find("inverted"), std::string::npos) << e;
  std::filesystem::remove(good);
  std::filesystem::remove(inverted);
}

TEST(ContinuumInput, MeshWithoutBaseIsRefused) {
  const std::string path = temp_file("nobase.msh", one_triangle_msh("1 2 3", 2));
  const std::string e = mesh_error(path);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("BoundaryID:1"), std::string::npos) << e;
  std::filesystem::remove(path);
}
