// Same scene and seed give the same result, whatever the thread count or the CPU's maths
// library variant, and a run stopped and restarted from its checkpoint ends exactly where an
// unbroken run ends.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "dem/dem_file.h"

using pilelab::dem::read_dem_file;
using pilelab::dem::Snapshot;
using pilelab::test::CliTest;
using pilelab::test::tiny_scene;

namespace {
void expect_identical(const std::string& a_path, const std::string& b_path) {
  const auto a = read_dem_file(a_path), b = read_dem_file(b_path);
  ASSERT_EQ(a.snapshot_names, b.snapshot_names);
  ASSERT_FALSE(a.snapshot_names.empty());
  for (const auto& name : a.snapshot_names) {
    const Snapshot x = a.snapshot(name), y = b.snapshot(name);
    EXPECT_EQ(x.time, y.time) << name;
    EXPECT_EQ(x.body, y.body) << name;
    EXPECT_EQ(x.position, y.position) << name;  // bit for bit
    EXPECT_EQ(x.angle, y.angle) << name;
    EXPECT_EQ(x.velocity, y.velocity) << name;
    EXPECT_EQ(x.angular_velocity, y.angular_velocity) << name;
    EXPECT_EQ(x.pair, y.pair) << name;
    EXPECT_EQ(x.force, y.force) << name;
  }
}

std::string bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Every output file of two runs, byte for byte: dem.h5 (so no clock or other run-dependent
// byte hides in HDF5's metadata), the frames and dem.pvd. report.json and checkpoint.h5 hold
// wall-clock times, and checkpoint_snapshots.h5 goes with the checkpoint: they are left out.
void expect_identical_outputs(const std::string& a_dir, const std::string& b_dir) {
  expect_identical(a_dir + "/dem.h5", b_dir + "/dem.h5");
  const auto names = [](const std::string& dir) {
    std::set<std::string> out;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      // The lock file (common/output_lock.h) belongs to the command, not to its outputs.
      if (name != "report.json" && name != "checkpoint.h5" && name != "checkpoint_snapshots.h5" && name != ".pilelab.lock")
        out.insert(name);
    }
    return out;
  };
  const std::set<std::string> files = names(a_dir);
  ASSERT_EQ(files, names(b_dir));
  ASSERT_TRUE(files.count("dem.h5") && files.count("dem.pvd"));
  for (const std::string& name : files)
    EXPECT_TRUE(bytes_of(a_dir + "/" + name) == bytes_of(b_dir + "/" + name)) << name << " differs";
}
}  // namespace

class Reproducibility : public CliTest {};

TEST_F(Reproducibility, SameSeedSameFilesAcrossThreadCounts) {
  const std::string scene = write_scene("scene.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("a") + " -q -j 1").exit_code, 0);
  ASSERT_EQ(run("dem " + scene + " -o " + path("b") + " -q -j 2").exit_code, 0);
  expect_identical_outputs(path("a"), path("b"));
}

// glibc chooses its sin, cos and atan by the CPU (FMA and AVX2 variants or not), and they can
// differ in the last bit, which a pile amplifies: with them this scene settled differently on a
// CPU without FMA. GLIBC_TUNABLES hides FMA and AVX2 from glibc, standing in for such a CPU.
namespace {
const char* const without_fma = "GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA";

// glibc's sin of an argument where its FMA and plain variants differ in the last bit (found by
// search), as computed by a child process with the given environment.
std::string glibc_sin_in_child(const std::string& environment) {
  const std::string cmd = environment + " /usr/bin/python3 -c \"import math; "
                          "print(math.sin(float.fromhex('0x1.32c744c93a96p+3')).hex())\"";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return "";
  char line[64] = {0};
  const bool ok = std::fgets(line, sizeof line, p) != nullptr;
  ::pclose(p);
  return ok ? line : "";
}
}  // namespace

TEST_F(Reproducibility, SameFilesWhateverTheCpuMathsVariant) {
  // The check means something only where hiding FMA and AVX2 changes glibc's results.
  const std::string plain = glibc_sin_in_child(""), hidden = glibc_sin_in_child(without_fma);
  ASSERT_FALSE(plain.empty()) << "could not run /usr/bin/python3";
  if (plain == hidden) GTEST_SKIP() << "glibc gives the same sin with and without FMA here; nothing to compare";
  const std::string scene = write_scene("scene.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("a") + " -q").exit_code, 0);
  ASSERT_EQ(run("dem " + scene + " -o " + path("b") + " -q", without_fma).exit_code, 0);
  expect_identical_outputs(path("a"), path("b"));
}

// The step's passes are compiled for AVX2 and for SSE2 and the processor picks one when the
// program starts (four_lanes.h); both must pour the same pile. The SSE2 half runs from a build
// of the DEM with that code alone.
TEST_F(Reproducibility, SameFilesWhateverTheInstructionSet) {
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "no AVX2 here: both runs would take the SSE2 code";
  const std::string scene = write_scene("scene.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("avx2") + " -q").exit_code, 0);
  const auto sse2 = run(std::string(PILELAB_DEM_SSE2_BINARY) + " " + scene + " " + path("sse2"), "", false);
  ASSERT_EQ(sse2.exit_code, 0) << sse2.output;
  expect_identical_outputs(path("avx2"), path("sse2"));
}

TEST_F(Reproducibility, DifferentSeedsGiveDifferentPiles) {
  const std::string one = write_scene("one.toml", tiny_scene());
  std::string text = tiny_scene();
  text.replace(text.find("seed = 3"), 8, "seed = 5");
  const std::string two = write_scene("two.toml", text);
  ASSERT_EQ(run("dem " + one + " -o " + path("a") + " -q").exit_code, 0);
  ASSERT_EQ(run("dem " + two + " -o " + path("b") + " -q").exit_code, 0);
  EXPECT_NE(read_dem_file(path("a/dem.h5")).snapshot("settled").position,
            read_dem_file(path("b/dem.h5")).snapshot("settled").position);
}

// A restart must carry everything a step depends on, which differs by integrator (Gear's
// higher derivatives, leapfrog's half-step velocities) and by protocol (a moving funnel's walls).
struct RestartCase {
  const char* name;
  const char* scheme;
  const char* extra_pour_keys;
};

class Restart : public CliTest, public ::testing::WithParamInterface<RestartCase> {};

TEST_P(Restart, EqualsAnUnbrokenRun) {
  std::string text = tiny_scene();
  text.replace(text.find("scheme = \"verlet\""), 17, std::string("scheme = \"") + GetParam().scheme + "\"");
  text.replace(text.find("[dem.pour]\n"), 11, std::string("[dem.pour]\n") + GetParam().extra_pour_keys);
  const std::string scene = write_scene("scene.toml", text);
  const auto u = run("dem " + scene + " -o " + path("unbroken") + " -q");
  ASSERT_EQ(u.exit_code, 0) << u.output;
  const auto report = [](const std::string& dir) {
    return nlohmann::json::parse(std::ifstream(dir + "/report.json"))["dem"];
  };
  const auto unbroken = report(path("unbroken"));
  // Stop once while pouring and once during the relaxation, after the "settled" snapshot, so
  // the restart must carry contacts, springs, the random stream and finished snapshots.
  const double steps = unbroken["steps"].get<double>(), total = unbroken["simulated_time_s"].get<double>();
  const double settled = unbroken["settling"]["settled"]["time_s"].get<double>();
  ASSERT_LT(settled, total);
  for (const double stop_time : {0.1 * settled, 0.5 * (settled + total)}) {
    const std::string stop = std::to_string(static_cast<long long>(steps * stop_time / total));
    const std::string out = path("broken_" + stop);
    ASSERT_EQ(run("dem " + scene + " -o " + out + " -q --stop-after-steps " + stop).exit_code, 0);
    ASSERT_FALSE(std::filesystem::exists(out + "/dem.h5"));
    const auto r = run("dem " + scene + " -o " + out + " -q --restart");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_identical_outputs(path("unbroken"), out);
    // The deepest-overlap and swing records travel through the checkpoint too.
    const auto restarted = report(out);
    EXPECT_EQ(unbroken["steps"], restarted["steps"]);
    for (const char* key : {"deepest_overlap_fraction", "deepest_overlap_time_s", "deepest_overlap_point_m",
                            "deepest_overlap_bodies", "longest_swing_steps", "longest_swing_time_s",
                            "longest_swing_bodies"})
      EXPECT_EQ(unbroken[key], restarted[key]) << key;
    // The counters are the whole run's, not the last session's: the list builds of both
    // sessions, which differ from the unbroken run's only by the resumed session's first build
    // and the margins it starts afresh (0 to 2 builds apart in every case here).
    const double builds = unbroken["neighbour_list_builds"].get<double>();
    EXPECT_NEAR(restarted["neighbour_list_builds"].get<double>(), builds, 2.0);  // the last session alone: 30-90 % of it
  }
}

INSTANTIATE_TEST_SUITE_P(
    SchemesAndFunnels, Restart,
    ::testing::Values(RestartCase{"verlet", "verlet", ""}, RestartCase{"leapfrog", "leapfrog", ""},
                      RestartCase{"gear5", "gear5", ""},
                      RestartCase{"verlet_moving_funnel", "verlet", "funnel_speed_m_per_s = 0.2\nfunnel_travel_m = 0.04\n"}),
    [](const ::testing::TestParamInfo<RestartCase>& info) { return std::string(info.param.name); });
