// `pilelab coarse`: continuum fields from DEM piles (coarse/coarse_run.h).
#include <memory>

#include "apps/commands.h"
#include "common/output_lock.h"
#include "coarse/coarse_run.h"

namespace pilelab::app {

void add_coarse_command(CLI::App& app) {
  auto opt = std::make_shared<coarse::CoarseRunOptions>();
  CLI::App* cmd = app.add_subcommand(
      "coarse", "Average DEM piles into continuum fields on the triangulation, as the scene's [coarse] table says:\n"
                "stress, strain, fabric, coordination, volume fraction (RVE discs or smooth kernels), an RVE-size\n"
                "study and profiles along horizontal cuts. Reads OUT/dem.h5 and OUT/pile.msh unless the scene names\n"
                "others; writes OUT/fields.h5, OUT/fields.vtu, OUT/profiles.csv, OUT/rve_study.csv, report.json.");
  cmd->add_option("scene", opt->scene_path, "Scene file (TOML); see docs/SCENES.md")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", opt->out_dir, "Output directory (created if missing)")->required();
  cmd->final_callback([opt] {
    const OutputLock lock(opt->out_dir, "pilelab coarse " + opt->scene_path);
    coarse::run_coarse(*opt);
  });
}

}  // namespace pilelab::app
