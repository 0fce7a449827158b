#include "dem/snapshot.h"

namespace pilelab::dem {

Snapshot take_snapshot(const World& world, const std::string& name) {
  Snapshot s;
  s.name = name;
  s.time = world.time();
  s.gravity = world.settings().gravity.norm();
  std::vector<std::int64_t> count(world.body_count(), 0);
  for (const Contact& c : world.contacts()) {
    ++count[c.a];
    ++count[c.b];
  }
  for (int i : world.active_grains()) {
    s.body.push_back(i);
    const Vec2 p = world.position(i), v = world.velocity(i), f = world.contact_force(i);
    s.position.insert(s.position.end(), {p.x(), p.y()});
    s.angle.push_back(world.angle(i));
    s.velocity.insert(s.velocity.end(), {v.x(), v.y()});
    s.angular_velocity.push_back(world.angular_velocity(i));
    s.contact_force.insert(s.contact_force.end(), {f.x(), f.y()});
    s.contact_count.push_back(count[i]);
  }
  for (const Contact& c : world.contacts()) {
    s.pair.insert(s.pair.end(), {c.a, c.b});
    s.point.insert(s.point.end(), {c.point.x(), c.point.y()});
    s.normal.insert(s.normal.end(), {c.normal.x(), c.normal.y()});
    s.normal_force.push_back(c.normal_force);
    s.tangential_force.push_back(c.tangential_force);
    const Vec2 f = c.force_on_b();
    s.force.insert(s.force.end(), {f.x(), f.y()});
    s.overlap_area.push_back(c.area);
    s.chord.push_back(c.chord);
  }
  return s;
}

}  // namespace pilelab::dem
