// `pilelab run` end to end on the tiny pile: every stage, every output readable by tools
// pilelab did not write (h5py, meshio), report.json with every documented key; a second run
// skips the unchanged stages.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "dem/dem_file.h"

using pilelab::test::CliTest;

class Pipeline : public CliTest {};

TEST_F(Pipeline, TinySceneThroughEveryStage) {
  const std::string scene = std::string(PILELAB_SOURCE_DIR) + "/tests/cli/tiny_pipeline.toml";
  // A relative output directory, as users type it: every stage must resolve paths the same way.
  const std::string out = std::filesystem::relative(path("out")).string();
  const auto first = run("run " + scene + " -o " + out + " -q");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  std::string sections = "dem mesh coarse compare fit";
#ifdef PILELAB_WITH_CONTINUUM
  sections += " continuum";
#endif
  const std::string check = "/usr/bin/python3 " + std::string(PILELAB_SOURCE_DIR) + "/tests/cli/check_outputs.py " +
                            path("out") + " " + PILELAB_SOURCE_DIR + "/docs/FORMAT.md " + sections + " > " +
                            path("check.log") + " 2>&1";
  const int status = std::system(check.c_str());
  std::ifstream log(path("check.log"));
  std::stringstream s;
  s << log.rdbuf();
  EXPECT_EQ(status, 0) << s.str();
#ifdef PILELAB_WITH_CONTINUUM
  // The solve takes what the earlier stages measured where the scene sets nothing: the pile's
  // angles (from the DEM, and said so), its bulk density and gravity (from coarse).
  {
    std::ifstream in(path("out/report.json"));
    const auto report = nlohmann::json::parse(in);
    const auto& fpa = report["continuum"]["fpa"];
    EXPECT_EQ(fpa["repose_angle_source"], "dem");
    EXPECT_EQ(fpa["left_repose_angle_deg"].get<double>(), report["dem"]["repose_angle_left_deg"].get<double>());
    EXPECT_EQ(fpa["right_repose_angle_deg"].get<double>(), report["dem"]["repose_angle_right_deg"].get<double>());
    EXPECT_EQ(report["continuum"]["density_kg_per_m2"].get<double>(), report["coarse"]["rho_bulk_kg_per_m2"].get<double>());
    EXPECT_EQ(report["continuum"]["gravity_m_per_s2"].get<double>(), report["coarse"]["gravity_m_per_s2"].get<double>());
    // The FPA on the pile's own outline: the weight it misses is its squared residual exactly
    // (docs/CONTINUUM.md), and on the smoothed outline it carries the weight to the level below
    // which the run warns.
    const double carried = fpa["base_force_over_weight"].get<double>(), e = fpa["equilibrium_residual_over_weight"].get<double>();
    EXPECT_NEAR(1 - carried, e * e, 1e-9);
    EXPECT_GE(carried, 0.99) << "outflow surface fraction " << fpa["outflow_surface_length_fraction"];
  }
#endif

  const auto second = run("run " + scene + " -o " + out);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  for (const char* stage : {"dem", "mesh", "coarse", "compare"})
    EXPECT_NE(second.output.find(std::string(stage) + std::string(8 - std::string(stage).size(), ' ') + " skipped"),
              std::string::npos)
        << stage << " was not skipped:\n" << second.output;

  // `pilelab figures OUT` draws the figures again from the outputs alone.
  std::filesystem::remove_all(path("out/figures"));
  const auto figures = run("figures " + out);
  ASSERT_EQ(figures.exit_code, 0) << figures.output;
  for (const char* png : {"base_pressure.png", "pile_pressure.png"})
    EXPECT_TRUE(std::filesystem::exists(path("out/figures/") + png)) << png << "\n" << figures.output;
}

// The snapshots the later stages measure (settled, relaxed) are frames of dem.pvd at their exact
// times, beside the frames at the frame interval, which keep their schedule (one per interval).
TEST_F(Pipeline, TheSnapshotsAreFramesOfTheSeries) {
  const std::string out = path("out");
  ASSERT_EQ(run("dem " + std::string(PILELAB_SOURCE_DIR) + "/tests/cli/tiny.toml -o " + out + " -q -j 1").exit_code, 0);
  std::ifstream in(out + "/dem.pvd");
  const std::string pvd((std::istreambuf_iterator<char>(in)), {});
  std::vector<double> times;  // of the grains' part
  for (std::size_t at = pvd.find("timestep=\""); at != std::string::npos; at = pvd.find("timestep=\"", at + 1))
    if (pvd.compare(pvd.find("part=\"", at) + 6, 1, "0") == 0) times.push_back(std::stod(pvd.substr(at + 10)));
  const pilelab::dem::DemFile dem = pilelab::dem::read_dem_file(out + "/dem.h5");
  int interval_frames = 0;
  for (const double t : times) interval_frames += std::abs(t / 0.1 - std::round(t / 0.1)) < 1e-3;  // 0.1 s interval
  for (const std::string& name : dem.snapshot_names) {
    const double t = dem.snapshot(name).time;
    EXPECT_NE(std::find(times.begin(), times.end(), t), times.end()) << name << " at " << t << " s is not a frame";
  }
  EXPECT_EQ(interval_frames, static_cast<int>(std::floor(times.back() / 0.1)) + 1) << pvd;
  EXPECT_EQ(times.size(), interval_frames + dem.snapshot_names.size()) << pvd;
}

// A wedge mesh under `pilelab run` is the poured pile's wedge, one pile as an ensemble: its
// height, flank angles and apex are the DEM's where the scene sets none (a default 0.33 m,
// 28-degree wedge around a 7 cm pile would leave most of the mesh without DEM data).
TEST_F(Pipeline, WedgeMeshTakesThePouredPile) {
  std::ifstream in(std::string(PILELAB_SOURCE_DIR) + "/tests/cli/tiny_pipeline.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const std::string outline = "kind = \"dem_outline\"";
  ASSERT_NE(toml.find(outline), std::string::npos);
  toml.replace(toml.find(outline), outline.size(), "kind = \"wedge\"");
  const std::string scene = write_scene("wedge.toml", toml);
  const auto result = run("run " + scene + " -o " + path("out") + " -q");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream report_in(path("out/report.json"));
  const auto report = nlohmann::json::parse(report_in);
  const auto& wedge = report["mesh"]["wedge"];
  EXPECT_TRUE(wedge["from_dem"].get<bool>()) << wedge.dump();
  EXPECT_EQ(wedge["height_m"].get<double>(), report["dem"]["height_m"].get<double>());
  EXPECT_EQ(wedge["left_angle_deg"].get<double>(), report["dem"]["repose_angle_left_deg"].get<double>());
  EXPECT_EQ(wedge["right_angle_deg"].get<double>(), report["dem"]["repose_angle_right_deg"].get<double>());
  EXPECT_EQ(wedge["apex_x_m"].get<double>(), report["dem"]["apex_x_m"].get<double>());
}

// A pipeline without a DEM stage, on a pile poured elsewhere (the coarse tests' fixture), with
// a relative output directory: mesh, coarse, solve, compare, and the fit's closed loop.
TEST_F(Pipeline, ExistingPileThroughTheClosedLoop) {
#ifndef PILELAB_WITH_CONTINUUM
  GTEST_SKIP() << "built without the continuum module";
#else
  const std::string pile = PILELAB_SMALL_PILE;
  ASSERT_TRUE(std::filesystem::exists(pile)) << "run through ctest: the fixture pour_small_pile makes " << pile;
  const std::string scene = write_scene("scene.toml", "[mesh]\nkind = \"dem_outline\"\ndem_file = \"" + pile +
                                                          "\"\nelement_size_m = 0.005\n[coarse]\ndem_files = [\"" + pile +
                                                          "\"]\nrve_radius_m = 0.012\n[continuum]\n[continuum.elastic]\n"
                                                          "degree = 1\n[compare]\nfit_resamples = 20\n");
  // Run from the test directory with OUT given as "out": paths relative to the working directory.
  const std::string cmd = "cd " + dir_.string() + " && " + PILELAB_BINARY + " run " + scene + " -o out -q > run.log 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream log(path("run.log"));
  std::stringstream text;
  text << log.rdbuf();
  ASSERT_EQ(status, 0) << text.str();
  std::ifstream in(path("out/report.json"));
  const auto report = nlohmann::json::parse(in);
  EXPECT_FALSE(report.contains("dem"));
  const auto& loop = report["fit"]["closed_loop"];
  ASSERT_TRUE(loop.contains("relative_l2_displacement")) << loop.dump();
  EXPECT_TRUE(std::isfinite(loop["relative_l2_displacement"].get<double>()));
  EXPECT_NEAR(report["coarse"]["gravity_change"].get<double>(), -0.1, 1e-12);
  // The OSL closure fitted to the DEM's stress, solved with those constants: the scene text
  // hands them over unrounded, and the closure's stress carries the pile's weight (the base
  // force is the weight up to the squared equilibrium residual, docs/CONTINUUM.md).
  const auto& osl = report["compare"]["osl_closure_fit"];
  ASSERT_TRUE(osl.contains("closed_loop")) << osl.dump();
  EXPECT_TRUE(std::isfinite(osl["closed_loop"]["relative_l2_stress_yy"].get<double>())) << osl.dump();
  std::ifstream loop_in(path("out/closed_loop_osl/report.json"));
  const auto solved = nlohmann::json::parse(loop_in)["continuum"]["osl"];
  EXPECT_EQ(solved["eta"].get<double>(), osl["eta"].get<double>());
  EXPECT_EQ(solved["mu"].get<double>(), osl["mu"].get<double>());
  const double e = solved["equilibrium_residual_over_weight"].get<double>();
  EXPECT_NEAR(solved["base_force_over_weight"].get<double>(), 1.0 - e * e, 1e-8) << solved.dump();
#endif
}
