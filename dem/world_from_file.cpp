#include "dem/world_from_file.h"

#include "common/error.h"

namespace pilelab::dem {

World world_from_snapshot(const DemFile& file, const std::string& name, const WorldSettings& settings) {
  const Snapshot s = file.snapshot(name);
  const WallPlacement walls = file.walls(name);
  World world(settings);
  const int wall_count = file.wall_count();
  for (int w = 0; w < wall_count; ++w)
    world.add_wall(file.shapes[w], {walls.position[2 * w], walls.position[2 * w + 1]}, walls.angle[w],
                   {walls.velocity[2 * w], walls.velocity[2 * w + 1]});
  for (int b = wall_count; b < file.body_count(); ++b)
    world.add_grain(file.shapes[b], file.mass[b] / file.shapes[b].area);
  for (std::size_t i = 0; i < s.body.size(); ++i)
    world.activate(static_cast<int>(s.body[i]), {s.position[2 * i], s.position[2 * i + 1]}, s.angle[i],
                   {s.velocity[2 * i], s.velocity[2 * i + 1]}, s.angular_velocity[i]);
  std::vector<Contact> contacts;
  for (std::size_t c = 0; c < s.normal_force.size(); ++c) {
    Contact k;
    k.a = static_cast<std::int32_t>(s.pair[2 * c]);
    k.b = static_cast<std::int32_t>(s.pair[2 * c + 1]);
    k.normal = {s.normal[2 * c], s.normal[2 * c + 1]};
    // The spring part of the tangential force (dem.h5 stores the total, spring + viscous); for
    // the contacts at rest of a settled snapshot the viscous part vanishes.
    k.spring = s.tangential_force[c];
    contacts.push_back(k);
  }
  world.restore_contacts(std::move(contacts));
  return world;
}

}  // namespace pilelab::dem
