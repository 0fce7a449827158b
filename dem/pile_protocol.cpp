#include "dem/pile_protocol.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "common/error.h"
#include "common/portable_math.h"
#include "dem/grain_generator.h"

namespace pilelab::dem {

const char* phase_name(Phase p) {
  switch (p) {
    case Phase::pour: return "pour";
    case Phase::settle: return "settle";
    case Phase::ramp: return "gravity-ramp";
    case Phase::relax_settle: return "relax-settle";
    case Phase::done: return "done";
  }
  return "?";
}

namespace {
// Grain shapes come from their own stream, so that changing the pouring (positions, angles)
// never changes the grains themselves.
std::vector<Shape> draw_shapes(const DemScene& scene, const std::string& source) {
  Rng rng(scene.seed);
  std::vector<Shape> shapes;
  shapes.reserve(scene.grain_count);
  for (int i = 0; i < scene.grain_count; ++i) {
    try {
      shapes.push_back(random_grain(scene.grains, rng));
    } catch (const std::invalid_argument& e) {  // a size so small that the corners round together
      std::ostringstream s;
      s << source << ": dem.grains.mean_diameter_m = " << scene.grains.mean_diameter << " m gives grain " << i
        << " no usable shape (" << e.what() << "); expected a size well above the rounding of coordinates";
      throw InputError(s.str());
    }
  }
  return shapes;
}

// Values each in its own range can still combine to a world double precision cannot hold: a
// grain so light or small that its mass, inertia or time step underflows or overflows. Refused
// here, with the keys that set them, before the run could step with a NaN time step.
void check_grain_scales(const DemScene& scene, const std::vector<Shape>& shapes, const TimeStepBound& bound,
                        const std::string& source) {
  const auto usable = [](double v) { return std::isnormal(v) && v > 0.0; };
  bool ok = usable(bound.stable_limit) && usable(bound.omega_max);
  for (const Shape& g : shapes) {
    const double mass = scene.areal_density * g.area, inertia = scene.areal_density * g.polar_moment;
    ok = ok && usable(g.area) && usable(mass) && usable(inertia);
  }
  if (ok) return;
  std::ostringstream s;
  s.precision(4);
  s << source << ": dem.grains.mean_diameter_m = " << scene.grains.mean_diameter
    << " m, dem.grains.areal_density_kg_per_m2 = " << scene.areal_density
    << " and dem.contact.youngs_modulus_N_per_m = " << scene.contact.youngs_modulus
    << " give grains whose mass, moment of inertia or stable time step (" << bound.stable_limit
    << " s) is zero, infinite or NaN in double precision; expected physical scales (paper: 6.8e-3 m, 5000 "
       "kg/m^2, 1e7 N/m)";
  throw InputError(s.str());
}

WorldSettings world_settings(const DemScene& scene, const TimeStepBound& bound, const std::string& source) {
  WorldSettings w;
  w.contact = scene.contact;
  w.scheme = scene.scheme;
  w.gravity = Vec2(0.0, -scene.gravity);
  w.neighbour_skin_fraction = scene.neighbour_skin_fraction;
  if (scene.time_step > 0.0) {
    if (scene.time_step > bound.stable_limit && !scene.allow_unstable_time_step) {
      std::ostringstream s;
      s.precision(4);
      s << source << ": dem.integrator.time_step_s = " << scene.time_step << " s exceeds the stability limit "
        << bound.stable_limit << " s of the " << scheme_name(scene.scheme)
        << " integrator for these grains (stiffest contact: omega = " << bound.omega_max
        << " 1/s, damping ratio " << bound.damping_ratio
        << "); choose time_step_s <= the limit, leave it out for the default, or set "
           "dem.integrator.allow_unstable_time_step = true to run anyway";
      throw InputError(s.str());
    }
    w.time_step = scene.time_step;
  } else {
    w.time_step = scene.time_step_fraction * bound.stable_limit;
  }
  return w;
}
}  // namespace

RunDuration run_duration(const DemScene& scene) {
  const double pour = (scene.grain_count - 1) / scene.pour.rate;
  const SettleSpec& st = scene.settle;
  const int settlings = scene.relax.enabled ? 2 : 1;
  const double ramp = scene.relax.enabled ? scene.relax.ramp_time : 0.0;
  return {pour + settlings * st.min_time + ramp, pour + settlings * st.max_time + ramp};
}

double longest_time_after_pour(const DemScene& scene, const ProtocolState& state, double t) {
  const double settle = scene.settle.max_time, ramp = scene.relax.enabled ? scene.relax.ramp_time : 0.0;
  const double relax_settle = scene.relax.enabled ? settle : 0.0;
  const double in_phase = t - state.phase_start;
  double left = 0.0;
  switch (state.phase) {
    case Phase::pour: left = settle + ramp + relax_settle; break;
    case Phase::settle: left = settle - in_phase + ramp + relax_settle; break;
    case Phase::ramp: left = ramp - in_phase + settle; break;
    case Phase::relax_settle: left = settle - in_phase; break;
    case Phase::done: break;
  }
  return std::max(left, 0.0);
}

RunCost run_cost(const DemScene& scene, double time_step) {
  RunCost c;
  c.time_step = time_step;
  c.simulated = run_duration(scene);
  const double n = scene.grain_count, pour = (n - 1) / scene.pour.rate;
  // While pouring, the grains in the world grow at the rate: the grain-steps are the area under
  // n(t), n^2 / (2 rate), over the step; after it, all n grains step.
  const auto grain_steps = [&](double total) { return (n * n / (2.0 * scene.pour.rate) + n * (total - pour)) / time_step; };
  c.steps_shortest = c.simulated.shortest / time_step;
  c.steps_longest = c.simulated.longest / time_step;
  c.grain_steps_shortest = grain_steps(c.simulated.shortest);
  c.grain_steps_longest = grain_steps(c.simulated.longest);
  return c;
}

void check_run_length(const DemScene& scene, double time_step, const std::string& source) {
  const RunCost cost = run_cost(scene, time_step);
  const RunDuration d = cost.simulated;
  const double steps = cost.steps_shortest, grain_steps = cost.grain_steps_shortest;
  std::ostringstream s;
  s.precision(3);
  if (steps > max_run_steps || grain_steps > max_run_grain_steps) {
    s << source << ": this run would take at least " << steps << " time steps and " << grain_steps
      << " grain-steps if all grains are poured (" << d.shortest << " s of simulated time at dt = " << time_step << " s for " << scene.grain_count
      << " grains); expected at most " << max_run_steps << " steps and " << max_run_grain_steps
      << " grain-steps, which already take days to a year. Check dem.pour.rate_grains_per_s (" << scene.pour.rate
      << " grains/s), dem.settle.min_time_s, dem.relax.ramp_time_s and the time step (dem.integrator.time_step_s, "
         "or the grain size, density and stiffness that set its bound)";
    throw InputError(s.str());
  }
  // An interval below the step writes every step. Frames are two files each (grains and
  // contacts); checkpoints rewrite one file, each write costing a copy of the world.
  const OutputSpec& o = scene.output;
  const auto writes = [&](double interval) { return interval > 0.0 ? d.shortest / std::max(interval, time_step) : 0.0; };
  if (writes(o.frame_interval) > max_run_files) {
    s << source << ": dem.output.frame_interval_s = " << o.frame_interval << " s would write at least "
      << writes(o.frame_interval) << " frames (twice as many files) over " << d.shortest
      << " s of simulated time; expected at most " << max_run_files << ": a longer interval, or 0 for the last only";
    throw InputError(s.str());
  }
  if (writes(o.checkpoint_interval) > max_run_files) {
    s << source << ": dem.output.checkpoint_interval_s = " << o.checkpoint_interval << " s would write a checkpoint "
      << "at least " << writes(o.checkpoint_interval) << " times over " << d.shortest
      << " s of simulated time; expected at most " << max_run_files << ": a longer interval, or 0 for none";
    throw InputError(s.str());
  }
}

PileProtocol::PileProtocol(const DemScene& scene, const std::string& source)
    : scene_(scene), world_(WorldSettings{}), rng_(scene.seed ^ 0x5eed5eed5eed5eedULL) {
  std::vector<Shape> shapes = draw_shapes(scene, source);
  bound_ = stable_time_step(shapes, scene.areal_density, scene.contact, scene.scheme);
  check_grain_scales(scene, shapes, bound_, source);
  world_ = World(world_settings(scene, bound_, source));
  check_run_length(scene, world_.settings().time_step, source);
  build_container();
  first_grain_ = world_.body_count();
  for (const Shape& s : shapes) world_.add_grain(s, scene.areal_density);
  state_.rng = rng_.state();
}

TimeStepBound PileProtocol::time_step_bound_at_deepest_overlap() const {
  std::vector<Shape> grains;
  grains.reserve(world_.body_count() - first_grain_);
  for (int b = first_grain_; b < world_.body_count(); ++b) grains.push_back(world_.shape(b));
  return stable_time_step_at_depth(grains, scene_.areal_density, scene_.contact, scene_.scheme,
                                   world_.deepest_overlap().fraction);
}

void PileProtocol::build_container() {
  const ContainerSpec& c = scene_.container;
  auto rectangle = [](double w, double h) {
    return make_polygon({{-w / 2, -h / 2}, {w / 2, -h / 2}, {w / 2, h / 2}, {-w / 2, h / 2}});
  };
  // Ground plate: its top surface is y = 0.
  world_.add_wall(rectangle(c.plate_width, c.plate_thickness), {0.0, -c.plate_thickness / 2}, 0.0);
  if (c.side_walls) {
    const Shape wall = rectangle(c.plate_thickness, c.side_wall_height);
    for (double side : {-1.0, 1.0})
      world_.add_wall(wall, {side * (c.plate_width + c.plate_thickness) / 2, c.side_wall_height / 2}, 0.0);
  }
  const PourSpec& p = scene_.pour;
  if (p.funnel_walls && p.kind == PourKind::point_source) {
    // Two plates sloping at 60 degrees above the outlet; their lower ends leave a gap one grain
    // wider than the outlet on each side and sit one grain diameter above the insertion height,
    // so that no inserted grain overlaps them.
    const double d = scene_.grains.largest_diameter();
    const double length = std::max(4.0 * d, p.outlet_width), thick = 0.5 * d;
    const Shape plate = rectangle(length, thick);
    const double slope = M_PI / 3.0;
    for (double side : {-1.0, 1.0}) {
      const Vec2 lower_end(p.funnel_x + side * (p.outlet_width / 2 + d), p.funnel_height + d);
      const Vec2 centre = lower_end + 0.5 * length * Vec2(side * portable_cos(slope), portable_sin(slope));
      funnel_walls_.push_back(world_.add_wall(plate, centre, side * slope, {p.funnel_speed, 0.0}));
    }
  }
  base_bodies_ = {0};
  if (c.base == BaseKind::grains) lay_base_grains();
}

void PileProtocol::lay_base_grains() {
  // Grains drawn like the pile's from a stream of their own (the pour's is untouched), each
  // turned at random and set down on the plate, lowest point at y = 0, side by side from the
  // plate's left end with a gap of a hundredth of a grain, as many as fit.
  Rng rng(scene_.seed ^ 0xba5eba5eba5eba5eULL);
  const double half = 0.5 * scene_.container.plate_width, gap = 0.01 * scene_.grains.mean_diameter;
  double left = -half;
  while (true) {
    const Shape shape = random_grain(scene_.grains, rng);
    const double angle = 2.0 * M_PI * rng.uniform();
    double lo_x = -shape.radius, hi_x = shape.radius, lo_y = -shape.radius;
    if (shape.kind == ShapeKind::polygon) {
      lo_x = lo_y = INFINITY;
      hi_x = -INFINITY;
      double sine, cosine;
      portable_sincos(angle, sine, cosine);
      for (const Vec2& v : shape.vertices) {
        const Vec2 turned(cosine * v.x() - sine * v.y(), sine * v.x() + cosine * v.y());
        lo_x = std::min(lo_x, turned.x());
        hi_x = std::max(hi_x, turned.x());
        lo_y = std::min(lo_y, turned.y());
      }
    }
    if (left + (hi_x - lo_x) > half) break;
    base_bodies_.push_back(world_.add_fixed_grain(shape, {left - lo_x, -lo_y}, angle));
    left += (hi_x - lo_x) + gap;
  }
}

std::string PileProtocol::body_name(int body) const {
  std::string what = "a grain";
  if (body == 0) {
    what = "the plate";
  } else if (scene_.container.side_walls && (body == 1 || body == 2)) {
    what = body == 1 ? "the left side wall" : "the right side wall";
  } else if (body > 0 && std::binary_search(base_bodies_.begin(), base_bodies_.end(), body)) {
    what = "a grain of the base";
  } else if (!funnel_walls_.empty() && (body == funnel_walls_.front() || body == funnel_walls_.back())) {
    what = body == funnel_walls_.front() ? "the funnel's left plate" : "the funnel's right plate";
  }
  return what + " (body " + std::to_string(body) + ")";
}

bool PileProtocol::funnel_moving(double t) const {
  const PourSpec& p = scene_.pour;
  return p.funnel_speed != 0.0 && (p.funnel_travel == 0.0 || std::abs(p.funnel_speed) * t < p.funnel_travel);
}

double PileProtocol::funnel_x(double t) const {
  const PourSpec& p = scene_.pour;
  if (p.funnel_speed == 0.0) return p.funnel_x;
  double travel = std::abs(p.funnel_speed) * t;
  if (p.funnel_travel > 0.0) travel = std::min(travel, p.funnel_travel);
  return p.funnel_x + std::copysign(travel, p.funnel_speed);
}

double PileProtocol::kinetic_energy_per_grain() const {
  const auto n = world_.active_grains().size();
  return n ? world_.kinetic_energy() / static_cast<double>(n) : 0.0;
}

void PileProtocol::try_insert() {
  const double t = world_.time();
  if (state_.poured >= scene_.grain_count || t < state_.next_insert_time) return;
  const int body = first_grain_ + state_.poured;
  const PourSpec& p = scene_.pour;
  // Draw the exit point and orientation, then insert only if the grain's bounding circle is
  // clear of every other grain, so no insertion starts with an overlap.
  const Vec2 at(funnel_x(t) + p.release_width() * (rng_.uniform() - 0.5), p.funnel_height);
  const double angle = 2.0 * M_PI * rng_.uniform();
  state_.rng = rng_.state();
  const double r = world_.shape(body).bounding_radius;
  for (int j : world_.active_grains()) {
    const double reach = r + world_.shape(j).bounding_radius;
    if ((world_.position(j) - at).squaredNorm() < reach * reach) {
      // Blocked. If the outlet stays blocked (the pile has reached the funnel), stop pouring.
      if (t - state_.last_insert_time > 2.0 + 10.0 / p.rate) state_.pour_stalled = true;
      return;
    }
  }
  const double vx = funnel_moving(t) ? p.funnel_speed : 0.0;
  world_.activate(body, at, angle, {vx, -p.inflow_speed}, 0.0);
  ++state_.poured;
  state_.last_insert_time = t;
  state_.next_insert_time = std::max(state_.next_insert_time + 1.0 / p.rate, t);
}

void PileProtocol::check_state_is_finite() const { world_.require_finite_state(); }

double PileProtocol::energy_fed_in() const {
  const PourSpec& p = scene_.pour;
  const double u2 = p.funnel_speed * p.funnel_speed;
  // Per kilogram: at the outlet (u, -v_in) and the fall to the loss height; then a funnel wall
  // moving at u: 1/2 (2u)^2, what a grain at rest takes from one bounce. A moving grain can take
  // more, and bounces between the funnel and the pile add up; the factor energy_growth_limit
  // covers that at the scenes' funnel speeds (u^2 below 1e-4 of the fall), not at any speed.
  // The gravity ramp only lowers g, so the scene's g bounds it.
  const double per_kg = 0.5 * (u2 + p.inflow_speed * p.inflow_speed) + 2.0 * u2 +
                        scene_.gravity * (p.funnel_height - scene_.container.lost_below);
  double poured_mass = 0.0;
  for (int b = first_grain_; b < first_grain_ + state_.poured; ++b) poured_mass += world_.mass(b);
  return per_kg * poured_mass;
}

double PileProtocol::mechanical_energy(int grain) const {
  const Vec2 v = world_.velocity(grain);
  const double spin = world_.angular_velocity(grain), m = world_.mass(grain);
  return 0.5 * m * v.squaredNorm() + 0.5 * world_.inertia(grain) * spin * spin -
         m * world_.settings().gravity.dot(world_.position(grain) - Vec2(0.0, scene_.container.lost_below));
}

double PileProtocol::mechanical_energy() const {
  double energy = 0.0;
  for (int i : world_.active_grains()) energy += mechanical_energy(i);
  return energy;
}

void PileProtocol::check_energy_is_bounded() const {
  const double energy = mechanical_energy(), bound = energy_bound();
  if (!(energy > energy_growth_limit * bound)) return;
  int fastest = -1;
  double fastest_speed = -1.0;
  for (int i : world_.active_grains()) {
    const double speed = world_.velocity(i).norm();
    if (speed > fastest_speed) fastest = i, fastest_speed = speed;
  }
  char text[640];
  std::snprintf(text, sizeof text,
                "the DEM run creates energy at t = %.9g s (step %lld): the grains' kinetic and potential energy, "
                "%.4g J, exceeds %g times the most the pour can have put in (less what lost grains carried off), "
                "%.4g J; the fastest is %s at "
                "%.4g m/s. The explicit integration is unstable: the time step is above the stability limit "
                "(dem.integrator), or the contacts are stiffer than the step allows",
                world_.time(), static_cast<long long>(world_.steps()), energy, energy_growth_limit, bound,
                body_name(fastest).c_str(), fastest_speed);
  throw std::runtime_error(text);
}

void PileProtocol::check_contacts_are_stable() const {
  const SwingingContact& swing = world_.longest_swing();
  if (swing.steps < unstable_swing_steps) return;
  const double dt = world_.settings().time_step, limit = time_step_bound().stable_limit;
  char text[768];
  std::snprintf(text, sizeof text,
                "a contact oscillated with a period of two time steps, found at t = %.9g s (step %lld): up to "
                "t = %.9g s the overlap of %s and %s at x = %.4g m, y = %.4g m grew and shrank in turn %d%s steps in "
                "a row (a stable contact's oscillation spans more than two steps). The explicit integration is unstable for this contact: "
                "the time step, %.4g s, is %.3g times the stability limit %.4g s (dem.integrator), or the "
                "contacts are stiffer than the step allows",
                world_.time(), static_cast<long long>(world_.steps()), swing.time, body_name(swing.a).c_str(),
                body_name(swing.b).c_str(), swing.point.x(), swing.point.y(), swing.steps,
                swing.steps == SwingingContact::longest_counted ? " or more" : "", dt, dt / limit, limit);
  throw std::runtime_error(text);
}

void PileProtocol::remove_lost_grains() {
  std::vector<int> lost;
  for (int i : world_.active_grains())
    if (world_.position(i).y() < scene_.container.lost_below) lost.push_back(i);
  for (int i : lost) {
    // What it takes away (a little below the loss height, its potential energy is slightly
    // negative).
    state_.lost_energy += mechanical_energy(i);
    world_.deactivate(i);
  }
  state_.lost += static_cast<int>(lost.size());
}

void PileProtocol::finish_settling(const std::string& snapshot_name, Phase next) {
  snapshots_.push_back(take_snapshot(world_, snapshot_name));
  wall_placements_.push_back(take_wall_placement(world_));
  state_.phase = next;
  state_.phase_start = world_.time();
}

void PileProtocol::advance_phase() {
  const double t = world_.time(), in_phase = t - state_.phase_start;
  const SettleSpec& s = scene_.settle;
  const bool quiet = kinetic_energy_per_grain() < s.kinetic_energy_per_grain;
  const bool settled = (in_phase >= s.min_time && quiet) || in_phase >= s.max_time;
  switch (state_.phase) {
    case Phase::pour:
      if (state_.poured >= scene_.grain_count || state_.pour_stalled) {
        state_.phase = Phase::settle;
        state_.phase_start = t;
        for (int w : funnel_walls_) world_.set_wall_velocity(w, {0.0, 0.0});
      }
      break;
    case Phase::settle:
      if (settled) finish_settling("settled", scene_.relax.enabled ? Phase::ramp : Phase::done);
      break;
    case Phase::ramp:
      if (in_phase >= scene_.relax.ramp_time) {
        world_.set_gravity({0.0, -scene_.gravity * (1.0 - scene_.relax.gravity_reduction)});
        state_.phase = Phase::relax_settle;
        state_.phase_start = t;
      }
      break;
    case Phase::relax_settle:
      if (settled) finish_settling("relaxed", Phase::done);
      break;
    case Phase::done: break;
  }
}

void PileProtocol::step() {
  if (done()) return;
  if (state_.phase == Phase::pour) try_insert();
  if (state_.phase == Phase::ramp) {
    // A slow, linear reduction of g, so that the pile follows quasi-statically (paper 3.2).
    const double f = std::min(1.0, (world_.time() - state_.phase_start) / scene_.relax.ramp_time);
    world_.set_gravity({0.0, -scene_.gravity * (1.0 - f * scene_.relax.gravity_reduction)});
  }
  if (!funnel_walls_.empty() && !funnel_moving(world_.time()) && world_.velocity(funnel_walls_[0]).squaredNorm() > 0.0)
    for (int w : funnel_walls_) world_.set_wall_velocity(w, {0.0, 0.0});  // the funnel has arrived
  world_.step();
  if (world_.steps() % check_interval == 0) {
    check_state_is_finite();
    check_energy_is_bounded();  // before the losses, which would carry the evidence away
    check_contacts_are_stable();
    remove_lost_grains();
    advance_phase();
  }
}

void PileProtocol::restore(const ProtocolState& state, std::vector<Snapshot> snapshots,
                           std::vector<WallPlacement> walls) {
  state_ = state;
  rng_.set_state(state.rng);
  snapshots_ = std::move(snapshots);
  wall_placements_ = std::move(walls);
}

}  // namespace pilelab::dem
