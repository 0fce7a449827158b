#pragma once
// The DEM world: bodies (walls first, then grains), their motion, the contacts with their
// tangential history, and the step that advances them all by dt:
//   move (predict, place shapes) -> find pairs -> collide and compute forces -> gather, correct.
//
// Pairs live on a Verlet list (sorted by pair key) that is rebuilt only when some body has
// moved farther than its margin. Everything a pair carries from step to step sits beside its
// entry: the contact of the last step (with its tangential spring) and the narrow phase's hint.
// A step then streams through the list in order, each pair on its own (so in parallel, in any
// order), and each body sums its pairs' forces in the order of the other body's index, through
// a per-body index of the list built with it: the sums, and so the results, do not depend on
// the number of threads.
//
// Bodies are known by their index (walls first, then grains, in the order they were added), but
// stored in slots that the world puts in the order of their place every few thousand steps
// (WorldSettings::order_bodies_by_place), so that bodies that touch sit near each other in
// memory. A pair is still the pair of its lower and higher body index, and a body still sums its
// pairs in the order of their other body's index: the results are those of index order, bit for
// bit, whatever the slots.
#include <cstdint>
#include <vector>

#include "dem/contact_law.h"
#include "dem/convex_overlap.h"
#include "dem/integrator.h"
#include "dem/shape.h"
#include "dem/vec2.h"
#include "dem/work_shares.h"

namespace pilelab::dem {

/// The key that orders contacts and candidate pairs: by a, then b.
inline std::uint64_t pair_key(int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); }

/// A contact between bodies a < b, with the spring history the contact law carries from step
/// to step and the values of the last evaluation (for output and coarse-graining).
struct Contact {
  std::int32_t a = 0, b = 0;
  double spring = 0.0;           ///< Cundall-Strack spring force [N]
  Vec2 point{0, 0};              ///< force point [m]
  Vec2 normal{0, 1};             ///< unit normal from a to b
  double normal_force = 0.0;     ///< [N], on b along +normal
  double tangential_force = 0.0; ///< [N], on b along +perp(normal)
  double area = 0.0;             ///< overlap area [m^2]
  double chord = 0.0;            ///< contact-line length [m]
  std::uint64_t key() const { return pair_key(a, b); }
  Vec2 force_on_b() const { return normal_force * normal + tangential_force * perp(normal); }
};

/// The deepest overlap a run has met: how deep, when and where. Its depth is 2 A / chord (no
/// point of a convex overlap lies farther from its chord) over the smaller inner radius of the
/// pair (the grain's, against a wall); the stable time step assumes it stays below
/// max_overlap_depth_fraction (time_step.h).
struct DeepestOverlap {
  double fraction = 0.0;  ///< depth over inner radius; 0 before any contact
  double time = 0.0;      ///< end of the step in which it occurred [s]
  Vec2 point{0, 0};       ///< the contact's force point [m]
  std::int32_t a = -1, b = -1;  ///< the bodies, a < b
};

/// The longest a contact has swung: its overlap area grew and shrank in turn, step after step,
/// each time by more than swing_floor of the area. Above its stability limit an explicit scheme
/// amplifies a contact's oscillation through a mode of eigenvalue below -1, whose period is two
/// steps; a stable mode's period is longer (Verlet at 0.8 of the limit: 3.4 steps), so its swings
/// fall out of step within a few steps (within 11 at 0.99 of the limit). A contact that swings
/// for 16 steps in a row or more is unstable (time_step.h).
struct SwingingContact {
  int steps = 0;          ///< consecutive reversals of the area's change; 0 before any
  double time = 0.0;      ///< end of the step in which it first reached them [s]
  Vec2 point{0, 0};       ///< the contact's force point then [m]
  std::int32_t a = -1, b = -1;  ///< the bodies, a < b
  /// A reversal counts when the area changed by more than this fraction of itself: far above
  /// the round-off of an area (about 1e-12 of it), far below a swing that matters.
  static constexpr double swing_floor = 1e-6;
  /// The count saturates here (it is kept in 7 bits beside the pair).
  static constexpr int longest_counted = 127;
};

/// Wall-clock seconds spent in each phase of the step.
struct StepProfile {
  double move = 0;            ///< predictor, the grains' corners in their new place (geometry)
  double broad_phase = 0;     ///< renewing the pair list when a body left its margin; wall boxes
  double narrow_phase = 0;    ///< every listed pair: overlap, contact law
  double gather_correct = 0;  ///< each grain's sum of forces, Newton, corrector
  double total() const { return move + broad_phase + narrow_phase + gather_correct; }
};

struct WorldSettings {
  ContactParameters contact;
  Scheme scheme = Scheme::gear5;
  double time_step = 1e-6;  ///< [s]
  Vec2 gravity{0.0, -9.81}; ///< [m/s^2]
  /// Verlet-list skin as a fraction of the largest grain's bounding radius: pairs of bodies at
  /// rest are listed when their bounding shapes come within this distance, and the list is
  /// rebuilt once some body has moved farther than its margin (half the skin at rest). Only a
  /// matter of speed: the pairs handed to the narrow phase are the same for any skin.
  double neighbour_skin_fraction = 0.3;
  /// A moving body's margin also covers the way its speed takes it in this many steps (at the
  /// last build), so that fast grains do not force a new list every few steps. Only a matter
  /// of speed, like the skin.
  double neighbour_lookahead_steps = 100.0;
  /// Skip the narrow phase of a polygon pair while it is proven apart: once a separating axis
  /// shows a gap, the pair cannot touch until its two grains have together moved that far
  /// (less convex_overlap.h's certain_separation). Only a matter of speed: the results are the
  /// same bit for bit (tests/dem/world_test.cpp pours a pile both ways).
  bool skip_separated_pairs = true;
  /// Keep the bodies in memory in the order of their place (a Z curve over the pile), renewed
  /// at a list build every few thousand steps, so that the pair loop finds a pair's two bodies
  /// near each other. Only a matter of speed: the results are the same bit for bit.
  bool order_bodies_by_place = true;
};

class World {
 public:
  explicit World(const WorldSettings& settings);

  /// Walls: immobile (or moving at a prescribed velocity) bodies of any size. All walls must
  /// be added before the first grain.
  int add_wall(const Shape& shape, const Vec2& position, double angle, const Vec2& velocity = {0, 0});
  /// A grain held in place (a base of immobile grains): a wall in every respect but the contact
  /// length, where its lever counts as a grain's (l = r_a r_b / (r_a + r_b)); a flat wall's lever
  /// is infinite. Added among the walls, before the first grain.
  int add_fixed_grain(const Shape& shape, const Vec2& position, double angle);
  /// Whether a wall is flat (its lever infinite in the contact length) or a fixed grain.
  bool is_flat_wall(int body) const { return body < wall_count_ && wall_is_flat_[body] != 0; }
  /// Grains: mobile bodies with mass from the areal density [kg/m^2]; inactive until activated.
  int add_grain(const Shape& shape, double areal_density);
  /// Puts an inactive grain into the world with the given state.
  void activate(int body, const Vec2& position, double angle, const Vec2& velocity, double angular_velocity);
  /// Changes the prescribed velocity of a wall (e.g. a funnel that stops).
  void set_wall_velocity(int wall, const Vec2& velocity);
  /// Takes a grain out (e.g. it fell off the plate); its contacts disappear.
  void deactivate(int body);

  /// One time step.
  void step();

  // --- state access -------------------------------------------------------------------
  int body_count() const { return static_cast<int>(shapes_.size()); }
  int wall_count() const { return wall_count_; }
  const Shape& shape(int body) const { return shapes_[slot_of_[body]]; }
  bool is_wall(int body) const { return body < wall_count_; }
  bool is_active(int body) const { return active_[slot_of_[body]] != 0; }
  /// The active grains' indices, ascending.
  const std::vector<int>& active_grains() const { return active_grains_; }
  Vec2 position(int body) const { return slot_position(slot_of_[body]); }
  double angle(int body) const { return motion_.d[0][3 * slot_of_[body] + 2]; }
  Vec2 velocity(int body) const { return slot_velocity(slot_of_[body]); }
  double angular_velocity(int body) const { return motion_.d[1][3 * slot_of_[body] + 2]; }
  double mass(int body) const { return mass_[slot_of_[body]]; }
  double inertia(int body) const { return inertia_[slot_of_[body]]; }
  /// Sum of contact forces and torque on a body from the last step (gravity excluded).
  Vec2 contact_force(int body) const { return {contact_force_[3 * slot_of_[body]], contact_force_[3 * slot_of_[body] + 1]}; }
  double contact_torque(int body) const { return contact_force_[3 * slot_of_[body] + 2]; }
  /// The touching pairs of the last step, sorted by key (assembled from the pair list when asked
  /// for, so do not call it every step: contact_count() is cheap).
  const std::vector<Contact>& contacts() const;
  std::size_t contact_count() const { return contact_count_; }
  /// World-frame corners of a polygon body (after the last step); a disc's are none (a pointer
  /// one past its predecessor's, maybe the array's end, never read).
  const Vec2* corners(int body) const { return world_vertices_.data() + geometry_[slot_of_[body]].first_corner; }
  int corner_count(int body) const { return geometry_[slot_of_[body]].corner_count; }

  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  const WorldSettings& settings() const { return settings_; }
  void set_gravity(const Vec2& g) { settings_.gravity = g; }
  /// Changes scheme and time step between steps; derivatives a scheme does not carry start at 0.
  void set_time_integration(Scheme scheme, double time_step);
  const StepProfile& profile() const { return profile_; }
  /// Candidate pairs examined in the last step (broad-phase output: bounding shapes overlap).
  std::size_t candidate_count() const { return candidate_count_; }
  /// Of those, the polygon pairs proven apart and so skipped (WorldSettings::skip_separated_pairs).
  std::size_t proven_apart_count() const { return proven_apart_count_; }
  /// The slot that stores a body (WorldSettings::order_bodies_by_place): only a matter of speed.
  int slot(int body) const { return slot_of_[body]; }
  /// Pairs on the Verlet list, and how many times it has been built.
  std::size_t neighbour_count() const { return neighbours_.size(); }
  std::int64_t neighbour_builds() const { return neighbour_builds_; }

  double kinetic_energy() const;  ///< of active grains, translation + rotation [J]
  /// The first active grain (lowest body index) whose position, angle or velocity is not a
  /// finite number, or -1. A NaN or an infinity never heals, so a run checks this now and then.
  int first_non_finite_grain() const;
  /// Throws std::runtime_error naming first_non_finite_grain(), its state, the time and the step,
  /// if there is one. Run before every neighbour-list build (a grid over an infinite coordinate
  /// would never end) and by the pile protocol every few steps.
  void require_finite_state() const;
  /// The deepest overlap met so far (the first, if two steps reach the same depth).
  const DeepestOverlap& deepest_overlap() const { return deepest_overlap_; }
  /// The contact that has swung longest so far (the first to reach that count).
  const SwingingContact& longest_swing() const { return longest_swing_; }

  // --- checkpointing: the complete dynamic state ---------------------------------------
  /// The state of every body, in body order, to read or change (the slots return to body order
  /// first, until the next reordering).
  MotionState& motion();
  /// A copy of the state of every body, in body order.
  MotionState motion_state() const;
  /// Replaces the contacts (sorted by key, bodies a < b) and their spring history, e.g. from a
  /// checkpoint; the next step continues them. swings, if given, holds each contact's swing
  /// (contact_swings()) in the same order; without it the swings start afresh.
  void restore_contacts(std::vector<Contact> contacts, const std::vector<std::uint8_t>& swings = {});
  /// Each contact's swing, in the order of contacts(): bit 7 set if its area grew in the last
  /// step, bits 0-6 the steps in a row its change reversed (SwingingContact). For checkpoints.
  std::vector<std::uint8_t> contact_swings() const;
  void restore_longest_swing(const SwingingContact& swing) { longest_swing_ = swing; }
  void restore_clock(double time, std::int64_t steps) { time_ = time; steps_ = steps; }
  void restore_deepest_overlap(const DeepestOverlap& deepest) { deepest_overlap_ = deepest; }
  /// Marks bodies active/inactive from a checkpoint and rebuilds derived lists and geometry.
  void restore_activity(const std::vector<std::uint8_t>& active);
  /// Which bodies are active (1), in body order.
  std::vector<std::uint8_t> activity() const;

 private:
  int append_body(const Shape& shape, double mass, double inertia, bool active);
  bool move_grains();
  void find_candidate_pairs(bool list_outdated);
  void build_neighbour_list();
  void list_grain_pairs(double rest_margin);
  void carry_pair_history(const std::vector<std::uint64_t>& old_neighbours);
  void reorder_pair_data(const std::vector<std::size_t>& earlier);
  void index_pairs_by_body();
  void collide_and_compute_forces();
  void gather_and_correct();
  // Where the part of the grains that thread t takes in every pass begins, as a position in
  // active_slots_ (t = threads: their end). Thread t takes grain_cut(t) to grain_cut(t + 1) - 1.
  int grain_cut(int thread, int threads) const;
  void place_body(int slot);                           // its corners from its place and angle
  void place_corners(int slot, double sine, double cosine);  // the same, given its angle's sine and cosine
  void order_bodies_by_place();
  void permute_bodies(const std::vector<int>& body_at);
  Vec2 slot_position(int slot) const { return {motion_.d[0][3 * slot], motion_.d[0][3 * slot + 1]}; }
  Vec2 slot_velocity(int slot) const { return {motion_.d[1][3 * slot], motion_.d[1][3 * slot + 1]}; }
  std::uint64_t body_key(std::size_t pair) const;
  std::uint8_t restored_swing(std::uint64_t body_key) const;  // from restored_swings_, else a fresh start

  WorldSettings settings_;
  int wall_count_ = 0;
  std::vector<std::uint8_t> wall_is_flat_;  // per wall (walls keep their slots): 0 for a fixed grain
  // Where each body is stored, and which body each slot holds (walls: their own index). Every
  // array below that is per body is per slot, and the pair list holds slots.
  std::vector<int> slot_of_, body_at_;
  std::int64_t next_ordering_step_ = 0;  // order the bodies by place at the first build from then
  std::vector<Shape> shapes_;
  // What the pair loop needs of each body's shape, packed (the Shape keeps its vertices apart).
  struct BodyGeometry {
    double bounding_radius, inner_radius, longest_edge, radius;
    std::int32_t first_corner, corner_count;  ///< its corners in world_vertices_ (none: a disc)
    bool is_disc;
  };
  std::vector<BodyGeometry> geometry_;
  std::vector<double> mass_, inertia_, inv_mass_, inv_inertia_;
  std::vector<std::uint8_t> active_;
  std::vector<int> active_grains_;   // body indices, ascending
  std::vector<int> active_slots_;    // their slots, ascending
  std::vector<int> moving_walls_;
  MotionState motion_;
  std::vector<double> contact_force_;  // 3 per body: fx, fy, torque
  std::vector<Vec2> body_vertices_, world_vertices_;  // every polygon's corners, in its frame and placed
  std::vector<Vec2> wall_lo_, wall_hi_;    // walls' bounding boxes this step

  // Verlet list: pairs within reach at the last build, where every body was then, and how far
  // each may move before the list must be built again. A pair's key is pair_key(slot of its
  // lower body index, slot of its higher), and the list is sorted by key.
  std::vector<std::uint64_t> neighbours_;  // sorted pair keys
  std::vector<Vec2> listed_position_;      // per body
  std::vector<double> listed_margin_;      // per body [m]
  std::vector<double> listed_angle_;       // per body [rad]
  // How far any corner of each body lies from where it was at the list's build, at most [m]:
  // |x - listed x| + bounding radius |angle - listed angle| (an arc is longer than its chord).
  std::vector<double> displacement_;
  bool neighbours_stale_ = true;
  std::int64_t neighbour_builds_ = 0;
  // Beside each listed pair: its contact at the last step (valid where touching) and the
  // narrow phase's hint.
  std::vector<Contact> pair_contact_;
  std::vector<std::uint8_t> pair_touching_;
  // Each pair's swing (SwingingContact): bit 7 set if its area grew in the last step, bits 0-6
  // how many steps in a row its change reversed.
  std::vector<std::uint8_t> pair_swing_;
  // Each thread's share of the grains, from the rates at which the threads got through their
  // steps (WorkShares): it moves, sums and corrects those grains and collides their pairs.
  WorkShares step_shares_;
  // What a thread of the pair loop works in, one chunk of pairs at a time; on cache lines of its
  // own, so that one thread's writes never share a line with another's.
  struct alignas(64) ChunkScratch {
    std::vector<Overlap> overlaps;
    // The pairs by the hint's corner in an edge, the others (then those still open), the touching.
    std::vector<std::size_t> by_corner, others, touching;
  };
  std::vector<ChunkScratch> chunk_scratch_;  // one per thread
  std::vector<OverlapHint> pair_hint_;
  // A polygon pair is proven apart while displacement_[a] + displacement_[b] stays below this
  // [m]; 0: not proven. Valid until the list is built again.
  std::vector<double> pair_apart_until_;
  // Each body's listed pairs in the order of the other body's index: body_pairs_ from
  // body_pair_start_[i] to body_pair_start_[i + 1] (i a slot), each entry 2 q + (1 if the body is
  // the pair's b). pair_ends_[2 q] and [2 q + 1] are pair q's entries in that index, for its a
  // and its b.
  std::vector<int> body_pair_start_, body_pairs_, pair_ends_;
  // What each entry of that index receives from its pair: the force on the body and the torque
  // about its centroid, zero where the pair does not touch. The pair loop writes both ends of
  // each pair; a body's sum then streams through its own entries.
  struct alignas(32) EndLoad {  // 32 bytes: an entry is found by a shift, stored in two moves
    double fx, fy, torque;
  };
  std::vector<EndLoad> end_load_;
  // Contacts restored from a checkpoint, taken into the list at its next build, and their swings
  // by the key of their bodies' indices (sorted).
  std::vector<Contact> restored_contacts_;
  std::vector<std::pair<std::uint64_t, std::uint8_t>> restored_swings_;
  std::size_t contact_count_ = 0, candidate_count_ = 0, proven_apart_count_ = 0;
  mutable std::vector<Contact> contacts_;  // assembled by contacts()
  mutable bool contacts_current_ = true;
  DeepestOverlap deepest_overlap_;
  SwingingContact longest_swing_;
  // Broad-phase cell list.
  std::vector<int> cell_start_, cell_bodies_, body_cell_;
  // What a build of the list works in, kept from build to build: once the pile has reached its
  // size a new list allocates nothing (fresh pages cost a fault each, on the build's critical
  // path). Each thread's pairs sit on cache lines of their own.
  struct alignas(64) ThreadPairs {
    std::vector<std::uint64_t> keys;
  };
  struct ListBuildScratch {
    std::vector<std::uint64_t> old_neighbours, merged;
    std::vector<ThreadPairs> thread_pairs;
    std::vector<std::size_t> earlier;  // reorder_pair_data's argument
    std::vector<int> fill;             // index_pairs_by_body's next free entry of each body
    // The pair arrays' other halves: reorder_pair_data fills these and swaps them in.
    std::vector<Contact> contact;
    std::vector<std::uint8_t> touching, swing;
    std::vector<OverlapHint> hint;
    std::vector<double> apart_until;
  } list_scratch_;
  double max_grain_radius_ = 0.0;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  StepProfile profile_;
};

}  // namespace pilelab::dem
