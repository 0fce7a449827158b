// The time step at 0.5, 1, 2, 3 and 10 times the integrator's stability limit (ctest -L extremes;
// docs/studies/extremes.md). The limit is the one `pilelab check` states when it refuses a
// larger step; the override (allow_unstable_time_step) runs the step anyway. At or below the
// limit the explicit scheme is stable: the pour completes with every number finite, and at half
// the limit no grain is lost. At twice the limit the contacts the pile actually makes (shallower
// than the bound assumes) are at the edge of their own limit: the run completes with finite
// files and a warning that names the step, or stops with exit 1 when a contact swings at the
// period of two steps. At ten times, the grains gain more energy than the pour put in, or a
// contact swings, and the run stops with exit 1 naming the time, the step and the grain or
// contact (or, if a number overflows first, the first non-finite grain); never a crash, a hang
// or a NaN in a file.
#include <regex>

#include <nlohmann/json.hpp>

#include "../cli/cli_test_support.h"

using pilelab::test::CliTest;
using pilelab::test::tiny_scene;

namespace {

// The tiny scene on a plate a metre wide: a grain of the 40-grain pile that rolls away from
// its foot (they can roll 0.15 m on polygons' corners) stays on it, so that at half the limit a
// lost grain can only be one thrown off by an unstable step.
std::string with_step(const std::string& scheme, const std::string& step_lines) {
  std::string text = tiny_scene();
  const std::string line = "scheme = \"verlet\"";
  text.replace(text.find(line), line.size(), "scheme = \"" + scheme + "\"\n" + step_lines);
  const std::string plate = "plate_width_m = 0.3";
  text.replace(text.find(plate), plate.size(), "plate_width_m = 1.0");
  return text;
}

struct Case {
  const char* scheme;
  double factor;
};

}  // namespace

class TimeStepExtremes : public CliTest, public ::testing::WithParamInterface<Case> {
 protected:
  // The limit the scene check names when it refuses a step far above it.
  double stability_limit(const std::string& scheme) {
    const auto refused = run("check " + write_scene("refused.toml", with_step(scheme, "time_step_s = 1.0")));
    EXPECT_NE(refused.exit_code, 0) << refused.output;
    std::smatch m;
    const std::regex limit("exceeds the stability limit ([0-9.eE+-]+) s");
    if (!std::regex_search(refused.output, m, limit)) {
      ADD_FAILURE() << "no stability limit in: " << refused.output;
      return 0.0;
    }
    return std::stod(m[1]);
  }
};

TEST_P(TimeStepExtremes, RunsFiniteOrStopsNamingTheGrain) {
  const Case c = GetParam();
  const double limit = stability_limit(c.scheme);
  ASSERT_GT(limit, 0.0);
  char step[160];
  std::snprintf(step, sizeof step, "time_step_s = %.9e\nallow_unstable_time_step = true", c.factor * limit);
  const std::string scene = write_scene("scene.toml", with_step(c.scheme, step));
  // `timeout` turns a hang into exit 124, which fails below like any other unexpected code.
  const auto r = run("timeout 300 " + std::string(PILELAB_BINARY) + " dem " + scene + " -o " + path("out") + " -q -j 1",
                     "", /*prefix_binary=*/false);
  std::string outcome;
  if (r.exit_code == 0) {
    ASSERT_TRUE(every_number_finite(path("out/dem.h5"))) << "a NaN or infinity in dem.h5";
    std::ifstream in(path("out/report.json"));
    const auto report = nlohmann::json::parse(in);
    const int lost = report["dem"]["lost"].get<int>();
    outcome = "completed, " + std::to_string(lost) + " grains lost";
    if (c.factor <= 0.5) {
      EXPECT_EQ(lost, 0) << "half the limit is stable: no grain may leave";
    }
    // A run above the limit says so, whatever became of its grains.
    if (c.factor > 1.0) {
      EXPECT_NE(r.output.find("times the stability limit"), std::string::npos) << r.output;
    }
    // Three times the limit swings contacts (every one of 16 seeds, docs/studies/extremes.md), ten
    // times also feeds in more energy than the pour: a check must stop it.
    EXPECT_LT(c.factor, 3.0) << c.factor << " times the limit completed: " << r.output;
  } else {
    EXPECT_GT(c.factor, 1.0) << "at or below the limit the run must complete: " << r.output;
    EXPECT_EQ(r.exit_code, 1) << "a crash, a hang (124) or another failure: " << r.output;
    // Caught as a contact that swings at the period of two steps, as energy the pour cannot
    // have put in, or as a number that overflowed.
    auto cause = r.output.find("period of two time steps");
    if (cause == std::string::npos) cause = r.output.find("creates energy");
    if (cause == std::string::npos) cause = r.output.find("no longer finite");
    ASSERT_NE(cause, std::string::npos) << r.output;
    EXPECT_NE(r.output.find("body "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("(step "), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(path("out/dem.h5"))) << "a stopped run leaves no dem.h5";
    outcome = "stopped: " + r.output.substr(cause, 120);
  }
  // The table of docs/studies/extremes.md is read off these lines.
  std::printf("EXTREMES time step %s x%g of %.3e s: %s\n", c.scheme, c.factor, limit, outcome.c_str());
}

INSTANTIATE_TEST_SUITE_P(Factors, TimeStepExtremes,
                         ::testing::Values(Case{"verlet", 0.5}, Case{"verlet", 1.0}, Case{"verlet", 2.0},
                                           Case{"verlet", 3.0}, Case{"verlet", 10.0}, Case{"leapfrog", 0.5},
                                           Case{"leapfrog", 1.0}, Case{"leapfrog", 2.0}, Case{"leapfrog", 3.0},
                                           Case{"leapfrog", 10.0}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           std::string name = std::string(info.param.scheme) + "_x" +
                                              std::to_string(static_cast<int>(info.param.factor * 10));
                           return name;
                         });
