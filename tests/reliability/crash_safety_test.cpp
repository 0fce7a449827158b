// Crash safety: `pilelab run` on the tiny pipeline, killed with SIGKILL at 20 or more seeded random
// moments and resumed each time with --restart. After every kill, every file in OUT must read
// whole, and every final output present must equal the unbroken run's byte for byte (a kill
// during a write must never leave a half-written file in place of a good one). The resumed run
// must then finish with the unbroken run's files.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <thread>

#include "../cli/cli_test_support.h"

using pilelab::test::CliTest;

namespace {
const std::string pipeline_scene = std::string(PILELAB_SOURCE_DIR) + "/tests/cli/tiny_pipeline.toml";
// The outputs a finished run has, all deterministic (report.json and stages.json hold wall
// times and fingerprints; figures are pictures).
const std::vector<std::string> final_outputs = {"dem.h5",     "dem.pvd",      "pile.msh",    "fields.h5",
                                                "fields.vtu", "profiles.csv", "compare.vtu", "fit_samples.csv",
                                                "rve_study.csv",
#ifdef PILELAB_WITH_CONTINUUM
                                                "models.h5",  "elastic.vtu",  "fpa.vtu"
#endif
};

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The stage the log says was running last ("pilelab run: coarse   running").
std::string last_stage(const std::string& log) {
  const std::string text = bytes_of(log);
  std::string stage = "start";
  for (std::size_t at = text.find("pilelab run: "); at != std::string::npos; at = text.find("pilelab run: ", at + 1)) {
    std::istringstream line(text.substr(at + 13, 40));
    std::string name, what;
    line >> name >> what;
    if (what == "running") stage = name;
    if (what == "done" || what == "skipped") stage = name + " (after)";
  }
  return stage;
}
}  // namespace

class CrashSafety : public CliTest {};

TEST_F(CrashSafety, TwentyKillsAcrossTheStagesLoseNothing) {
  const std::string reference = path("unbroken");
  const auto unbroken = run("run " + pipeline_scene + " -o " + reference + " -j 1");
  ASSERT_EQ(unbroken.exit_code, 0) << unbroken.output;

  std::mt19937 rng(2026);
  // Delays from 10 ms to 1.5 s, uniform in their logarithm: the stages of the tiny pipeline
  // last from milliseconds (mesh, coarse) to seconds (the figures).
  std::uniform_real_distribution<double> log_delay(std::log(0.01), std::log(1.5));
  const auto delay_s = [&](std::mt19937& r) { return std::exp(log_delay(r)); };
  std::map<std::string, int> kills_by_stage;
  int kills = 0;
  // Rounds: a fresh output directory, killed again and again (resumed each time with --restart)
  // until a run of it finishes; at most max_kills_per_stage kills per stage in one round, so
  // that the long figure script at the end does not take them all. Rounds repeat until 20 kills.
  const int max_kills_per_stage = 2;
  for (int round = 0; kills < 20 && round < 12; ++round) {
    const std::string out = path("killed_" + std::to_string(round));
    std::map<std::string, int> round_kills;
    for (int attempt = 0; attempt < 100; ++attempt) {
      const std::string log = path("attempt.log");
      const pid_t pid = fork();
      ASSERT_GE(pid, 0);
      if (pid == 0) {
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
        setenv("OMP_WAIT_POLICY", "passive", 1);
        execl(PILELAB_BINARY, PILELAB_BINARY, "run", pipeline_scene.c_str(), "-o", out.c_str(), "-j", "1", "--restart",
              static_cast<char*>(nullptr));
        _exit(127);
      }
      // A kill falls due after a random delay, unless the stage running then has had its share
      // of this round's kills: then the next random delay is waited for.
      auto due = std::chrono::steady_clock::now() +
                 std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(delay_s(rng)));
      int status = 0;
      bool finished = false;
      while (true) {
        finished = waitpid(pid, &status, WNOHANG) == pid;
        if (finished) break;
        if (std::chrono::steady_clock::now() >= due) {
          if (round_kills[last_stage(log)] < max_kills_per_stage) break;
          due += std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(delay_s(rng)));
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
      if (finished) {
        ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << bytes_of(log);
        break;
      }
      ::kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      ++kills;
      const std::string stage = last_stage(log);
      ++round_kills[stage];
      ++kills_by_stage[stage];
      // Everything present reads whole, and every final output present is the unbroken run's
      // (profiles.csv grows stage by stage and dem.pvd frame by frame: only their final forms
      // are compared).
      const auto readable = run("/usr/bin/python3 " + std::string(PILELAB_SOURCE_DIR) +
                                    "/tests/reliability/check_files_readable.py " + out,
                                "", /*prefix_binary=*/false);
      ASSERT_EQ(readable.exit_code, 0) << "after kill " << kills << ":\n" << readable.output;
      for (const std::string& f : final_outputs) {
        if (f != "profiles.csv" && f != "dem.pvd" && std::filesystem::exists(out + "/" + f))
          ASSERT_TRUE(bytes_of(out + "/" + f) == bytes_of(reference + "/" + f)) << f << " after kill " << kills;
      }
    }
    // The round's finished run has the unbroken run's files, and no stale temporary file.
    for (const std::string& f : final_outputs) {
      ASSERT_TRUE(std::filesystem::exists(out + "/" + f)) << f;
      EXPECT_TRUE(bytes_of(out + "/" + f) == bytes_of(reference + "/" + f)) << f << " differs from the unbroken run's";
    }
    for (const auto& e : std::filesystem::directory_iterator(out))
      EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
  EXPECT_GE(kills, 20);
  std::string spread;
  for (const auto& [stage, n] : kills_by_stage) spread += " " + stage + ": " + std::to_string(n) + ";";
  std::printf("%d kills by stage:%s\n", kills, spread.c_str());
  EXPECT_GE(kills_by_stage.size(), 3u) << "the kills did not spread over the stages:" << spread;
}
