#include "dem/dem_scene.h"

#include "common/error.h"

#include <cmath>
#include <sstream>

namespace pilelab::dem {

namespace {
[[noreturn]] void inconsistent(const std::string& source, const std::string& what) {
  throw InputError(source + ": " + what);
}

// Values each in range can still make an impossible experiment; say which keys clash.
void check_consistency(const DemScene& s, const std::string& source) {
  const double largest_radius = 0.5 * s.grains.largest_diameter();
  std::ostringstream m;
  m.precision(6);
  if (s.container.plate_thickness < s.grains.mean_diameter / 2) {
    m << "dem.container.plate_thickness_m = " << s.container.plate_thickness
      << " m is thinner than half a grain; expected at least " << s.grains.mean_diameter / 2 << " m";
    inconsistent(source, m.str());
  }
  if (s.pour.funnel_height < 2.0 * largest_radius) {
    m << "dem.pour.funnel_height_m = " << s.pour.funnel_height
      << " m: grains would be inserted into the plate; expected at least " << 2.0 * largest_radius << " m";
    inconsistent(source, m.str());
  }
  // Where the funnel ends: after its travel, or after pouring everything at the set rate.
  double end_x = s.pour.funnel_x;
  if (s.pour.funnel_speed != 0.0) {
    const double travel = s.pour.funnel_travel > 0.0 ? s.pour.funnel_travel
                                                     : std::abs(s.pour.funnel_speed) * s.grain_count / s.pour.rate;
    end_x += std::copysign(travel, s.pour.funnel_speed);
  }
  const double half = 0.5 * s.container.plate_width;
  for (double x : {s.pour.funnel_x, end_x})
    if (std::abs(x) + 0.5 * s.pour.release_width() >= half) {
      const double edge = x + std::copysign(0.5 * s.pour.release_width(), x == 0.0 ? 1.0 : x);
      m << "grains are released out to x = " << edge << " m (the "
        << (s.pour.kind == PourKind::rain ? "rain's edge: dem.pour.rain_width_m" : "outlet's edge: dem.pour.outlet_width_m")
        << " about x = " << x << " m, from dem.pour.funnel_x_m, funnel_speed_m_per_s, funnel_travel_m)"
        << " but the plate ends at +-" << half << " m (dem.container.plate_width_m)";
      inconsistent(source, m.str());
    }
  if (s.settle.min_time > s.settle.max_time) {
    m << "dem.settle.min_time_s = " << s.settle.min_time << " s exceeds dem.settle.max_time_s = " << s.settle.max_time
      << " s";
    inconsistent(source, m.str());
  }
  if (s.contact.friction_mu > 0.0 && s.contact.tangential_stiffness_ratio == 0.0)
    inconsistent(source, "dem.contact.tangential_stiffness_ratio = 0 with friction_mu > 0 would remove friction; "
                         "expected a positive ratio (paper: 2/7)");
}
}  // namespace

DemScene read_dem_scene(SceneReader& r) {
  DemScene s;
  s.seed = static_cast<std::uint64_t>(r.get_int("dem.seed", 1, 0, INT64_MAX));
  s.grain_count = static_cast<int>(r.get_int("dem.grain_count", s.grain_count, 1, 2'000'000));
  s.areal_density = r.get_double("dem.areal_density_kg_per_m2", s.areal_density, Range::positive());
  s.gravity = r.get_double("dem.gravity_m_per_s2", s.gravity, Range::positive());

  GrainSpec& g = s.grains;
  const std::string shape = r.get_choice("dem.grains.shape", "polygon", {"polygon", "disc"});
  g.kind = shape == "disc" ? ShapeKind::disc : ShapeKind::polygon;
  const std::string outline = r.get_choice("dem.grains.outline", "ellipse", {"ellipse", "circle"});
  g.outline = outline == "circle" ? GrainOutline::circle : GrainOutline::ellipse;
  g.corners_min = static_cast<int>(r.get_int("dem.grains.corners_min", g.corners_min, 3, 64));
  g.corners_max = static_cast<int>(r.get_int("dem.grains.corners_max", g.corners_max, 3, 64));
  if (g.corners_max < g.corners_min)
    throw InputError(r.source() + ": dem.grains.corners_max: " + std::to_string(g.corners_max) +
                     " is below dem.grains.corners_min = " + std::to_string(g.corners_min));
  g.mean_diameter = r.get_double("dem.grains.mean_diameter_m", g.mean_diameter, Range::positive());
  g.polydispersity = r.get_double("dem.grains.polydispersity", g.polydispersity, Range::closed(0.0, 0.9));
  g.corner_jitter = r.get_double("dem.grains.corner_jitter", g.corner_jitter, {0.0, 0.45, false});
  const std::string placement = r.get_choice("dem.grains.corner_placement", "jittered", {"jittered", "random"});
  g.corner_placement = placement == "random" ? CornerPlacement::random : CornerPlacement::jittered;
  g.corner_min_gap = r.get_double("dem.grains.corner_min_gap", g.corner_min_gap, {0.0, 0.9, false});

  ContactParameters& c = s.contact;
  c.youngs_modulus = r.get_double("dem.contact.youngs_modulus_N_per_m", c.youngs_modulus, Range::positive());
  c.damping_gamma = r.get_double("dem.contact.damping_gamma", c.damping_gamma, {0.0, 10.0, false});
  c.friction_mu = r.get_double("dem.contact.friction_mu", c.friction_mu, {0.0, 10.0, false});
  c.tangential_stiffness_ratio =
      r.get_double("dem.contact.tangential_stiffness_ratio", c.tangential_stiffness_ratio, {0.0, 10.0, false});
  const std::string length = r.get_choice("dem.contact.contact_length", "paper", {"paper", "book"});
  c.contact_length = length == "book" ? ContactLength::book : ContactLength::paper;
  const std::string history = r.get_choice("dem.contact.tangential_history", "spring", {"spring", "total"});
  c.tangential_history = history == "total" ? TangentialHistory::total : TangentialHistory::spring;
  const std::string point = r.get_choice("dem.contact.force_point", "area_centroid", {"area_centroid", "chord_midpoint"});
  c.force_point = point == "chord_midpoint" ? ForcePoint::chord_midpoint : ForcePoint::area_centroid;

  s.scheme = scheme_from_name(r.get_choice("dem.integrator.scheme", "leapfrog", {"gear5", "verlet", "leapfrog"}));
  s.time_step = r.get_double("dem.integrator.time_step_s", 0.0, Range::at_least(0.0));
  s.time_step_fraction = r.get_double("dem.integrator.time_step_fraction", s.time_step_fraction, {0.0, 1.0, true});
  s.allow_unstable_time_step = r.get_bool("dem.integrator.allow_unstable_time_step", false);
  s.neighbour_skin_fraction =
      r.get_double("dem.integrator.neighbour_skin_fraction", s.neighbour_skin_fraction, {0.0, 10.0, true});

  ContainerSpec& k = s.container;
  k.base = r.get_choice("dem.container.base", "flat", {"flat", "grains"}) == "grains" ? BaseKind::grains : BaseKind::flat;
  k.plate_width = r.get_double("dem.container.plate_width_m", k.plate_width, Range::positive());
  k.plate_thickness = r.get_double("dem.container.plate_thickness_m", k.plate_thickness, Range::positive());
  k.side_walls = r.get_bool("dem.container.side_walls", k.side_walls);
  k.side_wall_height = r.get_double("dem.container.side_wall_height_m", k.side_wall_height, Range::positive());
  k.lost_below = r.get_double("dem.container.lost_below_m", k.lost_below, {-1e3, 0.0, false});

  PourSpec& p = s.pour;
  const std::string kind = r.get_choice("dem.pour.kind", "point_source", {"point_source", "rain"});
  p.kind = kind == "rain" ? PourKind::rain : PourKind::point_source;
  if (p.kind == PourKind::rain) p.rain_width = r.require_double("dem.pour.rain_width_m", Range::positive());
  p.funnel_height = r.get_double("dem.pour.funnel_height_m", p.funnel_height, Range::positive());
  p.funnel_x = r.get_double("dem.pour.funnel_x_m", p.funnel_x, Range());
  p.funnel_speed = r.get_double("dem.pour.funnel_speed_m_per_s", p.funnel_speed, {-10.0, 10.0, false});
  p.funnel_travel = r.get_double("dem.pour.funnel_travel_m", p.funnel_travel, Range::at_least(0.0));
  p.inflow_speed = r.get_double("dem.pour.inflow_speed_m_per_s", p.inflow_speed, {0.0, 100.0, false});
  p.rate = r.get_double("dem.pour.rate_grains_per_s", p.rate, Range::positive());
  p.outlet_width = r.get_double("dem.pour.outlet_width_m", p.outlet_width, Range::at_least(0.0));
  p.funnel_walls = r.get_bool("dem.pour.funnel_walls", p.kind == PourKind::point_source);
  if (p.kind == PourKind::rain && p.funnel_walls)
    throw InputError(r.source() + ": dem.pour.funnel_walls = true: a rain has no funnel; expected false or no key");

  SettleSpec& st = s.settle;
  st.kinetic_energy_per_grain =
      r.get_double("dem.settle.kinetic_energy_per_grain_J", st.kinetic_energy_per_grain, Range::positive());
  st.min_time = r.get_double("dem.settle.min_time_s", st.min_time, Range::at_least(0.0));
  st.max_time = r.get_double("dem.settle.max_time_s", st.max_time, Range::positive());
  st.must_settle = r.get_bool("dem.settle.must_settle", st.must_settle);

  RelaxSpec& rl = s.relax;
  rl.enabled = r.get_bool("dem.relax.enabled", rl.enabled);
  rl.gravity_reduction = r.get_double("dem.relax.gravity_reduction", rl.gravity_reduction, {0.0, 0.99, true});
  rl.ramp_time = r.get_double("dem.relax.ramp_time_s", rl.ramp_time, Range::positive());

  OutputSpec& o = s.output;
  o.frame_interval = r.get_double("dem.output.frame_interval_s", o.frame_interval, Range::at_least(0.0));
  o.checkpoint_interval = r.get_double("dem.output.checkpoint_interval_s", o.checkpoint_interval, Range::at_least(0.0));
  o.progress_interval = r.get_double("dem.output.progress_interval_s", o.progress_interval, Range::positive());
  check_consistency(s, r.source());
  return s;
}

}  // namespace pilelab::dem
