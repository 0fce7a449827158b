#pragma once
// Checkpoints: the complete dynamic state of a pile run (world, contacts with their spring
// history, protocol, random stream, output counters), enough to continue bit for bit.
#include <cstdint>
#include <string>
#include <vector>

#include "dem/pile_protocol.h"

namespace pilelab::dem {

/// Counters of the run driver that a restart continues.
struct RunCounters {
  std::int64_t particle_steps = 0;   ///< sum over steps of active grains
  double wall_time = 0.0;            ///< [s] accumulated over all sessions of this run
  std::vector<double> frame_times;   ///< simulated times of the VTK frames written
  /// Of those, the frames of the snapshots (settled, relaxed), written when each is taken; the
  /// others fall at the frame interval.
  std::int64_t snapshot_frames = 0;
  std::int64_t checkpoints = 0;      ///< checkpoints written
  double last_checkpoint_time = 0.0;  ///< [s] simulated time of the last one
  double wall_time_settled = -1.0;    ///< [s] wall time when the pile had poured and settled; -1 before
  /// [s] processor time of all threads over all sessions (core-seconds: what the run costs
  /// whatever else shares the machine); a run resumed from a checkpoint without it (older
  /// builds') counts only its later sessions.
  double cpu_time = 0.0;
  /// Neighbour-list builds and the step's phase times [s] over all sessions up to the last
  /// checkpoint (a run resumed from an older build's checkpoint counts only its later sessions).
  std::int64_t neighbour_builds = 0;
  StepProfile profile;
};

void write_checkpoint(const std::string& path, const std::string& scene_text, const PileProtocol& protocol,
                      const RunCounters& counters);
/// Restores protocol and counters; throws InputError if the file is missing or corrupt, or was
/// written for another scene.
void read_checkpoint(const std::string& path, const std::string& scene_text, PileProtocol& protocol,
                     RunCounters& counters);

}  // namespace pilelab::dem
