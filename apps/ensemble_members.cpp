#include "apps/ensemble_members.h"

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <thread>

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <toml++/toml.h>

#include "apps/child_process.h"
#include "apps/parallel.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "common/report.h"
#include "dem/dem_result.h"
#include "dem/pile_run.h"

namespace pilelab::app {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

// Where a member stands: poured (its dem.h5 and report are there, for the scene it has now),
// stopped (a checkpoint of that scene is there), or to be poured from the start.
enum class MemberState { poured, stopped, fresh };

struct Member {
  std::int64_t seed = 0;
  std::string dir, scene_file, log_file;
  MemberState state = MemberState::fresh;
};

bool report_has_dem(const std::string& path) {
  try {
    return read_report(path).contains("dem");
  } catch (const InputError&) {
    return false;  // a damaged report: pour again
  }
}

// Whether the member's scene file holds the tables of text: compared as TOML, so that the
// comment naming the ensemble's file (renamed, or a study's copy of it) cannot make an hour's
// pour count as another scene's.
bool same_member_scene(const std::string& scene_file, const std::string& text) {
  if (!fs::exists(scene_file)) return false;
  try {
    return toml::parse_file(scene_file) == toml::parse(text);
  } catch (const toml::parse_error&) {
    return false;  // a damaged scene file: pour again
  }
}

// Readies a member's directory and says what it needs. A member whose scene changed (another
// [dem] table) starts afresh: its old pile and checkpoint belong to another scene.
Member prepare_member(const std::string& scene_path, const std::string& out_dir, std::int64_t seed) {
  Member m;
  m.seed = seed;
  m.dir = member_directory(out_dir, seed);
  m.scene_file = (fs::path(m.dir) / "scene.toml").string();
  m.log_file = (fs::path(m.dir) / "dem.log").string();
  const std::string text = member_scene_text(scene_path, seed);
  std::error_code ec;
  fs::create_directories(m.dir, ec);
  if (ec) throw InputError(m.dir + ": cannot create the member's directory: " + ec.message());
  const bool same_scene = same_member_scene(m.scene_file, text);
  if (same_scene && fs::exists(fs::path(m.dir) / "dem.h5") && report_has_dem((fs::path(m.dir) / "report.json").string()))
    m.state = MemberState::poured;
  else if (same_scene && fs::exists(fs::path(m.dir) / "checkpoint.h5"))
    m.state = MemberState::stopped;
  else {
    for (const char* stale : {"dem.h5", "checkpoint.h5", "report.json"}) fs::remove(fs::path(m.dir) / stale, ec);
    write_text_atomically(m.scene_file, text);
    m.state = MemberState::fresh;
  }
  return m;
}

const char* state_name(MemberState s) {
  switch (s) {
    case MemberState::poured: return "poured";
    case MemberState::stopped: return "stopped";
    case MemberState::fresh: return "fresh";
  }
  return "?";
}

// One member in this process.
void pour_here(const Member& m, int threads, bool quiet) {
  dem::DemRunOptions o;
  o.scene_path = m.scene_file;
  o.out_dir = m.dir;
  o.restart = m.state == MemberState::stopped;
  o.quiet = quiet;
  o.threads = threads;
  dem::run_dem(o);
}

// One member as a child `pilelab dem` process, its output in the member's dem.log; it dies
// with this process.
pid_t spawn_member(const Member& m, int threads) {
  std::vector<std::string> args = {own_executable(), "dem", m.scene_file, "-o", m.dir, "-j", std::to_string(threads)};
  if (m.state == MemberState::stopped) args.push_back("--restart");
  return start_child(args, m.log_file);
}

int cores() { return std::max(1u, std::thread::hardware_concurrency()); }

std::string describe_failures(const std::vector<std::string>& failures) {
  std::string text = std::to_string(failures.size()) + " member(s) failed:";
  for (const auto& f : failures) text += "\n  " + f;
  return text;
}

}  // namespace

void pour_members(const EnsembleSpec& ensemble, const MemberRunOptions& options) {
  const bool mpi = launched_by_mpi();
  if (mpi && options.processes > 1)
    throw InputError("pilelab run: -P (member processes) and mpirun (member ranks) do not mix; use one of them");
  const std::size_t n = ensemble.seeds.size();

  if (mpi) {
    MpiWorld& world = MpiWorld::get();
    // Threads per member: -j, else OMP_NUM_THREADS, else the machine's cores shared among the
    // ranks on it.
    const int threads = options.threads > 0                  ? options.threads
                        : std::getenv("OMP_NUM_THREADS") != nullptr ? 0
                                                                    : std::max(1, cores() / world.ranks_on_this_machine());
    std::vector<std::string> failures;
    {
      MpiWorld::SharedCounter next(world);
      for (long k = next.next(); k < static_cast<long>(n); k = next.next()) {
        const std::int64_t seed = ensemble.seeds[static_cast<std::size_t>(k)];
        try {
          const Member m = prepare_member(options.scene_path, options.out_dir, seed);
          if (m.state == MemberState::poured) continue;
          const auto start = Clock::now();
          if (!options.quiet)
            std::fprintf(stderr, "pilelab run: member %lld (%s) on rank %d\n", static_cast<long long>(seed),
                         state_name(m.state), world.rank());
          pour_here(m, threads, true);
          if (!options.quiet)
            std::fprintf(stderr, "pilelab run: member %lld done on rank %d in %.0f s\n", static_cast<long long>(seed),
                         world.rank(), std::chrono::duration<double>(Clock::now() - start).count());
        } catch (const std::exception& e) {
          failures.push_back("seed " + std::to_string(seed) + " (rank " + std::to_string(world.rank()) + "): " + e.what());
          std::fprintf(stderr, "pilelab run: member %lld failed: %s\n", static_cast<long long>(seed), e.what());
        }
      }
    }
    const bool failed_anywhere = world.any(!failures.empty());
    if (failed_anywhere)
      throw std::runtime_error(failures.empty() ? "a member failed on another rank (its message is in that rank's output)"
                                                : describe_failures(failures));
    return;
  }

  std::vector<Member> todo;
  for (std::int64_t seed : ensemble.seeds) {
    Member m = prepare_member(options.scene_path, options.out_dir, seed);
    if (m.state == MemberState::poured) {
      if (!options.quiet) std::fprintf(stderr, "pilelab run: member %lld already poured\n", static_cast<long long>(seed));
      continue;
    }
    todo.push_back(std::move(m));
  }
  std::vector<std::string> failures;
  if (options.processes <= 1) {
    for (const Member& m : todo) {
      if (!options.quiet)
        std::fprintf(stderr, "pilelab run: member %lld (%s)\n", static_cast<long long>(m.seed), state_name(m.state));
      try {
        pour_here(m, options.threads, options.quiet);
      } catch (const std::exception& e) {
        failures.push_back("seed " + std::to_string(m.seed) + ": " + e.what());
      }
    }
  } else {
    const int threads = options.threads > 0 ? options.threads : std::max(1, cores() / options.processes);
    std::map<pid_t, const Member*> running;
    std::size_t next = 0;
    while (next < todo.size() || !running.empty()) {
      while (next < todo.size() && static_cast<int>(running.size()) < options.processes) {
        const Member& m = todo[next++];
        if (!options.quiet)
          std::fprintf(stderr, "pilelab run: member %lld (%s), output in %s\n", static_cast<long long>(m.seed),
                       state_name(m.state), m.log_file.c_str());
        running[spawn_member(m, threads)] = &m;
      }
      int status = 0;
      const pid_t done = waitpid(-1, &status, 0);
      if (done < 0) {
        if (errno == EINTR) continue;
        throw std::runtime_error(std::string("waiting for member processes: ") + std::strerror(errno));
      }
      auto it = running.find(done);
      if (it == running.end()) continue;
      const Member& m = *it->second;
      running.erase(it);
      const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
      if (!ok)
        failures.push_back("seed " + std::to_string(m.seed) + ": " +
                           (WIFEXITED(status) ? "exit code " + std::to_string(WEXITSTATUS(status))
                                              : "killed by signal " + std::to_string(WTERMSIG(status))) +
                           "; see " + m.log_file);
      else if (!options.quiet)
        std::fprintf(stderr, "pilelab run: member %lld done\n", static_cast<long long>(m.seed));
    }
  }
  if (!failures.empty()) throw std::runtime_error(describe_failures(failures));
}

std::vector<std::string> member_dem_files(const EnsembleSpec& ensemble, const std::string& out_dir) {
  std::vector<std::string> files;
  for (std::int64_t seed : ensemble.seeds) files.push_back((fs::path(member_directory(out_dir, seed)) / "dem.h5").string());
  return files;
}

nlohmann::json summarize_members(const EnsembleSpec& ensemble, const std::string& out_dir) {
  nlohmann::json members = nlohmann::json::array();
  std::vector<double> left, right, pile_mean, height, lost, wall, plate_over_weight, plate_dip;
  const auto number_or_null = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  for (std::int64_t seed : ensemble.seeds) {
    const std::string report = (fs::path(member_directory(out_dir, seed)) / "report.json").string();
    const dem::DemResult d = dem::read_dem_result(report);
    left.push_back(d.repose_left_deg);
    right.push_back(d.repose_right_deg);
    pile_mean.push_back(0.5 * (d.repose_left_deg + d.repose_right_deg));
    height.push_back(d.height_m);
    lost.push_back(d.lost);
    wall.push_back(d.wall_time_s);
    plate_over_weight.push_back(d.plate_force_over_weight);
    plate_dip.push_back(d.plate_force_dip);
    members.push_back({{"seed", seed},
                       {"directory", fs::relative(member_directory(out_dir, seed), out_dir).string()},
                       {"repose_angle_left_deg", number_or_null(d.repose_left_deg)},
                       {"repose_angle_right_deg", number_or_null(d.repose_right_deg)},
                       {"height_m", d.height_m},
                       {"plate_force_over_weight", number_or_null(d.plate_force_over_weight)},
                       {"plate_force_dip", number_or_null(d.plate_force_dip)},
                       {"grains", d.grains},
                       {"lost", d.lost},
                       {"wall_time_s", d.wall_time_s}});
  }
  const auto statistics = [&](const std::vector<double>& v) {
    const SampleStatistics s = sample_statistics(v);
    return nlohmann::json{{"mean", number_or_null(s.mean)},
                          {"standard_deviation", number_or_null(s.standard_deviation)},
                          {"standard_error", number_or_null(s.standard_error)},
                          {"count", s.count},
                          {"missing", s.missing}};
  };
  return {{"members", members},
          {"member_count", ensemble.seeds.size()},
          {"repose_angle_left_deg", statistics(left)},
          {"repose_angle_right_deg", statistics(right)},
          {"repose_angle_pile_mean_deg", statistics(pile_mean)},
          {"height_m", statistics(height)},
          // The plate's load (dem/plate_force.h): its dip statistic, centre |x'| < 0.1 over the
          // ring 0.15 < |x'| < 0.35, minus 1, and its integral over the weight.
          {"plate_force_dip", statistics(plate_dip)},
          {"plate_force_over_weight", statistics(plate_over_weight)},
          {"lost", statistics(lost)},
          {"wall_time_s", statistics(wall)}};
}

}  // namespace pilelab::app
