#pragma once
// A named picture of the world at one instant, as written to dem.h5 and read by coarse/:
// every active grain's state and every contact with its force. Plain arrays, SI units.
#include <cstdint>
#include <string>
#include <vector>

#include "dem/world.h"

namespace pilelab::dem {

struct Snapshot {
  std::string name;              ///< e.g. "settled", "relaxed", "frame_0003"
  double time = 0.0;             ///< simulated time [s]
  double gravity = 0.0;          ///< |g| at this instant [m/s^2]
  // Grains (active, non-wall bodies), by body index.
  std::vector<std::int64_t> body;            ///< body index (same index as in /bodies of dem.h5)
  std::vector<double> position;              ///< (n, 2) [m]
  std::vector<double> angle;                 ///< (n) [rad]
  std::vector<double> velocity;              ///< (n, 2) [m/s]
  std::vector<double> angular_velocity;      ///< (n) [rad/s]
  std::vector<double> contact_force;         ///< (n, 2) sum of contact forces [N]
  std::vector<std::int64_t> contact_count;   ///< (n) contacts touching the grain
  // Contacts.
  std::vector<std::int64_t> pair;            ///< (c, 2) body indices a < b
  std::vector<double> point;                 ///< (c, 2) force point [m]
  std::vector<double> normal;                ///< (c, 2) unit normal from a to b
  std::vector<double> normal_force;          ///< (c) [N] on b along +normal (>= 0)
  std::vector<double> tangential_force;      ///< (c) [N] on b along normal turned +90 degrees
  std::vector<double> force;                 ///< (c, 2) total force on b [N]
  std::vector<double> overlap_area;          ///< (c) [m^2]
  std::vector<double> chord;                 ///< (c) contact-line length [m]
  std::size_t grain_count() const { return body.size(); }
  std::size_t contact_count_total() const { return normal_force.size(); }
};

Snapshot take_snapshot(const World& world, const std::string& name);

}  // namespace pilelab::dem
