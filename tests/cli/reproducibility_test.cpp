// Same scene and seed give the same result, whatever the thread count, and a run stopped and
// restarted from its checkpoint ends exactly where an unbroken run ends.
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
}  // namespace

class Reproducibility : public CliTest {};

TEST_F(Reproducibility, SameSeedSameFilesAcrossThreadCounts) {
  const std::string scene = write_scene("scene.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("a") + " -q -j 1").exit_code, 0);
  ASSERT_EQ(run("dem " + scene + " -o " + path("b") + " -q -j 2").exit_code, 0);
  expect_identical(path("a/dem.h5"), path("b/dem.h5"));
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

TEST_F(Reproducibility, RestartEqualsAnUnbrokenRun) {
  const std::string scene = write_scene("scene.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("unbroken") + " -q").exit_code, 0);
  // Stop once while pouring and once after the "settled" snapshot (during the relaxation), so
  // the restart must carry contacts, springs, the random stream and finished snapshots.
  for (const char* steps : {"1500", "9000"}) {
    const std::string out = path(std::string("broken_") + steps);
    ASSERT_EQ(run("dem " + scene + " -o " + out + " -q --stop-after-steps " + steps).exit_code, 0);
    ASSERT_FALSE(std::filesystem::exists(out + "/dem.h5"));
    const auto r = run("dem " + scene + " -o " + out + " -q --restart");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_identical(path("unbroken/dem.h5"), out + "/dem.h5");
    // The deepest-overlap record travels through the checkpoint too.
    const auto report = [](const std::string& dir) {
      return nlohmann::json::parse(std::ifstream(dir + "/report.json"))["dem"];
    };
    const auto unbroken = report(path("unbroken")), restarted = report(out);
    for (const char* key : {"deepest_overlap_fraction", "deepest_overlap_time_s", "deepest_overlap_point_m",
                            "deepest_overlap_bodies"})
      EXPECT_EQ(unbroken[key], restarted[key]) << key;
  }
}
