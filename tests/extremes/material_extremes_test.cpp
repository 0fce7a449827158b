// The grains and their contact law at the edges of the scene's ranges (ctest -L extremes;
// docs/studies/extremes.md): stiffness E from 1e4 to 1e10 N/m, friction 0 and 2, damping 0 and
// 10, polydispersity 0 and 0.8, elongated grains (aspect ratio 5), triangles and 64-gons,
// discs, and grains dropped from ten times the funnel height. Each pours the 40-grain pile of
// tests/cli/tiny.toml at the default step (0.8 of the stability limit, which follows E, the
// masses and the damping) and must complete with every number of dem.h5 finite, or stop with
// exit 1 naming what went wrong; never a crash, a hang or a NaN in a file. What each did is
// printed on an EXTREMES line, from which the page's table is read.
#include <nlohmann/json.hpp>

#include "../cli/cli_test_support.h"

using pilelab::test::CliTest;
using pilelab::test::tiny_scene;

namespace {

struct Case {
  const char* name;
  const char* table;  ///< the scene table the lines go into
  const char* lines;  ///< TOML lines added to it
  /// Whether grains with these properties can hold a slope: without friction no pile forms and
  /// the grains run off the plate, which is the physics, not a failure.
  bool holds_a_pile = true;
};

// The tiny scene with `lines` ("key = value", one a line) at the top of [table] (the table
// appended if missing), each replacing the scene's own line of that key.
std::string with_lines(const std::string& table, const std::string& lines) {
  std::string text = tiny_scene();
  std::istringstream each(lines);
  for (std::string line; std::getline(each, line);) {
    const std::string key = "\n" + line.substr(0, line.find(" =")) + " =";
    const auto old = text.find(key);
    if (old != std::string::npos) text.erase(old + 1, text.find('\n', old + 1) - old);
  }
  const std::string header = "[" + table + "]\n";
  const auto at = text.find(header);
  if (at == std::string::npos) return text + "\n" + header + lines + "\n";
  return text.insert(at + header.size(), lines + "\n");
}

}  // namespace

class MaterialExtremes : public CliTest, public ::testing::WithParamInterface<Case> {};

TEST_P(MaterialExtremes, RunsFiniteOrStopsWithTheCause) {
  const Case c = GetParam();
  const std::string scene = write_scene("scene.toml", with_lines(c.table, c.lines));
  const auto r = run("timeout 600 " + std::string(PILELAB_BINARY) + " dem " + scene + " -o " + path("out") + " -q -j 1",
                     "", /*prefix_binary=*/false);
  std::string outcome;
  if (r.exit_code == 0) {
    ASSERT_TRUE(every_number_finite(path("out/dem.h5"))) << "a NaN or infinity in dem.h5";
    std::ifstream in(path("out/report.json"));
    const auto dem = nlohmann::json::parse(in)["dem"];
    char text[400];
    std::snprintf(text, sizeof text, "completed: %d of 40 grains lost, deepest overlap %.3g of the inner radius, step %.3g s, %lld steps",
                  dem["lost"].get<int>(), dem["deepest_overlap_fraction"].get<double>(),
                  dem["time_step_s"].get<double>(), dem["steps"].get<long long>());
    outcome = text;
    // The pile is there: most grains stay on the plate.
    if (c.holds_a_pile) EXPECT_LE(dem["lost"].get<int>(), 20) << outcome;
    // An overlap deeper than the step's bound assumes is reported (the run's own check).
    const double limit_at_depth =
        dem["stable_time_step_at_deepest_overlap_s"].is_number() ? dem["stable_time_step_at_deepest_overlap_s"].get<double>() : INFINITY;
    if (dem["time_step_s"].get<double>() > limit_at_depth)
      EXPECT_NE(r.output.find("an overlap reached"), std::string::npos) << "a too-deep overlap without a warning: " << r.output;
  } else {
    EXPECT_EQ(r.exit_code, 1) << "a crash, a hang (124) or another failure: " << r.output;
    EXPECT_NE(r.output.find("t = "), std::string::npos) << "the message names no time: " << r.output;
    EXPECT_FALSE(std::filesystem::exists(path("out/dem.h5"))) << "a stopped run leaves no dem.h5";
    outcome = "stopped: " + r.output.substr(0, 200);
  }
  std::printf("EXTREMES %s: %s\n", c.name, outcome.c_str());
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MaterialExtremes,
    ::testing::Values(Case{"E_1e4", "dem.contact", "youngs_modulus_N_per_m = 1e4"},
                      Case{"E_1e10", "dem.contact", "youngs_modulus_N_per_m = 1e10"},
                      Case{"mu_0", "dem.contact", "friction_mu = 0.0", false},
                      Case{"mu_2", "dem.contact", "friction_mu = 2.0"},
                      Case{"gamma_0", "dem.contact", "damping_gamma = 0.0"},
                      Case{"gamma_10", "dem.contact", "damping_gamma = 10.0"},
                      Case{"polydispersity_0", "dem.grains", "polydispersity = 0.0"},
                      Case{"polydispersity_0_8", "dem.grains", "polydispersity = 0.8"},
                      // (1 + p) / (1 - p) = 5: axes up to five to one.
                      Case{"aspect_ratio_5", "dem.grains", "polydispersity = 0.6666666666666666"},
                      Case{"triangles", "dem.grains", "corners_min = 3\ncorners_max = 3"},
                      Case{"corners_64", "dem.grains", "corners_min = 64\ncorners_max = 64"},
                      Case{"discs", "dem.grains", "shape = \"disc\""},
                      // Ten times tiny.toml's 0.06 m: the first contacts are deep and fast.
                      Case{"dropped_from_10x_height", "dem.pour", "funnel_height_m = 0.6"}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });
