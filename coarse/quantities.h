#pragma once
// The named scalar fields coarse/ writes, each read off an averaged sample. One table for
// fields.h5, fields.vtu and profiles.csv, so their names and units always agree.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "coarse/rve_average.h"

namespace pilelab::coarse {

struct Quantity {
  std::string name;
  std::string unit;
  bool is_stress = false;  ///< normalised by rho g h (and made compression positive) in profiles
  std::function<std::optional<double>(const RveSample&)> value;  ///< nullopt: no data here
};

/// Every field: stress (tension positive, as in continuum mechanics) with pressure, anisotropy
/// and orientation of the major compressive axis; fabric; coordination; volume fraction;
/// strain (symmetric part of Cambou's gradient), its rotation, fit residual, anisotropy and
/// orientation of the principal strain of largest magnitude; mean grain displacement.
const std::vector<Quantity>& quantities();

}  // namespace pilelab::coarse
