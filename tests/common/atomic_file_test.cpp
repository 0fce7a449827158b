// Output files are replaced only by complete files: a writer that throws, or a file system that
// refuses the data (here a file-size limit, standing in for a full disk), leaves the previous
// file in place and no temporary file behind.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/hdf5_file.h"

using namespace pilelab;
namespace fs = std::filesystem;

namespace {
class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pilelab_atomic_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::size_t files_in_dir() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  fs::path dir_;
};

// Runs body in a child process whose files may not grow beyond limit_bytes (writes past it fail
// with EFBIG). Returns the child's exit code.
int run_with_file_size_limit(rlim_t limit_bytes, const std::function<int()>& body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);  // fail the write instead of killing the process
    const rlimit limit{limit_bytes, limit_bytes};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    ::_exit(body());
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
}  // namespace

TEST_F(AtomicFile, TextIsReplacedWhole) {
  write_text_atomically(path("a.txt"), "first");
  write_text_atomically(path("a.txt"), "second");
  EXPECT_EQ(read_text_file(path("a.txt")), "second");
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(AtomicFile, WriterThatThrowsLeavesTheOldFile) {
  write_text_atomically(path("a.txt"), "good");
  EXPECT_THROW(write_atomically(path("a.txt"),
                                [](const std::string& tmp) {
                                  std::ofstream(tmp) << "half";
                                  throw std::runtime_error("killed");
                                }),
               std::runtime_error);
  EXPECT_EQ(read_text_file(path("a.txt")), "good");
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(AtomicFile, RefusedTextLeavesTheOldFile) {
  write_text_atomically(path("a.txt"), "good");
  const int code = run_with_file_size_limit(1024, [&] {
    try {
      write_text_atomically(path("a.txt"), std::string(100000, 'x'));
    } catch (const InputError&) {
      return 0;
    }
    return 1;
  });
  EXPECT_EQ(code, 0) << "the refused write did not raise an InputError";
  EXPECT_EQ(read_text_file(path("a.txt")), "good");
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(AtomicFile, RefusedHdf5LeavesTheOldFile) {
  const std::vector<double> small{1.0, 2.0};
  write_atomically(path("a.h5"), [&](const std::string& tmp) {
    H5File f = H5File::create(tmp);
    f.write("/x", small);
    f.close();
  });
  // Many small datasets: HDF5 caches them and writes much of the file only when it is closed,
  // so the failure surfaces in close() (or earlier); either way the old file must survive.
  const int code = run_with_file_size_limit(4096, [&] {
    try {
      write_atomically(path("a.h5"), [&](const std::string& tmp) {
        H5File f = H5File::create(tmp);
        for (int k = 0; k < 50; ++k) f.write("/d" + std::to_string(k), std::vector<double>(64, 1.0 * k));
        f.close();
      });
    } catch (const InputError&) {
      return 0;
    }
    return 1;
  });
  EXPECT_EQ(code, 0) << "the refused write did not raise an InputError";
  EXPECT_EQ(H5File::open_read(path("a.h5")).read_doubles("/x"), small);
  EXPECT_EQ(files_in_dir(), 1u);
}

// The output directory is proved writable before a run starts, with the system's reason when
// it is not (root may write anywhere its permissions allow, but not into /proc).
TEST_F(AtomicFile, UnwritableOutputDirectoryIsFoundAtOnceWithTheReason) {
  EXPECT_NO_THROW(prepare_output_directory(path("new/deeper")));
  EXPECT_TRUE(fs::is_directory(path("new/deeper")));
  EXPECT_EQ(std::distance(fs::directory_iterator(path("new/deeper")), fs::directory_iterator()), 0) << "the probe stayed";
  std::ofstream(path("plain_file")) << "x";
  try {
    prepare_output_directory(path("plain_file/out"));
    ADD_FAILURE() << "a directory below a file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plain_file/out"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot create"), std::string::npos) << e.what();
  }
  try {
    prepare_output_directory("/proc");
    ADD_FAILURE() << "/proc was accepted as an output directory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/proc: cannot write in the output directory: "), std::string::npos) << e.what();
  }
}

// Temporary files of dead writers are removed at the next run; a live writer's, and names that
// only look alike, are kept.
TEST_F(AtomicFile, TemporaryFilesOfDeadProcessesAreRemoved) {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);  // now dead: its PID names no process (until reused, rarely soon)
  const std::string dead = path("dem.h5.tmp." + std::to_string(child));
  // gmsh picks its format from the extension, so the mesh stage's temporary carries one.
  const std::string dead_with_extension = path("pile.msh.tmp." + std::to_string(child) + ".msh");
  const std::string alive = path("dem.h5.tmp." + std::to_string(::getppid()));
  const std::string alive_with_extension = path("pile.msh.tmp." + std::to_string(::getppid()) + ".msh");
  const std::string lookalike = path("notes.tmp.draft");
  for (const auto& f : {dead, dead_with_extension, alive, alive_with_extension, lookalike}) std::ofstream(f) << "half";
  prepare_output_directory(dir_.string());
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_FALSE(fs::exists(dead_with_extension));
  EXPECT_TRUE(fs::exists(alive));
  EXPECT_TRUE(fs::exists(alive_with_extension));
  EXPECT_TRUE(fs::exists(lookalike));
}
