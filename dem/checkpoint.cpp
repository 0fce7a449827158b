#include "dem/checkpoint.h"

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/hdf5_file.h"
#include "dem/dem_file.h"

namespace pilelab::dem {

// Layout of checkpoint.h5 (the completed snapshots go to a sibling file in the dem.h5 format,
// written first, so the checkpoint never names a snapshot that is not on disk):
//   /scene                 scene text the run was started with
//   /world/d0 .. d5        MotionState derivatives, 3 per body
//   /world/active          per body 0/1
//   /world attrs           time_s, steps, gravity_y, time_step_s, scheme, bodies_fingerprint
//                          (what the run was built with: a restart by another build must match); deepest_overlap (fraction), deepest_overlap_time_s,
//                          deepest_overlap_x_m, deepest_overlap_y_m, deepest_overlap_a, deepest_overlap_b;
//                          longest_swing_steps, _time_s, _x_m, _y_m, _a, _b (optional)
//   /contacts/...          a, b, spring, point, normal, normal_force, tangential_force, area, chord,
//                          swing (optional: World::contact_swings)
//   /protocol attrs        phase, phase_start, poured, lost, next_insert_time, last_insert_time,
//                          pour_stalled, lost_energy_J (optional; 0 if absent); /protocol/rng (4 words)
//   /counters attrs        particle_steps, wall_time, checkpoints, snapshots,
//                          last_checkpoint_time, wall_time_settled, cpu_time, neighbour_builds,
//                          profile_{move,broad_phase,narrow_phase,gather_correct}_s; /counters/frame_times

namespace {
std::string snapshots_path(const std::string& checkpoint) {
  return checkpoint.substr(0, checkpoint.size() - 3) + "_snapshots.h5";
}

std::string exact(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// FNV-1a over every body's shape, mass and moment of inertia. The scene text alone does not
// fix them: a build with another grain generator would draw other grains from the same seed,
// and a restart would put them at the old grains' places with the old grains' springs.
std::int64_t bodies_fingerprint(const World& world) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](double v) {
    unsigned char bytes[sizeof v];
    std::memcpy(bytes, &v, sizeof v);
    for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  };
  for (int body = 0; body < world.body_count(); ++body) {
    const Shape& shape = world.shape(body);
    for (const Vec2& v : shape.vertices) mix(v.x()), mix(v.y());
    mix(shape.radius);
    mix(world.mass(body));
    mix(world.inertia(body));
  }
  std::int64_t signed_h;
  std::memcpy(&signed_h, &h, sizeof h);
  return signed_h;
}
}  // namespace

void write_checkpoint(const std::string& path, const std::string& scene_text, const PileProtocol& protocol,
                      const RunCounters& counters) {
  const World& world = protocol.world();
  if (!protocol.snapshots().empty())
    write_dem_file(snapshots_path(path), scene_text, world, protocol.snapshots(), protocol.wall_placements(),
                   nlohmann::json::object());
  write_atomically(path, [&](const std::string& tmp) {
    H5File f = H5File::create(tmp);
    f.write_string("/scene", scene_text);
    const MotionState m = world.motion_state();
    for (int k = 0; k < 6; ++k) f.write("/world/d" + std::to_string(k), m.d[k]);
    const std::vector<std::uint8_t> activity = world.activity();
    std::vector<std::int64_t> active(activity.begin(), activity.end());
    f.write("/world/active", active);
    f.set_attribute("/world", "time_s", world.time());
    f.set_attribute("/world", "steps", world.steps());
    f.set_attribute("/world", "gravity_y", world.settings().gravity.y());
    f.set_attribute("/world", "time_step_s", world.settings().time_step);
    f.set_attribute("/world", "scheme", std::string(scheme_name(world.settings().scheme)));
    f.set_attribute("/world", "bodies_fingerprint", bodies_fingerprint(world));
    const DeepestOverlap& deepest = world.deepest_overlap();
    f.set_attribute("/world", "deepest_overlap", deepest.fraction);
    f.set_attribute("/world", "deepest_overlap_time_s", deepest.time);
    f.set_attribute("/world", "deepest_overlap_x_m", deepest.point.x());
    f.set_attribute("/world", "deepest_overlap_y_m", deepest.point.y());
    f.set_attribute("/world", "deepest_overlap_a", static_cast<std::int64_t>(deepest.a));
    f.set_attribute("/world", "deepest_overlap_b", static_cast<std::int64_t>(deepest.b));
    const SwingingContact& swing = world.longest_swing();
    f.set_attribute("/world", "longest_swing_steps", static_cast<std::int64_t>(swing.steps));
    f.set_attribute("/world", "longest_swing_time_s", swing.time);
    f.set_attribute("/world", "longest_swing_x_m", swing.point.x());
    f.set_attribute("/world", "longest_swing_y_m", swing.point.y());
    f.set_attribute("/world", "longest_swing_a", static_cast<std::int64_t>(swing.a));
    f.set_attribute("/world", "longest_swing_b", static_cast<std::int64_t>(swing.b));

    const auto& cs = world.contacts();
    std::vector<std::int64_t> a, b;
    std::vector<double> spring, point, normal, fn, ft, area, chord;
    for (const Contact& c : cs) {
      a.push_back(c.a);
      b.push_back(c.b);
      spring.push_back(c.spring);
      point.insert(point.end(), {c.point.x(), c.point.y()});
      normal.insert(normal.end(), {c.normal.x(), c.normal.y()});
      fn.push_back(c.normal_force);
      ft.push_back(c.tangential_force);
      area.push_back(c.area);
      chord.push_back(c.chord);
    }
    f.write("/contacts/a", a);
    f.write("/contacts/b", b);
    f.write("/contacts/spring", spring);
    f.write("/contacts/point", point);
    f.write("/contacts/normal", normal);
    f.write("/contacts/normal_force", fn);
    f.write("/contacts/tangential_force", ft);
    f.write("/contacts/area", area);
    f.write("/contacts/chord", chord);
    const std::vector<std::uint8_t> swings = world.contact_swings();
    f.write("/contacts/swing", std::vector<std::int64_t>(swings.begin(), swings.end()));

    const ProtocolState& s = protocol.state();
    f.set_attribute("/protocol", "phase", static_cast<std::int64_t>(s.phase));
    f.set_attribute("/protocol", "phase_start", s.phase_start);
    f.set_attribute("/protocol", "poured", static_cast<std::int64_t>(s.poured));
    f.set_attribute("/protocol", "lost", static_cast<std::int64_t>(s.lost));
    f.set_attribute("/protocol", "next_insert_time", s.next_insert_time);
    f.set_attribute("/protocol", "last_insert_time", s.last_insert_time);
    f.set_attribute("/protocol", "pour_stalled", static_cast<std::int64_t>(s.pour_stalled));
    f.set_attribute("/protocol", "lost_energy_J", s.lost_energy);
    f.write("/protocol/rng", std::vector<std::uint64_t>(s.rng.begin(), s.rng.end()));

    f.set_attribute("/counters", "particle_steps", counters.particle_steps);
    f.set_attribute("/counters", "wall_time", counters.wall_time);
    f.set_attribute("/counters", "checkpoints", counters.checkpoints);
    f.set_attribute("/counters", "last_checkpoint_time", counters.last_checkpoint_time);
    f.set_attribute("/counters", "wall_time_settled", counters.wall_time_settled);
    f.set_attribute("/counters", "cpu_time", counters.cpu_time);
    f.set_attribute("/counters", "neighbour_builds", counters.neighbour_builds);
    f.set_attribute("/counters", "profile_move_s", counters.profile.move);
    f.set_attribute("/counters", "profile_broad_phase_s", counters.profile.broad_phase);
    f.set_attribute("/counters", "profile_narrow_phase_s", counters.profile.narrow_phase);
    f.set_attribute("/counters", "profile_gather_correct_s", counters.profile.gather_correct);
    f.set_attribute("/counters", "snapshots", static_cast<std::int64_t>(protocol.snapshots().size()));
    f.write("/counters/frame_times", counters.frame_times);
    f.set_attribute("/counters", "snapshot_frames", counters.snapshot_frames);
    f.close();
  });
}

void read_checkpoint(const std::string& path, const std::string& scene_text, PileProtocol& protocol,
                     RunCounters& counters) {
  if (!std::filesystem::exists(path))
    throw InputError(path + ": no checkpoint to restart from (run without --restart first)");
  H5File f = H5File::open_read(path);
  if (!f.exists("/world") || !f.exists("/protocol"))
    throw InputError(path + ": not a pilelab checkpoint (no /world or /protocol group); expected the "
                     "checkpoint.h5 a run of this scene wrote into its output directory");
  if (f.read_string("/scene") != scene_text)
    throw InputError(path + ": /scene: the checkpoint was written for a different scene text; "
                     "restart needs the scene file unchanged");
  World& world = protocol.world();
  // The scene text is the same; the build that reads it must also make the same world of it.
  const std::string rebuilt = ": this build makes a different world of the same scene (";
  const std::string restart_anew = "); restart needs the build that wrote the checkpoint, or run anew without --restart";
  std::string scheme;
  try {
    scheme = f.attribute_string("/world", "scheme");
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + ": written by a pilelab older than its build check; run anew "
                     "without --restart");
  }
  if (scheme != scheme_name(world.settings().scheme))
    throw InputError(path + ": /world scheme" + rebuilt + "integrator '" + scheme_name(world.settings().scheme) +
                     "', the checkpoint's '" + scheme + "'" + restart_anew);
  const double time_step = f.attribute_double("/world", "time_step_s");
  if (time_step != world.settings().time_step)
    throw InputError(path + ": /world time_step_s" + rebuilt + "time step " + exact(world.settings().time_step) +
                     " s, the checkpoint's " + exact(time_step) + " s" + restart_anew);
  if (f.attribute_int("/world", "bodies_fingerprint") != bodies_fingerprint(world))
    throw InputError(path + ": /world bodies_fingerprint" + rebuilt +
                     "other grain shapes, masses or moments of inertia than the checkpoint's" + restart_anew);
  MotionState& m = world.motion();
  for (int k = 0; k < 6; ++k) {
    std::vector<double> d = f.read_finite_doubles("/world/d" + std::to_string(k));
    if (d.size() != m.d[k].size())
      throw InputError(path + ": /world/d" + std::to_string(k) + ": expected " + std::to_string(m.d[k].size()) +
                       " values for this scene, found " + std::to_string(d.size()));
    m.d[k] = std::move(d);
  }
  const std::vector<std::int64_t> active = f.read_ints("/world/active");
  if (active.size() != static_cast<std::size_t>(world.body_count()))
    throw InputError(path + ": /world/active: body count does not match the scene");
  world.restore_activity(std::vector<std::uint8_t>(active.begin(), active.end()));
  world.restore_clock(f.attribute_double("/world", "time_s"), f.attribute_int("/world", "steps"));
  world.set_gravity({0.0, f.attribute_double("/world", "gravity_y")});
  DeepestOverlap deepest;
  deepest.fraction = f.attribute_double("/world", "deepest_overlap");
  deepest.time = f.attribute_double("/world", "deepest_overlap_time_s");
  deepest.point = {f.attribute_double("/world", "deepest_overlap_x_m"), f.attribute_double("/world", "deepest_overlap_y_m")};
  deepest.a = static_cast<std::int32_t>(f.attribute_int("/world", "deepest_overlap_a"));
  deepest.b = static_cast<std::int32_t>(f.attribute_int("/world", "deepest_overlap_b"));
  world.restore_deepest_overlap(deepest);
  // The swing record and each contact's swing (checkpoints before 2026-12-06 have none: the
  // counts then start afresh).
  if (f.has_attribute("/world", "longest_swing_steps")) {
    SwingingContact swing;
    swing.steps = static_cast<int>(f.attribute_int("/world", "longest_swing_steps"));
    swing.time = f.attribute_double("/world", "longest_swing_time_s");
    swing.point = {f.attribute_double("/world", "longest_swing_x_m"), f.attribute_double("/world", "longest_swing_y_m")};
    swing.a = static_cast<std::int32_t>(f.attribute_int("/world", "longest_swing_a"));
    swing.b = static_cast<std::int32_t>(f.attribute_int("/world", "longest_swing_b"));
    if (swing.steps < 0 || swing.steps > SwingingContact::longest_counted)
      throw InputError(path + ": /world: longest_swing_steps = " + std::to_string(swing.steps) + ", expected 0 to " +
                       std::to_string(SwingingContact::longest_counted));
    world.restore_longest_swing(swing);
  }

  const auto a = f.read_ints("/contacts/a"), b = f.read_ints("/contacts/b");
  const auto spring = f.read_finite_doubles("/contacts/spring"), point = f.read_finite_doubles("/contacts/point"),
             normal = f.read_finite_doubles("/contacts/normal"), fn = f.read_finite_doubles("/contacts/normal_force"),
             ft = f.read_finite_doubles("/contacts/tangential_force"), area = f.read_finite_doubles("/contacts/area"),
             chord = f.read_finite_doubles("/contacts/chord");
  const std::size_t n = a.size();
  if (b.size() != n || spring.size() != n || point.size() != 2 * n || normal.size() != 2 * n || fn.size() != n ||
      ft.size() != n || area.size() != n || chord.size() != n)
    throw InputError(path + ": /contacts: datasets of inconsistent length");
  // The contact list must be sorted by pair, with valid bodies: the step relies on both.
  for (std::size_t i = 0; i < n; ++i)
    if (a[i] < 0 || a[i] >= b[i] || b[i] >= world.body_count() || (i > 0 && pair_key(int(a[i - 1]), int(b[i - 1])) >= pair_key(int(a[i]), int(b[i]))))
      throw InputError(path + ": /contacts: entry " + std::to_string(i) + " is not a valid, ordered body pair");
  std::vector<Contact> contacts(n);
  for (std::size_t i = 0; i < n; ++i) {
    Contact& c = contacts[i];
    c.a = static_cast<std::int32_t>(a[i]);
    c.b = static_cast<std::int32_t>(b[i]);
    c.spring = spring[i];
    c.point = {point[2 * i], point[2 * i + 1]};
    c.normal = {normal[2 * i], normal[2 * i + 1]};
    c.normal_force = fn[i];
    c.tangential_force = ft[i];
    c.area = area[i];
    c.chord = chord[i];
  }
  std::vector<std::uint8_t> swings;
  if (f.exists("/contacts/swing")) {
    const auto stored = f.read_ints("/contacts/swing");
    if (stored.size() != n) throw InputError(path + ": /contacts/swing: expected one value a contact");
    for (std::int64_t s : stored) {
      if (s < 0 || s > 255) throw InputError(path + ": /contacts/swing: a value outside 0-255");
      swings.push_back(static_cast<std::uint8_t>(s));
    }
  }
  world.restore_contacts(std::move(contacts), swings);

  ProtocolState s;
  const std::int64_t phase = f.attribute_int("/protocol", "phase");
  if (phase < 0 || phase > static_cast<std::int64_t>(Phase::done))
    throw InputError(path + ": /protocol: phase " + std::to_string(phase) + " is not a valid phase");
  s.phase = static_cast<Phase>(phase);
  s.phase_start = f.attribute_double("/protocol", "phase_start");
  s.poured = static_cast<int>(f.attribute_int("/protocol", "poured"));
  if (s.poured < 0 || s.poured > protocol.scene().grain_count)
    throw InputError(path + ": /protocol: poured = " + std::to_string(s.poured) + " does not fit this scene");
  s.lost = static_cast<int>(f.attribute_int("/protocol", "lost"));
  s.next_insert_time = f.attribute_double("/protocol", "next_insert_time");
  s.last_insert_time = f.attribute_double("/protocol", "last_insert_time");
  s.pour_stalled = f.attribute_int("/protocol", "pour_stalled") != 0;
  // Older checkpoints have none: their energy bound keeps the lost grains' share, as it did.
  s.lost_energy = f.has_attribute("/protocol", "lost_energy_J") ? f.attribute_double("/protocol", "lost_energy_J") : 0.0;
  if (!std::isfinite(s.lost_energy))
    throw InputError(path + ": /protocol: lost_energy_J is not a finite number");
  const auto rng = f.read_uints("/protocol/rng");
  if (rng.size() != 4) throw InputError(path + ": /protocol/rng: expected 4 words");
  for (int k = 0; k < 4; ++k) s.rng[k] = rng[k];

  std::vector<Snapshot> snapshots;
  std::vector<WallPlacement> walls;
  const std::int64_t snapshot_count = f.attribute_int("/counters", "snapshots");
  if (snapshot_count > 0) {
    const DemFile done = read_dem_file(snapshots_path(path));
    if (static_cast<std::int64_t>(done.snapshot_names.size()) < snapshot_count)
      throw InputError(snapshots_path(path) + ": holds fewer snapshots than the checkpoint names");
    for (std::int64_t k = 0; k < snapshot_count; ++k) {
      snapshots.push_back(done.snapshot(done.snapshot_names[k]));
      walls.push_back(done.walls(done.snapshot_names[k]));
    }
  }
  protocol.restore(s, std::move(snapshots), std::move(walls));

  counters.particle_steps = f.attribute_int("/counters", "particle_steps");
  counters.wall_time = f.attribute_double("/counters", "wall_time");
  counters.checkpoints = f.attribute_int("/counters", "checkpoints");
  counters.last_checkpoint_time = f.attribute_double("/counters", "last_checkpoint_time");
  counters.wall_time_settled = f.attribute_double("/counters", "wall_time_settled");
  counters.cpu_time = f.has_attribute("/counters", "cpu_time") ? f.attribute_double("/counters", "cpu_time") : 0.0;
  if (f.has_attribute("/counters", "neighbour_builds")) {  // older builds' checkpoints have none
    counters.neighbour_builds = f.attribute_int("/counters", "neighbour_builds");
    counters.profile.move = f.attribute_double("/counters", "profile_move_s");
    counters.profile.broad_phase = f.attribute_double("/counters", "profile_broad_phase_s");
    counters.profile.narrow_phase = f.attribute_double("/counters", "profile_narrow_phase_s");
    counters.profile.gather_correct = f.attribute_double("/counters", "profile_gather_correct_s");
  }
  counters.frame_times = f.read_doubles("/counters/frame_times");
  // Older builds wrote no snapshot frames.
  counters.snapshot_frames = f.has_attribute("/counters", "snapshot_frames") ? f.attribute_int("/counters", "snapshot_frames") : 0;
  if (counters.snapshot_frames < 0 || counters.snapshot_frames > static_cast<std::int64_t>(counters.frame_times.size()))
    throw InputError(path + ": /counters attribute snapshot_frames is " + std::to_string(counters.snapshot_frames) +
                     "; expected 0 .. the number of frame times (" + std::to_string(counters.frame_times.size()) + ")");
}

}  // namespace pilelab::dem
