// Coarse-graining windows and meshes at the edges (ctest -L extremes; docs/studies/extremes.md):
// an RVE smaller than one grain and one larger than the pile, a kernel narrower than a grain,
// and meshes of a handful and of a hundred thousand cells. Each either runs to finite fields
// and models or stops with exit 2 naming the key, the value and what is allowed.
#include <nlohmann/json.hpp>

#include "../cli/cli_test_support.h"

using pilelab::test::CliTest;
using pilelab::test::tiny_scene;

class WindowAndMeshExtremes : public CliTest {
 protected:
  // The tiny pile, poured once for the suite.
  static void SetUpTestSuite() {
    pile_dir_ = (std::filesystem::temp_directory_path() / ("pilelab_extremes_pile_" + std::to_string(::getpid()))).string();
    std::filesystem::create_directories(pile_dir_);
    std::ofstream(pile_dir_ + "/tiny.toml") << tiny_scene();
    const std::string cmd = std::string(PILELAB_BINARY) + " dem " + pile_dir_ + "/tiny.toml -o " + pile_dir_ + " -q -j 1 > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(pile_dir_); }

  // Mesh the pile's outline, coarse-grain it and, with the continuum module, solve both models
  // on it: the scene's [mesh] and [coarse] lines given.
  pilelab::test::CommandResult run_stages(const std::string& mesh_lines, const std::string& coarse_lines) {
    std::string text = "[mesh]\nkind = \"dem_outline\"\ndem_file = \"" + pile_dir_ + "/dem.h5\"\n" + mesh_lines +
                       "\n[coarse]\ndem_files = [\"" + pile_dir_ + "/dem.h5\"]\n" + coarse_lines + "\n";
#ifdef PILELAB_WITH_CONTINUUM
    text += "[continuum]\nmodels = [\"elastic\", \"fpa\"]\n[continuum.elastic]\ndegree = 1\n";
#endif
    const std::string scene = write_scene("scene.toml", text);
    const std::string pilelab = "timeout 900 " + std::string(PILELAB_BINARY);
    std::string cmd = "( " + pilelab + " mesh " + scene + " -o " + path("out") + " && " + pilelab + " coarse " + scene + " -o " + path("out");
#ifdef PILELAB_WITH_CONTINUUM
    cmd += " && " + pilelab + " solve " + scene + " -o " + path("out");
#endif
    return run(cmd + " )", "", /*prefix_binary=*/false);
  }
  nlohmann::json report() const {
    std::ifstream in(path("out/report.json"));
    return nlohmann::json::parse(in);
  }
  void expect_finite_outputs() {
    EXPECT_TRUE(every_number_finite(path("out/fields.h5"))) << "a NaN or infinity in fields.h5";
#ifdef PILELAB_WITH_CONTINUUM
    EXPECT_TRUE(every_number_finite(path("out/models.h5"))) << "a NaN or infinity in models.h5";
#endif
  }
  static std::string pile_dir_;
};
std::string WindowAndMeshExtremes::pile_dir_;

TEST_F(WindowAndMeshExtremes, AnRveSmallerThanOneGrainIsRefused) {
  const auto r = run_stages("element_size_m = 0.004", "rve_radius_m = 1e-4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("coarse.rve_radius_m is 0.0001 m, smaller than the mean grain diameter"), std::string::npos) << r.output;
}

TEST_F(WindowAndMeshExtremes, AnRveLargerThanThePileAveragesItWholeAndSaysSo) {
  const auto r = run_stages("element_size_m = 0.004", "rve_radius_m = 1.0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("exceeds the pile's height"), std::string::npos) << r.output;
  expect_finite_outputs();
  const auto coarse = report()["coarse"];
  EXPECT_EQ(coarse["points_without_data"].get<int>(), 0);
  std::printf("EXTREMES RVE of 1 m: finite, every point averages %.1f grains (the pile has 40 or fewer)\n",
              coarse["mean_grain_count"].get<double>());
}

TEST_F(WindowAndMeshExtremes, AKernelNarrowerThanAGrainIsRefused) {
  const auto r = run_stages("element_size_m = 0.004", "method = \"gaussian\"\nkernel_width_m = 1e-4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("coarse.kernel_width_m is 0.0001 m"), std::string::npos) << r.output;
}

TEST_F(WindowAndMeshExtremes, AMeshOfAFewCellsGivesFiniteFields) {
  const auto r = run_stages("element_size_m = 0.5", "rve_radius_m = 0.012");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_finite_outputs();
  const int cells = report()["mesh"]["triangles"].get<int>();
  EXPECT_LE(cells, 40);
  std::printf("EXTREMES mesh of %d cells: finite fields%s\n", cells,
#ifdef PILELAB_WITH_CONTINUUM
              (", FPA carries " + std::to_string(report()["continuum"]["fpa"]["base_force_over_weight"].get<double>()) +
               " of the weight").c_str()
#else
              ""
#endif
  );
}

TEST_F(WindowAndMeshExtremes, AMeshOfAHundredThousandCellsGivesFiniteFields) {
  const auto r = run_stages("element_size_m = 0.0002", "rve_radius_m = 0.012");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_finite_outputs();
  const auto rep = report();
  const int cells = rep["mesh"]["triangles"].get<int>();
  EXPECT_GE(cells, 100000);
  std::printf("EXTREMES mesh of %d cells: mesh %.1f s, coarse %.1f s%s\n", cells, rep["mesh"]["wall_time_s"].get<double>(),
              rep["coarse"]["wall_time_s"].get<double>(),
#ifdef PILELAB_WITH_CONTINUUM
              (", solve " + std::to_string(rep["continuum"]["wall_time_s"].get<double>()) + " s, FPA carries " +
               std::to_string(rep["continuum"]["fpa"]["base_force_over_weight"].get<double>()) + " of the weight")
                  .c_str()
#else
              ""
#endif
  );
}
