// The pilelab command: one subcommand per stage of the pipeline, each in its own file
// (apps/*_command.cpp). Thin by design: a subcommand parses its options and calls the
// library; errors are printed once, plainly, with exit code 2 for bad input and 3 for a run
// whose status is fail (apps/run_status.h).
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "apps/commands.h"
#include "common/error.h"
#include "common/hdf5_file.h"

int main(int argc, char** argv) {
  pilelab::disable_hdf5_exit_handler();
  CLI::App app{"pilelab: 2D sand piles by DEM, coarse-grained and compared with continuum models"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "pilelab 0.1.0");
  pilelab::app::add_dem_command(app);
  pilelab::app::add_mesh_command(app);
  pilelab::app::add_coarse_command(app);
  pilelab::app::add_compare_command(app);
  pilelab::app::add_fit_command(app);
  pilelab::app::add_run_command(app);
  pilelab::app::add_check_command(app);
  pilelab::app::add_figures_command(app);
#ifdef PILELAB_WITH_CONTINUUM
  pilelab::app::add_solve_command(app);
#endif
  try {
    app.parse(argc, argv);  // runs the chosen subcommand's action
  } catch (const CLI::ParseError& e) {
    // --help and --version end here with 0; a bad option or a missing file is bad input.
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const pilelab::app::FailedRun& e) {
    std::fprintf(stderr, "pilelab: run failed: %s\n", e.what());
    return 3;
  } catch (const pilelab::InputError& e) {
    std::fprintf(stderr, "pilelab: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pilelab: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
