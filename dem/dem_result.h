#pragma once
#include <cmath>
// What the later stages take from a DEM run: the measured shape of the pile and what the run
// cost. Written by `pilelab dem` as the "dem" section of OUT/report.json; this is the one reader
// of that section, so every stage sees the same values with the same checks.
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace pilelab::dem {

struct DemResult {
  std::int64_t seed = 0;
  int grains = 0;               ///< on the plate at the end
  int lost = 0;                 ///< fell off the plate
  double height_m = 0.0;        ///< of the settled pile
  double apex_x_m = 0.0;
  double repose_left_deg = 0.0, repose_right_deg = 0.0;  ///< NaN where a flank had too few points
  double wall_time_s = 0.0;     ///< whole run, all sessions
  double wall_time_pour_and_settle_s = 0.0;
  /// The plate's load over the weight, and its dip statistic (plate_force.h); NaN in reports
  /// written before they were measured, or where a flank had no angle.
  double plate_force_over_weight = NAN, plate_force_dip = NAN;
  bool repose_measured() const;  ///< both angles are numbers in (0, 90)
};

/// The "dem" section of a report. Throws InputError naming `source` and the key if a value the
/// struct needs is missing or of the wrong kind (a null angle is NaN, not an error).
DemResult dem_result_from_report(const nlohmann::json& report, const std::string& source);
/// The same, from a report.json file.
DemResult read_dem_result(const std::string& report_path);

/// The pile's repose angle, the mean of its two flanks, from a report's "dem" section, when
/// both flanks are numbers in (0, 90). Reads nothing else, so a partial or hand-made section
/// gives an answer or nothing, never an error.
std::optional<double> mean_repose_angle_deg(const nlohmann::json& report);

}  // namespace pilelab::dem
