#pragma once
// Output shared by the models: VTU files (one piece per rank plus a .pvtu record under MPI,
// each written atomically), horizontal profiles sampled at points and gathered on rank 0, and
// the long-format OUT/profiles.csv that coarse/ writes too.
#include <functional>
#include <string>
#include <vector>

#include <deal.II/base/point.h>
#include <deal.II/numerics/data_out.h>

#include "continuum/pile_domain.h"

namespace pilelab::continuum {

/// Writes OUT/<name>.vtu on one rank; on several, OUT/<name>_rank<r>.vtu per rank and
/// OUT/<name>.pvtu from rank 0. Removes the other layout's stale file. data_out must hold
/// only this rank's cells and have its patches built. Returns the file to open in ParaView.
std::string write_vtu(const dealii::DataOut<2>& data_out, const std::string& out_dir, const std::string& name,
                      MPI_Comm comm);

struct ProfileRow {
  std::string source;    ///< "elastic" or "fpa"
  std::string quantity;  ///< e.g. "sigma_yy"
  double y_over_h = 0;
  double x_m = 0;
  double value = 0;
};

/// Values of named quantities at a point. Returns false when the point's cell is not owned by
/// this rank (exactly one rank owns it, so the gathered result does not depend on the ranks).
using PointEvaluator = std::function<bool(const dealii::Point<2>&, std::vector<double>& values)>;

/// Samples `quantities` along horizontal cuts at the given heights (fractions of the pile height)
/// at n_points points spread evenly over the width of the domain at that height (cell-centred:
/// x_i = x_left + (i + 1/2) (x_right - x_left) / n_points). Collective; the rows are complete on
/// rank 0 only.
std::vector<ProfileRow> sample_profiles(const dealii::Triangulation<2>& tria, const PileGeometry& pile,
                                        const std::vector<double>& heights, int n_points, const std::string& source,
                                        const std::vector<std::string>& quantities, const PointEvaluator& evaluate,
                                        MPI_Comm comm);

/// Rewrites csv_path atomically with the rows of other sources kept and those of the sources in
/// `rows` replaced. Columns: source,quantity,y_over_h,x_m,value,stderr (stderr empty: models).
void write_profiles_csv(const std::string& csv_path, const std::vector<ProfileRow>& rows);

}  // namespace pilelab::continuum
