#pragma once
// The status a `pilelab run` ends with: ok, warn or fail, with every warning of every stage and
// ensemble member, so that no bad pile or degenerate fit reaches the end of a run unsaid. It is
// written into report.json ("status") and repeated on the console; a fail exits with code 3.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/ensemble.h"

namespace pilelab::app {

/// A pile unfit for the later stages: its settled snapshot above the settling threshold, or
/// more than this share of its grains lost off the plate.
constexpr double lost_grain_fraction_limit = 0.02;
/// A continuum model whose base carries less than this share of the weight is flagged.
constexpr double carried_weight_limit = 0.99;

struct StatusItem {
  std::string stage;    ///< "dem", "member 3", "continuum.elastic", "fit.isotropic", ...
  std::string message;
  bool fails = false;   ///< makes the run fail (unless allowed: then a warning)
};

struct RunStatus {
  std::vector<StatusItem> items;
  bool allow_unsettled = false;  ///< failing piles only warn (`--allow-unsettled`)

  /// "fail" if an item fails and failing is not allowed, else "warn" if there is any item, else "ok".
  std::string level() const;
  bool pile_fails() const;  ///< an item fails (whether or not it is allowed)
  nlohmann::json to_json() const;
};

/// The pile's own findings, from its report's "dem" section: its warnings, and whether it is
/// unfit for the later stages (unsettled, or grains lost above the limit). `who` names it.
void assess_pile(const nlohmann::json& dem, const std::string& who, RunStatus& status);

/// Every pile of the run: OUT/report.json's "dem" section, or each member's report.
void assess_piles(const std::string& out_dir, const EnsembleSpec& ensemble, RunStatus& status);

/// The later stages' findings from OUT/report.json: models that do not carry the weight (and
/// their own warnings), degenerate fits (R^2 < 0, a constant's interval spanning zero, a closed
/// loop worse than no model at all), and a closure fit with R^2 < 0.
void assess_later_stages(const nlohmann::json& report, RunStatus& status);

}  // namespace pilelab::app
