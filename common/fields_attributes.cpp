#include "common/fields_attributes.h"

#include <cmath>

#include "common/error.h"

namespace pilelab {

nlohmann::json FieldsAttributes::to_json() const {
  return {{"method", method},
          {"rve_radius_m", rve_radius_m},
          {"kernel_width_m", kernel_width_m},
          {"piles", piles},
          {"snapshot", snapshot},
          {"strain_to", strain_to},
          {"gravity_change", gravity_change},
          {"height_m", height_m},
          {"rho_bulk_kg_per_m2", rho_bulk_kg_per_m2},
          {"gravity_m_per_s2", gravity_m_per_s2},
          {"snapshot_time_s", snapshot_time_s}};
}

void write_fields_attributes(H5File& f, const FieldsAttributes& a) {
  f.set_attribute("/", "format", std::string("pilelab-fields"));
  f.set_attribute("/", "format_version", std::int64_t(1));
  const nlohmann::json values = a.to_json();  // kept alive: items() refers into it
  for (const auto& [key, value] : values.items()) {
    if (value.is_number_integer()) f.set_attribute("/", key, value.get<std::int64_t>());
    else if (value.is_number()) f.set_attribute("/", key, value.get<double>());
    else f.set_attribute("/", key, value.get<std::string>());
  }
}

FieldsAttributes read_fields_attributes(const std::string& path) {
  const H5File f = H5File::open_read(path);
  FieldsAttributes a;
  const auto number = [&](const char* name, double& value) {
    if (!f.has_attribute("/", name)) return;
    value = f.attribute_double("/", name);
    if (!std::isfinite(value))
      throw InputError(path + ": root attribute " + name + " is " + std::to_string(value) + ": expected a finite number");
  };
  const auto text = [&](const char* name, std::string& value) {
    if (f.has_attribute("/", name)) value = f.attribute_string("/", name);
  };
  text("method", a.method);
  number("rve_radius_m", a.rve_radius_m);
  number("kernel_width_m", a.kernel_width_m);
  if (f.has_attribute("/", "piles")) a.piles = f.attribute_int("/", "piles");
  text("snapshot", a.snapshot);
  text("strain_to", a.strain_to);
  number("gravity_change", a.gravity_change);
  number("height_m", a.height_m);
  number("rho_bulk_kg_per_m2", a.rho_bulk_kg_per_m2);
  number("gravity_m_per_s2", a.gravity_m_per_s2);
  number("snapshot_time_s", a.snapshot_time_s);
  return a;
}

}  // namespace pilelab
