// Where the FPA's angles come from under `pilelab run` (continuum/models/fpa.cpp): the pile's
// measured angles where the scene sets none; the scene's where it does; and, where the run
// poured a pile whose flank could not be measured, the default, said so with a warning instead
// of passing as the scene's.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "../mpi_environment.h"
#include "continuum/solve.h"

using namespace pilelab::continuum;

namespace {

nlohmann::json solve_with(const MeasuredPile& measured, const std::string& fpa_table, const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("pilelab_fpa_angles_" + std::to_string(::getpid()) + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string scene = (dir / "scene.toml").string();
  std::ofstream(scene) << "[mesh]\nkind = \"wedge\"\nelement_size_m = 0.03\n[continuum]\nmodels = [\"fpa\"]\n" << fpa_table;
  SolveOptions o;
  o.scene_path = scene;
  o.out_dir = (dir / "out").string();
  o.quiet = true;
  o.measured = measured;
  const nlohmann::json report = run_solve(o)["fpa"];
  std::filesystem::remove_all(dir);
  return report;
}

}  // namespace

TEST(FpaAngles, MeasuredWhereTheSceneIsSilentTheSceneWhereItSpeaks) {
  MeasuredPile m;
  m.left_repose_angle_deg = 30.0;
  m.right_repose_angle_deg = 24.0;
  const auto measured = solve_with(m, "", "measured");
  EXPECT_EQ(measured["repose_angle_source"], "dem");
  EXPECT_EQ(measured["left_repose_angle_deg"].get<double>(), 30.0);
  EXPECT_EQ(measured["right_repose_angle_deg"].get<double>(), 24.0);
  const auto scene = solve_with(m, "[continuum.fpa]\nrepose_angle_deg = 33.0\n", "scene");
  EXPECT_EQ(scene["repose_angle_source"], "scene");
  EXPECT_EQ(scene["left_repose_angle_deg"].get<double>(), 33.0);
  EXPECT_FALSE(scene.contains("warning"));
}

TEST(FpaAngles, AnUnmeasuredFlankIsSaidNotPassedOffAsTheScenes) {
  MeasuredPile m;
  m.repose_unmeasured = true;
  const auto defaulted = solve_with(m, "", "unmeasured");
  EXPECT_EQ(defaulted["repose_angle_source"], "default");
  ASSERT_TRUE(defaulted.contains("warning")) << defaulted.dump();
  EXPECT_NE(defaulted["warning"].get<std::string>().find("could not be measured"), std::string::npos);
  // With the scene's own angle there is nothing to say.
  const auto scene = solve_with(m, "[continuum.fpa]\nrepose_angle_deg = 28.0\n", "unmeasured_scene");
  EXPECT_EQ(scene["repose_angle_source"], "scene");
  EXPECT_FALSE(scene.contains("warning"));
}
