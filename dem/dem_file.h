#pragma once
// OUT/dem.h5: the result of a DEM run, for coarse/ and for people with h5py. The scene text,
// the run's settings, every body's shape and mass, and named snapshots (grain states and the
// contact network). Layout, units and sign conventions: docs/FORMAT.md, section "dem.h5".
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dem/shape.h"
#include "dem/snapshot.h"
#include "dem/world.h"

namespace pilelab::dem {

constexpr const char* dem_file_format = "pilelab-dem";
constexpr std::int64_t dem_file_format_version = 1;

/// Where the walls (bodies 0..w-1) were at one instant. Walls may move (a funnel moving sideways
/// at a prescribed velocity), so each snapshot stores its own wall placement.
struct WallPlacement {
  std::vector<double> position;  ///< (w, 2) centroid [m]
  std::vector<double> angle;     ///< (w) [rad]
  std::vector<double> velocity;  ///< (w, 2) prescribed velocity [m/s]
};

/// The walls' placement now; take it together with take_snapshot() when walls can change
/// their velocity during a run.
WallPlacement take_wall_placement(const World& world);

/// Writes dem.h5 atomically. walls[k] is the wall placement at the time of snapshots[k].
/// run_info must be a flat JSON object (key -> number, string or bool); it becomes the
/// attributes of /run. Throws std::invalid_argument for a snapshot name that is empty,
/// repeated or contains ',' or '/', or for a walls vector of the wrong size; InputError if
/// the file cannot be written.
void write_dem_file(const std::string& path, const std::string& scene_text, const World& world,
                    const std::vector<Snapshot>& snapshots, const std::vector<WallPlacement>& walls,
                    const nlohmann::json& run_info);

/// As above, with each snapshot's wall placement reconstructed from the walls' state now:
/// position - velocity * (world.time() - snapshot.time). Exact for fixed walls; for walls that
/// kept one velocity it differs from the stepped position only by rounding. Wrong for a wall
/// whose velocity changed after a snapshot was taken (a funnel that stopped: the snapshot gets
/// the final position); such runs must use the overload with explicit placements.
void write_dem_file(const std::string& path, const std::string& scene_text, const World& world,
                    const std::vector<Snapshot>& snapshots, const nlohmann::json& run_info);

/// dem.h5 read back. The bodies are read at once; snapshots are read on demand, since a long
/// run can store many.
struct DemFile {
  std::string path;
  std::string scene_text;
  std::vector<Shape> shapes;  ///< per body; vertices, radius, area, bounding_radius as stored,
                              ///< polar_moment, inner_radius and longest_edge recomputed
  std::vector<std::int64_t> is_wall;         ///< per body, 0/1; walls are bodies 0..wall_count-1
  std::vector<double> mass;                  ///< per body [kg]; 0 means immobile (a wall)
  std::vector<double> moment_of_inertia;     ///< per body [kg m^2]; 0 for walls
  std::vector<std::string> snapshot_names;   ///< in the order they were written

  int body_count() const { return static_cast<int>(shapes.size()); }
  int wall_count() const;
  bool has_snapshot(const std::string& name) const;

  /// The named snapshot; InputError naming the file and the dataset if anything is missing or
  /// has the wrong shape, or if the name is not in the file.
  Snapshot snapshot(const std::string& name) const;
  /// The walls' placement at the named snapshot.
  WallPlacement walls(const std::string& name) const;

  /// Attributes of /run, e.g. run_int("seed"), run_number("time_step_s"), run_string("integrator").
  double run_number(const std::string& key) const;
  std::int64_t run_int(const std::string& key) const;
  std::string run_string(const std::string& key) const;
};

/// Reads the header and bodies of dem.h5. Throws InputError naming the file (and the dataset
/// or attribute) if the file is missing, is not HDF5, is not a pilelab-dem file of a version
/// this build reads, or has a missing or ill-shaped dataset.
DemFile read_dem_file(const std::string& path);

}  // namespace pilelab::dem
