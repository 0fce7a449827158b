#pragma once
// Output shared by the models: VTU files (one piece per rank plus a .pvtu record under MPI,
// each written atomically) and horizontal profiles sampled at points and gathered on rank 0,
// at the points coarse/ uses, for OUT/profiles.csv (common/profiles_csv.h).
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <deal.II/base/point.h>
#include <deal.II/numerics/data_out.h>

#include "common/profiles_csv.h"
#include "continuum/pile_domain.h"

namespace pilelab::continuum {

/// Writes OUT/<name>.vtu on one rank; on several, OUT/<name>_rank<r>.vtu per rank and
/// OUT/<name>.pvtu from rank 0. Removes the other layout's stale file. data_out must hold
/// only this rank's cells and have its patches built. Returns the file to open in ParaView.
std::string write_vtu(dealii::DataOut<2>& data_out, const std::string& out_dir, const std::string& name,
                      MPI_Comm comm);

/// Values of named quantities at a point. Returns false when the point's cell is not owned by
/// this rank (exactly one rank owns it, so the gathered result does not depend on the ranks).
using PointEvaluator = std::function<bool(const dealii::Point<2>&, std::vector<double>& values)>;

/// Samples a model's fields (named as in models.h5) along horizontal cuts at the given heights
/// (fractions of the pile height), at n_points points across the width of the domain there
/// (pilelab::profile_points: cell-centred, as coarse/ samples the DEM), and turns them into
/// profile rows the way coarse/ does: stress_Q becomes sigma_Q = -stress_Q / (rho g h), pressure
/// is divided by rho g h (compression positive), principal stresses are left out, every other
/// field is kept as it is. Collective; every rank gets all rows.
std::vector<ProfileValue> sample_profiles(const dealii::Triangulation<2>& tria, const PileGeometry& pile,
                                        const std::vector<double>& heights, int n_points, const std::string& source,
                                        const std::vector<std::string>& field_names, const PointEvaluator& fields,
                                        double rho_g_h, MPI_Comm comm);

/// Evaluates n_values quantities at every point (collective). values[q][i]; NaN where no rank
/// owns a cell containing point i (outside the mesh).
std::vector<std::vector<double>> evaluate_at_points(const std::vector<dealii::Point<2>>& points, std::size_t n_values,
                                                    const PointEvaluator& evaluate, MPI_Comm comm);

/// One model's fields at points, for OUT/models.h5 (what compare/ reads).
struct ModelFields {
  std::string model;                           ///< group name: "elastic" or "fpa"
  std::vector<std::string> names, units;       ///< one per quantity
  std::vector<std::vector<double>> values;     ///< [quantity][point]
  std::map<std::string, double> attributes;    ///< of the group, e.g. elastic: gravity_change
};

/// Writes OUT/models.h5 atomically: root attributes format = "pilelab-models", format_version = 1,
/// vertex_count (the first vertex_count points are the mesh vertices, the rest the cell
/// centres), /mesh/triangles (m, 3) in those vertex indices, and per model a group with
/// /MODEL/points (k, 2), one dataset per quantity (attribute unit) and the model's attributes.
/// points are model_output_points(tria).
void write_models_h5(const std::string& path, const dealii::Triangulation<2>& tria,
                     const std::vector<dealii::Point<2>>& points, const std::vector<ModelFields>& models,
                     double rho_g_h, double height_m);

/// The points models.h5 carries: every mesh vertex, then every cell centre (coarse/ samples the
/// DEM at one or the other, and compare/ matches points by their coordinates).
std::vector<dealii::Point<2>> model_output_points(const dealii::Triangulation<2>& tria);

}  // namespace pilelab::continuum
