// `pilelab dem`: pour, settle and relax a pile (dem/pile_run.h).
#include <cstdint>
#include <memory>

#include "apps/commands.h"
#include "common/output_lock.h"
#include "dem/pile_run.h"

namespace pilelab::app {

void add_dem_command(CLI::App& app) {
  auto opt = std::make_shared<dem::DemRunOptions>();
  CLI::App* dem = app.add_subcommand(
      "dem", "Pour a pile from the scene's [dem] section: pour, settle, optional gravity ramp.\n"
             "Writes OUT/dem.h5, OUT/dem.pvd with grains_*.vtu and contacts_*.vtu frames, OUT/checkpoint.h5\n"
             "and the \"dem\" section of OUT/report.json (see docs/FORMAT.md).");
  dem->add_option("scene", opt->scene_path, "Scene file (TOML); see docs/SCENES.md")->required()->check(CLI::ExistingFile);
  dem->add_option("-o,--out", opt->out_dir, "Output directory (created if missing)")->required();
  dem->add_flag("--restart", opt->restart, "Continue from OUT/checkpoint.h5 (bit for bit as if never stopped)");
  dem->add_flag("-q,--quiet", opt->quiet, "No progress lines (warnings still print)");
  dem->add_option("-j,--threads", opt->threads, "OpenMP threads for the force loop (default: all cores)")
      ->check(CLI::Range(1, 1024));
  dem->add_option("--stop-after-steps", opt->stop_after_steps,
                  "Write a checkpoint and stop after this many steps (for testing --restart)")
      ->check(CLI::Range(std::int64_t(1), INT64_MAX))
      ->group("");  // for tests: not in the user's help
  dem->final_callback([opt] {
    const OutputLock lock(opt->out_dir, "pilelab dem " + opt->scene_path);
    dem::run_dem(*opt);
  });
}

}  // namespace pilelab::app
