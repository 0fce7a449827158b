#include "coarse/packing.h"

#include <cmath>

#include "common/portable_math.h"

namespace pilelab::coarse {

std::vector<int> Packing::index_by_body() const {
  std::int64_t max_body = -1;
  for (const Grain& g : grains) max_body = std::max(max_body, g.body);
  std::vector<int> index(static_cast<std::size_t>(max_body + 1), -1);
  for (std::size_t i = 0; i < grains.size(); ++i)
    if (grains[i].body >= 0) index[static_cast<std::size_t>(grains[i].body)] = static_cast<int>(i);
  return index;
}

Packing packing_from_snapshot(const dem::DemFile& file, const dem::Snapshot& s) {
  Packing p;
  p.source = file.path + " (snapshot '" + s.name + "')";
  p.gravity = {0.0, -s.gravity};
  p.shapes = file.shapes;
  std::vector<int> grain_of_body(file.shapes.size(), -1);
  p.grains.resize(s.grain_count());
  for (std::size_t g = 0; g < s.grain_count(); ++g) {
    const auto body = static_cast<std::size_t>(s.body[g]);
    Grain& grain = p.grains[g];
    grain.body = s.body[g];
    grain.centre = {s.position[2 * g], s.position[2 * g + 1]};
    grain.angle = s.angle[g];
    grain.mass = file.mass.at(body);
    grain.shape = &p.shapes[body];
    grain.area = grain.shape->area;
    grain.residual_force = Vec2(s.contact_force[2 * g], s.contact_force[2 * g + 1]) + grain.mass * p.gravity;
    grain_of_body[body] = static_cast<int>(g);
  }
  // dem.h5 stores pairs a < b with the force on b; walls are the lowest body indices.
  for (std::size_t c = 0; c < s.contact_count_total(); ++c) {
    const int ga = grain_of_body.at(static_cast<std::size_t>(s.pair[2 * c]));
    const int gb = grain_of_body.at(static_cast<std::size_t>(s.pair[2 * c + 1]));
    const Vec2 point(s.point[2 * c], s.point[2 * c + 1]);
    const Vec2 force_on_b(s.force[2 * c], s.force[2 * c + 1]);
    if (gb < 0) continue;  // two walls never touch; a contact with an inactive body is skipped
    Contact contact;
    contact.point = point;
    if (ga < 0) {  // wall - grain
      contact.a = gb;
      contact.b = -1;
      contact.force_on_a = force_on_b;
    } else {
      contact.a = ga;
      contact.b = gb;
      contact.force_on_a = -force_on_b;
    }
    p.contacts.push_back(contact);
  }
  return p;
}

void grain_displacements(const Packing& from, const Packing& to, std::vector<Vec2>& displacement,
                         std::vector<char>& moved) {
  const std::vector<int> index = to.index_by_body();
  displacement.assign(from.grains.size(), Vec2::Zero());
  moved.assign(from.grains.size(), 0);
  for (std::size_t p = 0; p < from.grains.size(); ++p) {
    const auto body = from.grains[p].body;
    if (body < 0 || body >= static_cast<std::int64_t>(index.size()) || index[body] < 0) continue;
    displacement[p] = to.grains[index[body]].centre - from.grains[p].centre;
    moved[p] = 1;
  }
}

std::vector<Vec2> world_outline(const Grain& g) {
  std::vector<Vec2> out;
  if (!g.shape || g.shape->kind == dem::ShapeKind::disc) return out;
  double s, c;
  rotation_sincos(g.angle, s, c);
  out.reserve(g.shape->vertices.size());
  for (const Vec2& v : g.shape->vertices) out.push_back(g.centre + dem::rotate(v, c, s));
  return out;
}

}  // namespace pilelab::coarse
