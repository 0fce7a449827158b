// One writer per output folder (common/output_lock.h): a second lock on a held folder is refused
// naming the holder, the lock is free again when its holder ends, and a lock file left by a run
// that died holds nothing (the kernel released its flock).
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>

#include <gtest/gtest.h>

#include "common/error.h"
#include "common/output_lock.h"

using pilelab::InputError;
using pilelab::OutputLock;

namespace {
std::string fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("pilelab_lock_test_" + std::to_string(::getpid()) + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}
}  // namespace

TEST(OutputLock, ASecondWriterIsRefusedNamingTheHolder) {
  const std::string dir = fresh_dir("a");
  std::optional<OutputLock> first;
  first.emplace(dir, "pilelab dem first.toml");
  try {
    OutputLock second(dir, "pilelab dem second.toml");
    FAIL() << "the second writer was let in";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(dir), std::string::npos) << m;
    EXPECT_NE(m.find("pid " + std::to_string(::getpid())), std::string::npos) << m;
    EXPECT_NE(m.find("first.toml"), std::string::npos) << m;
  }
  first.reset();
  EXPECT_NO_THROW(OutputLock again(dir, "pilelab dem second.toml"));
  // Released, the lock file is empty: two runs' folders stay byte-identical.
  EXPECT_EQ(std::filesystem::file_size(std::filesystem::path(dir) / ".pilelab.lock"), 0u);
  std::filesystem::remove_all(dir);
}

TEST(OutputLock, ALockFileOfADeadRunHoldsNothing) {
  const std::string dir = fresh_dir("b");
  std::filesystem::create_directories(dir);
  std::ofstream(std::filesystem::path(dir) / ".pilelab.lock") << "pid 999999, pilelab run killed.toml";
  EXPECT_NO_THROW(OutputLock lock(dir, "pilelab run next.toml"));
  std::filesystem::remove_all(dir);
}

TEST(OutputLock, AnUnwritableFolderIsNamed) {
  if (::geteuid() == 0) GTEST_SKIP() << "root writes into read-only folders";
  const std::string dir = fresh_dir("c");
  std::filesystem::create_directories(dir);
  std::filesystem::permissions(dir, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  try {
    OutputLock lock(dir, "pilelab dem x.toml");
    FAIL() << "a lock in a read-only folder";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir), std::string::npos) << e.what();
  }
  std::filesystem::permissions(dir, std::filesystem::perms::owner_all);
  std::filesystem::remove_all(dir);
}
