// common/hdf5_probe: a file that makes HDF5 itself loop is refused within the time limit, even
// in a process that handles SIGALRM itself (libFuzzer does: the child inherited the handler and
// never stopped), and a readable file passes.
#include "common/hdf5_probe.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>

#include "common/error.h"
#include "common/hdf5_file.h"

using namespace pilelab;

namespace {
void ignore_alarm(int) {}
}  // namespace

TEST(Hdf5Probe, AFileThatHangsHdf5IsRefusedWithinTheLimitWhateverTheAlarmHandler) {
  struct sigaction handler {}, previous {};
  handler.sa_handler = ignore_alarm;
  sigaction(SIGALRM, &handler, &previous);
  const std::string hang = std::string(PILELAB_SOURCE_DIR) + "/fuzz/known/dem_file_hang.h5";
  const auto start = std::chrono::steady_clock::now();
  try {
    probe_hdf5_file(hang, 1);
    ADD_FAILURE() << "a file that hangs HDF5 passed the probe";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did not finish reading this file within 1 s"), std::string::npos) << e.what();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  sigaction(SIGALRM, &previous, nullptr);
  // The child's alarm at 1 s, or the parent's kill one second later.
  EXPECT_LT(seconds, 4.0);
}

TEST(Hdf5Probe, AReadableFilePasses) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("pilelab_probe_" + std::to_string(::getpid()) + ".h5")).string();
  {
    H5File f = H5File::create(path);
    f.write("/x", std::vector<double>{1.0, 2.0, 3.0}, {}, "m");
  }
  EXPECT_NO_THROW(probe_hdf5_file(path, 5));
  std::filesystem::remove(path);
}
