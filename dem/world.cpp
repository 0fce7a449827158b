#include "dem/world.h"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <numeric>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "common/portable_math.h"
#include "dem/contact_law_x4.h"
#include "dem/convex_overlap.h"
#include "dem/four_lanes.h"
#include "dem/rotation_x4.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pilelab::dem {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
// Two doubles in one SSE2 register (GCC's and Clang's vector extension): element-wise
// arithmetic, each lane rounded exactly as the scalar operation would be.
using Double2 = double __attribute__((vector_size(16)));
// The pair loop's chunk: each thread takes chunks of this many listed pairs, batches their
// corner-in-edge contacts, then applies the contact law to the chunk's touching pairs.
constexpr std::size_t pair_chunk = 512;
// The move takes the grains in blocks: the rotations of a block's grains are computed together,
// four in the lanes of a vector and several such groups in flight (rotation_sincos_x4). The
// threads' parts of the passes over the grains are cut between blocks.
constexpr int grain_block = 32;
// Below this many grains (or pairs) a parallel region costs more than it saves.
constexpr int parallel_threshold = 256;
// How often the bodies take the order of their place (at the first list build after this many
// steps): sorting and moving them costs about ten steps.
constexpr std::int64_t ordering_interval_steps = 2000;
// No earlier pair (World::reorder_pair_data).
constexpr std::size_t no_pair = ~std::size_t{0};

// The threads of the enclosing parallel region and this one's number (1 and 0 without OpenMP).
int thread_count() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}
int thread_number() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}
// The most threads a parallel region may have.
int max_thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

// v resized to n; when it must grow, with room for an eighth more, so that an array whose
// length wanders around one size (the pair list's) stops allocating: each fresh page costs a
// fault, about 10 microseconds on the virtual machines we measured (docs/PERFORMANCE.md).
template <class T>
void resize_with_room(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(n + n / 8);
  v.resize(n);
}

}  // namespace

World::World(const WorldSettings& settings) : settings_(settings) {}

int World::append_body(const Shape& shape, double mass, double inertia, bool active) {
  if (static_cast<int>(shape.vertices.size()) > max_polygon_corners)
    throw std::invalid_argument("World: polygons have at most 64 corners");
  const int id = body_count();  // and its slot, at the end
  slot_of_.push_back(id);
  body_at_.push_back(id);
  shapes_.push_back(shape);
  geometry_.push_back({shape.bounding_radius, shape.inner_radius, shape.longest_edge, shape.radius,
                       static_cast<std::int32_t>(body_vertices_.size()), static_cast<std::int32_t>(shape.vertices.size()),
                       shape.kind == ShapeKind::disc});
  mass_.push_back(mass);
  inertia_.push_back(inertia);
  inv_mass_.push_back(1.0 / mass);  // 0 for walls, whose mass is infinite
  inv_inertia_.push_back(1.0 / inertia);
  active_.push_back(active ? 1 : 0);
  motion_.resize(shapes_.size());
  contact_force_.resize(3 * shapes_.size(), 0.0);
  body_vertices_.insert(body_vertices_.end(), shape.vertices.begin(), shape.vertices.end());
  world_vertices_.resize(body_vertices_.size());
  return id;
}

int World::add_wall(const Shape& shape, const Vec2& position, double angle, const Vec2& velocity) {
  if (body_count() != wall_count_) throw std::logic_error("World: walls must be added before grains");
  const int id = append_body(shape, INFINITY, INFINITY, true);
  motion_.d[0][3 * id] = position.x();
  motion_.d[0][3 * id + 1] = position.y();
  motion_.d[0][3 * id + 2] = angle;
  motion_.d[1][3 * id] = velocity.x();
  motion_.d[1][3 * id + 1] = velocity.y();
  if (velocity.squaredNorm() > 0) moving_walls_.push_back(id);
  ++wall_count_;
  wall_is_flat_.push_back(1);
  place_body(id);
  neighbours_stale_ = true;
  return id;
}

int World::add_fixed_grain(const Shape& shape, const Vec2& position, double angle) {
  const int id = add_wall(shape, position, angle);
  wall_is_flat_[id] = 0;
  return id;
}

int World::add_grain(const Shape& shape, double areal_density) {
  const int id = append_body(shape, areal_density * shape.area, areal_density * shape.polar_moment, false);
  max_grain_radius_ = std::max(max_grain_radius_, shape.bounding_radius);
  return id;
}

void World::activate(int body, const Vec2& position, double angle, const Vec2& velocity, double angular_velocity) {
  if (is_wall(body) || is_active(body)) throw std::logic_error("World::activate: not an inactive grain");
  const int slot = slot_of_[body];
  for (auto& d : motion_.d) std::fill_n(d.begin() + 3 * slot, 3, 0.0);
  motion_.d[0][3 * slot] = position.x();
  motion_.d[0][3 * slot + 1] = position.y();
  motion_.d[0][3 * slot + 2] = angle;
  motion_.d[1][3 * slot] = velocity.x();
  motion_.d[1][3 * slot + 1] = velocity.y();
  motion_.d[1][3 * slot + 2] = angular_velocity;
  // Start with the free-flight acceleration so the first predictor step is consistent.
  motion_.d[2][3 * slot] = settings_.gravity.x();
  motion_.d[2][3 * slot + 1] = settings_.gravity.y();
  active_[slot] = 1;
  active_grains_.insert(std::upper_bound(active_grains_.begin(), active_grains_.end(), body), body);
  active_slots_.insert(std::upper_bound(active_slots_.begin(), active_slots_.end(), slot), slot);
  place_body(slot);
  neighbours_stale_ = true;
}

void World::set_wall_velocity(int wall, const Vec2& velocity) {
  if (!is_wall(wall)) throw std::logic_error("World::set_wall_velocity: not a wall");
  motion_.d[1][3 * wall] = velocity.x();
  motion_.d[1][3 * wall + 1] = velocity.y();
  moving_walls_.erase(std::remove(moving_walls_.begin(), moving_walls_.end(), wall), moving_walls_.end());
  if (velocity.squaredNorm() > 0) moving_walls_.push_back(wall);
  std::sort(moving_walls_.begin(), moving_walls_.end());
}

void World::set_time_integration(Scheme scheme, double time_step) {
  if (scheme != settings_.scheme)
    for (int k = 3; k < 6; ++k) std::fill(motion_.d[k].begin(), motion_.d[k].end(), 0.0);
  settings_.scheme = scheme;
  settings_.time_step = time_step;
}

void World::deactivate(int body) {
  if (is_wall(body) || !is_active(body)) return;
  const int slot = slot_of_[body];
  active_[slot] = 0;
  active_grains_.erase(std::lower_bound(active_grains_.begin(), active_grains_.end(), body));
  active_slots_.erase(std::lower_bound(active_slots_.begin(), active_slots_.end(), slot));
  neighbours_stale_ = true;
  // Its contacts end now (the list drops its pairs at the next build).
  if (!body_pair_start_.empty())
    for (int k = body_pair_start_[slot]; k < body_pair_start_[slot + 1]; ++k) {
      const int q = body_pairs_[k] >> 1;
      if (pair_touching_[q]) --contact_count_;
      pair_touching_[q] = 0;
      end_load_[pair_ends_[2 * q]] = end_load_[pair_ends_[2 * q + 1]] = {0.0, 0.0, 0.0};
    }
  restored_contacts_.erase(std::remove_if(restored_contacts_.begin(), restored_contacts_.end(),
                                          [&](const Contact& c) { return c.a == body || c.b == body; }),
                           restored_contacts_.end());
  if (!restored_contacts_.empty()) contact_count_ = restored_contacts_.size();
  contacts_current_ = false;
}

void World::restore_contacts(std::vector<Contact> contacts, const std::vector<std::uint8_t>& swings) {
  restored_swings_.clear();
  if (!swings.empty()) {
    if (swings.size() != contacts.size()) throw std::logic_error("World::restore_contacts: one swing a contact");
    for (std::size_t i = 0; i < contacts.size(); ++i) restored_swings_.emplace_back(contacts[i].key(), swings[i]);
    std::sort(restored_swings_.begin(), restored_swings_.end());
  }
  neighbours_.clear();
  pair_contact_.clear();
  pair_touching_.clear();
  pair_swing_.clear();
  pair_hint_.clear();
  pair_apart_until_.clear();
  end_load_.clear();
  pair_ends_.clear();
  body_pair_start_.clear();
  body_pairs_.clear();
  neighbours_stale_ = true;
  restored_contacts_ = std::move(contacts);
  contact_count_ = restored_contacts_.size();
  contacts_current_ = false;
}

const std::vector<Contact>& World::contacts() const {
  if (contacts_current_) return contacts_;
  contacts_.clear();
  if (!restored_contacts_.empty()) {
    contacts_ = restored_contacts_;
  } else {
    contacts_.reserve(contact_count_);
    for (std::size_t q = 0; q < neighbours_.size(); ++q)
      if (pair_touching_[q]) {
        contacts_.push_back(pair_contact_[q]);
        contacts_.back().a = body_at_[contacts_.back().a];
        contacts_.back().b = body_at_[contacts_.back().b];
      }
    std::sort(contacts_.begin(), contacts_.end(), [](const Contact& c, const Contact& d) { return c.key() < d.key(); });
  }
  contacts_current_ = true;
  return contacts_;
}

// A restored contact's swing, where the checkpoint kept one; else a fresh start (it grew, none
// reversed).
std::uint8_t World::restored_swing(std::uint64_t body_key) const {
  const auto swing = std::lower_bound(restored_swings_.begin(), restored_swings_.end(), std::make_pair(body_key, std::uint8_t{0}));
  return swing != restored_swings_.end() && swing->first == body_key ? swing->second : 0x80;
}

std::vector<std::uint8_t> World::contact_swings() const {
  const std::vector<Contact>& listed = contacts();
  std::vector<std::uint8_t> swings(listed.size(), 0x80);
  if (!restored_contacts_.empty()) {  // not yet taken into the list
    for (std::size_t i = 0; i < listed.size(); ++i) swings[i] = restored_swing(listed[i].key());
    return swings;
  }
  // The touching pairs by their bodies' key: the order of contacts().
  std::vector<std::pair<std::uint64_t, std::uint8_t>> by_key;
  by_key.reserve(listed.size());
  for (std::size_t q = 0; q < neighbours_.size(); ++q)
    if (pair_touching_[q]) by_key.emplace_back(body_key(q), pair_swing_[q]);
  std::sort(by_key.begin(), by_key.end());
  for (std::size_t i = 0; i < by_key.size(); ++i) swings[i] = by_key[i].second;
  return swings;
}

void World::restore_activity(const std::vector<std::uint8_t>& active) {
  active_grains_.clear();
  active_slots_.clear();
  for (int i = 0; i < body_count(); ++i) {
    active_[slot_of_[i]] = active[i];
    if (active[i] && !is_wall(i)) active_grains_.push_back(i);
  }
  for (int slot = wall_count_; slot < body_count(); ++slot)
    if (active_[slot]) active_slots_.push_back(slot);
  moving_walls_.clear();
  for (int w = 0; w < wall_count_; ++w)
    if (velocity(w).squaredNorm() > 0) moving_walls_.push_back(w);
  for (int slot = 0; slot < body_count(); ++slot)
    if (active_[slot]) place_body(slot);
  neighbours_stale_ = true;
}

std::vector<std::uint8_t> World::activity() const {
  std::vector<std::uint8_t> active(body_count());
  for (int i = 0; i < body_count(); ++i) active[i] = active_[slot_of_[i]];
  return active;
}

MotionState& World::motion() {
  std::vector<int> body_order(body_count());
  std::iota(body_order.begin(), body_order.end(), 0);
  permute_bodies(body_order);
  next_ordering_step_ = steps_;  // order them by place again at the next build
  neighbours_stale_ = true;      // the caller may move bodies
  return motion_;
}

MotionState World::motion_state() const {
  MotionState m;
  m.resize(body_count());
  for (int i = 0; i < body_count(); ++i) {
    const int slot = slot_of_[i];
    for (int k = 0; k < 6; ++k) std::copy_n(motion_.d[k].begin() + 3 * slot, 3, m.d[k].begin() + 3 * i);
    std::copy_n(motion_.half_velocity.begin() + 3 * slot, 3, m.half_velocity.begin() + 3 * i);
  }
  return m;
}

// The bodies in the order of their place: the active grains along a Z curve (Morton order) over
// their bounding box, then the inactive ones, ties and the inactive ones by index; the walls
// stay first. Nearby grains so sit near each other in memory, whatever order they were poured in.
// The curve splits across x first (its first half is the box's left half), so that the threads'
// parts, cut along it, meet along a line up through the pile, which is wider than tall, rather
// than across it: fewer pairs straddle two threads' parts.
void World::order_bodies_by_place() {
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
  for (int slot : active_slots_) {
    xmin = std::min(xmin, motion_.d[0][3 * slot]), xmax = std::max(xmax, motion_.d[0][3 * slot]);
    ymin = std::min(ymin, motion_.d[0][3 * slot + 1]), ymax = std::max(ymax, motion_.d[0][3 * slot + 1]);
  }
  // 16 bits of each coordinate, interleaved; ~0 for an inactive grain.
  const auto spread_bits = [](std::uint64_t v) {
    v &= 0xffff;
    v = (v | (v << 8)) & 0x00ff00ff;
    v = (v | (v << 4)) & 0x0f0f0f0f;
    v = (v | (v << 2)) & 0x33333333;
    return (v | (v << 1)) & 0x55555555;
  };
  const double sx = 65535.0 / std::max(xmax - xmin, 1e-300), sy = 65535.0 / std::max(ymax - ymin, 1e-300);
  std::vector<std::pair<std::uint64_t, int>> place(body_count() - wall_count_);
  for (int body = wall_count_; body < body_count(); ++body) {
    const int slot = slot_of_[body];
    std::uint64_t key = ~std::uint64_t{0};
    if (active_[slot]) {
      const auto cell = [](double u) { return static_cast<std::uint64_t>(std::min(std::max(u, 0.0), 65535.0)); };
      key = spread_bits(cell((motion_.d[0][3 * slot] - xmin) * sx)) << 1 |
            spread_bits(cell((motion_.d[0][3 * slot + 1] - ymin) * sy));
    }
    place[body - wall_count_] = {key, body};
  }
  std::sort(place.begin(), place.end());
  std::vector<int> body_at(body_count());
  std::iota(body_at.begin(), body_at.begin() + wall_count_, 0);
  for (std::size_t k = 0; k < place.size(); ++k) body_at[wall_count_ + k] = place[k].second;
  permute_bodies(body_at);
}

// Moves every body to the slot body_at gives it, and the pair list with them: its keys to the
// new slots (the pairs keep their ends: a is the lower body index), sorted again with all they
// carry.
void World::permute_bodies(const std::vector<int>& body_at) {
  const int n = body_count();
  std::vector<int> from(n);  // the slot each new slot's body comes from
  for (int slot = 0; slot < n; ++slot) from[slot] = slot_of_[body_at[slot]];
  bool moved = false;
  for (int slot = 0; slot < n && !moved; ++slot) moved = from[slot] != slot;
  if (!moved) return;
  const auto permute = [&](auto& values, int per_body) {
    if (values.size() != static_cast<std::size_t>(per_body) * n) return;  // not in use yet
    auto old = std::move(values);
    values.clear();
    values.reserve(old.size());
    for (int slot = 0; slot < n; ++slot)
      for (int c = 0; c < per_body; ++c) values.push_back(std::move(old[per_body * from[slot] + c]));
  };
  permute(shapes_, 1);
  permute(geometry_, 1);
  permute(mass_, 1);
  permute(inertia_, 1);
  permute(inv_mass_, 1);
  permute(inv_inertia_, 1);
  permute(active_, 1);
  for (auto& d : motion_.d) permute(d, 3);
  permute(motion_.half_velocity, 3);
  permute(contact_force_, 3);
  permute(listed_position_, 1);
  permute(listed_margin_, 1);
  permute(listed_angle_, 1);
  permute(displacement_, 1);
  // The corners, body after body in the new order.
  std::vector<Vec2> body_vertices, world_vertices;
  body_vertices.reserve(body_vertices_.size());
  world_vertices.reserve(world_vertices_.size());
  for (BodyGeometry& g : geometry_) {
    const int first = g.first_corner;
    g.first_corner = static_cast<std::int32_t>(body_vertices.size());
    body_vertices.insert(body_vertices.end(), body_vertices_.begin() + first, body_vertices_.begin() + first + g.corner_count);
    world_vertices.insert(world_vertices.end(), world_vertices_.begin() + first, world_vertices_.begin() + first + g.corner_count);
  }
  body_vertices_.swap(body_vertices);
  world_vertices_.swap(world_vertices);
  std::vector<int> to(n);  // the new slot of each old one
  for (int slot = 0; slot < n; ++slot) to[from[slot]] = slot;
  body_at_ = body_at;
  for (int slot = 0; slot < n; ++slot) slot_of_[body_at_[slot]] = slot;
  active_slots_.clear();
  for (int slot = wall_count_; slot < n; ++slot)
    if (active_[slot]) active_slots_.push_back(slot);

  // The pair list in the new slots.
  const std::size_t pairs = neighbours_.size();
  if (pairs == 0) return;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> renamed(pairs);
  for (std::size_t q = 0; q < pairs; ++q)
    renamed[q] = {pair_key(to[static_cast<int>(neighbours_[q] >> 32)], to[static_cast<int>(neighbours_[q] & 0xffffffffu)]),
                  static_cast<std::uint32_t>(q)};
  std::sort(renamed.begin(), renamed.end());
  std::vector<std::size_t> earlier(pairs);
  for (std::size_t q = 0; q < pairs; ++q) {
    neighbours_[q] = renamed[q].first;
    earlier[q] = renamed[q].second;
  }
  reorder_pair_data(earlier);
  for (Contact& c : pair_contact_) c.a = to[c.a], c.b = to[c.b];
  index_pairs_by_body();  // with zero loads: the next pair loop writes those of the pairs that touch
}

void World::place_body(int slot) {
  double sn, c;
  rotation_sincos(motion_.d[0][3 * slot + 2], sn, c);  // one reduction for both
  place_corners(slot, sn, c);
}

[[gnu::always_inline]] inline void World::place_corners(int slot, double sn, double c) {
  const int first = geometry_[slot].first_corner, count = geometry_[slot].corner_count;
  if (count == 0) return;  // a disc
  // p + R(theta) v for each body-frame corner v, both coordinates in one register:
  // (px, py) + vx (c, s) + vy (-s, c). The same bits as vec2.h's rotate: vy (-s) is -(s vy)
  // exactly, and adding it is subtracting s vy.
  const Double2 p = {motion_.d[0][3 * slot], motion_.d[0][3 * slot + 1]};
  const Double2 first_column = {c, sn}, second_column = {-sn, c};
  const double* from = body_vertices_[first].data();
  double* out = world_vertices_[first].data();
  for (int k = 0; k < count; ++k) {
    const Double2 vx = {from[2 * k], from[2 * k]}, vy = {from[2 * k + 1], from[2 * k + 1]};
    const Double2 placed = p + (vx * first_column + vy * second_column);
    std::memcpy(out + 2 * k, &placed, sizeof placed);
  }
}

// One step, in four passes: each grain moves and takes its new shape; the pair list is renewed
// if some body went beyond its margin; every listed pair collides; each grain sums its forces
// and completes its step. Each thread takes one run of the slots in the passes over the grains
// and those grains' pairs in the pair loop (the pairs follow the slots), so that a grain's data
// mostly stays in one core's cache; the runs' lengths follow the rates the threads reached in
// the last steps (WorkShares).
void World::step() {
  auto t0 = Clock::now();
  const bool list_outdated = move_grains();
  profile_.move += seconds_since(t0);

  auto t1 = Clock::now();
  find_candidate_pairs(list_outdated);
  profile_.broad_phase += seconds_since(t1);

  auto t2 = Clock::now();
  collide_and_compute_forces();
  profile_.narrow_phase += seconds_since(t2);

  auto t3 = Clock::now();
  gather_and_correct();
  time_ += settings_.time_step;
  ++steps_;
  profile_.gather_correct += seconds_since(t3);
}

// The predictor and the grains' new corners; true if some body has gone farther than its
// margin since the pair list was built.
PILELAB_AVX2_AND_SSE2
bool World::move_grains() {
  const double dt = settings_.time_step;
  const Stepper stepper(settings_.scheme, dt);
  const int n = static_cast<int>(active_slots_.size());
  const bool listed = !neighbours_stale_ && listed_margin_.size() == static_cast<std::size_t>(body_count());
  bool outdated = !listed;
  step_shares_.prepare(n >= parallel_threshold ? max_thread_count() : 1);
#pragma omp parallel reduction(|| : outdated) if (n >= parallel_threshold)
  {
    const auto start = Clock::now();
    const int begin = grain_cut(thread_number(), thread_count()), end = grain_cut(thread_number() + 1, thread_count());
    for (int first = begin; first < end; first += grain_block) {
      const int* const slot = active_slots_.data() + first;
      const int count = std::min(grain_block, end - first);
      double angle[grain_block], sn[grain_block], c[grain_block];
      for (int k = 0; k < count; ++k) {
        stepper.predict(motion_, slot[k]);
        angle[k] = motion_.d[0][3 * slot[k] + 2];
      }
      rotation_sincos_x4(angle, sn, c, count);
      for (int k = 0; k < count; ++k) {
        const int i = slot[k];
        place_corners(i, sn[k], c[k]);
        if (listed) {
          const double moved2 = (slot_position(i) - listed_position_[i]).squaredNorm();
          outdated = outdated || moved2 > listed_margin_[i] * listed_margin_[i];
          displacement_[i] =
              std::sqrt(moved2) + geometry_[i].bounding_radius * std::abs(motion_.d[0][3 * i + 2] - listed_angle_[i]);
        }
      }
    }
    step_shares_.record(thread_number(), thread_count(), end - begin, seconds_since(start));
  }
  for (int w : moving_walls_) {  // prescribed motion: x += v dt (walls keep their own slots)
    for (int c = 0; c < 2; ++c) motion_.d[0][3 * w + c] += dt * motion_.d[1][3 * w + c];
    place_body(w);
    if (listed) {
      const double moved2 = (slot_position(w) - listed_position_[w]).squaredNorm();
      outdated = outdated || moved2 > listed_margin_[w] * listed_margin_[w];
      displacement_[w] = std::sqrt(moved2);  // walls do not turn
    }
  }
  return outdated;
}

namespace {
// Axis-aligned bounding box of a wall in its current place.
void wall_box(const Shape& s, const Vec2& position, const Vec2* corners, int corner_count, Vec2& lo, Vec2& hi) {
  if (s.kind == ShapeKind::disc) {
    lo = position - Vec2(s.radius, s.radius);
    hi = position + Vec2(s.radius, s.radius);
    return;
  }
  lo = hi = corners[0];
  for (int k = 1; k < corner_count; ++k) {
    lo = lo.cwiseMin(corners[k]);
    hi = hi.cwiseMax(corners[k]);
  }
}
bool circle_meets_box(double x, double y, double r, const Vec2& lo, const Vec2& hi) {
  return x + r >= lo.x() && x - r <= hi.x() && y + r >= lo.y() && y - r <= hi.y();
}
}  // namespace

// Broad phase. A pair is a candidate when the bounding circles of two grains overlap, or a
// grain's bounding circle meets a wall's bounding box. Testing that for all pairs near each
// other every step is what a Verlet list saves: it lists the pairs that come within a margin
// of being candidates, each body with a margin of its own, and stays valid while no body has
// moved farther than its margin since the list was built (two bodies approach by at most the
// sum of their displacements). A body at rest gets half the skin; a moving one also the way
// its speed takes it in neighbour_lookahead_steps steps, so that the grains falling from the
// funnel do not force a new list every few steps. The narrow phase then tests every listed
// pair exactly, so the candidates are the same pairs as a fresh search every step would give:
// no pair is ever missed, and the result does not depend on the margins or on when the list
// was rebuilt.
void World::find_candidate_pairs(bool list_outdated) {
  if (list_outdated) build_neighbour_list();
  wall_lo_.resize(wall_count_);
  wall_hi_.resize(wall_count_);
  for (int w = 0; w < wall_count_; ++w) wall_box(shapes_[w], position(w), corners(w), corner_count(w), wall_lo_[w], wall_hi_[w]);
}

void World::build_neighbour_list() {
  require_finite_state();
  // Every few thousand steps the bodies take the order of their place; the list keeps its pairs.
  if (settings_.order_bodies_by_place && steps_ >= next_ordering_step_) {
    order_bodies_by_place();
    next_ordering_step_ = steps_ + ordering_interval_steps;
  }
  std::vector<std::uint64_t>& old_neighbours = list_scratch_.old_neighbours;
  old_neighbours.swap(neighbours_);
  neighbours_.clear();
  neighbours_stale_ = false;
  ++neighbour_builds_;
  const double rest_margin = 0.5 * settings_.neighbour_skin_fraction * max_grain_radius_;
  const double lookahead = settings_.neighbour_lookahead_steps * settings_.time_step;
  const int n = body_count();
  listed_position_.resize(n);
  listed_margin_.resize(n);
  listed_angle_.resize(n);
  displacement_.resize(n);
#pragma omp parallel for schedule(static) if (n >= parallel_threshold)
  for (int i = 0; i < n; ++i) {
    listed_position_[i] = slot_position(i);
    listed_angle_[i] = motion_.d[0][3 * i + 2];
    listed_margin_[i] = is_wall(i) && slot_velocity(i).squaredNorm() == 0.0 ? 0.0 : rest_margin + slot_velocity(i).norm() * lookahead;
    displacement_[i] = 0.0;
  }

  // Walls against grains: bounding box of the wall, widened by both margins. Walls have the
  // lowest indices and slots, so these keys come first and in order.
  for (int w = 0; w < wall_count_; ++w) {
    Vec2 lo, hi;
    wall_box(shapes_[w], position(w), corners(w), corner_count(w), lo, hi);
    for (int i : active_slots_)
      if (circle_meets_box(motion_.d[0][3 * i], motion_.d[0][3 * i + 1],
                           geometry_[i].bounding_radius + listed_margin_[i] + listed_margin_[w], lo, hi))
        neighbours_.push_back(pair_key(w, i));
  }
  if (!active_slots_.empty()) list_grain_pairs(rest_margin);
  carry_pair_history(old_neighbours);
  index_pairs_by_body();
}

// Grains against grains: a cell list, with cells wide enough that two grains of the usual reach
// (bounding radius plus margin, a margin up to 1.5 times the rest margin) that are within reach
// of each other sit in the same or adjacent cells. Those pairs are listed per grain slot i (the
// pairs in which i is the lower body index, sorted by the other's slot), so concatenating the
// per-thread lists of consecutive blocks of slots gives the same sorted list whatever the thread
// count. The few grains of longer reach (moving fast) search
// as far as they reach; their pairs are sorted apart and merged in.
void World::list_grain_pairs(double rest_margin) {
  const double usual_reach = max_grain_radius_ + 1.5 * rest_margin;
  const auto reach = [this](int i) { return geometry_[i].bounding_radius + listed_margin_[i]; };
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY, longest_reach = 0.0;
  for (int i : active_slots_) {
    xmin = std::min(xmin, motion_.d[0][3 * i]);
    xmax = std::max(xmax, motion_.d[0][3 * i]);
    ymin = std::min(ymin, motion_.d[0][3 * i + 1]);
    ymax = std::max(ymax, motion_.d[0][3 * i + 1]);
    longest_reach = std::max(longest_reach, reach(i));
  }
  double h = 2.0 * usual_reach;
  // Keep the grid no larger than a few cells per grain, whatever the spread of the grains.
  const double max_cells = 4.0 * static_cast<double>(active_slots_.size()) + 1024.0;
  while (((xmax - xmin) / h + 1.0) * ((ymax - ymin) / h + 1.0) > max_cells) h *= 2.0;
  const int nx = static_cast<int>((xmax - xmin) / h) + 1, ny = static_cast<int>((ymax - ymin) / h) + 1;
  const int ncells = nx * ny;
  cell_start_.assign(ncells + 1, 0);
  body_cell_.resize(body_count());
  for (int i : active_slots_) {
    const int cx = static_cast<int>((motion_.d[0][3 * i] - xmin) / h);
    const int cy = static_cast<int>((motion_.d[0][3 * i + 1] - ymin) / h);
    body_cell_[i] = cy * nx + cx;
    ++cell_start_[body_cell_[i] + 1];
  }
  for (int c = 0; c < ncells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_bodies_.resize(active_slots_.size());
  {
    std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (int i : active_slots_) cell_bodies_[fill[body_cell_[i]]++] = i;  // ascending within a cell
  }
  const auto far_reaching = [&](int i) { return reach(i) > usual_reach; };
  // Visits every grain j of the cells within `range` cells of grain i's.
  const auto for_cells_around = [&](int i, int range, auto&& visit) {
    const int cx = body_cell_[i] % nx, cy = body_cell_[i] / nx;
    for (int y = std::max(cy - range, 0); y <= std::min(cy + range, ny - 1); ++y)
      for (int x = std::max(cx - range, 0); x <= std::min(cx + range, nx - 1); ++x) {
        const int c = y * nx + x;
        for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) visit(cell_bodies_[k]);
      }
  };
  const auto within_reach = [&](int i, int j) {
    const double dx = motion_.d[0][3 * j] - motion_.d[0][3 * i], dy = motion_.d[0][3 * j + 1] - motion_.d[0][3 * i + 1];
    const double r = reach(i) + reach(j);
    return dx * dx + dy * dy < r * r;
  };

  const int n_active = static_cast<int>(active_slots_.size());
  std::vector<ThreadPairs>& thread_pairs = list_scratch_.thread_pairs;
  if (thread_pairs.size() < static_cast<std::size_t>(max_thread_count())) thread_pairs.resize(max_thread_count());
  const std::size_t wall_pairs = neighbours_.size();
#pragma omp parallel if (n_active >= parallel_threshold)
  {
    const int nt = thread_count(), t = thread_number();
    std::vector<std::uint64_t>& local = thread_pairs[t].keys;
    local.clear();
    const int begin = static_cast<int>(static_cast<long long>(n_active) * t / nt);
    const int end = static_cast<int>(static_cast<long long>(n_active) * (t + 1) / nt);
    for (int idx = begin; idx < end; ++idx) {
      const int i = active_slots_[idx];
      if (far_reaching(i)) continue;
      const std::size_t first = local.size();
      // Each pair from the side of its lower body index, i's keys sorted by the other slot.
      for_cells_around(i, 1, [&](int j) {
        if (body_at_[j] > body_at_[i] && !far_reaching(j) && within_reach(i, j)) local.push_back(pair_key(i, j));
      });
      std::sort(local.begin() + first, local.end());
    }
    // The threads' lists one after the other, each copied by its thread.
#pragma omp barrier
#pragma omp single
    {
      std::size_t total = wall_pairs;
      for (int k = 0; k < nt; ++k) total += thread_pairs[k].keys.size();
      resize_with_room(neighbours_, total);
    }
    std::size_t offset = wall_pairs;
    for (int k = 0; k < t; ++k) offset += thread_pairs[k].keys.size();
    std::copy(local.begin(), local.end(), neighbours_.begin() + static_cast<std::ptrdiff_t>(offset));
  }

  // Pairs with a far-reaching grain, found from its side (from the lower slot if both are).
  std::vector<std::uint64_t> far;
  for (int i : active_slots_) {
    if (!far_reaching(i)) continue;
    const int range = static_cast<int>(std::ceil((reach(i) + longest_reach) / h));
    for_cells_around(i, range, [&](int j) {
      if (j == i || (far_reaching(j) && j < i) || !within_reach(i, j)) return;
      far.push_back(body_at_[i] < body_at_[j] ? pair_key(i, j) : pair_key(j, i));
    });
  }
  if (far.empty()) return;
  std::sort(far.begin(), far.end());
  const std::size_t grain_pairs_begin = static_cast<std::size_t>(
      std::find_if(neighbours_.begin(), neighbours_.end(), [this](std::uint64_t key) { return !is_wall(static_cast<int>(key >> 32)); }) -
      neighbours_.begin());
  std::vector<std::uint64_t>& merged = list_scratch_.merged;
  resize_with_room(merged, neighbours_.size() + far.size());
  const auto grain_pairs = neighbours_.begin() + static_cast<std::ptrdiff_t>(grain_pairs_begin);
  std::merge(grain_pairs, neighbours_.end(), far.begin(), far.end(), std::copy(neighbours_.begin(), grain_pairs, merged.begin()));
  neighbours_.swap(merged);
}

// What each pair of the new list carries over from the old one (both sorted by key): the
// contact and its spring, the narrow phase's hint. Contacts restored from a checkpoint take the
// place of the old list once.
void World::carry_pair_history(const std::vector<std::uint64_t>& old_neighbours) {
  const std::size_t n = neighbours_.size();
  std::vector<std::size_t>& earlier = list_scratch_.earlier;
  resize_with_room(earlier, n);
  if (!restored_contacts_.empty()) {
    std::fill(earlier.begin(), earlier.end(), no_pair);
  } else {
    // Both lists are sorted: each thread merges its part of the new list, from where its first
    // key stands in the old.
    const std::uint64_t *const fresh = neighbours_.data(), *const old_begin = old_neighbours.data(),
                               *const old_end = old_begin + old_neighbours.size();
#pragma omp parallel if (n >= static_cast<std::size_t>(parallel_threshold))
    {
      const std::size_t threads = static_cast<std::size_t>(thread_count()), thread = static_cast<std::size_t>(thread_number());
      const std::size_t begin = n * thread / threads, end = n * (thread + 1) / threads;
      const std::uint64_t* r = begin < end ? std::lower_bound(old_begin, old_end, fresh[begin]) : old_end;
      for (std::size_t q = begin; q < end; ++q) {
        while (r < old_end && *r < fresh[q]) ++r;
        earlier[q] = r < old_end && *r == fresh[q] ? static_cast<std::size_t>(r - old_begin) : no_pair;
      }
    }
  }
  reorder_pair_data(earlier);
  pair_apart_until_.assign(n, 0.0);  // the proofs count from the last build's places
  if (!restored_contacts_.empty()) {
    // The restored contacts name bodies: in slots, sorted as the list.
    std::vector<Contact> restored = std::move(restored_contacts_);
    restored_contacts_.clear();
    for (Contact& c : restored) c.a = slot_of_[c.a], c.b = slot_of_[c.b];
    std::sort(restored.begin(), restored.end(), [](const Contact& c, const Contact& d) { return c.key() < d.key(); });
    std::size_t r = 0;
    for (std::size_t q = 0; q < n; ++q) {
      while (r < restored.size() && restored[r].key() < neighbours_[q]) ++r;
      if (r < restored.size() && restored[r].key() == neighbours_[q]) {
        pair_contact_[q] = restored[r];
        pair_touching_[q] = 1;
        pair_swing_[q] = restored_swing(pair_key(body_at_[restored[r].a], body_at_[restored[r].b]));
      }
    }
    restored_swings_.clear();
  }
  contact_count_ = static_cast<std::size_t>(std::count(pair_touching_.begin(), pair_touching_.end(), 1));
}

// What each pair of the list carries from step to step (its contact and spring, whether it
// touched, the narrow phase's hint and proof), for the list in a new order: pair q takes what
// pair earlier[q] carried, or nothing where earlier[q] is no_pair.
void World::reorder_pair_data(const std::vector<std::size_t>& earlier) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(earlier.size());
  ListBuildScratch& next = list_scratch_;
  resize_with_room(next.contact, n);
  resize_with_room(next.touching, n);
  resize_with_room(next.swing, n);
  resize_with_room(next.hint, n);
  resize_with_room(next.apart_until, n);
#pragma omp parallel for schedule(static) if (n >= parallel_threshold)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const std::size_t old = earlier[q];
    const bool carried = old != no_pair;
    next.contact[q] = carried ? pair_contact_[old] : Contact{};
    next.touching[q] = carried ? pair_touching_[old] : 0;
    next.swing[q] = carried ? pair_swing_[old] : 0;
    next.hint[q] = carried ? pair_hint_[old] : OverlapHint{};
    next.apart_until[q] = carried ? pair_apart_until_[old] : 0.0;
  }
  pair_contact_.swap(next.contact);
  pair_touching_.swap(next.touching);
  pair_swing_.swap(next.swing);
  pair_hint_.swap(next.hint);
  pair_apart_until_.swap(next.apart_until);
}

// Each body's pairs in the order of their other body's index: the order in which a serial loop
// over the pairs sorted by body index would add their forces to it, whatever the slots.
void World::index_pairs_by_body() {
  const int bodies = body_count();
  const std::ptrdiff_t entries = 2 * static_cast<std::ptrdiff_t>(neighbours_.size());
  body_pair_start_.assign(bodies + 1, 0);
  for (std::uint64_t key : neighbours_) {
    ++body_pair_start_[static_cast<int>(key >> 32) + 1];
    ++body_pair_start_[static_cast<int>(key & 0xffffffffu) + 1];
  }
  for (int i = 0; i < bodies; ++i) body_pair_start_[i + 1] += body_pair_start_[i];
  resize_with_room(body_pairs_, entries);
  resize_with_room(pair_ends_, entries);
  resize_with_room(end_load_, entries);
  std::vector<int>& fill = list_scratch_.fill;
  fill.assign(body_pair_start_.begin(), body_pair_start_.end() - 1);
  for (std::size_t q = 0; q < neighbours_.size(); ++q) {
    body_pairs_[fill[static_cast<int>(neighbours_[q] >> 32)]++] = 2 * static_cast<int>(q);
    body_pairs_[fill[static_cast<int>(neighbours_[q] & 0xffffffffu)]++] = 2 * static_cast<int>(q) + 1;
  }
  // In key order each body's pairs run by the other body's slot; sort them by its index (a few
  // entries a body, mostly in order already). Then each pair's two entries, and zero loads: the
  // next pair loop writes those of the pairs that touch.
  const auto other_body = [this](int entry) {
    const std::uint64_t key = neighbours_[entry >> 1];
    return body_at_[static_cast<int>(entry & 1 ? key >> 32 : key & 0xffffffffu)];
  };
#pragma omp parallel if (entries >= parallel_threshold)
  {
#pragma omp for schedule(static)
    for (int i = 0; i < bodies; ++i)
      for (int k = body_pair_start_[i] + 1; k < body_pair_start_[i + 1]; ++k) {
        const int entry = body_pairs_[k], other = other_body(entry);
        int m = k;
        for (; m > body_pair_start_[i] && other_body(body_pairs_[m - 1]) > other; --m) body_pairs_[m] = body_pairs_[m - 1];
        body_pairs_[m] = entry;
      }
#pragma omp for schedule(static)
    for (std::ptrdiff_t k = 0; k < entries; ++k) {
      pair_ends_[body_pairs_[k]] = static_cast<int>(k);
      end_load_[k] = EndLoad{0.0, 0.0, 0.0};
    }
  }
}

// The pair loop. Like the step's other passes over the grains, it is compiled for AVX2 and for
// SSE2 (four_lanes.h), and the four-lane kernels (corner in edge, contact law) are inlined into
// it, so that their lanes go from the world's arrays straight into vector registers.
PILELAB_AVX2_AND_SSE2
void World::collide_and_compute_forces() {
  const std::size_t n = neighbours_.size();
  const ContactParameters& law = settings_.contact;
  const double dt = settings_.time_step;

  // The deepest overlap of this step: each thread's deepest, the pair of lower body indices
  // breaking ties, so the record is the same whatever the threads, the order they take the pairs
  // in and the slots.
  double step_deepest = 0.0;
  std::size_t step_deepest_pair = n, candidates = 0, touching_pairs = 0, proven_apart = 0;
  int step_longest_swing = 0;

  // The arrays the loop reads and writes, as plain pointers: the compiler cannot tell that the
  // stores into the pair arrays leave the vectors' own bookkeeping alone, and would reload it.
  const std::uint64_t* const pair_keys = neighbours_.data();
  const BodyGeometry* const geometry = geometry_.data();
  const double* const x = motion_.d[0].data();
  const double* const v = motion_.d[1].data();
  const double* const inv_mass = inv_mass_.data();
  const double* const inv_inertia = inv_inertia_.data();
  const Vec2* const world_vertices = world_vertices_.data();
  const Vec2* const wall_lo = wall_lo_.data();
  const Vec2* const wall_hi = wall_hi_.data();
  const int wall_count = wall_count_;
  const std::uint8_t* const wall_is_flat = wall_is_flat_.data();
  std::uint8_t* const pair_touching = pair_touching_.data();
  std::uint8_t* const pair_swing = pair_swing_.data();
  OverlapHint* const hints = pair_hint_.data();
  double* const apart_until = pair_apart_until_.data();
  const double* const displacement = displacement_.data();
  const bool skip_separated = settings_.skip_separated_pairs;
  Contact* const pair_contact = pair_contact_.data();
  const int* const pair_ends = pair_ends_.data();
  EndLoad* const end_load = end_load_.data();

  // Each thread's working arrays for a chunk, kept from step to step: no allocation in the step.
  if (chunk_scratch_.size() < static_cast<std::size_t>(max_thread_count())) {
    chunk_scratch_.resize(max_thread_count());
    for (ChunkScratch& c : chunk_scratch_) {
      c.overlaps.resize(pair_chunk);
      c.by_corner.resize(pair_chunk);
      c.others.resize(pair_chunk);
      c.touching.resize(pair_chunk);
    }
  }
  ChunkScratch* const chunk_scratch = chunk_scratch_.data();

  // Each listed pair is independent: test it, collide it and evaluate the contact law in place,
  // reading the spring it carried from the last step.
#pragma omp parallel if (n >= static_cast<std::size_t>(parallel_threshold)) reduction(+ : candidates, touching_pairs, proven_apart) \
    reduction(max : step_longest_swing)
  {
    double deepest = 0.0;
    std::size_t deepest_pair = n;
    // The overlap of polygon pair q the scalar way (convex_overlap.h), false if it does not
    // touch; a pair found apart is proven so until its grains have moved as far as the gap.
    const auto polygon_overlap = [&](std::size_t q, Overlap& o) __attribute__((always_inline)) -> bool {
      const int a = static_cast<int>(pair_keys[q] >> 32), b = static_cast<int>(pair_keys[q] & 0xffffffffu);
      const BodyGeometry& sa = geometry[a];
      const BodyGeometry& sb = geometry[b];
      const Vec2 pa(x[3 * a], x[3 * a + 1]), pb(x[3 * b], x[3 * b + 1]);
      const double longest_edge = std::max(sa.longest_edge, sb.longest_edge);
      o = overlap_polygons(world_vertices + sa.first_corner, sa.corner_count, pa, world_vertices + sb.first_corner,
                           sb.corner_count, pb, longest_edge, hints[q]);
      if (o.touching()) return true;
      if (skip_separated) {
        // The gap must stay above certain_separation, plus the round-off of the corners'
        // coordinates (a few ulp of their size, here bounded far above).
        const double moved = displacement[a] + displacement[b];
        const double size = std::abs(pa.x()) + std::abs(pa.y()) + std::abs(pb.x()) + std::abs(pb.y()) +
                            sa.bounding_radius + sb.bounding_radius;
        const double spare = o.gap - (certain_separation * longest_edge + 1e-12 * size);
        apart_until[q] = spare > moved ? spare - moved : 0.0;
      }
      return false;
    };
    // The exact broad-phase test of a listed pair: bounding circles, or a grain's circle against
    // a wall's box (the wall's pairs come first in the list, so that branch is foreseeable).
    const auto may_touch = [&](std::size_t q) __attribute__((always_inline)) -> bool {
      const int a = static_cast<int>(pair_keys[q] >> 32), b = static_cast<int>(pair_keys[q] & 0xffffffffu);
      const BodyGeometry& sb = geometry[b];
      const Vec2 pb(x[3 * b], x[3 * b + 1]);
      if (a < wall_count) return circle_meets_box(pb.x(), pb.y(), sb.bounding_radius, wall_lo[a], wall_hi[a]);
      const Vec2 pa(x[3 * a], x[3 * a + 1]);
      const double r = geometry[a].bounding_radius + sb.bounding_radius;
      return !((pb - pa).squaredNorm() >= r * r);  // a NaN distance goes on to the narrow phase, as before
    };
    // A polygon pair proven apart stays apart until its corners have moved as far as the gap
    // was. Between two steps they moved at most the sum of their displacements from the list's
    // build at both. Only a polygon pair is ever proven apart (polygon_overlap); any other keeps
    // the 0 of the list's build, which no displacement is below.
    const auto proven_apart_still = [&](std::size_t q) __attribute__((always_inline)) -> bool {
      const int a = static_cast<int>(pair_keys[q] >> 32), b = static_cast<int>(pair_keys[q] & 0xffffffffu);
      return displacement[a] + displacement[b] < apart_until[q];
    };
    // The overlap of a candidate pair the scalar way; false if it does not touch.
    const auto narrow = [&](std::size_t q, Overlap& o) __attribute__((always_inline)) -> bool {
      const int a = static_cast<int>(pair_keys[q] >> 32), b = static_cast<int>(pair_keys[q] & 0xffffffffu);
      const BodyGeometry& sa = geometry[a];
      const BodyGeometry& sb = geometry[b];
      const Vec2 pa(x[3 * a], x[3 * a + 1]), pb(x[3 * b], x[3 * b + 1]);
      if (!sa.is_disc && !sb.is_disc) return polygon_overlap(q, o);
      if (sa.is_disc && sb.is_disc) {
        o = overlap_discs(pa, sa.radius, pb, sb.radius);
      } else if (sa.is_disc) {
        o = overlap_disc_polygon(pa, sa.radius, world_vertices + sb.first_corner, sb.corner_count, pb);
      } else {
        o = overlap_disc_polygon(pb, sb.radius, world_vertices + sa.first_corner, sa.corner_count, pa);
        o.normal = -o.normal;
      }
      return o.touching();
    };

    // Each pair's touching flag ends the step as whether it touches now. A pair that stopped
    // touching has zero loads at its ends (it held some only while it touched).
    const auto no_contact = [&](std::size_t q) __attribute__((always_inline)) {
      if (pair_touching[q]) {
        pair_touching[q] = 0;
        end_load[pair_ends[2 * q]] = end_load[pair_ends[2 * q + 1]] = {0.0, 0.0, 0.0};
      }
    };
    // The contact law of four touching pairs q[0..3] (contact_law_x4), whose overlaps the caller
    // has put in the lanes of `in`; the lanes whose bit is set in `store` are kept: the pair's
    // contact, the loads at its two ends, its swing, its touching flag and the deepest overlap.
    // Whether a pair continues the last step's contact (and its spring) is the flag's old value.
    const auto apply_contact_law = [&](const std::size_t* q, unsigned store, ContactLanes& in) __attribute__((always_inline)) {
      ContactLaneForces out;
      int a[4], b[4];
      for (std::size_t lane = 0; lane < 4; ++lane)
        a[lane] = static_cast<int>(pair_keys[q[lane]] >> 32), b[lane] = static_cast<int>(pair_keys[q[lane]] & 0xffffffffu);
      in.centre_a_x = lanes_of([&](int k) { return x[3 * a[k]]; });
      in.centre_a_y = lanes_of([&](int k) { return x[3 * a[k] + 1]; });
      in.centre_b_x = lanes_of([&](int k) { return x[3 * b[k]]; });
      in.centre_b_y = lanes_of([&](int k) { return x[3 * b[k] + 1]; });
      in.velocity_a_x = lanes_of([&](int k) { return v[3 * a[k]]; });
      in.velocity_a_y = lanes_of([&](int k) { return v[3 * a[k] + 1]; });
      in.spin_a = lanes_of([&](int k) { return v[3 * a[k] + 2]; });
      in.velocity_b_x = lanes_of([&](int k) { return v[3 * b[k]]; });
      in.velocity_b_y = lanes_of([&](int k) { return v[3 * b[k] + 1]; });
      in.spin_b = lanes_of([&](int k) { return v[3 * b[k] + 2]; });
      in.inverse_mass_a = lanes_of([&](int k) { return inv_mass[a[k]]; });
      in.inverse_mass_b = lanes_of([&](int k) { return inv_mass[b[k]]; });
      in.inverse_inertia_a = lanes_of([&](int k) { return inv_inertia[a[k]]; });
      in.inverse_inertia_b = lanes_of([&](int k) { return inv_inertia[b[k]]; });
      const Double4 inner_a = lanes_of([&](int k) { return geometry[a[k]].inner_radius; });
      const Double4 inner_b = lanes_of([&](int k) { return geometry[b[k]].inner_radius; });
      in.lever_floor_a = 0.5 * inner_a;
      in.lever_floor_b = 0.5 * inner_b;
      in.a_has_no_lever = Mask4{a[0] < wall_count && wall_is_flat[a[0]], a[1] < wall_count && wall_is_flat[a[1]],
                                a[2] < wall_count && wall_is_flat[a[2]], a[3] < wall_count && wall_is_flat[a[3]]} *
                          -1;
      const Mask4 continues =
          Mask4{pair_touching[q[0]], pair_touching[q[1]], pair_touching[q[2]], pair_touching[q[3]]} != 0;
      const Double4 zero = {0.0, 0.0, 0.0, 0.0};
      in.old_spring = continues ? lanes_of([&](int k) { return pair_contact[q[k]].spring; }) : zero;
      in.old_normal_x = continues ? lanes_of([&](int k) { return pair_contact[q[k]].normal.x(); }) : zero;
      in.old_normal_y = continues ? lanes_of([&](int k) { return pair_contact[q[k]].normal.y(); }) : zero;
      // The force point: on the contact line, where the law places it (ForcePoint).
      if (law.force_point == ForcePoint::area_centroid) {
        in.point_x = in.point_x - in.centroid_shift * in.normal_y;
        in.point_y = in.point_y + in.centroid_shift * in.normal_x;
      }
      contact_law_lanes(law, dt, in, out);

      // The swing (SwingingContact): does the area's change reverse that of the last step? A
      // new contact's area grew from nothing (no reversal yet); the last step's area is still
      // in pair_contact where the contact continues.
      const Double4 last_area = continues ? lanes_of([&](int k) { return pair_contact[q[k]].area; }) : zero;
      const Double4 change = in.area - last_area;
      const Mask4 grew = ~continues | (change > 0.0);
      const Mask4 may_reverse = continues & (lane_abs(change) > SwingingContact::swing_floor * in.area);
      // The overlap is convex and the chord joins two points of its boundary, so no point of it
      // lies farther than 2 A / chord from the chord: a bound on how deep the contact cuts, over
      // the pair's smaller inner radius (the grain's, against a wall).
      const Mask4 has_chord = in.chord > 0.0;
      Double4 depth = 2.0 * in.area / in.chord;
      if (!(has_chord[0] & has_chord[1] & has_chord[2] & has_chord[3]))
        depth = has_chord ? depth : lane_sqrt(in.area);
      const Double4 inner = in.a_has_no_lever ? inner_b : lane_min(inner_a, inner_b);
      const Double4 fraction = depth / inner;

      for (std::size_t lane = 0; lane < 4; ++lane) {
        if (!(store >> lane & 1)) continue;
        Contact& ct = pair_contact[q[lane]];
        ct.a = a[lane];
        ct.b = b[lane];
        ct.spring = out.spring[lane];
        ct.point = Vec2(in.point_x[lane], in.point_y[lane]);
        ct.normal = Vec2(in.normal_x[lane], in.normal_y[lane]);
        ct.normal_force = out.normal[lane];
        ct.tangential_force = out.tangential[lane];
        ct.area = in.area[lane];
        ct.chord = in.chord[lane];
        const std::uint8_t grew_bit = grew[lane] ? 0x80 : 0, swing = pair_swing[q[lane]];
        const bool reverses = may_reverse[lane] && grew_bit != (swing & 0x80);
        const int swings = reverses ? std::min((swing & 0x7f) + 1, SwingingContact::longest_counted) : 0;
        pair_swing[q[lane]] = static_cast<std::uint8_t>(grew_bit | swings);
        step_longest_swing = std::max(step_longest_swing, swings);
        end_load[pair_ends[2 * q[lane] + 1]] = {out.force_x[lane], out.force_y[lane], out.torque_b[lane]};
        end_load[pair_ends[2 * q[lane]]] = {-out.force_x[lane], -out.force_y[lane], out.torque_a[lane]};
        if (fraction[lane] > deepest || (fraction[lane] == deepest && body_key(q[lane]) < body_key(deepest_pair))) {
          deepest = fraction[lane];
          deepest_pair = q[lane];
        }
        pair_touching[q[lane]] = 1;
        ++touching_pairs;
      }
    };

    // The pairs whose hint is a corner of one polygon in an edge of the other, four at a time
    // (two_crossing::corner_in_edge_lanes). The lanes the kernel proves touch go on in their
    // registers to the contact law; the others, and any whose hint does not fit its shapes, are
    // handed to unproven(q), for the scalar way. Returns how many it proved.
    const auto corner_in_edge_contacts = [&](const std::size_t* pairs, std::size_t count, auto&& unproven) __attribute__((always_inline)) -> std::size_t {
      two_crossing::CornerInEdgeOverlaps out;
      std::size_t proven_count = 0;
      for (std::size_t first = 0; first < count; first += 4) {
        const std::size_t lanes = std::min<std::size_t>(4, count - first);
        // Each lane's corner c with its neighbours p0 and p2, the edge e0 -> e1 and the centre of
        // the edge's polygon; then each coordinate as one vector of the four lanes' values.
        const Vec2 *p0[4], *c[4], *p2[4], *e0[4], *e1[4], *edge_polygon[4];
        std::size_t q[4];
        int centre[4], edge_polygon_count[4];
        double margin[4];
        std::int64_t corner_of_b[4];
        unsigned fits = 0;
        for (std::size_t lane = 0; lane < 4; ++lane) {
          q[lane] = pairs[first + std::min(lane, lanes - 1)];  // spare lanes repeat the last
          const int a = static_cast<int>(pair_keys[q[lane]] >> 32), b = static_cast<int>(pair_keys[q[lane]] & 0xffffffffu);
          const BodyGeometry& sa = geometry[a];
          const BodyGeometry& sb = geometry[b];
          const OverlapHint& hint = hints[q[lane]];
          const int i = hint.edge[0], k = hint.edge[1], j = hint.edge[2], l = hint.edge[3];
          // a's corner j after a's corner i, in b's edge k; or b's corner k after b's corner l, in
          // a's edge i (two_crossing_overlap). Chosen without a branch: either is as likely.
          const bool of_b = k != l;
          corner_of_b[lane] = of_b ? -1 : 0;
          const BodyGeometry& corner_body = of_b ? sb : sa;
          const BodyGeometry& edge_body = of_b ? sa : sb;
          const int before = of_b ? l : i, corner = of_b ? k : j, edge = of_b ? i : k;
          // The hint's edges exist and make that shape (the others go the scalar way, which
          // decides what they are); a lane that does not fit reads a point of nowhere instead
          // (its bodies may have no corners: a disc).
          static const Vec2 nowhere(0.0, 0.0);
          const bool fit = two_crossing::corner_in_edge_hint(hint, sa.corner_count, sb.corner_count);
          fits |= unsigned(fit) << lane;
          const int corner_count = corner_body.corner_count, edge_count = edge_body.corner_count;
          const Vec2* const corners = world_vertices + corner_body.first_corner;
          const Vec2* const edges = world_vertices + edge_body.first_corner;
          p0[lane] = fit ? &corners[before] : &nowhere, c[lane] = fit ? &corners[corner] : &nowhere;
          p2[lane] = fit ? &corners[two_crossing::next_index(corner, corner_count)] : &nowhere;
          e0[lane] = fit ? &edges[edge] : &nowhere, e1[lane] = fit ? &edges[two_crossing::next_index(edge, edge_count)] : &nowhere;
          edge_polygon[lane] = edges, edge_polygon_count[lane] = edge_count;
          centre[lane] = of_b ? a : b;
          margin[lane] = two_crossing::clear_margin * std::max(sa.longest_edge, sb.longest_edge);
        }
        two_crossing::CornerInEdgeBatch in;
        in.p0x = lanes_of([&](int k) { return p0[k]->x(); }), in.p0y = lanes_of([&](int k) { return p0[k]->y(); });
        in.cx = lanes_of([&](int k) { return c[k]->x(); }), in.cy = lanes_of([&](int k) { return c[k]->y(); });
        in.p2x = lanes_of([&](int k) { return p2[k]->x(); }), in.p2y = lanes_of([&](int k) { return p2[k]->y(); });
        in.e0x = lanes_of([&](int k) { return e0[k]->x(); }), in.e0y = lanes_of([&](int k) { return e0[k]->y(); });
        in.e1x = lanes_of([&](int k) { return e1[k]->x(); }), in.e1y = lanes_of([&](int k) { return e1[k]->y(); });
        in.qx = lanes_of([&](int k) { return x[3 * centre[k]]; }), in.qy = lanes_of([&](int k) { return x[3 * centre[k] + 1]; });
        in.margin = lanes_of([&](int k) { return margin[k]; });
        in.chord_reversed = Mask4{corner_of_b[0], corner_of_b[1], corner_of_b[2], corner_of_b[3]};
        two_crossing::corner_in_edge_lanes(in, out);
        unsigned proven = 0;
        for (std::size_t lane = 0; lane < lanes; ++lane) {
          bool ok = out.ok[lane];
          if (out.needs_polygon_test[lane] && (fits >> lane & 1))  // an oblique push: is the corner inside every edge?
            ok = two_crossing::clearly_inside({c[lane]->x(), c[lane]->y()}, edge_polygon[lane], edge_polygon_count[lane],
                                              margin[lane] * margin[lane]);
          proven |= unsigned(ok) << lane;
        }
        proven &= fits;
        for (std::size_t lane = 0; lane < lanes; ++lane)
          if (!(proven >> lane & 1)) unproven(q[lane]);
        if (proven == 0) continue;
        proven_count += static_cast<std::size_t>(__builtin_popcount(proven));
        ContactLanes law_in;
        law_in.area = out.area;
        law_in.chord = out.chord;
        law_in.point_x = out.point_x;
        law_in.point_y = out.point_y;
        law_in.centroid_shift = out.centroid_shift;
        law_in.normal_x = out.normal_x;
        law_in.normal_y = out.normal_y;
        apply_contact_law(q, proven, law_in);
      }
      return proven_count;
    };

    const std::size_t threads = static_cast<std::size_t>(thread_count()),
                      thread = static_cast<std::size_t>(thread_number());
    ChunkScratch& scratch = chunk_scratch[thread];
    Overlap* const overlaps = scratch.overlaps.data();
    std::size_t *const by_corner = scratch.by_corner.data(), *const others = scratch.others.data(),
                      *const touching = scratch.touching.data();
    // Each thread takes the pairs of a wall with one of the grains it moved and the pairs whose
    // lower body is one of them, so that it works on the bodies of one part of the pile, whose
    // corners it placed and whose sums it will form: a body's data then stays in one core's
    // cache, which matters most where the two cores share no cache. Its grains are the slots
    // first_slot to end_slot - 1; a wall's pairs come before the grains' and follow the slot of
    // their grain, so each wall's pairs with them are one run of the list.
    const auto start = Clock::now();
    const auto slot_at_cut = [&](std::size_t t) -> int {
      const int k = grain_cut(static_cast<int>(t), static_cast<int>(threads));
      return k == static_cast<int>(active_slots_.size()) ? body_count() : active_slots_[k];
    };
    const int first_slot = thread == 0 ? wall_count : slot_at_cut(thread), end_slot = slot_at_cut(thread + 1);
    const auto pairs_from = [&](int lower, int upper) -> std::size_t {
      return static_cast<std::size_t>(std::lower_bound(pair_keys, pair_keys + n, pair_key(lower, upper)) - pair_keys);
    };
    for (int lower = 0; lower <= wall_count; ++lower) {
      const bool of_wall = lower < wall_count;
      const std::size_t run_end = of_wall ? pairs_from(lower, end_slot) : pairs_from(end_slot, 0);
      for (std::size_t first = of_wall ? pairs_from(lower, first_slot) : pairs_from(first_slot, 0); first < run_end;
           first += pair_chunk) {
        const std::size_t last = std::min(run_end, first + pair_chunk);
        // The chunk's pairs pass through filters, each writing the list of those that pass on
        // without a branch (every pair is written, the count advanced if it passes): the outcome
        // of each test is close to a coin's toss, which the processor would mispredict.
        //
        // A pair whose last step left a corner of one grain in an edge of the other (by its hint)
        // goes to the four-lane kernel, the rest to the broad-phase test. A contact the kernel
        // proves needs no such test: the corner lies in both grains, so their bounding circles
        // meet, and a pair that touched is never proven apart.
        std::size_t corner_count = 0, other_count = 0;
        for (std::size_t q = first; q < last; ++q) {
          const OverlapHint& hint = hints[q];
          const bool corner_in_edge = two_crossing::corner_in_edge_shape(hint);
          by_corner[corner_count] = q;
          corner_count += corner_in_edge;
          others[other_count] = q;
          other_count += !corner_in_edge;
        }
        const std::size_t proven_by_corner =
            corner_in_edge_contacts(by_corner, corner_count, [&](std::size_t q) __attribute__((always_inline)) {
              others[other_count++] = q;
            });
        // The rest: candidates not proven apart (open, compacted in place) to the scalar narrow
        // phase, then the contact law of those that touch, four at a time.
        std::size_t open_count = 0, candidate_count = 0, proven_count = 0;
        for (std::size_t k = 0; k < other_count; ++k) {
          const std::size_t q = others[k];
          const bool candidate = may_touch(q), proven = proven_apart_still(q), open = candidate & !proven;
          if (!open) no_contact(q);  // rare for a pair that touched: a foreseeable branch
          others[open_count] = q;
          open_count += open;
          candidate_count += candidate;
          proven_count += candidate & proven;
        }
        candidates += candidate_count + proven_by_corner;
        proven_apart += proven_count;
        std::size_t touching_count = 0;
        for (std::size_t k = 0; k < open_count; ++k) {
          const std::size_t q = others[k];
          const bool touches = narrow(q, overlaps[q - first]);
          if (!touches) no_contact(q);
          touching[touching_count] = q;
          touching_count += touches;
        }
        for (std::size_t group = 0; group < touching_count; group += 4) {
          const std::size_t lanes = std::min<std::size_t>(4, touching_count - group);
          std::size_t q[4];
          for (std::size_t lane = 0; lane < 4; ++lane) q[lane] = touching[group + std::min(lane, lanes - 1)];
          ContactLanes in;
          in.area = lanes_of([&](int k) { return overlaps[q[k] - first].area; });
          in.chord = lanes_of([&](int k) { return overlaps[q[k] - first].chord; });
          in.point_x = lanes_of([&](int k) { return overlaps[q[k] - first].point.x(); });
          in.point_y = lanes_of([&](int k) { return overlaps[q[k] - first].point.y(); });
          in.centroid_shift = lanes_of([&](int k) { return overlaps[q[k] - first].centroid_shift; });
          in.normal_x = lanes_of([&](int k) { return overlaps[q[k] - first].normal.x(); });
          in.normal_y = lanes_of([&](int k) { return overlaps[q[k] - first].normal.y(); });
          apply_contact_law(q, (1u << lanes) - 1, in);
        }
      }
    }
    step_shares_.record(static_cast<int>(thread), static_cast<int>(threads), 0.0, seconds_since(start));
#pragma omp critical
    if (deepest > step_deepest || (deepest == step_deepest && body_key(deepest_pair) < body_key(step_deepest_pair))) {
      step_deepest = deepest;
      step_deepest_pair = deepest_pair;
    }
  }
  candidate_count_ = candidates;
  proven_apart_count_ = proven_apart;
  contact_count_ = touching_pairs;
  contacts_current_ = false;
  if (step_deepest > deepest_overlap_.fraction) {
    const Contact& ct = pair_contact_[step_deepest_pair];
    deepest_overlap_ = {step_deepest, time_ + dt, ct.point, body_at_[ct.a], body_at_[ct.b]};
  }
  // A longer swing than any before (rare: at most SwingingContact::longest_counted times a run):
  // the touching pair of lowest body key with that count, whatever the threads.
  if (step_longest_swing > longest_swing_.steps) {
    std::size_t first = n;
    for (std::size_t q = 0; q < n; ++q)
      if (pair_touching_[q] && (pair_swing_[q] & 0x7f) == step_longest_swing && (first == n || body_key(q) < body_key(first)))
        first = q;
    const Contact& ct = pair_contact_[first];
    longest_swing_ = {step_longest_swing, time_ + dt, ct.point, body_at_[ct.a], body_at_[ct.b]};
  }
}

// Each body's sum over its pairs in the order of their other body's index (the order of a
// serial loop over the pairs sorted by body index), so that the sums are the same whatever the threads; the pair loop gave the two ends
// of a pair opposite forces (Newton's third law). Pairs that do not touch carry zeros, which
// leave a sum unchanged. Then each grain's acceleration (paper eq. 1) and the corrector, and a
// check that the grain's state is still finite.
PILELAB_AVX2_AND_SSE2
void World::gather_and_correct() {
  const int* const pair_start = body_pair_start_.data();
  const EndLoad* const end_load = end_load_.data();
  double* const force_sum = contact_force_.data();
  const auto sum_over_pairs = [=](int i) {
    double fx = 0.0, fy = 0.0, torque = 0.0;
    for (int k = pair_start[i]; k < pair_start[i + 1]; ++k) {
      fx += end_load[k].fx;
      fy += end_load[k].fy;
      torque += end_load[k].torque;
    }
    force_sum[3 * i] = fx;
    force_sum[3 * i + 1] = fy;
    force_sum[3 * i + 2] = torque;
  };
  const Stepper stepper(settings_.scheme, settings_.time_step);
  const int n = static_cast<int>(active_slots_.size());
  const Vec2 g = settings_.gravity;
  int first_unstable = body_count();  // the first grain (by index) whose state is not finite
  // Each thread corrects the grains it moved.
#pragma omp parallel reduction(min : first_unstable) if (n >= parallel_threshold)
  {
    const auto start = Clock::now();
    const int begin = grain_cut(thread_number(), thread_count()), end = grain_cut(thread_number() + 1, thread_count());
    for (int k = begin; k < end; ++k) {
      const int i = active_slots_[k];
      sum_over_pairs(i);
      const double accel[3] = {contact_force_[3 * i] * inv_mass_[i] + g.x(), contact_force_[3 * i + 1] * inv_mass_[i] + g.y(),
                               contact_force_[3 * i + 2] * inv_inertia_[i]};
      stepper.correct(motion_, i, accel);
      // Any NaN or infinity makes the sum NaN or infinite (as in first_non_finite_grain); a
      // finite state whose sum overflows (values near 1e308) is reported too, which is no loss.
      const double* d0 = &motion_.d[0][3 * i];
      const double* d1 = &motion_.d[1][3 * i];
      const double sum = d0[0] + d0[1] + d0[2] + d1[0] + d1[1] + d1[2];
      if (!std::isfinite(sum) && body_at_[i] < first_unstable) first_unstable = body_at_[i];
    }
    step_shares_.record(thread_number(), thread_count(), 0.0, seconds_since(start));
  }
  step_shares_.update();
  for (int w = 0; w < wall_count_; ++w) sum_over_pairs(w);
  if (first_unstable == body_count()) return;
  std::ostringstream s;
  s << "the simulation became unstable at t = " << time_ + settings_.time_step << " s (step " << steps_ + 1
    << "): grain " << first_unstable
    << " has a non-finite position or velocity. Likely causes: a time step (" << settings_.time_step
    << " s) above the stability limit, or bodies placed overlapping deeply";
  throw std::runtime_error(s.str());
}

int World::grain_cut(int thread, int threads) const {
  const int n = static_cast<int>(active_slots_.size());
  const int blocks = (n + grain_block - 1) / grain_block;
  return std::min(n, grain_block * static_cast<int>(std::lround(blocks * step_shares_.begin(thread, threads))));
}

std::uint64_t World::body_key(std::size_t pair) const {
  if (pair >= neighbours_.size()) return ~std::uint64_t{0};  // no pair
  const std::uint64_t key = neighbours_[pair];
  return pair_key(body_at_[static_cast<int>(key >> 32)], body_at_[static_cast<int>(key & 0xffffffffu)]);
}

int World::first_non_finite_grain() const {
  int first = -1;
  for (int i : active_grains_) {
    const double* d0 = &motion_.d[0][3 * slot_of_[i]];
    const double* d1 = &motion_.d[1][3 * slot_of_[i]];
    // Any NaN or infinity makes the sum NaN or infinite (inf + -inf is NaN).
    const double sum = d0[0] + d0[1] + d0[2] + d1[0] + d1[1] + d1[2];
    if (!std::isfinite(sum) && (first < 0 || i < first)) first = i;
  }
  return first;
}

void World::require_finite_state() const {
  const int body = first_non_finite_grain();
  if (body < 0) return;
  const Vec2 x = position(body), v = velocity(body);
  char text[640];
  std::snprintf(text, sizeof text,
                "the DEM state is no longer finite at t = %.9g s (step %lld): body %d has position (%g, %g) m, angle "
                "%g rad, velocity (%g, %g) m/s, angular velocity %g rad/s (the first such body by index, not "
                "necessarily the first to go wrong). Usual causes: a time step above the stability limit "
                "(dem.integrator), or grains placed deeply overlapping",
                time(), static_cast<long long>(steps()), body, x.x(), x.y(), angle(body), v.x(), v.y(),
                angular_velocity(body));
  throw std::runtime_error(text);
}

double World::kinetic_energy() const {
  double e = 0.0;
  for (int i : active_grains_) {
    const Vec2 v = velocity(i);
    const double w = angular_velocity(i);
    e += 0.5 * mass(i) * v.squaredNorm() + 0.5 * inertia(i) * w * w;
  }
  return e;
}

}  // namespace pilelab::dem
