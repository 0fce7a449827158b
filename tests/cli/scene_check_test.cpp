// `pilelab check` and the check `pilelab run` makes before its first stage: every bundled scene
// is accepted by every stage's reader, and a bad key in a late stage's table is refused before
// anything is poured.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "cli_test_support.h"

using pilelab::test::CliTest;

class SceneCheck : public CliTest {};

TEST_F(SceneCheck, EveryBundledSceneIsAcceptedByEveryStage) {
  int scenes = 0;
  for (const auto& dir : {"/scenes", "/tests/cli"})
    for (const auto& entry : std::filesystem::directory_iterator(std::string(PILELAB_SOURCE_DIR) + dir)) {
      if (entry.path().extension() != ".toml") continue;
      ++scenes;
      const auto r = run("check " + entry.path().string());
      EXPECT_EQ(r.exit_code, 0) << entry.path() << "\n" << r.output;
      EXPECT_NE(r.output.find(": ok ("), std::string::npos) << r.output;
    }
  EXPECT_GE(scenes, 5);
}

TEST_F(SceneCheck, ABadKeyInALateTableIsFoundBeforeThePour) {
  struct Case {
    std::string table, expected;
  };
  std::vector<Case> cases = {Case{"[compare]\nfit_resample = 10\n", "fit_resample"},
                             Case{"[compare]\nrepose_angle_deg = 60.0\n", "compare.repose_angle_deg"},
                             Case{"[mesh]\nkind = \"sphere\"\n", "mesh.kind"},
                             Case{"[coarse]\nmethod = \"voronoi\"\n", "coarse.method"}};
#ifdef PILELAB_WITH_CONTINUUM
  cases.push_back(Case{"[continuum]\nmodels = [\"plastic\"]\n", "plastic"});
#endif
  for (const Case& c : cases) {
    const std::string scene = write_scene("bad.toml", pilelab::test::tiny_scene() + c.table);
    const auto check = run("check " + scene);
    EXPECT_EQ(check.exit_code, 2) << c.table << check.output;
    EXPECT_NE(check.output.find(c.expected), std::string::npos) << c.table << check.output;
    EXPECT_NE(check.output.find("bad.toml"), std::string::npos) << check.output;
    const auto pipeline = run("run " + scene + " -o " + path("out") + " -q");
    EXPECT_EQ(pipeline.exit_code, 2) << c.table << pipeline.output;
    EXPECT_NE(pipeline.output.find(c.expected), std::string::npos) << c.table << pipeline.output;
    EXPECT_FALSE(std::filesystem::exists(path("out") + "/dem.h5")) << "poured before the scene was checked: " << c.table;
  }
}

// Every key a preset fills in is one its stage's reader knows: a scene with every table and a
// preset passes every reader (an unknown key would be refused as the scene's own).
TEST_F(SceneCheck, EveryPresetIsAcceptedByEveryStage) {
  for (const char* preset : {"fast", "accurate"}) {
    std::string text = pilelab::test::tiny_scene();
    text.insert(text.find("[scene]\n") + 8, "preset = \"" + std::string(preset) + "\"\n");
    const std::string scene = write_scene(std::string(preset) + ".toml", text + "[mesh]\n[coarse]\n[compare]\n"
#ifdef PILELAB_WITH_CONTINUUM
                                           "[continuum]\n"
#endif
    );
    const auto r = run("check " + scene);
    EXPECT_EQ(r.exit_code, 0) << preset << "\n" << r.output;
  }
}

// Files a stage reads and no stage of the scene makes are found missing by the check, before
// anything is poured, naming the key and the file; so is a [coarse] with no mesh to sample on.
TEST_F(SceneCheck, MissingInputFilesAreFoundBeforeThePour) {
  struct Case {
    std::string tables, expected;
  };
  std::vector<Case> cases = {
      Case{"[mesh]\nkind = \"wedge\"\n[coarse]\nmesh_file = \"no_such.msh\"\n", "coarse.mesh_file = "},
      Case{"[mesh]\nkind = \"wedge\"\n[coarse]\ndem_files = [\"no_such.h5\"]\n", "coarse.dem_files = "},
      Case{"[coarse]\nrve_grain_count = 30\n", "[coarse] samples its fields on OUT/pile.msh, which only the mesh stage makes"}};
#ifdef PILELAB_WITH_CONTINUUM
  cases.push_back(Case{"[continuum]\nmesh_file = \"no_such.msh\"\n", "continuum.mesh_file = "});
#endif
  for (const Case& c : cases) {
    const std::string scene = write_scene("missing.toml", pilelab::test::tiny_scene() + c.tables);
    const auto check = run("check " + scene);
    EXPECT_EQ(check.exit_code, 2) << c.tables << check.output;
    EXPECT_NE(check.output.find(c.expected), std::string::npos) << c.tables << check.output;
    const auto pipeline = run("run " + scene + " -o " + path("out") + " -q");
    EXPECT_EQ(pipeline.exit_code, 2) << c.tables << pipeline.output;
    EXPECT_FALSE(std::filesystem::exists(path("out") + "/dem.h5")) << "poured before the scene was checked: " << c.tables;
  }
}

// `pilelab check` prints what the pour costs, and the numbers follow from the scene: the tiny
// pile pours 39 grain intervals at 400 grains/s (0.0975 s), then settles twice (0.05 to 0.25 s
// each) around a 0.05 s ramp, so 0.2475 to 0.6475 s; its steps are those times over dt, and its
// grain-steps are n^2 / (2 rate) / dt while pouring plus n per step after. A pour no computer
// would finish is refused by check, not only when it starts.
TEST_F(SceneCheck, TheCheckEstimatesThePourAndRefusesOneNoComputerWouldFinish) {
  const auto r = run("check " + write_scene("tiny.toml", pilelab::test::tiny_scene()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  double dt = 0, t0 = 0, t1 = 0, s0 = 0, s1 = 0, g0 = 0, g1 = 0;
  const std::size_t at = r.output.find("the pour: ");
  ASSERT_NE(at, std::string::npos) << r.output;
  ASSERT_EQ(std::sscanf(r.output.c_str() + at,
                        "the pour: 40 grains at dt = %lf s, %lf to %lf s simulated (settling at its minimum or its limit): "
                        "%lf to %lf steps, %lf to %lf grain-steps, about ",
                        &dt, &t0, &t1, &s0, &s1, &g0, &g1),
            7)
      << r.output;
  const double n = 40, rate = 400, pour = 39 / rate;
  const auto near = [](double printed, double exact) { return std::abs(printed / exact - 1) < 5e-3; };  // 3 digits
  EXPECT_TRUE(near(t0, pour + 2 * 0.05 + 0.05)) << t0;
  EXPECT_TRUE(near(t1, pour + 2 * 0.25 + 0.05)) << t1;
  EXPECT_TRUE(near(s0, t0 / dt) && near(s1, t1 / dt)) << s0 << " " << s1;
  EXPECT_TRUE(near(g0, (n * n / (2 * rate) + n * (t0 - pour)) / dt)) << g0;
  EXPECT_TRUE(near(g1, (n * n / (2 * rate) + n * (t1 - pour)) / dt)) << g1;
  EXPECT_NE(r.output.find("on one core at 5e+06 grain-steps/s"), std::string::npos) << r.output;

  // A pour of days (the tiny pile's grains at 1e-5 grains/s: 3.9e6 s of pouring) warns as it
  // starts, quiet or not, with the time on one core; it is stopped after a step here.
  std::string days = pilelab::test::tiny_scene();
  days.replace(days.find("rate_grains_per_s = 400.0"), 25, "rate_grains_per_s = 1e-5");
  days.replace(days.find("frame_interval_s = 0.1"), 22, "frame_interval_s = 0.0");
  days.replace(days.find("checkpoint_interval_s = 0.1"), 27, "checkpoint_interval_s = 0.0");
  const auto started = run("dem " + write_scene("days.toml", days) + " -o " + path("days") + " -q -j 1 --stop-after-steps 1");
  EXPECT_NE(started.output.find("warning: this pour may take up to"), std::string::npos) << started.output;
  EXPECT_NE(started.output.find(" days on one core"), std::string::npos) << started.output;

  std::string slow = pilelab::test::tiny_scene();
  slow.replace(slow.find("rate_grains_per_s = 400.0"), 25, "rate_grains_per_s = 1e-6");
  const auto refused = run("check " + write_scene("slow.toml", slow));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("this run would take at least"), std::string::npos) << refused.output;
}

#ifdef PILELAB_WITH_CONTINUUM
// Fields coarse-grained on one mesh and models solved on another cannot be compared (compare
// matches their points): the check says so before anything runs, naming both keys.
TEST_F(SceneCheck, FieldsAndModelsOnTwoMeshesAreFoundBeforeThePour) {
  const std::string other = path("other.msh");
  std::ofstream(other) << "";  // exists; never read by the check
  const std::string text = pilelab::test::tiny_scene() +
                           "\n[mesh]\nkind = \"dem_outline\"\n\n[coarse]\nrve_radius_m = 0.012\n\n[continuum]\nmesh_file = \"" +
                           other + "\"\n\n[compare]\n";
  const auto r = run("check " + write_scene("two_meshes.toml", text));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const std::string& word : {std::string("coarse.mesh_file"), std::string("continuum.mesh_file"), other})
    EXPECT_NE(r.output.find(word), std::string::npos) << r.output;
}
#endif
