#pragma once
// The [dem] part of a scene file: every parameter of a pile simulation, in SI units named in
// the keys (see docs/SCENES.md for the full table with defaults and ranges).
#include <cstdint>
#include <string>

#include "common/scene_reader.h"
#include "dem/contact_law.h"
#include "dem/grain_generator.h"
#include "dem/integrator.h"

namespace pilelab::dem {

/// What the pile stands on: the flat plate, or a row of immobile grains laid on it (the paper's
/// base of "specially shaped particles"), drawn like the pile's grains.
enum class BaseKind { flat, grains };

struct ContainerSpec {
  BaseKind base = BaseKind::flat;
  double plate_width = 2.0;        ///< ground plate length [m]; its top surface is y = 0
  double plate_thickness = 0.02;   ///< [m]
  bool side_walls = false;         ///< vertical walls at both plate ends
  double side_wall_height = 0.3;   ///< [m]
  double lost_below = -0.1;        ///< grains whose centre falls below this y are removed [m]
};

/// How grains enter: from a funnel's outlet (a point source, the paper's), or as a uniform rain
/// over a width (the construction history that Vanel et al. 1999 found gives no dip).
enum class PourKind { point_source, rain };

struct PourSpec {
  PourKind kind = PourKind::point_source;
  double rain_width = 0.0;           ///< rain: grains released at random x across this width, centred on funnel_x [m]
  double funnel_height = 0.5;        ///< outlet (or rain) height above the plate [m] (paper: 0.5)
  double funnel_x = 0.0;             ///< outlet position at t = 0 [m]
  double funnel_speed = 0.0;         ///< sideways funnel speed [m/s]; 0: symmetric pile
  double funnel_travel = 0.0;        ///< the funnel stops after moving this far [m]; 0: no limit
  double inflow_speed = 0.2;         ///< downward speed of grains leaving the outlet [m/s] (paper: 0.2)
  double rate = 100.0;               ///< grains per second (at most; a blocked outlet waits)
  double outlet_width = 0.03;        ///< grains leave at a random point across this width [m]
  bool funnel_walls = true;          ///< immobile funnel walls above the outlet (a point source only)
  /// The width across which grains are released [m]: the outlet's, or the rain's.
  double release_width() const { return kind == PourKind::rain ? rain_width : outlet_width; }
};

struct SettleSpec {
  double kinetic_energy_per_grain = 1e-7;  ///< settled when mean kinetic energy per grain is below [J]
  double min_time = 0.2;                   ///< settle at least this long [s]
  double max_time = 5.0;                   ///< stop settling after this long even if not settled [s]
  bool must_settle = true;                 ///< a pile that does not settle fails `pilelab run` (else: a warning)
};

struct RelaxSpec {
  bool enabled = false;            ///< run the gravity reduction (needed for strains)
  double gravity_reduction = 0.1;  ///< fraction by which g is reduced (paper: 0.1)
  double ramp_time = 0.5;          ///< g changes linearly over this time [s]
};

struct OutputSpec {
  double frame_interval = 0.5;       ///< simulated time between VTK frames [s]; 0: none
  double checkpoint_interval = 2.0;  ///< simulated time between checkpoints [s]; 0: none
  double progress_interval = 2.0;    ///< wall-clock seconds between progress lines
};

struct DemScene {
  std::uint64_t seed = 1;
  int grain_count = 500;
  double areal_density = 5000.0;  ///< [kg/m^2] (paper: 5000)
  double gravity = 9.81;          ///< [m/s^2]
  GrainSpec grains;
  ContactParameters contact;
  Scheme scheme = Scheme::leapfrog;
  double time_step = 0.0;             ///< [s]; 0: time_step_fraction of the stability limit
  double time_step_fraction = 0.8;    ///< default dt as a fraction of the stable limit
  bool allow_unstable_time_step = false;
  /// Verlet-list skin over the largest grain's bounding radius (WorldSettings): speed only.
  double neighbour_skin_fraction = 0.3;
  ContainerSpec container;
  PourSpec pour;
  SettleSpec settle;
  RelaxSpec relax;
  OutputSpec output;
};

/// Reads [dem] (all keys optional; defaults above) and checks ranges. Unknown keys are
/// reported by the caller's SceneReader::reject_unknown.
DemScene read_dem_scene(SceneReader& reader);

}  // namespace pilelab::dem
