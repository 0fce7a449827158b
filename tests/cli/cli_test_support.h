#pragma once
// Runs the pilelab command on scenes written into a fresh temporary directory.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace pilelab::test {

inline std::string tiny_scene() {
  std::ifstream in(std::string(PILELAB_SOURCE_DIR) + "/tests/cli/tiny.toml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct CommandResult {
  int exit_code;
  std::string output;  // stdout and stderr
};

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    // A parametrised test's names hold '/' (Cases/Name/3): one directory level, not three, so
    // that TearDown removes all of it.
    std::string name = "pilelab_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" + std::to_string(::getpid());
    std::replace(name.begin(), name.end(), '/', '_');
    dir_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) std::filesystem::remove_all(dir_);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write_scene(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  // Runs pilelab with args; environment is "NAME=value ..." put before the command. With
  // prefix_binary false, args is the whole command (e.g. mpirun ... pilelab ...).
  CommandResult run(const std::string& args, const std::string& environment = "", bool prefix_binary = true) const {
    const std::string log = path("command.log");
    const std::string cmd = environment + " " + (prefix_binary ? std::string(PILELAB_BINARY) + " " : std::string()) + args +
                            " > " + log + " 2>&1";
    const int status = std::system(cmd.c_str());
    std::ifstream in(log);
    std::stringstream s;
    s << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, s.str()};
  }
  // Whether every floating-point dataset of the HDF5 file h5 is finite (no NaN, no infinity).
  bool every_number_finite(const std::string& h5) const {
    const auto r = run("/usr/bin/python3 -c \"import h5py, numpy as np, sys; f = h5py.File('" + h5 +
                           "'); bad = []; f.visititems(lambda n, o: bad.append(n) if isinstance(o, h5py.Dataset) and "
                           "o.dtype.kind == 'f' and not np.isfinite(o[()]).all() else None); print(bad); "
                           "sys.exit(1 if bad else 0)\"",
                       "", /*prefix_binary=*/false);
    return r.exit_code == 0;
  }
  std::filesystem::path dir_;
};

}  // namespace pilelab::test
