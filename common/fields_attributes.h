#pragma once
// The root attributes of a fields.h5 (docs/FORMAT.md): what coarse-graining hands to the later
// stages about the fields it averaged. One writer (coarse/) and one reader for every stage that
// takes them (the comparison, the closed loop of the fit, the solve's measured density), so
// that what a missing attribute means is decided here and nowhere else.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "common/hdf5_file.h"

namespace pilelab {

struct FieldsAttributes {
  std::string method = "rve";      ///< the averaging window: "rve" or a registered kernel's name (coarse/kernel_registry.cpp)
  double rve_radius_m = 0.0;       ///< the RVE's radius; 0: none (a user's own fields)
  double kernel_width_m = 0.0;     ///< the kernel's width; 0 for RVEs
  std::int64_t piles = 1;          ///< piles averaged (an ensemble's members)
  std::string snapshot = "settled";  ///< the DEM snapshot of the stresses and fabric
  std::string strain_to;           ///< the later snapshot of the strains; empty: no strains
  double gravity_change = 0.0;     ///< relative change of g from snapshot to strain_to; 0: none
  double height_m = 0.0;           ///< the pile's height (the members' mean) [m]
  double rho_bulk_kg_per_m2 = 0.0; ///< bulk areal density (grains' mass over pile area) [kg/m^2]
  double gravity_m_per_s2 = 0.0;   ///< gravity of the snapshot [m/s^2]
  double snapshot_time_s = 0.0;    ///< simulated time of the snapshot (the members' mean) [s]; 0: not known

  /// rho g of the stresses: a gravity stress scales with it.
  double rho_g() const { return rho_bulk_kg_per_m2 * gravity_m_per_s2; }
  nlohmann::json to_json() const;
};

/// Writes them as root attributes, beside format = "pilelab-fields" and its version.
void write_fields_attributes(H5File& file, const FieldsAttributes& attributes);

/// Reads them back. An attribute a user's own fields.h5 may leave out keeps its default above;
/// one that is present but not a finite number is refused, naming the file and the attribute.
FieldsAttributes read_fields_attributes(const std::string& path);

}  // namespace pilelab
