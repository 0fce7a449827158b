#pragma once
// Pouring the members of an ensemble (common/ensemble.h): each seed's pile is a complete DEM
// run in OUT/members/<seed>/ with its own scene, report, checkpoints and frames. A member that
// finished is not poured again; one that was stopped continues from its checkpoint.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/ensemble.h"

namespace pilelab::app {

struct MemberRunOptions {
  std::string scene_path;  ///< the ensemble's scene
  std::string out_dir;     ///< OUT; members go to OUT/members/<seed>
  int processes = 1;       ///< members poured side by side as child processes (-P); 1: in this process
  int threads = 0;         ///< OpenMP threads per member; 0: the cores shared among the members poured at once
  bool quiet = false;
};

/// Pours every member not yet poured. Without MPI (or on one rank) the members run one after
/// another in this process, or `processes` at a time as child `pilelab dem` processes; under
/// mpirun each rank takes the next member whenever it is free. Every member's files depend only
/// on its seed, not on who poured it or when. Returns on every rank once all members are done;
/// throws (on every rank) if a member failed, naming it and its log.
void pour_members(const EnsembleSpec& ensemble, const MemberRunOptions& options);

/// The "ensemble" section of report.json from the members' reports: per member its seed, repose
/// angles, height, grains lost and wall time; mean, standard deviation and standard error of
/// each angle, of the mean of a pile's two angles, and of the height.
nlohmann::json summarize_members(const EnsembleSpec& ensemble, const std::string& out_dir);

/// The members' dem.h5 files, in seed order.
std::vector<std::string> member_dem_files(const EnsembleSpec& ensemble, const std::string& out_dir);

}  // namespace pilelab::app
