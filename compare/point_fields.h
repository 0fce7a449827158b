#pragma once
// Named scalar fields at a set of points of the pile triangulation, as the DEM (fields.h5) and
// the continuum models (models.h5) deliver them, with a validity mask per field. compare/ puts
// them side by side: points are matched by their coordinates, integrals use the triangulation
// with linear interpolation between its nodes.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "dem/vec2.h"

namespace pilelab::compare {

using dem::Vec2;

struct PointFields {
  std::string source;                               ///< file (and group), for messages
  std::vector<Vec2> points;
  std::map<std::string, std::vector<double>> values;
  std::map<std::string, std::vector<char>> valid;   ///< per field and point: 1 = has data

  bool has(const std::string& name) const { return values.count(name) > 0; }
  const std::vector<double>& at(const std::string& name) const;
  bool valid_at(const std::string& name, std::size_t i) const { return valid.at(name)[i] != 0; }
  void set(const std::string& name, std::vector<double> v, std::vector<char> ok);
};

/// A triangulation whose nodes are the field points (fields at nodes).
struct Triangulation {
  std::vector<Vec2> nodes;
  std::vector<std::array<int, 3>> triangles;
};

/// fields.h5 of coarse/: every /fields/Q with its /fields/Q_count as validity, and the mesh.
/// InputError naming the file and the dataset if it is missing, not a pilelab-fields file, or
/// malformed: with a mesh, /mesh/nodes (n, 2), /mesh/triangles (t, 3) with indices in [0, n),
/// and one point per node (location "nodes") or per triangle ("cells").
PointFields read_dem_fields(const std::string& path, Triangulation* mesh = nullptr, bool* on_nodes = nullptr);

/// models.h5 of continuum/: the group of one model (its /MODEL/points and /MODEL/Q).
PointFields read_model_fields(const std::string& path, const std::string& model);
std::vector<std::string> model_names(const std::string& path);

/// For each point of `to`, the index of the point of `from` at the same place (within tol),
/// or -1. Exact matches are expected: both sides sample the same mesh points.
std::vector<int> match_points(const std::vector<Vec2>& from, const std::vector<Vec2>& to, double tol);

/// match_points of a model's points (models.h5, group `model_name`) onto the DEM's (fields.h5),
/// which must find every one: a model solved on another mesh than the one the fields were
/// coarse-grained on is an InputError naming both files and the count matched, not a
/// comparison over no points.
std::vector<int> match_model_points(const PointFields& model, const PointFields& dem, double tol, const std::string& models_path,
                                    const std::string& model_name, const std::string& fields_path);

/// `from` re-indexed onto `to`'s points (unmatched points invalid).
PointFields reindex(const PointFields& from, const std::vector<int>& index_into_from, std::size_t size);

}  // namespace pilelab::compare
