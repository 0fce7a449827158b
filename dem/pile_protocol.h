#pragma once
// The experiment of the paper (section 2, 3.2): pour grains from a point source onto a flat
// plate, let the pile settle, and optionally relax it by a slow reduction of gravity. The
// protocol owns the world and advances it one time step at a time through these phases:
//   pour -> settle -> [ramp -> relax_settle] -> done
// taking the snapshots "settled" and (after the ramp) "relaxed".
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/rng.h"
#include "dem/dem_file.h"
#include "dem/dem_scene.h"
#include "dem/snapshot.h"
#include "dem/time_step.h"
#include "dem/world.h"

namespace pilelab::dem {

enum class Phase : int { pour = 0, settle = 1, ramp = 2, relax_settle = 3, done = 4 };
const char* phase_name(Phase p);

/// Bounds on the simulated time a run of the scene lasts [s]: the pour at its rate, then each
/// settling phase between its shortest and longest time, and the gravity ramp if asked for.
struct RunDuration {
  double shortest = 0.0;
  double longest = 0.0;
};
RunDuration run_duration(const DemScene& scene);

/// What a run costs at a time step: its simulated time, steps and grain-steps, from the
/// shortest (every settling ends at its minimum time) to the longest (every settling runs to its
/// limit), if every grain is poured on schedule.
struct RunCost {
  double time_step = 0.0;  ///< [s]
  RunDuration simulated;   ///< [s]
  double steps_shortest = 0.0, steps_longest = 0.0;
  double grain_steps_shortest = 0.0, grain_steps_longest = 0.0;
};
RunCost run_cost(const DemScene& scene, double time_step);
/// A step of a settled paper pile costs about this on one core of the reference machine
/// (docs/PERFORMANCE.md: 8.4e6 for Verlet, fewer for Gear 5 and while pouring): the rate the
/// cost estimates of `pilelab check` assume.
constexpr double reference_grain_steps_per_core_s = 5e6;

/// Refuses, with an InputError naming `source` and the keys, a run that no computer would
/// finish: more time steps or grain-steps than the limits below even at its shortest (if every
/// grain is poured; a stalled pour ends sooner), or more frames or checkpoint writes than a run
/// can usefully make.
void check_run_length(const DemScene& scene, double time_step, const std::string& source);
constexpr double max_run_steps = 1e12;         ///< days even for a lone grain
constexpr double max_run_grain_steps = 1e14;   ///< about a year at 4e6 grain-steps/s (2 cores)
constexpr double max_run_files = 1e4;          ///< frames, or checkpoint writes

/// Everything besides the world that a restart needs to continue exactly.
struct ProtocolState {
  Phase phase = Phase::pour;
  double phase_start = 0.0;       ///< simulated time the phase began [s]
  int poured = 0;                 ///< grains inserted so far
  int lost = 0;                   ///< grains removed after leaving the plate
  double next_insert_time = 0.0;  ///< [s]
  double last_insert_time = 0.0;  ///< [s]
  bool pour_stalled = false;      ///< the outlet stayed blocked: pouring stopped early
  /// Kinetic plus potential energy (above the loss height) the lost grains held when they were
  /// removed [J]: energy that left the pile, no longer available to it.
  double lost_energy = 0.0;
  std::array<std::uint64_t, 4> rng{};
};

/// The longest simulated time the phases after the pour can still take at time t [s]: the
/// time limits of each settling and the gravity ramp ahead, counted from the current phase's
/// start; 0 once done.
double longest_time_after_pour(const DemScene& scene, const ProtocolState& state, double t);

class PileProtocol {
 public:
  /// Builds the container and draws every grain's shape from the scene's seed; throws
  /// InputError (naming source) if the scene's time step exceeds the stability limit.
  PileProtocol(const DemScene& scene, const std::string& source);

  /// One time step of the world plus the protocol's bookkeeping.
  void step();
  bool done() const { return state_.phase == Phase::done; }

  World& world() { return world_; }
  const World& world() const { return world_; }
  /// The bodies the pile stands on: the plate (body 0) and the base's fixed grains, ascending.
  const std::vector<int>& base_bodies() const { return base_bodies_; }
  const DemScene& scene() const { return scene_; }
  const TimeStepBound& time_step_bound() const { return bound_; }
  /// The bound again for contacts as deep as the deepest overlap the run has reached
  /// (stable_time_step_at_depth): whether the step stayed stable for the contacts it made.
  TimeStepBound time_step_bound_at_deepest_overlap() const;
  const ProtocolState& state() const { return state_; }
  const std::vector<Snapshot>& snapshots() const { return snapshots_; }
  /// Where the walls were at each snapshot (the funnel may have moved since).
  const std::vector<WallPlacement>& wall_placements() const { return wall_placements_; }
  /// Mean kinetic energy per active grain [J].
  double kinetic_energy_per_grain() const;
  /// The most mechanical energy the pour can have put in so far [J], counted from the height at
  /// which grains are lost: each poured grain's kinetic energy at the outlet, its fall from the
  /// outlet to that height, and an estimate of what a moving funnel adds (a grain at rest that
  /// bounces off a wall moving at u leaves it at 2u). Contacts only dissipate and gravity only
  /// falls, so in a stable run the grains' kinetic plus potential energy stays below this (with
  /// a fixed funnel strictly; docs/DEM.md, "Protocol").
  double energy_fed_in() const;
  /// The most the active grains can hold: energy_fed_in() less what the lost grains carried off
  /// (ProtocolState::lost_energy) [J].
  double energy_bound() const { return energy_fed_in() - state_.lost_energy; }
  /// The active grains' kinetic energy plus their potential energy above the loss height [J].
  double mechanical_energy() const;
  /// The same for one grain [J].
  double mechanical_energy(int grain) const;
  /// A run whose mechanical energy exceeds this multiple of energy_bound() creates energy: the
  /// explicit scheme is unstable (a step above the limit), and the pile protocol stops it.
  static constexpr double energy_growth_limit = 2.0;
  /// A contact whose overlap grows and shrinks in turn for this many steps in a row
  /// (World::longest_swing) oscillates at the period of two steps: the explicit scheme is
  /// unstable for it, and the pile protocol stops the run. A stable mode reverses its change
  /// this often in a row only within half a per cent of its limit; no run of the 40-grain pile
  /// that completed, at any multiple of the limit, reversed more than 10 times in a row, and
  /// none at or below the limit more than 4 (docs/studies/extremes.md).
  static constexpr int unstable_swing_steps = 16;
  /// What a body is, with its index, for messages: "the plate (body 0)", "a grain (body 47)".
  std::string body_name(int body) const;

  /// For checkpoints.
  void restore(const ProtocolState& state, std::vector<Snapshot> snapshots, std::vector<WallPlacement> walls);

  static constexpr int check_interval = 64;  ///< steps between settling/loss checks

 private:
  void build_container();
  void lay_base_grains();  ///< the base of fixed grains (ContainerSpec::base)
  void try_insert();
  void check_state_is_finite() const;  ///< throws, naming the first grain that is not
  void check_energy_is_bounded() const;  ///< throws, naming the time, step and fastest grain
  void check_contacts_are_stable() const;  ///< throws, naming the contact that swings
  void remove_lost_grains();
  void advance_phase();
  double funnel_x(double t) const;
  bool funnel_moving(double t) const;
  void finish_settling(const std::string& snapshot_name, Phase next);

  DemScene scene_;
  World world_;
  TimeStepBound bound_;
  ProtocolState state_;
  Rng rng_;
  std::vector<int> funnel_walls_;
  int first_grain_ = 0;
  std::vector<int> base_bodies_;
  std::vector<Snapshot> snapshots_;
  std::vector<WallPlacement> wall_placements_;
};

}  // namespace pilelab::dem
