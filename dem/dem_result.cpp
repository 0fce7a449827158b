#include "dem/dem_result.h"

#include <cmath>

#include "common/error.h"
#include "common/report.h"

namespace pilelab::dem {

bool DemResult::repose_measured() const {
  return repose_left_deg > 0 && repose_left_deg < 90 && repose_right_deg > 0 && repose_right_deg < 90;
}

DemResult dem_result_from_report(const nlohmann::json& report, const std::string& source) {
  if (!report.contains("dem") || !report["dem"].is_object())
    throw InputError(source + ": no \"dem\" section (the DEM stage has not finished here)");
  const nlohmann::json& d = report["dem"];
  const auto number = [&](const char* key, bool nullable) -> double {
    if (!d.contains(key)) throw InputError(source + ": dem." + key + ": missing");
    if (d[key].is_null() && nullable) return NAN;
    if (!d[key].is_number()) throw InputError(source + ": dem." + key + ": expected a number, found " + d[key].dump());
    return d[key].get<double>();
  };
  DemResult r;
  r.seed = d.contains("seed") && d["seed"].is_number_integer() ? d["seed"].get<std::int64_t>() : 0;
  r.grains = static_cast<int>(number("particles", false));
  r.lost = static_cast<int>(number("lost", false));
  r.height_m = number("height_m", false);
  r.apex_x_m = number("apex_x_m", false);
  r.repose_left_deg = number("repose_angle_left_deg", true);
  r.repose_right_deg = number("repose_angle_right_deg", true);
  r.wall_time_s = number("wall_time_s", false);
  r.wall_time_pour_and_settle_s = d.contains("wall_time_pour_and_settle_s") ? number("wall_time_pour_and_settle_s", true) : NAN;
  r.plate_force_over_weight = d.contains("plate_force_over_weight") ? number("plate_force_over_weight", true) : NAN;
  if (d.contains("plate_force_dip")) {
    const nlohmann::json& dip = d["plate_force_dip"];
    if (!dip.is_object() || !dip.contains("centre_over_ring_minus_1"))
      throw InputError(source + ": dem.plate_force_dip: expected an object with centre_over_ring_minus_1, found " + dip.dump());
    const nlohmann::json& v = dip["centre_over_ring_minus_1"];
    if (!v.is_null() && !v.is_number())
      throw InputError(source + ": dem.plate_force_dip.centre_over_ring_minus_1: expected a number, found " + v.dump());
    r.plate_force_dip = v.is_number() ? v.get<double>() : NAN;
  }
  return r;
}

std::optional<double> mean_repose_angle_deg(const nlohmann::json& report) {
  if (!report.is_object() || !report.contains("dem") || !report["dem"].is_object()) return std::nullopt;
  const nlohmann::json& d = report["dem"];
  const auto angle = [&](const char* key) {
    return d.contains(key) && d[key].is_number() ? d[key].get<double>() : NAN;
  };
  DemResult r;
  r.repose_left_deg = angle("repose_angle_left_deg");
  r.repose_right_deg = angle("repose_angle_right_deg");
  if (!r.repose_measured()) return std::nullopt;
  return 0.5 * (r.repose_left_deg + r.repose_right_deg);
}

DemResult read_dem_result(const std::string& report_path) {
  return dem_result_from_report(read_report(report_path), report_path);
}

}  // namespace pilelab::dem
