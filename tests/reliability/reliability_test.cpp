// Failures of the machine and of the numbers end in a clear message and a non-zero exit, never
// a crash: a full disk (a file-size limit, and a real small tmpfs where mounting is allowed), a
// read-only file system, a time step far above the stability limit forced through, and an
// empty scene.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <vector>

#include "../cli/cli_test_support.h"

using pilelab::test::CliTest;
using pilelab::test::tiny_scene;

class Reliability : public CliTest {
 protected:
  static std::string read_file(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  // No temporary file of a writer is left behind.
  void expect_no_temporary_files(const std::string& dir) {
    if (!std::filesystem::exists(dir)) return;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
};

TEST_F(Reliability, AFullDiskIsAClearErrorWithoutACrash) {
  // Files may not grow past a limit: one below any file the run writes, so that nothing can be
  // written, and one between the largest file written before dem.h5 and dem.h5 itself, so that
  // the frames and checkpoints fit and dem.h5 does not. The sizes come from a run without a
  // limit (they change with the pile's realisation). The ignored SIGXFSZ makes the write fail
  // (EFBIG) instead of killing the process.
  const std::string scene = write_scene("tiny.toml", tiny_scene());
  const std::string free_run = path("unlimited");
  ASSERT_EQ(run("dem " + scene + " -o " + free_run + " -q -j 1").exit_code, 0);
  std::uintmax_t dem_size = 0, largest_other = 0;
  for (const auto& e : std::filesystem::directory_iterator(free_run)) {
    const std::uintmax_t size = std::filesystem::file_size(e.path());
    if (e.path().filename() == "dem.h5")
      dem_size = size;
    else
      largest_other = std::max(largest_other, size);
  }
  ASSERT_GT(dem_size, largest_other + 2048) << "dem.h5 must be the largest file by a margin for this test";
  // 4 KiB: below any frame or checkpoint (each holds every grain's state, tens of KB here).
  for (const std::uintmax_t kib : {std::uintmax_t(4), (largest_other + dem_size) / 2 / 1024}) {
    const std::string out = path("out" + std::to_string(kib));
    const auto r = run("bash -c \"trap '' XFSZ; ulimit -f " + std::to_string(kib) + "; exec " + std::string(PILELAB_BINARY) +
                           " dem " + scene + " -o " + out + " -q -j 1\"",
                       "", /*prefix_binary=*/false);
    EXPECT_EQ(r.exit_code, 2) << kib << " KiB: expected a clear error (exit code 2), not a crash:\n" << r.output;
    EXPECT_NE(r.output.find("pilelab: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(out), std::string::npos) << "the message should name the file:\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(out + "/dem.h5"));
    expect_no_temporary_files(out);
  }
}

// A small tmpfs mounted for one test, unmounted when it ends; where mounting is not allowed (not
// root, no CAP_SYS_ADMIN in a container) the test skips, saying so.
class MountedTmpfs {
 public:
  MountedTmpfs(const std::string& dir, const std::string& options) : dir_(dir) {
    std::filesystem::create_directories(dir);
    mounted_ = std::system(("mount -t tmpfs -o " + options + " tmpfs " + dir + " 2>/dev/null").c_str()) == 0;
  }
  ~MountedTmpfs() {
    if (mounted_) (void)std::system(("umount " + dir_).c_str());
  }
  bool mounted() const { return mounted_; }

 private:
  std::string dir_;
  bool mounted_ = false;
};

TEST_F(Reliability, ARealFullDiskIsAClearErrorWithoutACrash) {
  // A 96 KiB file system: the frames and the first checkpoints fit, dem.h5 does not.
  const MountedTmpfs disk(path("disk"), "size=96k");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  const std::string out = path("disk/out");
  const auto r = run("dem " + write_scene("tiny.toml", tiny_scene()) + " -o " + out + " -q -j 1");
  EXPECT_EQ(r.exit_code, 2) << "expected a clear error (exit code 2), not a crash:\n" << r.output;
  EXPECT_NE(r.output.find("pilelab: error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(out), std::string::npos) << "the message should name the file:\n" << r.output;
  EXPECT_FALSE(std::filesystem::exists(out + "/dem.h5"));
  expect_no_temporary_files(out);
}

TEST_F(Reliability, AReadOnlyFileSystemIsFoundBeforeTheRun) {
  const MountedTmpfs disk(path("readonly"), "size=64k,ro");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  const auto r = run("dem " + write_scene("tiny.toml", tiny_scene()) + " -o " + path("readonly/out") + " -q -j 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(path("readonly/out")), std::string::npos) << "the message should name the folder:\n" << r.output;
  EXPECT_NE(r.output.find("Read-only file system"), std::string::npos) << "and the system's reason:\n" << r.output;
  EXPECT_EQ(r.output.find("[pour"), std::string::npos) << "nothing may be poured first:\n" << r.output;
}

TEST_F(Reliability, ATimeStepFarAboveTheLimitStops) {
  // Forced to 28 times the stability limit (4e-4 s against 1.43e-5 s), the contacts gain
  // energy each step: the run must stop, when the grains hold more energy than the pour put in
  // or when a number overflows, whichever comes first, naming a grain, the time and the step,
  // and write no dem.h5.
  std::string text = tiny_scene();
  const std::string scheme = "scheme = \"verlet\"";
  text.replace(text.find(scheme), scheme.size(),
               scheme + "\ntime_step_s = 4e-4\nallow_unstable_time_step = true");
  const auto r = run("dem " + write_scene("unstable.toml", text) + " -o " + path("out") + " -q -j 1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(r.output.find("creates energy") != std::string::npos ||
              r.output.find("no longer finite") != std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("body "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(step "), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(path("out/dem.h5")));
}

TEST_F(Reliability, AnEmptySceneSaysItPoursTheDefaultPile) {
  const auto r = run("dem " + write_scene("empty.toml", "") + " -o " + path("out") + " -q --stop-after-steps 10");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("has no [dem] table: pouring the default pile (500 grains"), std::string::npos) << r.output;
}

TEST_F(Reliability, AnInterruptedPourWritesACheckpointAndSaysHowToContinue) {
  // SIGINT once the first checkpoint exists: exit 128 + SIGINT, a message naming --restart, and
  // the restarted run ends with the unbroken run's dem.h5.
  const std::string scene = write_scene("tiny.toml", tiny_scene());
  ASSERT_EQ(run("dem " + scene + " -o " + path("unbroken") + " -q -j 1").exit_code, 0);
  const std::string out = path("out");
  const auto r = run("bash -c '" + std::string(PILELAB_BINARY) + " dem " + scene + " -o " + out + " -j 1 & pid=$!; " +
                         "while [ ! -e " + out + "/checkpoint.h5 ] && kill -0 $pid 2>/dev/null; do sleep 0.01; done; " +
                         "kill -INT $pid; wait $pid'",
                     "", /*prefix_binary=*/false);
  if (std::filesystem::exists(out + "/dem.h5")) GTEST_SKIP() << "the pour ended before the signal came";
  EXPECT_EQ(r.exit_code, 128 + 2) << r.output;
  EXPECT_NE(r.output.find("interrupted by SIGINT"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--restart"), std::string::npos) << r.output;
  ASSERT_EQ(run("dem " + scene + " -o " + out + " -q -j 1 --restart").exit_code, 0);
  EXPECT_EQ(std::system(("cmp -s " + out + "/dem.h5 " + path("unbroken") + "/dem.h5").c_str()), 0)
      << "the continued run differs from the unbroken one";
}

TEST_F(Reliability, AFullDiskDuringMeshKeepsTheGoodMesh) {
  // A pile meshed once; then its folder on a tmpfs with 8 KiB left, and the mesh asked again:
  // gmsh's write is cut short without a word, so the stage must find the file incomplete, say
  // so naming it, exit 2 and leave the first pile.msh as it was, with no temporary file.
  const std::string scene =
      write_scene("tiny.toml", tiny_scene() + "\n[mesh]\nkind = \"dem_outline\"\nelement_size_m = 0.002\n");
  const std::string first = path("first");
  ASSERT_EQ(run("dem " + scene + " -o " + first + " -q -j 1").exit_code, 0);
  ASSERT_EQ(run("mesh " + scene + " -o " + first).exit_code, 0);
  const std::string good = read_file(first + "/pile.msh");
  ASSERT_GT(good.size(), 16384u) << "the mesh must be larger than what the disk leaves room for";
  const MountedTmpfs disk(path("disk"), "size=4m");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  const std::string out = path("disk/out");
  std::filesystem::copy(first, out, std::filesystem::copy_options::recursive);
  const std::uintmax_t room = std::filesystem::space(out).available;
  ASSERT_GT(room, 8192u);
  {
    std::ofstream filler(path("disk/filler"), std::ios::binary);
    const std::string block(4096, '\0');
    for (std::uintmax_t n = 0; n + 8192 < room; n += block.size()) filler << block;
  }
  const auto r = run("mesh " + scene + " -o " + out);
  EXPECT_EQ(r.exit_code, 2) << "expected a clear error (exit code 2):\n" << r.output;
  EXPECT_NE(r.output.find("pile.msh"), std::string::npos) << "the message should name the file:\n" << r.output;
  EXPECT_TRUE(read_file(out + "/pile.msh") == good) << "the good mesh was replaced";
  expect_no_temporary_files(out);
}

// Every stage on a full disk and on a read-only folder, in a folder holding a finished run: a
// clear error (exit code 2) naming a file or the folder, every file of the finished run left as
// it was (no good file replaced by a bad one), and no temporary file (issue 58 points 1 and 2).
TEST_F(Reliability, EveryStageOnAFullDiskOrAReadOnlyFolderKeepsTheGoodFiles) {
  const std::string scene = std::string(PILELAB_SOURCE_DIR) + "/tests/cli/tiny_pipeline.toml";
  const std::string good = path("good");
  ASSERT_EQ(run("run " + scene + " -o " + good + " -q --no-figures").exit_code, 0);
  std::map<std::string, std::string> before;
  for (const auto& e : std::filesystem::recursive_directory_iterator(good))
    if (e.is_regular_file() && e.path().filename() != ".pilelab.lock")
      before[std::filesystem::relative(e.path(), good).string()] = read_file(e.path().string());
  std::vector<std::string> stages = {"mesh", "coarse", "compare"};
#ifdef PILELAB_WITH_CONTINUUM
  stages.push_back("solve");
#endif
  for (const std::string& stage : stages)
    for (const bool read_only : {false, true}) {
      SCOPED_TRACE(stage + (read_only ? " on a read-only folder" : " on a full disk"));
      const std::string mount_point = path("disk_" + stage + (read_only ? "_ro" : "_full"));
      const MountedTmpfs disk(mount_point, "size=4m");
      if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
      const std::string out = mount_point + "/out";
      std::filesystem::copy(good, out, std::filesystem::copy_options::recursive);
      if (read_only) {
        ASSERT_EQ(std::system(("mount -o remount,ro " + mount_point).c_str()), 0);
      } else {
        // 8 KiB left: room for a stage's probe, not for report.json (18 KB) or any output.
        const std::uintmax_t room = std::filesystem::space(out).available;
        std::ofstream filler(mount_point + "/filler", std::ios::binary);
        const std::string block(4096, '\0');
        for (std::uintmax_t n = 0; n + 8192 < room; n += block.size()) filler << block;
      }
      const auto r = run(stage + " " + scene + " -o " + out);
      EXPECT_EQ(r.exit_code, 2) << "expected a clear error (exit code 2):\n" << r.output;
      EXPECT_NE(r.output.find(out), std::string::npos) << "the message should name the file or folder:\n" << r.output;
      EXPECT_NE(r.output.find(read_only ? "Read-only file system" : "pilelab: error: "), std::string::npos) << r.output;
      for (const auto& [file, bytes] : before)
        EXPECT_TRUE(read_file(out + "/" + file) == bytes) << file << " was changed";
      expect_no_temporary_files(out);
    }
}

#ifdef PILELAB_WITH_CONTINUUM
TEST_F(Reliability, SolveFindsAReadOnlyFolderBeforeItComputes) {
  // `pilelab solve` into a read-only folder: exit 2 naming the folder and the system's reason,
  // before any model is solved (no model's progress line).
  const MountedTmpfs disk(path("readonly"), "size=64k,ro");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  const std::string scene = write_scene(
      "wedge.toml", "[mesh]\nkind = \"wedge\"\nelement_size_m = 0.05\n\n[continuum]\nmodels = [\"elastic\"]\n");
  const auto r = run("solve " + scene + " -o " + path("readonly/out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(path("readonly/out")), std::string::npos) << "the message should name the folder:\n" << r.output;
  EXPECT_NE(r.output.find("Read-only file system"), std::string::npos) << "and the system's reason:\n" << r.output;
  EXPECT_EQ(r.output.find("elastic:"), std::string::npos) << "nothing may be solved first:\n" << r.output;
}
#endif

// Two writers into one folder: the second is refused at once, naming the first, and the first
// finishes its pile untouched (before, both exited 0 with dem.h5 from one and frames from the
// other).
TEST_F(Reliability, ASecondWriterIntoTheSameFolderIsRefused) {
  std::string text = tiny_scene();
  const std::string count = "grain_count = 40";
  ASSERT_NE(text.find(count), std::string::npos);
  text.replace(text.find(count), count.size(), "grain_count = 400");  // a pour of some seconds
  const std::string scene = write_scene("longer.toml", text), out = path("shared");
  const std::string first = "bash -c '" + std::string(PILELAB_BINARY) + " dem " + scene + " -o " + out +
                            " -q -j 1 > " + path("first.log") + " 2>&1; echo $? > " + path("first.code") + "' &";
  ASSERT_EQ(std::system(first.c_str()), 0);
  // Wait until the first holds the lock (its note is in the lock file).
  const std::string lock = out + "/.pilelab.lock";
  for (int i = 0; i < 200 && !(std::filesystem::exists(lock) && std::filesystem::file_size(lock) > 0); ++i)
    ::usleep(50000);
  ASSERT_GT(std::filesystem::file_size(lock), 0u) << "the first writer never took the lock";
  const auto second = run("dem " + scene + " -o " + out + " -q -j 1");
  EXPECT_EQ(second.exit_code, 2) << second.output;
  EXPECT_NE(second.output.find("another pilelab process"), std::string::npos) << second.output;
  EXPECT_NE(second.output.find("longer.toml"), std::string::npos) << "the holder's command is named:\n" << second.output;
  for (int i = 0; i < 1200 && !std::filesystem::exists(path("first.code")); ++i) ::usleep(100000);
  std::ifstream code_in(path("first.code"));
  int code = -1;
  code_in >> code;
  std::ifstream log(path("first.log"));
  EXPECT_EQ(code, 0) << std::string(std::istreambuf_iterator<char>(log), {});
  EXPECT_TRUE(std::filesystem::exists(out + "/dem.h5"));
}

// A second scene poured into a folder where a first left more frames: afterwards every frame in
// the folder is one of dem.pvd's, and every one dem.pvd names is there (before: the first pile's
// later frames stood beside the second's series).
TEST_F(Reliability, ASecondPourIntoAFolderLeavesNoStaleFrames) {
  std::string dense = tiny_scene();
  const std::string interval = "frame_interval_s = 0.1";
  ASSERT_NE(dense.find(interval), std::string::npos);
  dense.replace(dense.find(interval), interval.size(), "frame_interval_s = 0.02");
  const std::string out = path("out");
  ASSERT_EQ(run("dem " + write_scene("dense.toml", dense) + " -o " + out + " -q -j 1").exit_code, 0);
  const auto frames = [&] {
    std::set<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(out)) {
      const std::string name = e.path().filename().string();
      if (name.size() > 4 && name.compare(name.size() - 4, 4, ".vtu") == 0) names.insert(name);
    }
    return names;
  };
  const std::size_t first_pour = frames().size();
  ASSERT_EQ(run("dem " + write_scene("tiny.toml", tiny_scene()) + " -o " + out + " -q -j 1").exit_code, 0);
  const std::set<std::string> left = frames();
  ASSERT_LT(left.size(), first_pour) << "the second pour must write fewer frames for this test";
  const std::string pvd = read_file(out + "/dem.pvd");
  std::set<std::string> listed;
  for (std::size_t at = pvd.find("file=\""); at != std::string::npos; at = pvd.find("file=\"", at + 1)) {
    const std::size_t start = at + 6;
    listed.insert(pvd.substr(start, pvd.find('"', start) - start));
  }
  EXPECT_EQ(left, listed);
}

// The figures on a full disk: the folder and the system's reason, exit code 2, no traceback and
// no temporary file left (before: a Python traceback and exit 1).
TEST_F(Reliability, FiguresOnAFullDiskAreAClearError) {
  const std::string scene = std::string(PILELAB_SOURCE_DIR) + "/tests/cli/tiny_pipeline.toml";
  const std::string out = path("run");
  ASSERT_EQ(run("run " + scene + " -o " + out + " -q --no-figures").exit_code, 0);
  const MountedTmpfs disk(path("disk"), "size=8k");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  std::filesystem::create_symlink(path("disk"), out + "/figures");
  const auto r = run("env MATPLOTLIBRC=/usr/share/matplotlib/mpl-data/matplotlibrc /usr/bin/python3 " +
                         std::string(PILELAB_SOURCE_DIR) + "/scripts/figures.py " + out,
                     "", /*prefix_binary=*/false);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("Traceback"), std::string::npos) << r.output;
  expect_no_temporary_files(path("disk"));
}
