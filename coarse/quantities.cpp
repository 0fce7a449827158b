#include "coarse/quantities.h"

#include <cmath>

namespace pilelab::coarse {

namespace {
using Value = std::optional<double>;
Value if_data(const RveSample& s, double v) { return s.has_data() ? Value(v) : std::nullopt; }
Value if_strain(const RveSample& s, double v) { return s.has_strain ? Value(v) : std::nullopt; }
}  // namespace

RveSample mean_sample(const std::vector<RveSample>& piles) {
  RveSample m;
  int with_data = 0, with_strain = 0, with_change = 0;
  double grains = 0, residual = 0;
  for (const RveSample& s : piles) {
    if (!s.has_data()) continue;
    ++with_data;
    grains += s.grain_count;
    m.volume += s.volume;
    m.stress += s.stress;
    m.fabric += s.fabric;
    m.coordination += s.coordination;
    m.volume_fraction += s.volume_fraction;
    if (s.has_strain) {
      ++with_strain;
      m.displacement_gradient += s.displacement_gradient;
      m.displacement += s.displacement;
      residual += s.strain_fit_residual;
      m.strain_contacts += s.strain_contacts;
    }
    if (s.has_stress_change) ++with_change, m.stress_change += s.stress_change;
  }
  if (with_data == 0) return RveSample{};
  m.grain_count = static_cast<int>(std::lround(grains / with_data));
  if (m.grain_count == 0) m.grain_count = 1;  // averaged from piles that have grains here
  m.volume /= with_data;
  m.stress /= with_data;
  m.fabric /= with_data;
  m.coordination /= with_data;
  m.volume_fraction /= with_data;
  if (with_strain) {
    m.has_strain = true;
    m.displacement_gradient /= with_strain;
    m.displacement /= with_strain;
    m.strain_fit_residual = residual / with_strain;
    m.strain_contacts /= with_strain;
  }
  if (with_change) m.has_stress_change = true, m.stress_change /= with_change;
  return m;
}

const std::vector<Quantity>& quantities() {
  static const std::vector<Quantity> table = {
      {"grain_count", "1", false, [](const RveSample& s) { return Value(s.grain_count); }},
      {"stress_xx", "N/m", true, [](const RveSample& s) { return if_data(s, s.stress(0, 0)); }},
      {"stress_yy", "N/m", true, [](const RveSample& s) { return if_data(s, s.stress(1, 1)); }},
      {"stress_xy", "N/m", true, [](const RveSample& s) { return if_data(s, 0.5 * (s.stress(0, 1) + s.stress(1, 0))); }},
      {"pressure", "N/m", false, [](const RveSample& s) { return if_data(s, -0.5 * s.stress.trace()); }},
      {"stress_anisotropy", "1", false, [](const RveSample& s) { return if_data(s, summarise(s.stress, -1).anisotropy); }},
      {"stress_orientation_deg", "degree", false,
       [](const RveSample& s) { return if_data(s, summarise(s.stress, -1).orientation_deg); }, true},
      {"fabric_xx", "1", false, [](const RveSample& s) { return if_data(s, s.fabric(0, 0)); }},
      {"fabric_yy", "1", false, [](const RveSample& s) { return if_data(s, s.fabric(1, 1)); }},
      {"fabric_xy", "1", false, [](const RveSample& s) { return if_data(s, s.fabric(0, 1)); }},
      {"fabric_trace", "1", false, [](const RveSample& s) { return if_data(s, s.fabric.trace()); }},
      {"fabric_anisotropy", "1", false, [](const RveSample& s) { return if_data(s, summarise(s.fabric).anisotropy); }},
      {"fabric_orientation_deg", "degree", false,
       [](const RveSample& s) { return if_data(s, summarise(s.fabric).orientation_deg); }, true},
      {"coordination", "1", false, [](const RveSample& s) { return if_data(s, s.coordination); }},
      {"volume_fraction", "1", false, [](const RveSample& s) { return if_data(s, s.volume_fraction); }},
      {"strain_xx", "1", false, [](const RveSample& s) { return if_strain(s, s.strain()(0, 0)); }},
      {"strain_yy", "1", false, [](const RveSample& s) { return if_strain(s, s.strain()(1, 1)); }},
      {"strain_xy", "1", false, [](const RveSample& s) { return if_strain(s, s.strain()(0, 1)); }},
      {"strain_rotation", "rad", false, [](const RveSample& s) { return if_strain(s, s.rotation()); }},
      {"strain_fit_residual", "1", false, [](const RveSample& s) { return if_strain(s, s.strain_fit_residual); }},
      {"strain_anisotropy", "1", false,
       [](const RveSample& s) { return if_strain(s, summarise(s.strain(), 1, true).anisotropy); }},
      {"strain_orientation_deg", "degree", false,
       [](const RveSample& s) { return if_strain(s, summarise(s.strain(), 1, true).orientation_deg); }, true},
      {"stress_change_xx", "N/m", false,
       [](const RveSample& s) { return s.has_stress_change ? Value(s.stress_change(0, 0)) : std::nullopt; }},
      {"stress_change_yy", "N/m", false,
       [](const RveSample& s) { return s.has_stress_change ? Value(s.stress_change(1, 1)) : std::nullopt; }},
      {"stress_change_xy", "N/m", false, [](const RveSample& s) {
         return s.has_stress_change ? Value(0.5 * (s.stress_change(0, 1) + s.stress_change(1, 0))) : std::nullopt;
       }},
      {"displacement_x", "m", false, [](const RveSample& s) { return if_strain(s, s.displacement.x()); }},
      {"displacement_y", "m", false, [](const RveSample& s) { return if_strain(s, s.displacement.y()); }},
  };
  return table;
}

}  // namespace pilelab::coarse
