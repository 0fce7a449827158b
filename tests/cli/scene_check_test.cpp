// `pilelab check` and the check `pilelab run` makes before its first stage: every bundled scene
// is accepted by every stage's reader, and a bad key in a late stage's table is refused before
// anything is poured.
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
