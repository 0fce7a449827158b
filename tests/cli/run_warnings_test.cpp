// A finished run reports what did not stop it but should be known: an overlap too deep for the
// step it ran at (time_step.h), with when and where it happened; a stalled pour; lost grains.
#include <nlohmann/json.hpp>

#include "cli_test_support.h"

using pilelab::test::CliTest;
using pilelab::test::tiny_scene;

namespace {
nlohmann::json dem_report(const std::string& dir) {
  return nlohmann::json::parse(std::ifstream(dir + "/report.json"))["dem"];
}
bool warns_of_deep_overlap(const nlohmann::json& report) {
  for (const auto& w : report["warnings"])
    if (w.get<std::string>().find("an overlap reached") != std::string::npos) return true;
  return false;
}
}  // namespace

class RunWarnings : public CliTest {};

TEST_F(RunWarnings, ShallowContactsGiveNoOverlapWarning) {
  // Grains dropped 6 cm onto stiff contacts: overlaps stay far below a quarter of an inner radius.
  const std::string scene = write_scene("scene.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("out") + " -q").exit_code, 0);
  const auto report = dem_report(path("out"));
  EXPECT_GT(report["deepest_overlap_fraction"].get<double>(), 0.0);
  EXPECT_LT(report["deepest_overlap_fraction"].get<double>(), 0.25);
  // Contacts that shallow are stable at the default step, 0.8 of the bound for a quarter radius.
  EXPECT_GT(report["stable_time_step_at_deepest_overlap_s"].get<double>(), report["time_step_s"].get<double>());
  EXPECT_FALSE(warns_of_deep_overlap(report));
}

TEST_F(RunWarnings, DeepOverlapIsReportedWithWhenAndWhere) {
  // Contacts 100x softer than the paper's, and grains dropped from 30 cm: a grain of mass m
  // landing at v sinks about v sqrt(m / E) = 2.4 m/s * sqrt(0.18 kg / 1e5 N/m) = 3 mm, about
  // its inner radius, far beyond the quarter the time-step bound assumes. Levers shortened to
  // half and chords across the grain make such contacts stable only well below the default step.
  std::string text = tiny_scene();
  text.replace(text.find("funnel_height_m = 0.06"), 22, "funnel_height_m = 0.30");
  text.replace(text.find("[dem.integrator]"), 16, "[dem.contact]\nyoungs_modulus_N_per_m = 1e5\n\n[dem.integrator]");
  const std::string scene = write_scene("soft.toml", text);
  const auto r = run("dem " + scene + " -o " + path("out") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto report = dem_report(path("out"));
  const double fraction = report["deepest_overlap_fraction"].get<double>();
  EXPECT_GT(fraction, 0.25);
  const double dt = report["time_step_s"].get<double>();
  const double limit = report["stable_time_step_at_deepest_overlap_s"].get<double>();
  EXPECT_LT(limit, dt);
  EXPECT_TRUE(warns_of_deep_overlap(report));
  // --quiet silences the progress lines, not the warnings.
  EXPECT_NE(r.output.find("warning: an overlap reached"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("[pour"), std::string::npos) << r.output;
  // When: within the run. Where: above the plate, between two bodies that exist.
  const double t = report["deepest_overlap_time_s"].get<double>();
  EXPECT_GT(t, 0.0);
  EXPECT_LE(t, report["simulated_time_s"].get<double>());
  const auto bodies = report["deepest_overlap_bodies"];
  EXPECT_GE(bodies[0].get<int>(), 0);
  EXPECT_LT(bodies[0].get<int>(), bodies[1].get<int>());
  // The message says what the bodies are. Walls come first and never touch each other, so the
  // higher index is a grain; body 0 is the plate.
  const auto named = [&](int body) { return "(body " + std::to_string(body) + ")"; };
  EXPECT_NE(r.output.find("a grain " + named(bodies[1].get<int>())), std::string::npos) << r.output;
  if (bodies[0].get<int>() == 0) {
    EXPECT_NE(r.output.find("the plate " + named(0)), std::string::npos) << r.output;
  }
  EXPECT_NE(r.output.find(named(bodies[0].get<int>())), std::string::npos) << r.output;
  const double y = report["deepest_overlap_point_m"][1].get<double>();
  EXPECT_GT(y, -0.02);  // the plate's top is y = 0 (docs/SCENES.md)
  EXPECT_LT(y, 0.30);
}

TEST_F(RunWarnings, StalledPourSaysHowManyGrainsWereLeftOut) {
  // An outlet 15 mm above the plate: a pile of 120 grains 6.8 mm wide reaches it long before all
  // are in (a heap 15 mm high holds a few dozen), so pouring stops early.
  std::string text = tiny_scene();
  text.replace(text.find("funnel_height_m = 0.06"), 22, "funnel_height_m = 0.015");
  text.replace(text.find("grain_count = 40"), 16, "grain_count = 120");
  const std::string scene = write_scene("low.toml", text);
  const auto r = run("dem " + scene + " -o " + path("out") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto report = dem_report(path("out"));
  ASSERT_TRUE(report["pour_stalled"].get<bool>());
  const int poured = report["poured"].get<int>();
  EXPECT_LT(poured, 120);
  const std::string expected = "the pour stopped after " + std::to_string(poured) + " of 120 grains";
  EXPECT_NE(r.output.find("warning: " + expected), std::string::npos) << r.output;
  bool reported = false;
  for (const auto& w : report["warnings"]) reported = reported || w.get<std::string>().find(expected) == 0;
  EXPECT_TRUE(reported);
}

TEST_F(RunWarnings, FullPourGivesNoStallWarning) {
  const std::string scene = write_scene("scene.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("out") + " -q").exit_code, 0);
  const auto report = dem_report(path("out"));
  EXPECT_FALSE(report["pour_stalled"].get<bool>());
  EXPECT_EQ(report["poured"].get<int>(), 40);
  for (const auto& w : report["warnings"]) EXPECT_EQ(w.get<std::string>().find("the pour stopped"), std::string::npos);
}

TEST_F(RunWarnings, GrainsOffThePlateAreCountedAndNamed) {
  // The outlet 2 cm inside the plate's edge: grains that land on the outer side roll off it.
  std::string text = tiny_scene();
  text.replace(text.find("outlet_width_m = 0.02"), 21, "outlet_width_m = 0.02\nfunnel_x_m = 0.13");
  const std::string scene = write_scene("edge.toml", text);
  const auto r = run("dem " + scene + " -o " + path("out") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto report = dem_report(path("out"));
  const int lost = report["lost"].get<int>();
  ASSERT_GT(lost, 0);
  // Every grain poured is either on the plate at the end or counted as lost.
  EXPECT_EQ(report["particles"].get<int>() + lost, report["poured"].get<int>());
  const std::string expected = std::to_string(lost) + (lost == 1 ? " grain fell" : " grains fell") + " off the plate";
  EXPECT_NE(r.output.find("warning: " + expected), std::string::npos) << r.output;
}
