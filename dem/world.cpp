#include "dem/world.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/portable_math.h"
#include "dem/convex_overlap.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pilelab::dem {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
// Below this many grains (or pairs) a parallel region costs more than it saves.
constexpr int parallel_threshold = 256;

// Inside a parallel region: this thread's consecutive block [begin, end) of n items, and the
// number of threads. Blocks in thread order cover 0..n in order.
struct ThreadBlock {
  std::size_t begin, end;
  int threads;
};
ThreadBlock this_threads_block(std::size_t n) {
  int nt = 1, t = 0;
#ifdef _OPENMP
  nt = omp_get_num_threads();
  t = omp_get_thread_num();
#endif
  return {n * t / nt, n * (t + 1) / nt, nt};
}
}  // namespace

World::World(const WorldSettings& settings) : settings_(settings) {}

int World::append_body(const Shape& shape, double mass, double inertia, bool active) {
  if (static_cast<int>(shape.vertices.size()) > max_polygon_corners)
    throw std::invalid_argument("World: polygons have at most 64 corners");
  const int id = body_count();
  shapes_.push_back(shape);
  mass_.push_back(mass);
  inertia_.push_back(inertia);
  inv_mass_.push_back(1.0 / mass);  // 0 for walls, whose mass is infinite
  inv_inertia_.push_back(1.0 / inertia);
  active_.push_back(active ? 1 : 0);
  motion_.resize(shapes_.size());
  contact_force_.resize(3 * shapes_.size(), 0.0);
  accel_.resize(3 * shapes_.size(), 0.0);
  vertex_offset_.push_back(vertex_offset_.back() + static_cast<int>(shape.vertices.size()));
  world_vertices_.resize(vertex_offset_.back());
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
  place_body(id);
  neighbours_stale_ = true;
  return id;
}

int World::add_grain(const Shape& shape, double areal_density) {
  const int id = append_body(shape, areal_density * shape.area, areal_density * shape.polar_moment, false);
  max_grain_radius_ = std::max(max_grain_radius_, shape.bounding_radius);
  return id;
}

void World::activate(int body, const Vec2& position, double angle, const Vec2& velocity, double angular_velocity) {
  if (is_wall(body) || active_[body]) throw std::logic_error("World::activate: not an inactive grain");
  for (auto& d : motion_.d) std::fill_n(d.begin() + 3 * body, 3, 0.0);
  motion_.d[0][3 * body] = position.x();
  motion_.d[0][3 * body + 1] = position.y();
  motion_.d[0][3 * body + 2] = angle;
  motion_.d[1][3 * body] = velocity.x();
  motion_.d[1][3 * body + 1] = velocity.y();
  motion_.d[1][3 * body + 2] = angular_velocity;
  // Start with the free-flight acceleration so the first predictor step is consistent.
  motion_.d[2][3 * body] = settings_.gravity.x();
  motion_.d[2][3 * body + 1] = settings_.gravity.y();
  active_[body] = 1;
  active_grains_.insert(std::upper_bound(active_grains_.begin(), active_grains_.end(), body), body);
  place_body(body);
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
  if (is_wall(body) || !active_[body]) return;
  active_[body] = 0;
  active_grains_.erase(std::lower_bound(active_grains_.begin(), active_grains_.end(), body));
  neighbours_stale_ = true;
  contacts_.erase(std::remove_if(contacts_.begin(), contacts_.end(),
                                 [&](const Contact& c) { return c.a == body || c.b == body; }),
                  contacts_.end());
}

void World::restore_activity(const std::vector<std::uint8_t>& active) {
  active_ = active;
  active_grains_.clear();
  for (int i = wall_count_; i < body_count(); ++i)
    if (active_[i]) active_grains_.push_back(i);
  moving_walls_.clear();
  for (int w = 0; w < wall_count_; ++w)
    if (velocity(w).squaredNorm() > 0) moving_walls_.push_back(w);
  for (int i = 0; i < body_count(); ++i)
    if (active_[i]) place_body(i);
  neighbours_stale_ = true;
}

void World::place_body(int body) {
  const Shape& s = shapes_[body];
  if (s.vertices.empty()) return;
  const double th = motion_.d[0][3 * body + 2];
  double sn, c;
  portable_sincos(th, sn, c);  // one reduction for both
  const Vec2 p(motion_.d[0][3 * body], motion_.d[0][3 * body + 1]);
  Vec2* out = &world_vertices_[vertex_offset_[body]];
  for (std::size_t k = 0; k < s.vertices.size(); ++k) out[k] = p + rotate(s.vertices[k], c, sn);
}

void World::step() {
  const double dt = settings_.time_step;
  auto t0 = Clock::now();
  predict(settings_.scheme, motion_, active_grains_, dt);
  for (int w : moving_walls_)  // prescribed motion: x += v dt
    for (int c = 0; c < 2; ++c) motion_.d[0][3 * w + c] += dt * motion_.d[1][3 * w + c];
  profile_.predict += seconds_since(t0);

  auto t1 = Clock::now();
  place_shapes();
  profile_.geometry += seconds_since(t1);

  auto t2 = Clock::now();
  find_candidate_pairs();
  profile_.broad_phase += seconds_since(t2);

  auto t3 = Clock::now();
  collide_and_compute_forces();
  profile_.narrow_phase += seconds_since(t3);

  auto t4 = Clock::now();
  // Newton (paper eq. 1): contact forces plus gravity.
  for (int i : active_grains_) {
    accel_[3 * i] = contact_force_[3 * i] * inv_mass_[i] + settings_.gravity.x();
    accel_[3 * i + 1] = contact_force_[3 * i + 1] * inv_mass_[i] + settings_.gravity.y();
    accel_[3 * i + 2] = contact_force_[3 * i + 2] * inv_inertia_[i];
  }
  correct(settings_.scheme, motion_, accel_, active_grains_, dt);
  time_ += dt;
  ++steps_;
  check_finite();
  profile_.correct += seconds_since(t4);
}

void World::check_finite() const {
  for (int i : active_grains_)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(motion_.d[0][3 * i + c]) || !std::isfinite(motion_.d[1][3 * i + c])) {
        std::ostringstream s;
        s << "the simulation became unstable at t = " << time_ << " s (step " << steps_ << "): grain " << i
          << " has a non-finite position or velocity. Likely causes: a time step (" << settings_.time_step
          << " s) above the stability limit, or bodies placed overlapping deeply";
        throw std::runtime_error(s.str());
      }
}

void World::place_shapes() {
  const int n = static_cast<int>(active_grains_.size());
#pragma omp parallel for schedule(static) if (n >= parallel_threshold)
  for (int k = 0; k < n; ++k) place_body(active_grains_[k]);
  for (int w : moving_walls_) place_body(w);
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
// other every step is what a Verlet list saves: it lists the pairs that come within a skin of
// being candidates, and stays valid while no body has moved more than half the skin since it
// was built (two bodies approach by at most the sum of their displacements). The candidates
// are then filtered from the list with the exact test, so they are the same pairs, in the
// same order, as a fresh search every step would give: no pair is ever missed, and the result
// does not depend on the skin or on when the list was rebuilt.
void World::find_candidate_pairs() {
  const double skin = settings_.neighbour_skin_fraction * max_grain_radius_;
  if (neighbours_stale_ || skin != listed_skin_ || neighbour_list_outdated()) build_neighbour_list(skin);

  wall_lo_.resize(wall_count_);
  wall_hi_.resize(wall_count_);
  for (int w = 0; w < wall_count_; ++w) wall_box(shapes_[w], position(w), corners(w), corner_count(w), wall_lo_[w], wall_hi_[w]);
  // The filter runs over consecutive blocks of the sorted list, one per thread, and the
  // blocks' survivors are joined in order: the candidates come out sorted whatever the threads.
  candidates_.clear();
  const std::size_t listed = neighbours_.size();
#pragma omp parallel if (listed >= 4 * static_cast<std::size_t>(parallel_threshold))
  {
    std::vector<std::uint64_t> local;
    const ThreadBlock block = this_threads_block(listed);
    for (std::size_t q = block.begin; q < block.end; ++q) {
      const std::uint64_t key = neighbours_[q];
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      const double xb = motion_.d[0][3 * b], yb = motion_.d[0][3 * b + 1], rb = shapes_[b].bounding_radius;
      bool near;
      if (is_wall(a)) {
        near = circle_meets_box(xb, yb, rb, wall_lo_[a], wall_hi_[a]);
      } else {
        const double dx = xb - motion_.d[0][3 * a], dy = yb - motion_.d[0][3 * a + 1];
        const double r = shapes_[a].bounding_radius + rb;
        near = dx * dx + dy * dy < r * r;
      }
      if (near) local.push_back(key);
    }
#pragma omp for ordered schedule(static, 1)
    for (int k = 0; k < block.threads; ++k) {
#pragma omp ordered
      candidates_.insert(candidates_.end(), local.begin(), local.end());
    }
  }
}

bool World::neighbour_list_outdated() const {
  double max_moved2 = 0.0;
  for (int i : active_grains_) max_moved2 = std::max(max_moved2, (position(i) - listed_position_[i]).squaredNorm());
  for (int w : moving_walls_) max_moved2 = std::max(max_moved2, (position(w) - listed_position_[w]).squaredNorm());
  return 4.0 * max_moved2 > listed_skin_ * listed_skin_;
}

void World::build_neighbour_list(double skin) {
  neighbours_.clear();
  listed_skin_ = skin;
  neighbours_stale_ = false;
  ++neighbour_builds_;
  listed_position_.resize(body_count());
  for (int i = 0; i < body_count(); ++i) listed_position_[i] = position(i);

  // Walls against grains: bounding box of the wall, widened by the skin. Walls have the lowest
  // indices, so these keys come first and in order.
  for (int w = 0; w < wall_count_; ++w) {
    Vec2 lo, hi;
    wall_box(shapes_[w], position(w), corners(w), corner_count(w), lo, hi);
    for (int i : active_grains_)
      if (circle_meets_box(motion_.d[0][3 * i], motion_.d[0][3 * i + 1], shapes_[i].bounding_radius + skin, lo, hi))
        neighbours_.push_back(pair_key(w, i));
  }
  if (active_grains_.empty()) return;

  // Grains against grains: a cell list with cells no smaller than the largest bounding
  // diameter plus the skin, so any two grains within the skin sit in the same or adjacent cells.
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
  for (int i : active_grains_) {
    xmin = std::min(xmin, motion_.d[0][3 * i]);
    xmax = std::max(xmax, motion_.d[0][3 * i]);
    ymin = std::min(ymin, motion_.d[0][3 * i + 1]);
    ymax = std::max(ymax, motion_.d[0][3 * i + 1]);
  }
  double h = 2.0 * max_grain_radius_ + skin;
  // Keep the grid no larger than a few cells per grain, whatever the spread of the grains.
  const double max_cells = 4.0 * static_cast<double>(active_grains_.size()) + 1024.0;
  while (((xmax - xmin) / h + 1.0) * ((ymax - ymin) / h + 1.0) > max_cells) h *= 2.0;
  const int nx = static_cast<int>((xmax - xmin) / h) + 1, ny = static_cast<int>((ymax - ymin) / h) + 1;
  const int ncells = nx * ny;
  cell_start_.assign(ncells + 1, 0);
  body_cell_.resize(body_count());
  for (int i : active_grains_) {
    const int cx = static_cast<int>((motion_.d[0][3 * i] - xmin) / h);
    const int cy = static_cast<int>((motion_.d[0][3 * i + 1] - ymin) / h);
    body_cell_[i] = cy * nx + cx;
    ++cell_start_[body_cell_[i] + 1];
  }
  for (int c = 0; c < ncells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_bodies_.resize(active_grains_.size());
  {
    std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (int i : active_grains_) cell_bodies_[fill[body_cell_[i]]++] = i;  // ascending within a cell
  }
  // Pairs are listed per grain i (j > i, sorted), so concatenating the per-thread lists of
  // consecutive blocks of grains gives the same sorted list whatever the thread count.
  const int n_active = static_cast<int>(active_grains_.size());
#pragma omp parallel if (n_active >= parallel_threshold)
  {
    std::vector<std::uint64_t> local;
#ifdef _OPENMP
    const int nt = omp_get_num_threads(), t = omp_get_thread_num();
#else
    const int nt = 1, t = 0;
#endif
    const int begin = static_cast<int>(static_cast<long long>(n_active) * t / nt);
    const int end = static_cast<int>(static_cast<long long>(n_active) * (t + 1) / nt);
    for (int idx = begin; idx < end; ++idx) {
      const int i = active_grains_[idx];
      const std::size_t first = local.size();
      const int cx = body_cell_[i] % nx, cy = body_cell_[i] / nx;
      const double xi = motion_.d[0][3 * i], yi = motion_.d[0][3 * i + 1], ri = shapes_[i].bounding_radius + skin;
      for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, ny - 1); ++y)
        for (int x = std::max(cx - 1, 0); x <= std::min(cx + 1, nx - 1); ++x) {
          const int c = y * nx + x;
          for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
            const int j = cell_bodies_[k];
            if (j <= i) continue;
            const double dx = motion_.d[0][3 * j] - xi, dy = motion_.d[0][3 * j + 1] - yi;
            const double r = ri + shapes_[j].bounding_radius;
            if (dx * dx + dy * dy < r * r) local.push_back(pair_key(i, j));
          }
        }
      std::sort(local.begin() + first, local.end());
    }
#pragma omp for ordered schedule(static, 1)
    for (int k = 0; k < nt; ++k) {
#pragma omp ordered
      neighbours_.insert(neighbours_.end(), local.begin(), local.end());
    }
  }
}

void World::collide_and_compute_forces() {
  const std::size_t n = candidates_.size();
  scratch_contacts_.resize(n);
  touching_.assign(n, 0);
  const ContactParameters& law = settings_.contact;
  const double dt = settings_.time_step;

  // The deepest overlap of this step: each thread's deepest, the smaller pair key breaking
  // ties, so the record is the same whatever the threads.
  double step_deepest = 0.0;
  std::size_t step_deepest_pair = n;

  // Each candidate pair is independent: collide and evaluate the contact law in parallel, each
  // thread over a consecutive block of the sorted candidates.
#pragma omp parallel if (n >= static_cast<std::size_t>(parallel_threshold))
  {
    const ThreadBlock block = this_threads_block(n);
    const std::size_t begin = block.begin, end = block.end;
    double deepest = 0.0;
    std::size_t deepest_pair = n;
    // The spring history of contacts that persist: both lists are sorted by key, so one search
    // finds where the block starts in the old contacts and a merge walk does the rest.
    std::size_t old = begin == end ? 0
                                 : std::lower_bound(contacts_.begin(), contacts_.end(), candidates_[begin],
                                                    [](const Contact& ct, std::uint64_t key) { return ct.key() < key; }) -
                                       contacts_.begin();
    for (std::size_t c = begin; c < end; ++c) {
      while (old < contacts_.size() && contacts_[old].key() < candidates_[c]) ++old;
      const bool persists = old < contacts_.size() && contacts_[old].key() == candidates_[c];
      const double old_spring = persists ? contacts_[old].spring : 0.0;
      const Vec2 old_normal = persists ? contacts_[old].normal : Vec2(0.0, 0.0);

      const int a = static_cast<int>(candidates_[c] >> 32), b = static_cast<int>(candidates_[c] & 0xffffffffu);
      const Shape& sa = shapes_[a];
      const Shape& sb = shapes_[b];
      const Vec2 pa = position(a), pb = position(b);
      Overlap o;
      if (sa.kind == ShapeKind::polygon && sb.kind == ShapeKind::polygon) {
        o = overlap_polygons(corners(a), corner_count(a), pa, corners(b), corner_count(b), pb,
                             std::max(sa.longest_edge, sb.longest_edge));
      } else if (sa.kind == ShapeKind::disc && sb.kind == ShapeKind::disc) {
        o = overlap_discs(pa, sa.radius, pb, sb.radius);
      } else if (sa.kind == ShapeKind::disc) {
        o = overlap_disc_polygon(pa, sa.radius, corners(b), corner_count(b), pb);
      } else {
        o = overlap_disc_polygon(pb, sb.radius, corners(a), corner_count(a), pa);
        o.normal = -o.normal;
      }
      if (!o.touching()) continue;

      const Vec2 ra = o.point - pa, rb = o.point - pb;
      const Vec2 ua = velocity(a) + cross(angular_velocity(a), ra);
      const Vec2 ub = velocity(b) + cross(angular_velocity(b), rb);
      const Vec2 t = perp(o.normal);
      ContactKinematics k;
      k.area = o.area;
      k.chord = o.chord;
      // A wall is flat on the grain's scale: its lever is infinite, so that l is the grain's lever
      // (the paper's formula for r_j -> infinity) wherever along the wall the grain touches, rather
      // than depending on the distance to the wall's centroid.
      k.lever_a = is_wall(a) ? INFINITY : std::max(ra.norm(), 0.5 * sa.inner_radius);
      k.lever_b = std::max(rb.norm(), 0.5 * sb.inner_radius);
      k.approach_speed = o.normal.dot(ua - ub);
      k.slip_speed = t.dot(ua - ub);
      k.normal_mass = 1.0 / (inv_mass_[a] + inv_mass_[b]);
      k.tangential_mass = 1.0 / (inv_mass_[a] + inv_mass_[b] + ra.squaredNorm() * inv_inertia_[a] +
                                 rb.squaredNorm() * inv_inertia_[b]);
      const double l = contact_length(law, k.lever_a, k.lever_b);
      // The spring is a vector in the contact plane: as the normal turns, keep its projection on
      // the new tangent (t_old . t_new = n_old . n_new); a contact that turned by more than 60
      // degrees in one step (a jump to another edge) starts afresh.
      const double turn = old_normal.dot(o.normal);
      const double spring = turn > 0.5 ? turn * old_spring : 0.0;
      const ContactForce f = dem::contact_force(law, k, l, spring, dt);

      Contact& out = scratch_contacts_[c];
      out.a = a;
      out.b = b;
      out.spring = f.spring;
      out.point = o.point;
      out.normal = o.normal;
      out.normal_force = f.normal;
      out.tangential_force = f.tangential;
      out.area = o.area;
      out.chord = o.chord;
      touching_[c] = 1;
      // The overlap is convex and the chord joins two points of its boundary, so no point of it
      // lies farther than 2 A / chord from the chord: a bound on how deep the contact cuts.
      const double depth = o.chord > 0.0 ? 2.0 * o.area / o.chord : std::sqrt(o.area);
      const double inner = is_wall(a) ? sb.inner_radius : std::min(sa.inner_radius, sb.inner_radius);
      const double fraction = depth / inner;
      if (fraction > deepest) {
        deepest = fraction;
        deepest_pair = c;
      }
    }
#pragma omp critical
    if (deepest > step_deepest || (deepest == step_deepest && deepest_pair < step_deepest_pair)) {
      step_deepest = deepest;
      step_deepest_pair = deepest_pair;
    }
  }
  if (step_deepest > deepest_overlap_.fraction) {
    const Contact& ct = scratch_contacts_[step_deepest_pair];
    deepest_overlap_ = {step_deepest, time_ + dt, ct.point, ct.a, ct.b};
  }

  // Gather: sum forces and torques on bodies in pair order (deterministic whatever the
  // threads), compacting the touching pairs in place into the new contact list.
  std::fill(contact_force_.begin(), contact_force_.end(), 0.0);
  std::size_t kept = 0;
  for (std::size_t c = 0; c < n; ++c) {
    if (!touching_[c]) continue;
    if (kept != c) scratch_contacts_[kept] = scratch_contacts_[c];
    const Contact& ct = scratch_contacts_[kept++];
    const Vec2 f = ct.force_on_b();
    const Vec2 ra = ct.point - position(ct.a), rb = ct.point - position(ct.b);
    contact_force_[3 * ct.a] -= f.x();
    contact_force_[3 * ct.a + 1] -= f.y();
    contact_force_[3 * ct.a + 2] -= cross(ra, f);
    contact_force_[3 * ct.b] += f.x();
    contact_force_[3 * ct.b + 1] += f.y();
    contact_force_[3 * ct.b + 2] += cross(rb, f);
  }
  scratch_contacts_.resize(kept);
  contacts_.swap(scratch_contacts_);
}

double World::kinetic_energy() const {
  double e = 0.0;
  for (int i : active_grains_) {
    const Vec2 v = velocity(i);
    const double w = angular_velocity(i);
    e += 0.5 * mass_[i] * v.squaredNorm() + 0.5 * inertia_[i] * w * w;
  }
  return e;
}

}  // namespace pilelab::dem
