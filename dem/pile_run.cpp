#include "dem/pile_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

#include <sys/resource.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "common/atomic_file.h"
#include "common/duration_text.h"
#include "common/error.h"
#include "common/report.h"
#include "common/scene_reader.h"
#include "common/scene_tables.h"
#include "dem/checkpoint.h"
#include "dem/dem_file.h"
#include "dem/dem_scene.h"
#include "dem/pile_protocol.h"
#include "dem/pile_shape.h"
#include "dem/plate_force.h"
#include "dem/thread_binding.h"
#include "dem/vtk_writer.h"

namespace pilelab::dem {

namespace {
using Clock = std::chrono::steady_clock;

// Processor time of every thread of this process so far (user and system) [s].
double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

std::string frame_name(const char* kind, std::size_t index) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%05zu.vtu", kind, index);
  return buf;
}

// The frames of a pour (grains_K.vtu, contacts_K.vtu, walls_K.vtu) and their series dem.pvd.
class FrameWriter {
 public:
  FrameWriter(const std::string& out_dir) : dir_(out_dir), pvd_(out_dir + "/dem.pvd") {}
  void write(const World& world, std::vector<double>& times) {
    const std::size_t k = times.size();
    write_grains_vtu(dir_ + "/" + frame_name("grains", k), world);
    write_contacts_vtu(dir_ + "/" + frame_name("contacts", k), world);
    write_walls_vtu(dir_ + "/" + frame_name("walls", k), world);
    times.push_back(world.time());
    add_to_series(k, times[k]);
    pvd_.write();
  }
  /// The series of the frames `times` (none for a new pour, a checkpoint's at a restart),
  /// written whole; frames of a later time left by an earlier pour into the folder (another
  /// scene, or this one beyond its checkpoint) are removed, so that none stands beside the
  /// series as if it were this pour's.
  void start(const std::vector<double>& times) {
    remove_frames_from(times.size());
    pvd_ = PvdSeries(dir_ + "/dem.pvd");
    for (std::size_t k = 0; k < times.size(); ++k) add_to_series(k, times[k]);
    pvd_.write();
  }

 private:
  void add_to_series(std::size_t k, double time) {
    pvd_.add(time, frame_name("grains", k), 0, "grains");
    pvd_.add(time, frame_name("contacts", k), 1, "contacts");
    pvd_.add(time, frame_name("walls", k), 2, "walls");
  }
  void remove_frames_from(std::size_t first) const {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir_, ec)) {
      const std::string name = entry.path().filename().string();
      for (const char* kind : {"grains_", "contacts_", "walls_"}) {
        const std::size_t prefix = std::strlen(kind);
        const bool frame = name.size() == prefix + 9 && name.compare(0, prefix, kind) == 0 &&
                           name.compare(prefix + 5, 4, ".vtu") == 0 &&
                           name.find_first_not_of("0123456789", prefix) == prefix + 5;
        if (frame && std::stoul(name.substr(prefix, 5)) >= first) std::filesystem::remove(entry.path(), ec);
      }
    }
  }
  std::string dir_;
  PvdSeries pvd_;
};

void print_progress(const PileProtocol& p, double steps_per_s, double grain_steps_per_s) {
  const auto& s = p.state();
  const DemScene& scene = p.scene();
  const double t = p.world().time(), dt = p.world().settings().time_step;
  // Wall time left. A step costs about as much as the grains in the world. While pouring they
  // grow at the pouring rate, so the grain-steps left in the pour are the area under n(t) up to
  // its end, (N^2 - n^2) / (2 rate), over the step. What follows is bounded by the phases' time
  // limits (each settling may end sooner), with every grain stepping.
  const double n = s.poured, total = scene.grain_count;
  const double pour_grain_steps =
      s.phase == Phase::pour ? (total * total - n * n) / (2.0 * scene.pour.rate) / dt : 0.0;
  const double stepping = s.phase == Phase::pour ? total : static_cast<double>(p.world().active_grains().size());
  const double run_grain_steps = pour_grain_steps + stepping * longest_time_after_pour(scene, s, t) / dt;
  std::fprintf(stderr, "[%-12s] t = %8.4f s  grains %d/%d (lost %d)  KE %.3e J  %.3g steps/s  %.3g grain-steps/s",
               phase_name(s.phase), t, s.poured, scene.grain_count, s.lost, p.world().kinetic_energy(), steps_per_s,
               grain_steps_per_s);
  if (s.phase != Phase::pour)
    std::fprintf(stderr, "  KE/grain %.2e J (settles below %.2e J)", p.kinetic_energy_per_grain(),
                 scene.settle.kinetic_energy_per_grain);
  if (grain_steps_per_s > 0) {
    // While pouring, the estimate assumes grains go in on schedule (a blocked outlet delays
    // them); after it, the settling limits make it an upper bound.
    if (s.phase == Phase::pour)
      std::fprintf(stderr, "  pour ends in ~%s, run in ~%s", duration_text(pour_grain_steps / grain_steps_per_s).c_str(),
                   duration_text(run_grain_steps / grain_steps_per_s).c_str());
    else
      std::fprintf(stderr, ", run ends within ~%s", duration_text(run_grain_steps / grain_steps_per_s).c_str());
  }
  std::fprintf(stderr, "\n");
}

// Mean kinetic energy per grain of a snapshot [J].
double kinetic_energy_per_grain(const World& w, const Snapshot& s) {
  double e = 0.0;
  for (std::size_t g = 0; g < s.grain_count(); ++g) {
    const int b = static_cast<int>(s.body[g]);
    const double vx = s.velocity[2 * g], vy = s.velocity[2 * g + 1], om = s.angular_velocity[g];
    e += 0.5 * w.mass(b) * (vx * vx + vy * vy) + 0.5 * w.inertia(b) * om * om;
  }
  return s.grain_count() ? e / s.grain_count() : 0.0;
}

// What a user should know about a finished run that did not stop it, one sentence each.
std::vector<std::string> run_warnings(const PileProtocol& p, const nlohmann::json& report) {
  std::vector<std::string> warnings;
  char text[512];
  // First, because it qualifies the warnings after it. A run above the limit that completed
  // had no contact that swung 16 steps in a row (PileProtocol stops those); shorter swings may
  // still be unstable contacts that opened first, and the bound is for the stiffest contact a
  // grain can make, which another pour may make.
  const double limit = p.time_step_bound().stable_limit, step = p.world().settings().time_step;
  if (step > limit) {
    std::snprintf(text, sizeof text,
                  "the time step %.4g s is %.4g times the stability limit %.3g s (dem.integrator."
                  "allow_unstable_time_step): no contact swung %d steps in a row (the longest: %d), but the "
                  "stiffest contacts a grain can make are unstable at this step, and another pour may make them",
                  step, step / limit, limit, PileProtocol::unstable_swing_steps, p.world().longest_swing().steps);
    warnings.emplace_back(text);
  }
  if (p.state().lost > 0) {
    const int lost = p.state().lost;
    std::snprintf(text, sizeof text, "%d grain%s fell off the plate; a wider dem.container.plate_width_m keeps them",
                  lost, lost == 1 ? "" : "s");
    warnings.emplace_back(text);
  }
  if (p.state().pour_stalled) {
    std::snprintf(text, sizeof text,
                  "the pour stopped after %d of %d grains: the pile reached the outlet and blocked it; a higher "
                  "dem.pour.funnel_height_m makes room for all",
                  p.state().poured, p.scene().grain_count);
    warnings.emplace_back(text);
  }
  // The default step assumes overlaps up to max_overlap_depth_fraction; what matters is whether
  // the step is stable for the depth the run actually reached.
  const DeepestOverlap& deepest = p.world().deepest_overlap();
  const double dt = p.world().settings().time_step;
  // JSON has no infinity: a run whose contacts never stiffened (a disc barely touched) has null.
  const nlohmann::json& limit_json = report["stable_time_step_at_deepest_overlap_s"];
  const double limit_at_depth = limit_json.is_number() ? limit_json.get<double>() : INFINITY;
  if (dt > limit_at_depth) {
    std::snprintf(text, sizeof text,
                  "an overlap reached %.2f of a grain's inner radius, between %s and %s at t = %.4g s, x = %.4g m, "
                  "y = %.4g m; contacts that deep are stable only below dt = %.3g s, and this run stepped %.3g s: "
                  "a smaller dem.integrator.time_step_fraction (or time_step_s) keeps them stable",
                  deepest.fraction, p.body_name(deepest.a).c_str(), p.body_name(deepest.b).c_str(), deepest.time,
                  deepest.point.x(), deepest.point.y(), limit_at_depth, dt);
    warnings.emplace_back(text);
  }
  for (const auto& [name, info] : report["settling"].items())
    if (!info["reached_threshold"].get<bool>()) {
      std::snprintf(text, sizeof text,
                    "snapshot '%s' was taken at dem.settle.max_time_s with %.3g J per grain, above "
                    "dem.settle.kinetic_energy_per_grain_J",
                    name.c_str(), info["kinetic_energy_per_grain_J"].get<double>());
      warnings.emplace_back(text);
    }
  return warnings;
}

// The scene file as dem.h5 records it: relative to the output directory when it lies inside it
// (an ensemble member's scene.toml), so that the same member poured into another OUT gives the
// same bytes; otherwise as the user gave it.
std::string recorded_scene_path(const std::string& scene_path, const std::string& out_dir) {
  std::error_code ec;
  const auto scene = std::filesystem::weakly_canonical(scene_path, ec);
  const auto out = std::filesystem::weakly_canonical(out_dir, ec);
  if (ec) return scene_path;
  const auto inside = scene.lexically_relative(out);
  if (!inside.empty() && *inside.begin() != "..") return inside.string();
  return scene_path;
}

nlohmann::json dem_report(const PileProtocol& p, const RunCounters& c, int threads) {
  const World& w = p.world();
  const DemScene& scene = p.scene();
  // The pile is measured as it settled under full gravity, before any relaxation.
  const Snapshot& settled = p.snapshots().front();
  const PileShape shape = measure_pile(w, settled, 2.0 * scene.grains.mean_diameter);
  const StepProfile& prof = c.profile;
  nlohmann::json r;
  r["seed"] = scene.seed;
  r["particles"] = w.active_grains().size();
  r["poured"] = p.state().poured;
  r["lost"] = p.state().lost;
  r["pour_stalled"] = p.state().pour_stalled;
  r["height_m"] = shape.height;
  r["apex_x_m"] = shape.apex_x;
  r["repose_angle_left_deg"] = shape.repose_left_deg;
  r["repose_angle_right_deg"] = shape.repose_right_deg;
  r["repose_angle_fit_se_deg"] = {shape.repose_left_se_deg, shape.repose_right_se_deg};
  r["repose_fit_points"] = {shape.left_points, shape.right_points};
  // The load on the plate (and the base's grains, if any), binned a grain diameter wide, and the
  // dip statistic of its profile, with
  // x' measured in the half-width of the wedge of the pile's height and flanks.
  const double plate_width = scene.container.plate_width;
  const PlateLoad load =
      plate_load(w, settled, p.base_bodies(), -0.5 * plate_width, plate_width, scene.grains.mean_diameter);
  r["plate_force_over_weight"] = load.total_force / load.weight;
  const double half_width =
      0.5 * shape.height * (1.0 / std::tan(shape.repose_left_deg * M_PI / 180.0) + 1.0 / std::tan(shape.repose_right_deg * M_PI / 180.0));
  const DipWindows windows;
  const double dip = centre_over_ring(load.x, load.load, shape.apex_x, half_width, windows);
  r["plate_force_dip"] = {{"centre_over_ring_minus_1", std::isfinite(dip) ? nlohmann::json(dip) : nlohmann::json()},
                          {"half_width_m", std::isfinite(half_width) ? nlohmann::json(half_width) : nlohmann::json()},
                          {"centre_window_x_over_R", windows.centre},
                          {"ring_window_x_over_R", {windows.ring_inner, windows.ring_outer}}};
  r["plate_force_profile"] = {{"bin_width_m", load.bin_width}, {"x_m", load.x}, {"load_N_per_m", load.load}};
  r["simulated_time_s"] = w.time();
  r["steps"] = w.steps();
  r["wall_time_s"] = c.wall_time;
  r["wall_time_pour_and_settle_s"] = c.wall_time_settled;
  r["cpu_time_s"] = c.cpu_time;
  r["particle_steps_per_s"] = c.wall_time > 0 ? c.particle_steps / c.wall_time : 0.0;
  r["kinetic_energy_final_J"] = w.kinetic_energy();
  r["contacts_final"] = w.contact_count();
  r["time_step_s"] = w.settings().time_step;
  r["stable_time_step_s"] = p.time_step_bound().stable_limit;
  const DeepestOverlap& deepest = w.deepest_overlap();
  r["deepest_overlap_fraction"] = deepest.fraction;
  r["deepest_overlap_time_s"] = deepest.time;
  r["deepest_overlap_point_m"] = {deepest.point.x(), deepest.point.y()};
  r["deepest_overlap_bodies"] = {deepest.a, deepest.b};
  r["stable_time_step_at_deepest_overlap_s"] = p.time_step_bound_at_deepest_overlap().stable_limit;
  const SwingingContact& swing = w.longest_swing();
  r["longest_swing_steps"] = swing.steps;
  r["longest_swing_time_s"] = swing.time;
  r["longest_swing_bodies"] = {swing.a, swing.b};
  r["integrator"] = scheme_name(scene.scheme);
  r["threads"] = threads;
  r["cores"] = std::thread::hardware_concurrency();
  r["snapshots"] = nlohmann::json::array();
  r["must_settle"] = scene.settle.must_settle;
  r["settling"] = nlohmann::json::object();
  for (const Snapshot& s : p.snapshots()) {
    r["snapshots"].push_back(s.name);
    const double e = kinetic_energy_per_grain(w, s);
    r["settling"][s.name] = {{"time_s", s.time},
                             {"kinetic_energy_per_grain_J", e},
                             {"reached_threshold", e < scene.settle.kinetic_energy_per_grain}};
  }
  r["profile_s"] = {{"move", prof.move},
                    {"broad_phase", prof.broad_phase},
                    {"narrow_phase", prof.narrow_phase},
                    {"gather_correct", prof.gather_correct}};
  r["neighbour_list_builds"] = c.neighbour_builds;
  return r;
}
}  // namespace

namespace {
// SIGINT or SIGTERM during the pour: the loop writes a checkpoint at the end of its step and
// stops, so that an interrupted run loses nothing and says how to go on.
volatile std::sig_atomic_t interrupted_by = 0;
extern "C" void note_interrupt(int signal) { interrupted_by = signal; }

// Installs the handlers for the run and puts the previous ones back after it.
struct InterruptGuard {
  void (*previous_int)(int), (*previous_term)(int);
  InterruptGuard() {
    interrupted_by = 0;
    previous_int = std::signal(SIGINT, note_interrupt);
    previous_term = std::signal(SIGTERM, note_interrupt);
  }
  ~InterruptGuard() {
    std::signal(SIGINT, previous_int);
    std::signal(SIGTERM, previous_term);
  }
};
}  // namespace

namespace {

// The end of an interrupted run: the checkpoint was just written; say how to continue, and exit
// as a shell reports a process ended by the signal.
[[noreturn]] void exit_interrupted(const World& world, const std::string& checkpoint_path, const DemRunOptions& opt) {
  const int signal = interrupted_by;
  std::fprintf(stderr,
               "interrupted by %s at t = %.6f s (step %lld); the checkpoint %s holds the run: continue with "
               "`pilelab dem %s -o %s --restart` (or `pilelab run ... --restart`)\n",
               signal == SIGINT ? "SIGINT" : "SIGTERM", world.time(), static_cast<long long>(world.steps()),
               checkpoint_path.c_str(), opt.scene_path.c_str(), opt.out_dir.c_str());
  std::fflush(stderr);
  std::_Exit(128 + signal);
}

// The finished pour's files: dem.h5 (refused if no grain is left), the report section and its
// warnings.
nlohmann::json finish_pour(const DemRunOptions& opt, const DemScene& scene, const std::string& scene_text,
                           PileProtocol& protocol, const RunCounters& counters, int threads) {
  const World& world = protocol.world();
  nlohmann::json run_info;
  run_info["seed"] = scene.seed;
  run_info["time_step_s"] = world.settings().time_step;
  run_info["integrator"] = scheme_name(scene.scheme);
  run_info["scene_file"] = recorded_scene_path(opt.scene_path, opt.out_dir);
  // Checked before anything is written: a failed run leaves no dem.h5 for later stages to read.
  if (world.active_grains().empty())
    throw InputError(opt.scene_path + ": no grain is left on the plate at the end (poured " +
                     std::to_string(protocol.state().poured) + ", lost " + std::to_string(protocol.state().lost) +
                     "): check that dem.pour.funnel_x_m lies over the plate (dem.container.plate_width_m), and that "
                     "grains cannot pass through it: contacts too soft for the impact speed (dem.contact."
                     "youngs_modulus_N_per_m, dem.gravity_m_per_s2, dem.pour.funnel_height_m) or a forced "
                     "dem.integrator.time_step_s");
  write_dem_file(opt.out_dir + "/dem.h5", scene_text, world, protocol.snapshots(), protocol.wall_placements(),
                 run_info);
  nlohmann::json report = dem_report(protocol, counters, threads);
  report["warnings"] = run_warnings(protocol, report);
  // Warnings print even with --quiet, which silences progress only.
  for (const auto& w : report["warnings"]) std::fprintf(stderr, "warning: %s\n", w.get<std::string>().c_str());
  write_report_section(opt.out_dir + "/report.json", "dem", report);
  if (!opt.quiet)
    std::fprintf(stderr, "done: %zu grains, height %.4f m, repose angles %.1f / %.1f deg, %.3g s wall, %.3g grain-steps/s\n",
                 world.active_grains().size(), report["height_m"].get<double>(),
                 report["repose_angle_left_deg"].is_number() ? report["repose_angle_left_deg"].get<double>() : NAN,
                 report["repose_angle_right_deg"].is_number() ? report["repose_angle_right_deg"].get<double>() : NAN,
                 counters.wall_time, report["particle_steps_per_s"].get<double>());
  return report;
}

}  // namespace

nlohmann::json run_dem(const DemRunOptions& opt) {
  SceneReader reader = SceneReader::from_file(opt.scene_path);
  reader.get_string("scene.name", "");
  reader.get_string("scene.description", "");
  const DemScene scene = read_dem_scene(reader);
  reader.reject_unknown({"scene", "dem"}, scene_tables());
  // Every key has a default, so an empty or unrelated scene pours a pile; say so (also quiet).
  if (!reader.has("dem"))
    std::fprintf(stderr, "warning: %s has no [dem] table: pouring the default pile (%d grains, docs/SCENES.md)\n",
                 opt.scene_path.c_str(), scene.grain_count);

  prepare_output_directory(opt.out_dir);
#ifdef _OPENMP
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  const int threads = omp_get_max_threads();
  bind_threads_to_cores();
#else
  const int threads = 1;
#endif

  PileProtocol protocol(scene, opt.scene_path);
  RunCounters counters;
  const InterruptGuard interrupt_guard;
  const std::string checkpoint_path = opt.out_dir + "/checkpoint.h5";
  FrameWriter frames(opt.out_dir);
  if (opt.restart) {
    read_checkpoint(checkpoint_path, reader.text(), protocol, counters);
    frames.start(counters.frame_times);
    if (!opt.quiet)
      std::fprintf(stderr, "restarting from %s at t = %.6f s (step %lld)\n", checkpoint_path.c_str(),
                   protocol.world().time(), static_cast<long long>(protocol.world().steps()));
  } else {
    frames.start({});
    // What the pour will cost, at the reference rate: said before it starts, and said even
    // when quiet if it is more than a day on one core (a scene of tiny grains must not start a
    // pour of months silently).
    const RunCost cost = run_cost(scene, protocol.world().settings().time_step);
    const double longest_s = cost.grain_steps_longest / reference_grain_steps_per_core_s;
    if (!opt.quiet) {
      const TimeStepBound& b = protocol.time_step_bound();
      std::fprintf(stderr, "pilelab dem: %d grains, %s, dt = %.3e s (stable limit %.3e s), %d thread(s)\n",
                   scene.grain_count, scheme_name(scene.scheme), protocol.world().settings().time_step, b.stable_limit,
                   threads);
      std::fprintf(stderr, "pilelab dem: %.3g to %.3g grain-steps, about %s to %s on one core\n", cost.grain_steps_shortest,
                   cost.grain_steps_longest, duration_text(cost.grain_steps_shortest / reference_grain_steps_per_core_s).c_str(),
                   duration_text(longest_s).c_str());
    }
    if (longest_s > 86400.0)
      std::fprintf(stderr, "warning: this pour may take up to %s on one core (%.3g grain-steps at %.0e a second): "
                           "pilelab check estimates a scene's cost before it runs\n",
                   duration_text(longest_s).c_str(), cost.grain_steps_longest, reference_grain_steps_per_core_s);
  }

  World& world = protocol.world();
  const OutputSpec& out = scene.output;
  auto session_start = Clock::now(), last_progress = session_start;
  std::int64_t progress_steps = world.steps(), progress_grain_steps = counters.particle_steps;
  const std::int64_t first_step = world.steps();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - session_start).count(); };
  const double wall_before = counters.wall_time;
  const double cpu_start = process_cpu_seconds(), cpu_before = counters.cpu_time;
  const auto cpu_elapsed = [&] { return process_cpu_seconds() - cpu_start; };
  // Every counter the report gives is the whole run's: the sessions before this one, plus it.
  const std::int64_t builds_before = counters.neighbour_builds;
  const StepProfile profile_before = counters.profile;
  const auto count_this_session = [&] {
    counters.wall_time = wall_before + elapsed();
    counters.cpu_time = cpu_before + cpu_elapsed();
    counters.neighbour_builds = builds_before + world.neighbour_builds();
    const StepProfile& p = world.profile();
    counters.profile = {profile_before.move + p.move, profile_before.broad_phase + p.broad_phase,
                        profile_before.narrow_phase + p.narrow_phase, profile_before.gather_correct + p.gather_correct};
  };

  while (!protocol.done()) {
    const std::size_t snapshots_before = protocol.snapshots().size();
    protocol.step();
    counters.particle_steps += static_cast<std::int64_t>(world.active_grains().size());
    if (counters.wall_time_settled < 0 && !protocol.snapshots().empty()) counters.wall_time_settled = wall_before + elapsed();
    // A frame at each multiple of the interval, and one of each snapshot as it is taken (the
    // settled pile is then a frame of dem.pvd, the state the later stages measure).
    const auto scheduled = static_cast<double>(static_cast<std::int64_t>(counters.frame_times.size()) - counters.snapshot_frames);
    if (out.frame_interval > 0 && world.time() >= scheduled * out.frame_interval) frames.write(world, counters.frame_times);
    if (protocol.snapshots().size() > snapshots_before) {
      frames.write(world, counters.frame_times);
      ++counters.snapshot_frames;
    }
    const bool interrupted = interrupted_by != 0;
    const bool stop_now =
        interrupted || (opt.stop_after_steps > 0 && world.steps() - first_step >= opt.stop_after_steps);
    // Regular checkpoints fall due at multiples of the interval, whatever extra ones were written.
    const bool due = out.checkpoint_interval > 0 &&
                     std::floor(world.time() / out.checkpoint_interval) > std::floor(counters.last_checkpoint_time /
                                                                                      out.checkpoint_interval);
    if (due || stop_now) {
      ++counters.checkpoints;
      counters.last_checkpoint_time = world.time();
      count_this_session();
      write_checkpoint(checkpoint_path, reader.text(), protocol, counters);
    }
    if (interrupted) exit_interrupted(world, checkpoint_path, opt);
    if (stop_now) {
      if (!opt.quiet) std::fprintf(stderr, "stopped after %lld steps as asked; continue with --restart\n",
                                   static_cast<long long>(opt.stop_after_steps));
      return nlohmann::json::object();
    }
    if (!opt.quiet && (world.steps() & 255) == 0) {
      const auto now = Clock::now();
      const double dt_wall = std::chrono::duration<double>(now - last_progress).count();
      if (dt_wall >= out.progress_interval) {
        print_progress(protocol, (world.steps() - progress_steps) / dt_wall,
                       (counters.particle_steps - progress_grain_steps) / dt_wall);
        last_progress = now;
        progress_steps = world.steps();
        progress_grain_steps = counters.particle_steps;
      }
    }
  }
  count_this_session();
  if (counters.frame_times.empty() || counters.frame_times.back() != world.time()) frames.write(world, counters.frame_times);
  return finish_pour(opt, scene, reader.text(), protocol, counters, threads);
}

}  // namespace pilelab::dem
