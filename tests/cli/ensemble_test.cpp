// `pilelab run` on an ensemble: every member poured into OUT/members/<seed>/, the same files
// whether the members are poured one after another, as two processes side by side, or on two
// MPI ranks; a stopped member continues from its checkpoint to the same files; the report's
// ensemble statistics are the sample formulas on the members' values; the mesh is the members'
// mean wedge and the coarse fields average all members.
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_test_support.h"

using pilelab::test::CliTest;

namespace {
const std::string ensemble_scene = std::string(PILELAB_SOURCE_DIR) + "/tests/cli/tiny_ensemble.toml";
const std::vector<int> seeds = {3, 4, 5};

nlohmann::json report_of(const std::string& out) {
  std::ifstream in(out + "/report.json");
  return nlohmann::json::parse(in);
}

bool same_bytes(const std::string& a, const std::string& b) {
  return std::system(("cmp -s '" + a + "' '" + b + "'").c_str()) == 0;
}
}  // namespace

class Ensemble : public CliTest {
 protected:
  // The files of a member that must not depend on how it was poured (the report and the
  // checkpoint hold wall-clock times).
  void expect_same_members(const std::string& out_a, const std::string& out_b) {
    for (int seed : seeds) {
      const std::string member = "/members/" + std::to_string(seed);
      for (const char* file : {"dem.h5", "scene.toml", "dem.pvd", "grains_00001.vtu", "contacts_00001.vtu"})
        EXPECT_TRUE(same_bytes(out_a + member + "/" + file, out_b + member + "/" + file))
            << member << "/" << file << " differs between " << out_a << " and " << out_b;
    }
  }
};

TEST_F(Ensemble, SerialProcessesAndMpiRanksPourTheSameMembers) {
  const auto serial = run("run " + ensemble_scene + " -o " + path("serial") + " -q -j 1");
  ASSERT_EQ(serial.exit_code, 0) << serial.output;
  const auto processes = run("run " + ensemble_scene + " -o " + path("processes") + " -q -P 2");
  ASSERT_EQ(processes.exit_code, 0) << processes.output;
  expect_same_members(path("serial"), path("processes"));
  EXPECT_TRUE(same_bytes(path("serial") + "/fields.h5", path("processes") + "/fields.h5"));
  EXPECT_TRUE(same_bytes(path("serial") + "/pile.msh", path("processes") + "/pile.msh"));
#ifdef PILELAB_MPIEXEC
  // Under the sanitizers, the ranks check memory errors but not leaks: Open MPI's plugins leave
  // allocations at exit from code it has unloaded by then, which no suppression can name
  // (docs/RELIABILITY.md). The variable means nothing to an uninstrumented build.
  const auto ranks = run(std::string(PILELAB_MPIEXEC) + " --allow-run-as-root --oversubscribe -x ASAN_OPTIONS=detect_leaks=0 -np 2 " +
                             PILELAB_BINARY +
                             " run " + ensemble_scene + " -o " + path("ranks") + " -q",
                         "", /*prefix_binary=*/false);
  ASSERT_EQ(ranks.exit_code, 0) << ranks.output;
  expect_same_members(path("serial"), path("ranks"));
  EXPECT_TRUE(same_bytes(path("serial") + "/fields.h5", path("ranks") + "/fields.h5"));
#endif
}

// srun without its MPI plugin starts each task as an MPI world of its own: every task would run
// the whole pipeline into the same OUT. A task that srun says is one of several, while MPI sees
// it alone, is refused before it writes anything.
TEST_F(Ensemble, SrunTasksThatDoNotSeeEachOtherAreRefused) {
  const auto r = run("run " + ensemble_scene + " -o " + path("out") + " -q -j 1", "SLURM_STEP_NUM_TASKS=2 SLURM_PROCID=1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("srun --mpi=pmix"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(path("out/members"))) << "nothing may be poured";
  // One task of one: the same command runs.
  const auto one = run("run " + ensemble_scene + " -o " + path("one") + " -q -j 1", "SLURM_STEP_NUM_TASKS=1");
  EXPECT_EQ(one.exit_code, 0) << one.output;
}

TEST_F(Ensemble, TheReportHoldsEveryMemberAndTheSampleStatistics) {
  const auto result = run("run " + ensemble_scene + " -o " + path("out") + " -q -P 2");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto report = report_of(path("out"));
  ASSERT_TRUE(report.contains("ensemble")) << report.dump(1);
  const auto& e = report["ensemble"];
  ASSERT_EQ(e["members"].size(), seeds.size());
  // Each member's values are its own report's, and the statistics are the sample formulas.
  std::vector<double> means, heights;
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    const auto& m = e["members"][k];
    EXPECT_EQ(m["seed"].get<int>(), seeds[k]);
    const auto own = report_of(path("out") + "/members/" + std::to_string(seeds[k]))["dem"];
    EXPECT_EQ(m["height_m"].get<double>(), own["height_m"].get<double>());
    EXPECT_EQ(own["seed"].get<int>(), seeds[k]);
    // A pile this small may have a flank too short to fit (null): it counts as missing.
    if (own["repose_angle_left_deg"].is_number() && own["repose_angle_right_deg"].is_number())
      means.push_back(0.5 * (own["repose_angle_left_deg"].get<double>() + own["repose_angle_right_deg"].get<double>()));
    heights.push_back(own["height_m"].get<double>());
  }
  ASSERT_GE(means.size(), 2u) << "too few members with both flanks for a standard deviation";
  EXPECT_EQ(e["repose_angle_pile_mean_deg"]["missing"].get<int>(), int(seeds.size() - means.size()));
  const auto expect_statistics = [&](const nlohmann::json& s, const std::vector<double>& v) {
    double mean = 0, ss = 0;
    for (double x : v) mean += x / v.size();
    for (double x : v) ss += (x - mean) * (x - mean);
    const double sd = std::sqrt(ss / (v.size() - 1));
    EXPECT_NEAR(s["mean"].get<double>(), mean, 1e-12 * std::abs(mean));
    EXPECT_NEAR(s["standard_deviation"].get<double>(), sd, 1e-12 * sd);
    EXPECT_NEAR(s["standard_error"].get<double>(), sd / std::sqrt(double(v.size())), 1e-12 * sd);
    EXPECT_EQ(s["count"].get<int>(), int(v.size()));
  };
  expect_statistics(e["repose_angle_pile_mean_deg"], means);
  expect_statistics(e["height_m"], heights);
  // The members differ (they are different piles), so the spread is a real one.
  EXPECT_GT(e["height_m"]["standard_deviation"].get<double>(), 0.0);
  // The mesh is the mean wedge, and the coarse fields average every member.
  const auto& wedge = report["mesh"]["wedge"];
  EXPECT_TRUE(wedge["from_dem"].get<bool>());
  EXPECT_NEAR(wedge["height_m"].get<double>(), e["height_m"]["mean"].get<double>(), 1e-12);
  EXPECT_NEAR(wedge["left_angle_deg"].get<double>(), e["repose_angle_left_deg"]["mean"].get<double>(), 1e-12);
  EXPECT_EQ(report["coarse"]["dem_files"].size(), seeds.size());
  // The other ensemble mesh: the members' mean outline, from the same members (not poured again).
  std::string text;
  {
    std::ifstream in(ensemble_scene);
    std::stringstream s;
    s << in.rdbuf();
    text = s.str();
  }
  const std::string wedge_line = "kind = \"wedge\"";
  ASSERT_NE(text.find(wedge_line), std::string::npos);
  text.replace(text.find(wedge_line), wedge_line.size(), "kind = \"dem_outline\"");
  const auto outline = run("run " + write_scene("outline.toml", text) + " -o " + path("out") + " -q");
  ASSERT_EQ(outline.exit_code, 0) << outline.output;
  const auto mesh = report_of(path("out"))["mesh"];
  EXPECT_EQ(mesh["kind"], "dem_outline");
  EXPECT_EQ(mesh["mean_outline_of"].get<int>(), int(seeds.size()));
  // Its height is the mean outline's peak: no higher than the tallest member.
  double tallest = 0;
  for (double h : heights) tallest = std::max(tallest, h);
  EXPECT_LE(mesh["height_m"].get<double>(), tallest * (1 + 1e-9) + 0.004);
}

TEST_F(Ensemble, AStoppedOrKilledMemberContinuesToTheSameFiles) {
  // The unbroken ensemble, then one whose second member was stopped part way (as a killed run
  // leaves it: a checkpoint and no dem.h5) and is then continued by `pilelab run`.
  ASSERT_EQ(run("run " + ensemble_scene + " -o " + path("unbroken") + " -q -j 1").exit_code, 0);
  const std::string member = path("broken") + "/members/4";
  std::filesystem::create_directories(member);
  std::filesystem::copy_file(path("unbroken") + "/members/4/scene.toml", member + "/scene.toml");
  const auto stopped = run("dem " + member + "/scene.toml -o " + member + " -q -j 1 --stop-after-steps 3000");
  ASSERT_EQ(stopped.exit_code, 0) << stopped.output;
  ASSERT_TRUE(std::filesystem::exists(member + "/checkpoint.h5"));
  ASSERT_FALSE(std::filesystem::exists(member + "/dem.h5"));
  const auto resumed = run("run " + ensemble_scene + " -o " + path("broken") + " -j 1");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("member 4 (stopped)"), std::string::npos) << resumed.output;
  expect_same_members(path("unbroken"), path("broken"));
  // A run killed with SIGKILL while two members pour side by side (their children die with
  // it), then resumed: the same files as the unbroken ensemble.
  const std::string killed = path("killed");
  const std::string script = "( " + std::string(PILELAB_BINARY) + " run " + ensemble_scene + " -o " + killed +
                             " -q -P 2 -j 1 & pid=$!; while [ ! -e " + killed +
                             "/members/4/checkpoint.h5 ] && kill -0 $pid 2>/dev/null; do sleep 0.02; done; "
                             "kill -9 $pid; wait $pid; sleep 0.5 )";
  run(script, "", /*prefix_binary=*/false);
  ASSERT_FALSE(std::filesystem::exists(killed + "/members/5/dem.h5")) << "the kill came after the members were poured";
  const auto after_kill = run("run " + ensemble_scene + " -o " + killed + " -j 1");
  ASSERT_EQ(after_kill.exit_code, 0) << after_kill.output;
  expect_same_members(path("unbroken"), killed);
  EXPECT_TRUE(same_bytes(path("unbroken") + "/fields.h5", killed + "/fields.h5"));
  // A second run pours nothing again.
  const auto again = run("run " + ensemble_scene + " -o " + path("broken") + " -j 1");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  for (int seed : seeds)
    EXPECT_NE(again.output.find("member " + std::to_string(seed) + " already poured"), std::string::npos) << again.output;
  // Nor does the same ensemble under another file name (the member scene's comment names it).
  const std::string renamed = path("renamed_ensemble.toml");
  std::filesystem::copy_file(ensemble_scene, renamed);
  const auto renamed_run = run("run " + renamed + " -o " + path("broken") + " -j 1");
  ASSERT_EQ(renamed_run.exit_code, 0) << renamed_run.output;
  for (int seed : seeds)
    EXPECT_NE(renamed_run.output.find("member " + std::to_string(seed) + " already poured"), std::string::npos)
        << renamed_run.output;
}

TEST_F(Ensemble, BadEnsembleTablesAreNamed) {
  const std::string base = "[dem]\ngrain_count = 10\n";
  struct Case {
    std::string table, expected;
  };
  for (const Case& c : {Case{"[ensemble]\nseeds = [1, 2, 1]\n", "seed 1 is listed twice"},
                        Case{"[ensemble]\nseeds = [1]\ncount = 3\n", "not both"},
                        Case{"[ensemble]\nseeds = []\n", "at least one seed"},
                        Case{"[ensemble]\ncount = 0\n", "ensemble.count"},
                        Case{"[ensemble]\nseeds = [1.5]\n", "integers"},
                        Case{"[ensemble]\n", "needs seeds"},
                        Case{"[ensemble]\nseeds = [1]\nsize = 3\n", "ensemble.size"}}) {
    const auto r = run("run " + write_scene("bad.toml", base + c.table) + " -o " + path("bad"));
    EXPECT_EQ(r.exit_code, 2) << c.table << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.table << "\n" << r.output;
  }
}
