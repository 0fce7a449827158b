#include "coarse/virial_identity.h"

namespace pilelab::coarse {

VirialIdentity virial_identity(const Packing& p) {
  VirialIdentity v;
  for (const Contact& c : p.contacts) {
    v.grain_sum += c.force_on_a * (c.point - p.grains[c.a].centre).transpose();
    if (c.b >= 0) v.grain_sum += -c.force_on_a * (c.point - p.grains[c.b].centre).transpose();
    else v.wall += c.force_on_a * c.point.transpose();
  }
  for (const Grain& g : p.grains) {
    v.gravity += g.mass * p.gravity * g.centre.transpose();
    v.residual += g.residual_force * g.centre.transpose();
    v.scale += g.mass * p.gravity.norm() * g.centre.norm();
  }
  return v;
}

}  // namespace pilelab::coarse
