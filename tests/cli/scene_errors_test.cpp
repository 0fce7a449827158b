// Every way a scene or a restart can be wrong gives a clear message that names the file and
// the field, and a non-zero exit, never a crash or a silent run.
#include <hdf5.h>

#include <algorithm>
#include <regex>

#include "cli_test_support.h"

using pilelab::test::CliTest;
using pilelab::test::tiny_scene;

namespace {
// The tiny scene with one line replaced (or appended when `from` is empty).
std::string edited(const std::string& from, const std::string& to) {
  std::string s = tiny_scene();
  if (from.empty()) return s + "\n" + to + "\n";
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}
}  // namespace

class SceneErrors : public CliTest {
 protected:
  void expect_error(const std::string& scene_text, const std::string& message) {
    const std::string scene = write_scene("scene.toml", scene_text);
    const auto r = run("dem " + scene + " -o " + path("out") + " -q");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(scene), std::string::npos) << "message does not name the file: " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << "expected '" << message << "' in: " << r.output;
    EXPECT_FALSE(std::filesystem::exists(path("out/dem.h5")));
  }
};

TEST_F(SceneErrors, UnknownKeyIsNamedWithTheKnownOnes) {
  expect_error(edited("grain_count = 40", "grain_count = 40\ngrain_cuont = 3"),
               "unknown key 'dem.grain_cuont'");
}

TEST_F(SceneErrors, UnknownTableIsNamed) {
  expect_error(edited("", "[dem.grain]\nshape = \"disc\""), "unknown key 'dem.grain.shape'");
}

TEST_F(SceneErrors, UnknownEmptyTableIsNamed) {
  // An empty table holds no key to catch the typo by; the table itself is checked.
  expect_error(edited("", "[dem.grian]"), "unknown table [dem.grian] (known tables: [dem.contact], [dem.container], ");
}

TEST_F(SceneErrors, EmptyKnownTableIsAccepted) {
  const std::string scene = write_scene("scene.toml", edited("", "[dem.grains]"));
  const auto r = run("dem " + scene + " -o " + path("out") + " -q --stop-after-steps 10");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST_F(SceneErrors, UnknownTopLevelTableIsNamed) {
  expect_error(edited("", "[dme]\nseed = 1"), "unknown top-level key or table 'dme'");
}

TEST_F(SceneErrors, OutOfRangeValueStatesTheRange) {
  expect_error(edited("", "[dem.contact]\nfriction_mu = -0.5"),
               "dem.contact.friction_mu: -0.5 is out of range: expected 0 <= value <= 10");
}

TEST_F(SceneErrors, WrongTypeIsNamed) {
  expect_error(edited("grain_count = 40", "grain_count = \"many\""), "dem.grain_count: expected an integer");
}

TEST_F(SceneErrors, UnknownChoiceListsTheChoices) {
  expect_error(edited("scheme = \"verlet\"", "scheme = \"rk4\""),
               "dem.integrator.scheme: \"rk4\" is not one of \"gear5\", \"verlet\", \"leapfrog\"");
}

TEST_F(SceneErrors, NotANumberIsRefused) {
  expect_error(edited("", "[dem.contact]\nfriction_mu = nan"), "dem.contact.friction_mu: expected a finite number");
}

TEST_F(SceneErrors, InfinityIsRefused) {
  expect_error(edited("", "[dem.contact]\nyoungs_modulus_N_per_m = inf"),
               "dem.contact.youngs_modulus_N_per_m: expected a finite number");
}

TEST_F(SceneErrors, WrongTypeForASwitchIsNamed) {
  expect_error(edited("enabled = true", "enabled = \"yes\""), "dem.relax.enabled: expected true or false");
}

TEST_F(SceneErrors, FrictionWithoutTangentialStiffnessIsRefused) {
  expect_error(edited("", "[dem.contact]\ntangential_stiffness_ratio = 0.0"),
               "dem.contact.tangential_stiffness_ratio = 0 with friction_mu > 0 would remove friction");
}

TEST_F(SceneErrors, InconsistentCornerRange) {
  expect_error(edited("", "[dem.grains]\ncorners_min = 8\ncorners_max = 6"), "is below dem.grains.corners_min");
}

TEST_F(SceneErrors, TimeStepAboveTheStabilityLimitIsRefused) {
  expect_error(edited("scheme = \"verlet\"", "scheme = \"verlet\"\ntime_step_s = 1e-3"),
               "dem.integrator.time_step_s = 0.001 s exceeds the stability limit");
}

TEST_F(SceneErrors, InvalidTomlGivesTheLine) {
  const std::string text = edited("grain_count = 40", "grain_count = = 40");
  const auto line = 1 + std::count(text.begin(), text.begin() + text.find("grain_count = = 40"), '\n');
  expect_error(text, "scene.toml:" + std::to_string(line) + ":");
  expect_error(text, "not valid TOML");
}

TEST_F(SceneErrors, CornerCountOutOfRange) {
  expect_error(edited("", "[dem.grains]\ncorners_max = 65"), "dem.grains.corners_max: 65 is out of range: expected 3 <= value <= 64");
}

// Axes are drawn from mean * [1 - p, 1 + p]: p = 1 would allow grains of zero size.
TEST_F(SceneErrors, PolydispersityThatAllowsVanishingGrainsIsRefused) {
  expect_error(edited("", "[dem.grains]\npolydispersity = 1.0"),
               "dem.grains.polydispersity: 1 is out of range: expected 0 <= value <= 0.9");
}

// Each value in range, but together beyond double precision: no NaN time step, no bare error.
TEST_F(SceneErrors, GrainsTooSmallToHaveAShapeAreRefused) {
  expect_error(edited("", "[dem.grains]\nmean_diameter_m = 1e-200"),
               "dem.grains.mean_diameter_m = 1e-200 m gives grain 0 no usable shape");
}

TEST_F(SceneErrors, GrainsWhoseInertiaUnderflowsAreRefused) {
  // Inertia ~ density d^4 = 5000 * 1e-400: below the smallest double.
  expect_error(edited("", "[dem.grains]\nmean_diameter_m = 1e-100"),
               "give grains whose mass, moment of inertia or stable time step");
}

TEST_F(SceneErrors, GrainsWhoseMassUnderflowsAreRefused) {
  // A grain of 3.6e-5 m^2 at 1e-305 kg/m^2: 3.6e-310 kg, below the smallest normal double.
  expect_error(edited("grain_count = 40", "grain_count = 40\nareal_density_kg_per_m2 = 1e-305"),
               "give grains whose mass, moment of inertia or stable time step");
}

// Runs no computer would finish are refused up front instead of running "forever".
TEST_F(SceneErrors, PourSoSlowItCannotEndIsRefused) {
  // 39 grains at one per 1e6 s: 3.9e7 s of pouring in steps of about 1e-5 s.
  expect_error(edited("rate_grains_per_s = 400.0", "rate_grains_per_s = 1e-6"),
               "this run would take at least");
}

TEST_F(SceneErrors, ForcedTinyTimeStepIsRefused) {
  // 0.25 s of simulated time in steps of 1e-15 s: 2.5e14 steps.
  expect_error(edited("scheme = \"verlet\"", "scheme = \"verlet\"\ntime_step_s = 1e-15"),
               "this run would take at least");
}

TEST_F(SceneErrors, FrameEveryStepIsRefusedWhenTheyWouldBeTooMany) {
  // At least 0.2475 s of run at a step near 1e-5 s: about 2.5e4 frames, one per step.
  expect_error(edited("frame_interval_s = 0.1", "frame_interval_s = 1e-7"),
               "dem.output.frame_interval_s = 1e-07 s would write at least");
}

TEST_F(SceneErrors, MissingSceneFile) {
  const auto r = run("dem " + path("nowhere.toml") + " -o " + path("out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("File does not exist: " + path("nowhere.toml")), std::string::npos) << r.output;
}

TEST_F(SceneErrors, RestartWithoutCheckpoint) {
  const std::string scene = write_scene("scene.toml", tiny_scene());
  const auto r = run("dem " + scene + " -o " + path("out") + " -q --restart");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("no checkpoint to restart from"), std::string::npos) << r.output;
}

TEST_F(SceneErrors, RestartWithAChangedSceneIsRefused) {
  const std::string scene = write_scene("scene.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("out") + " -q --stop-after-steps 200").exit_code, 0);
  write_scene("scene.toml", edited("seed = 3", "seed = 4"));
  const auto r = run("dem " + scene + " -o " + path("out") + " -q --restart");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("written for a different scene"), std::string::npos) << r.output;
}

namespace {
// Overwrites a scalar attribute of /world in a checkpoint, as a build that makes a different
// world of the same scene text would have written it.
template <typename T>
void set_world_attribute(const std::string& file, const char* name, T value, hid_t type) {
  // Deleted and created anew: HDF5 1.10 cannot rewrite an attribute in dense storage in place.
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t world = H5Gopen2(f, "/world", H5P_DEFAULT);
  ASSERT_GE(world, 0);
  EXPECT_GE(H5Adelete(world, name), 0);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(world, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(a, 0);
  EXPECT_GE(H5Awrite(a, type, &value), 0);
  H5Aclose(a);
  H5Sclose(space);
  H5Gclose(world);
  H5Fclose(f);
}
}  // namespace

TEST_F(SceneErrors, RestartByABuildThatMakesAnotherWorldIsRefused) {
  // Same scene text, but another time-step bound or grain generator in the build: a restart
  // would put other grains, or another step, into the old state.
  const std::string scene = write_scene("scene.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("out") + " -q --stop-after-steps 200").exit_code, 0);
  const std::string checkpoint = path("out/checkpoint.h5"), kept = path("kept.h5");
  std::filesystem::copy_file(checkpoint, kept);
  set_world_attribute(checkpoint, "time_step_s", 1.0e-6, H5T_NATIVE_DOUBLE);
  auto r = run("dem " + scene + " -o " + path("out") + " -q --restart");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("checkpoint.h5: /world time_step_s: this build makes a different world"), std::string::npos)
      << r.output;
  std::filesystem::copy_file(kept, checkpoint, std::filesystem::copy_options::overwrite_existing);
  set_world_attribute(checkpoint, "bodies_fingerprint", std::int64_t{12345}, H5T_NATIVE_INT64);
  r = run("dem " + scene + " -o " + path("out") + " -q --restart");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("checkpoint.h5: /world bodies_fingerprint: this build makes a different world"),
            std::string::npos)
      << r.output;
  // The untouched checkpoint restarts.
  std::filesystem::copy_file(kept, checkpoint, std::filesystem::copy_options::overwrite_existing);
  r = run("dem " + scene + " -o " + path("out") + " -q --restart");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST_F(SceneErrors, CorruptCheckpointIsNamed) {
  const std::string scene = write_scene("scene.toml", tiny_scene());
  std::filesystem::create_directories(path("out"));
  std::ofstream(path("out/checkpoint.h5")) << "not an hdf5 file";
  const auto r = run("dem " + scene + " -o " + path("out") + " -q --restart");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("checkpoint.h5: not an HDF5 file"), std::string::npos) << r.output;
}

TEST_F(SceneErrors, FunnelOutsideThePlate) {
  expect_error(edited("funnel_height_m = 0.06", "funnel_height_m = 0.06\nfunnel_x_m = 0.5"),
               "but the plate ends at +-0.15 m (dem.container.plate_width_m)");
}

TEST_F(SceneErrors, MovingFunnelThatWouldLeaveThePlate) {
  expect_error(edited("funnel_height_m = 0.06", "funnel_height_m = 0.06\nfunnel_speed_m_per_s = 3.0"),
               "grains are released out to x =");
}

TEST_F(SceneErrors, TheErrorNamesTheEdgeOfTheRelease) {
  // A centred outlet 0.4 m wide on a 0.3 m plate: the error points at its edge, x = 0.2 m.
  expect_error(edited("outlet_width_m = 0.02", "outlet_width_m = 0.4"),
               "grains are released out to x = 0.2 m (the outlet's edge: dem.pour.outlet_width_m about x = 0 m");
}

TEST_F(SceneErrors, ARainWiderThanThePlate) {
  expect_error(edited("outlet_width_m = 0.02", "kind = \"rain\"\nrain_width_m = 0.5"),
               "grains are released out to x = 0.25 m (the rain's edge: dem.pour.rain_width_m");
}

TEST_F(SceneErrors, ARainNeedsItsWidthAndNoFunnel) {
  expect_error(edited("outlet_width_m = 0.02", "kind = \"rain\""), "dem.pour.rain_width_m");
  expect_error(edited("outlet_width_m = 0.02", "kind = \"rain\"\nrain_width_m = 0.1\nfunnel_walls = true"),
               "dem.pour.funnel_walls = true: a rain has no funnel");
}

TEST_F(SceneErrors, FunnelInsideThePlate) {
  expect_error(edited("funnel_height_m = 0.06", "funnel_height_m = 0.001"),
               "dem.pour.funnel_height_m = 0.001 m: grains would be inserted into the plate");
}

TEST_F(SceneErrors, PlateThinnerThanHalfAGrain) {
  expect_error(edited("plate_width_m = 0.3", "plate_width_m = 0.3\nplate_thickness_m = 0.001"),
               "dem.container.plate_thickness_m = 0.001 m is thinner than half a grain");
}

TEST_F(SceneErrors, SettleMinimumAboveMaximum) {
  expect_error(edited("min_time_s = 0.05", "min_time_s = 0.5"), "dem.settle.min_time_s = 0.5 s exceeds dem.settle.max_time_s");
}

// The later stages check their own tables the same way.
class StageSceneErrors : public CliTest {
 protected:
  void expect_error(const std::string& command, const std::string& scene_text, const std::string& message) {
    const std::string scene = write_scene("scene.toml", scene_text);
    const auto r = run(command + " " + scene + " -o " + path("out"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << "expected '" << message << "' in: " << r.output;
  }
};

TEST_F(StageSceneErrors, MeshAngleOutOfRange) {
  expect_error("mesh", "[mesh]\nleft_angle_deg = 95\n", "mesh.left_angle_deg");
}

TEST_F(StageSceneErrors, MeshUnknownKey) {
  expect_error("mesh", "[mesh]\nelement_size = 0.01\n", "unknown key 'mesh.element_size'");
}

TEST_F(StageSceneErrors, CoarseUnknownChoice) {
  expect_error("coarse", "[coarse]\nmethod = \"voronoi\"\n", "coarse.method");
}

TEST_F(StageSceneErrors, CoarseMissingDemFile) {
  const std::string mesh_scene = write_scene("mesh.toml", "[mesh]\nelement_size_m = 0.05\n");
  ASSERT_EQ(run("mesh " + mesh_scene + " -o " + path("out")).exit_code, 0);
  expect_error("coarse", "[coarse]\ndem_files = [\"missing.h5\"]\n", "missing.h5");
}
