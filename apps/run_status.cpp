#include "apps/run_status.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/report.h"

namespace pilelab::app {

namespace {

bool number(const nlohmann::json& j, const char* key) { return j.contains(key) && j[key].is_number(); }

std::string format(const char* pattern, double a, double b = 0) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b);
  return text;
}

}  // namespace

std::string RunStatus::level() const {
  if (items.empty()) return "ok";
  return pile_fails() && !allow_unsettled ? "fail" : "warn";
}

bool RunStatus::pile_fails() const {
  for (const StatusItem& i : items)
    if (i.fails) return true;
  return false;
}

nlohmann::json RunStatus::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const StatusItem& i : items) list.push_back({{"stage", i.stage}, {"message", i.message}, {"fails", i.fails}});
  return {{"level", level()},
          {"warnings", list},
          {"allow_unsettled", allow_unsettled},
          {"lost_grain_fraction_limit", lost_grain_fraction_limit},
          {"carried_weight_limit", carried_weight_limit}};
}

void assess_pile(const nlohmann::json& dem, const std::string& who, RunStatus& status) {
  if (dem.contains("warnings"))
    for (const auto& w : dem["warnings"]) status.items.push_back({who, w.get<std::string>(), false});
  if (dem.contains("settling") && dem["settling"].contains("settled")) {
    const auto& settled = dem["settling"]["settled"];
    const bool must_settle = !dem.contains("must_settle") || dem["must_settle"].get<bool>();
    if (settled.contains("reached_threshold") && !settled["reached_threshold"].get<bool>())
      status.items.push_back({who, std::string("the pile never settled: its settled snapshot was taken at "
                                               "dem.settle.max_time_s above the kinetic energy threshold; the later "
                                               "stages would measure a moving pile") +
                                       (must_settle ? "" : " (dem.settle.must_settle = false: a warning only)"),
                              must_settle});
  }
  if (number(dem, "lost") && number(dem, "particles")) {
    const double lost = dem["lost"].get<double>(), kept = dem["particles"].get<double>();
    if (lost > lost_grain_fraction_limit * (lost + kept))
      status.items.push_back(
          {who, format("%.0f of %.0f grains were lost off the plate, more than the limit of ", lost, lost + kept) +
                    format("%g %%: the pile is not the one poured", 100 * lost_grain_fraction_limit),
           true});
  }
}

void assess_piles(const std::string& out_dir, const EnsembleSpec& ensemble, RunStatus& status) {
  const auto report_of = [](const std::string& dir) {
    const std::string path = (std::filesystem::path(dir) / "report.json").string();
    return std::filesystem::exists(path) ? read_report(path) : nlohmann::json::object();
  };
  if (ensemble.empty()) {
    const nlohmann::json report = report_of(out_dir);
    if (report.contains("dem")) assess_pile(report["dem"], "dem", status);
    return;
  }
  for (std::int64_t seed : ensemble.seeds) {
    const nlohmann::json report = report_of(member_directory(out_dir, seed));
    if (report.contains("dem")) assess_pile(report["dem"], "member " + std::to_string(seed), status);
  }
}

void assess_later_stages(const nlohmann::json& report, RunStatus& status) {
  if (report.contains("continuum"))
    for (const auto& [name, model] : report["continuum"].items()) {
      if (!model.is_object() || !number(model, "base_force_over_weight")) continue;
      const std::string who = "continuum." + name;
      if (model.contains("warning")) {
        status.items.push_back({who, model["warning"].get<std::string>()});
      } else if (!(model["base_force_over_weight"].get<double>() >= carried_weight_limit)) {
        status.items.push_back({who, format("the model's base carries %.4g of the weight, below %g: refine the mesh "
                                            "or raise the degree",
                                            model["base_force_over_weight"].get<double>(), carried_weight_limit)});
      }
    }
  if (report.contains("fit") && report["fit"].contains("models"))
    for (const auto& [name, fit] : report["fit"]["models"].items()) {
      const std::string who = "fit." + name;
      if (number(fit, "r2") && fit["r2"].get<double>() < 0)
        status.items.push_back({who, format("R^2 = %.3g < 0: the fitted relation predicts the stress change worse "
                                            "than its mean",
                                            fit["r2"].get<double>())});
      for (const auto& [key, value] : fit.items())
        if (key.size() > 5 && key.compare(key.size() - 5, 5, "_ci95") == 0 && value.is_array() && value.size() == 2 &&
            value[0].is_number() && value[1].is_number() && value[0].get<double>() < 0 && value[1].get<double>() > 0 &&
            key.rfind("nu", 0) != 0)  // Poisson's ratio may be either sign
          status.items.push_back({who, key.substr(0, key.size() - 5) + ": its 95 % interval [" +
                                           format("%.3g, %.3g", value[0].get<double>(), value[1].get<double>()) +
                                           "] spans zero: the data do not determine it"});
    }
  if (report.contains("fit") && report["fit"].contains("closed_loop")) {
    const auto& loop = report["fit"]["closed_loop"];
    if (number(loop, "relative_l2_displacement") && loop["relative_l2_displacement"].get<double>() > 1)
      status.items.push_back({"fit.closed_loop", format("the fitted material's displacements differ from the DEM's by "
                                                        "%.3g of their size: worse than no model",
                                                        loop["relative_l2_displacement"].get<double>())});
  }
  if (report.contains("compare") && report["compare"].contains("osl_closure_fit")) {
    const auto& osl = report["compare"]["osl_closure_fit"];
    if (number(osl, "r_squared") && osl["r_squared"].get<double>() < 0)
      status.items.push_back({"compare.osl_closure_fit", format("R^2 = %.3g < 0: the closure does not describe the "
                                                                "DEM's stress", osl["r_squared"].get<double>())});
  }
}

}  // namespace pilelab::app
