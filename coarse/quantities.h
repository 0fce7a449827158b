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
  bool is_axis = false;    ///< an orientation in degrees mod 180 (averaged as an axis)
};

/// The ensemble mean of samples of several piles at one point: tensors, scalars and
/// displacements averaged over the piles that have them. Derived quantities (principal values,
/// anisotropy, orientation) are then taken from the mean tensors, never averaged themselves
/// (axes at 178 and 2 degrees must not average to 90).
RveSample mean_sample(const std::vector<RveSample>& piles);

/// Every field: stress (tension positive, as in continuum mechanics) with pressure, anisotropy
/// and orientation of the major compressive axis; fabric; coordination; volume fraction;
/// strain (symmetric part of Cambou's gradient), its rotation, fit residual, anisotropy and
/// orientation of the principal strain of largest magnitude; mean grain displacement.
const std::vector<Quantity>& quantities();

}  // namespace pilelab::coarse
