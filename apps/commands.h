#pragma once
// One function per pilelab subcommand. Each registers its options and the action that runs
// when the subcommand is chosen; the action throws InputError for bad input (exit code 2).
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

namespace pilelab::app {

/// A run that finished with status "fail" (apps/run_status.h): exit code 3.
struct FailedRun : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void add_dem_command(CLI::App& app);
void add_mesh_command(CLI::App& app);
void add_coarse_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_fit_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_check_command(CLI::App& app);
void add_figures_command(CLI::App& app);

/// How figures are drawn: required (an error when Python or the script is missing; `pilelab run`
/// skips them then), with the ParaView pictures, quietly.
struct FigureOptions {
  bool required = false;
  bool paraview = false;
  bool quiet = false;
};
/// scripts/figures.py on out_dir, and scripts/paraview_pictures.py with options.paraview.
void draw_figures(const std::string& out_dir, const FigureOptions& options);
#ifdef PILELAB_WITH_CONTINUUM
void add_solve_command(CLI::App& app);
#endif

}  // namespace pilelab::app
