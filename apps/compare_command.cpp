// `pilelab compare` and `pilelab fit` (compare/compare_run.h).
#include <memory>

#include "apps/commands.h"
#include "common/output_lock.h"
#include "compare/compare_run.h"

namespace pilelab::app {

void add_compare_command(CLI::App& app) {
  auto opt = std::make_shared<compare::CompareRunOptions>();
  CLI::App* cmd = app.add_subcommand(
      "compare", "Put the DEM fields (OUT/fields.h5) beside the continuum models (OUT/models.h5) on the common\n"
                 "triangulation: relative L2 differences, base-pressure dips, principal-axis angles, the DEM's\n"
                 "stress/strain/fabric misalignment, the best-fitting FPA angle, and stress-strain fits. Writes\n"
                 "OUT/compare.vtu and the \"compare\" and \"fit\" sections of OUT/report.json.");
  cmd->add_option("scene", opt->scene_path, "Scene file (TOML); see docs/SCENES.md")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", opt->out_dir, "Output directory holding the earlier stages' files")->required();
  cmd->final_callback([opt] {
    const OutputLock lock(opt->out_dir, "pilelab compare " + opt->scene_path);
    compare::run_compare(*opt);
  });
}

void add_fit_command(CLI::App& app) {
  auto opt = std::make_shared<compare::FitOptions>();
  CLI::App* cmd = app.add_subcommand(
      "fit", "Fit stress-strain relations (isotropic, fabric-orthotropic, pressure-dependent) to the incremental\n"
             "stress and strain of any fields.h5; bootstrap intervals, AIC and cross-validation. Writes the \"fit\"\n"
             "section of OUT/report.json.");
  cmd->add_option("fields", opt->fields_path, "A fields.h5 (docs/FORMAT.md)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", opt->out_dir, "Output directory")->required();
  cmd->add_option("--resamples", opt->resamples, "Bootstrap resamples (default 200)")->check(CLI::Range(0, 100000));
  cmd->add_option("--folds", opt->folds, "Cross-validation folds (default 5)")->check(CLI::Range(2, 100));
  cmd->add_option("--spacing", opt->sample_spacing_m, "Sample spacing in m (default: the RVE radius)")->check(CLI::Range(0.0, 1e6));
  cmd->final_callback([opt] {
    const OutputLock lock(opt->out_dir, "pilelab fit " + opt->fields_path);
    compare::run_fit(*opt);
  });
}

}  // namespace pilelab::app
