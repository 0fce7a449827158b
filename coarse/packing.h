#pragma once
// A static granular packing as coarse-graining sees it: grains (centre, mass, shape) and
// contacts (the pair, the contact point, the force). Built from a dem.h5 snapshot, or by hand
// in tests. Plain arrays, SI units; walls are not grains, but their contacts are kept.
#include <string>
#include <vector>

#include "dem/dem_file.h"
#include "dem/shape.h"
#include "dem/vec2.h"

namespace pilelab::coarse {

using dem::Vec2;

struct Grain {
  std::int64_t body = -1;        ///< body index in dem.h5 (identifies the grain across snapshots)
  Vec2 centre{0, 0};             ///< centre of mass [m]
  double angle = 0.0;            ///< [rad]
  double mass = 0.0;             ///< [kg]
  double area = 0.0;             ///< [m^2]
  const dem::Shape* shape = nullptr;  ///< outline in the body frame (null: a point grain)
  Vec2 residual_force{0, 0};     ///< sum of contact forces + weight [N]: zero in equilibrium
};

/// A contact between grain a and grain b, or between grain a and a wall (b = -1).
struct Contact {
  int a = -1, b = -1;            ///< indices into Packing::grains; b = -1 for a wall
  Vec2 point{0, 0};              ///< contact point [m]
  Vec2 force_on_a{0, 0};         ///< force exerted on grain a [N] (b feels the opposite)
};

struct Packing {
  std::string source;            ///< file and snapshot, for messages
  std::vector<Grain> grains;
  std::vector<Contact> contacts;
  Vec2 gravity{0, -9.81};        ///< [m/s^2]
  std::vector<dem::Shape> shapes;  ///< owned shapes the grains point into (from dem.h5)

  /// Index of each grain by body, or -1 (for mapping displacements between snapshots).
  std::vector<int> index_by_body() const;
};

/// The grains and contacts of a snapshot of dem.h5. Wall contacts keep their point and force.
Packing packing_from_snapshot(const dem::DemFile& file, const dem::Snapshot& snapshot);

/// Grain-centre displacements from `from` to `to`, grains matched by body: displacement[p] for
/// grain p of `from`, and moved[p] = 0 for grains missing from `to`.
void grain_displacements(const Packing& from, const Packing& to, std::vector<Vec2>& displacement,
                         std::vector<char>& moved);

/// Grain outline in the world frame (polygon corners; a disc gives an empty vector).
std::vector<Vec2> world_outline(const Grain& grain);

}  // namespace pilelab::coarse
