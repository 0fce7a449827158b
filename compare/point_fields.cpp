#include "compare/point_fields.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "common/error.h"
#include "common/hdf5_file.h"

namespace pilelab::compare {

const std::vector<double>& PointFields::at(const std::string& name) const {
  const auto it = values.find(name);
  if (it == values.end()) throw InputError(source + ": no field '" + name + "'");
  return it->second;
}

void PointFields::set(const std::string& name, std::vector<double> v, std::vector<char> ok) {
  values[name] = std::move(v);
  valid[name] = std::move(ok);
}

namespace {

// The files' layout is version 1 (docs/FORMAT.md); a later version is another layout that this
// build cannot read, and is refused rather than misread.
void check_format_version(const H5File& f, const std::string& path, const char* kind) {
  std::int64_t version = 0;
  try {
    version = f.attribute_int("/", "format_version");
  } catch (const InputError&) {
    throw InputError(path + ": root attribute format_version missing: expected 1 (a pilelab " + kind + " file)");
  }
  if (version != 1)
    throw InputError(path + ": root attribute format_version = " + std::to_string(version) +
                     ": this build reads version 1 of the " + kind + " file (docs/FORMAT.md)");
}

}  // namespace

PointFields read_dem_fields(const std::string& path, Triangulation* mesh, bool* on_nodes) {
  H5File f = H5File::open_read(path);
  std::string format;
  try {
    format = f.attribute_string("/", "format");
  } catch (const InputError&) {
  }
  if (format != "pilelab-fields")
    throw InputError(path + ": not a pilelab fields file (root attribute format = \"pilelab-fields\" expected)");
  check_format_version(f, path, "fields");
  PointFields out;
  out.source = path;
  std::vector<std::uint64_t> dims;
  const auto xy = f.read_finite_doubles("/fields/points", &dims);
  if (dims.size() != 2 || dims[1] != 2 || xy.size() != 2 * dims[0])
    throw InputError(path + ": /fields/points must have shape (k, 2)");
  for (std::size_t i = 0; i < dims[0]; ++i) out.points.emplace_back(xy[2 * i], xy[2 * i + 1]);
  const std::vector<std::string> names = f.list("/fields");
  auto is_field = [&](const std::string& n) { return std::find(names.begin(), names.end(), n) != names.end(); };
  auto ends_with = [](const std::string& n, const std::string& tail) {
    return n.size() > tail.size() && n.compare(n.size() - tail.size(), tail.size(), tail) == 0;
  };
  for (const std::string& name : names) {
    if (name == "points" || name == "piles_with_data") continue;
    // A field Q comes with Q_count (and Q_stderr for an ensemble); grain_count is a field of its
    // own (it has grain_count_count). A count or error whose field is missing is a damaged file.
    if (!is_field(name + "_count")) {
      const bool belongs = (ends_with(name, "_count") && is_field(name.substr(0, name.size() - 6))) ||
                           (ends_with(name, "_stderr") && is_field(name.substr(0, name.size() - 7)));
      if (belongs) continue;
      throw InputError(path + ": /fields/" + name + ": expected a field with its count /fields/" + name +
                       "_count, or the count or standard error of a field; the field it belongs to is missing");
    }
    auto values = f.read_doubles("/fields/" + name);
    const auto count = f.read_ints("/fields/" + name + "_count");
    if (values.size() != out.points.size() || count.size() != out.points.size())
      throw InputError(path + ": /fields/" + name + " does not have one value per point");
    std::vector<char> ok(count.size());
    for (std::size_t i = 0; i < count.size(); ++i) {
      // A value counted from grains must be a number; where nothing was counted it is unused.
      if (count[i] > 0 && !std::isfinite(values[i]))
        throw InputError(path + ": /fields/" + name + " row " + std::to_string(i) + " is " + std::to_string(values[i]) +
                         " where " + std::to_string(count[i]) + " grains were counted (/fields/" + name +
                         "_count); expected a finite number");
      ok[i] = count[i] > 0;
    }
    out.set(name, std::move(values), std::move(ok));
  }
  const std::string location = f.attribute_string("/fields", "location");
  if (location != "nodes" && location != "cells")
    throw InputError(path + ": /fields attribute location is \"" + location + "\"; expected \"nodes\" or \"cells\"");
  if (mesh) {
    // Integrals index the fields by node and the nodes by triangle: shapes and indices are
    // checked here, once, so that a damaged file is an error and not a read past an array.
    const auto nodes = f.read_finite_doubles("/mesh/nodes", &dims);
    if (dims.size() != 2 || dims[1] != 2 || nodes.size() != 2 * dims[0])
      throw InputError(path + ": /mesh/nodes must have shape (n, 2)");
    mesh->nodes.clear();
    for (std::size_t i = 0; i < dims[0]; ++i) mesh->nodes.emplace_back(nodes[2 * i], nodes[2 * i + 1]);
    const auto tri = f.read_ints("/mesh/triangles", &dims);
    if (dims.size() != 2 || dims[1] != 3 || tri.size() != 3 * dims[0])
      throw InputError(path + ": /mesh/triangles must have shape (t, 3)");
    const auto n = static_cast<std::int64_t>(mesh->nodes.size());
    mesh->triangles.clear();
    for (std::size_t t = 0; t < dims[0]; ++t) {
      for (int k = 0; k < 3; ++k)
        if (tri[3 * t + k] < 0 || tri[3 * t + k] >= n)
          throw InputError(path + ": /mesh/triangles row " + std::to_string(t) + " has node index " +
                           std::to_string(tri[3 * t + k]) + "; expected 0 .. " + std::to_string(n - 1) +
                           " (/mesh/nodes has " + std::to_string(n) + " rows)");
      mesh->triangles.push_back({static_cast<int>(tri[3 * t]), static_cast<int>(tri[3 * t + 1]), static_cast<int>(tri[3 * t + 2])});
      // Integrals weigh by area: a triangle of no area is a damaged mesh, not a zero weight.
      const auto& c = mesh->triangles.back();
      const Vec2 e1 = mesh->nodes[c[1]] - mesh->nodes[c[0]], e2 = mesh->nodes[c[2]] - mesh->nodes[c[0]];
      if (!(std::abs(e1.x() * e2.y() - e1.y() * e2.x()) > 0))
        throw InputError(path + ": /mesh/triangles row " + std::to_string(t) + " (nodes " + std::to_string(c[0]) + ", " +
                         std::to_string(c[1]) + ", " + std::to_string(c[2]) + ") has no area: expected a triangle");
    }
    const std::size_t expected = location == "nodes" ? mesh->nodes.size() : mesh->triangles.size();
    if (out.points.size() != expected)
      throw InputError(path + ": /fields/points has " + std::to_string(out.points.size()) + " rows; with location = \"" +
                       location + "\" expected one per " + (location == "nodes" ? "row of /mesh/nodes (" : "row of /mesh/triangles (") +
                       std::to_string(expected) + ")");
  }
  if (on_nodes) *on_nodes = location == "nodes";
  return out;
}

std::vector<std::string> model_names(const std::string& path) {
  H5File f = H5File::open_read(path);
  std::vector<std::string> names;
  for (const std::string& name : f.list("/"))
    if (name != "mesh") names.push_back(name);  // the triangulation, not a model
  return names;
}

PointFields read_model_fields(const std::string& path, const std::string& model) {
  H5File f = H5File::open_read(path);
  check_format_version(f, path, "models");
  const std::string g = "/" + model;
  if (!f.exists(g)) throw InputError(path + ": no model '" + model + "' (group " + g + ")");
  PointFields out;
  out.source = path + " (" + model + ")";
  std::vector<std::uint64_t> dims;
  const auto xy = f.read_finite_doubles(g + "/points", &dims);
  if (dims.size() != 2 || dims[1] != 2) throw InputError(path + ": " + g + "/points must have shape (k, 2)");
  for (std::size_t i = 0; i < dims[0]; ++i) out.points.emplace_back(xy[2 * i], xy[2 * i + 1]);
  for (const std::string& name : f.list(g)) {
    if (name == "points") continue;
    // A model is evaluated at its own mesh's nodes, so every value is a number: a NaN or an
    // infinity is damage, refused with its row, not a point quietly left out of the comparison.
    auto values = f.read_finite_doubles(g + "/" + name);
    if (values.size() != out.points.size())
      throw InputError(path + ": " + g + "/" + name + " does not have one value per point");
    std::vector<char> ok(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) ok[i] = std::isfinite(values[i]);
    out.set(name, std::move(values), std::move(ok));
  }
  return out;
}

std::vector<int> match_points(const std::vector<Vec2>& from, const std::vector<Vec2>& to, double tol) {
  // Hash the source points on a grid of cell tol*4; look up the 3x3 neighbourhood.
  const double cell = std::max(tol * 4, 1e-300);
  auto key = [&](long i, long j) { return i * 73856093L ^ j * 19349663L; };
  std::unordered_multimap<long, int> grid;
  for (std::size_t k = 0; k < from.size(); ++k)
    grid.emplace(key(std::lround(from[k].x() / cell), std::lround(from[k].y() / cell)), static_cast<int>(k));
  std::vector<int> index(to.size(), -1);
  for (std::size_t k = 0; k < to.size(); ++k) {
    const long i0 = std::lround(to[k].x() / cell), j0 = std::lround(to[k].y() / cell);
    double best = tol;
    for (long i = i0 - 1; i <= i0 + 1; ++i)
      for (long j = j0 - 1; j <= j0 + 1; ++j) {
        const auto range = grid.equal_range(key(i, j));
        for (auto it = range.first; it != range.second; ++it) {
          const double d = (from[it->second] - to[k]).norm();
          if (d <= best) best = d, index[k] = it->second;
        }
      }
  }
  return index;
}

std::vector<int> match_model_points(const PointFields& model, const PointFields& dem, double tol, const std::string& models_path,
                                    const std::string& model_name, const std::string& fields_path) {
  std::vector<int> index = match_points(model.points, dem.points, tol);
  const auto matched = static_cast<std::size_t>(std::count_if(index.begin(), index.end(), [](int i) { return i >= 0; }));
  if (matched < dem.points.size())
    throw InputError(models_path + ": /" + model_name + "/points: " + std::to_string(matched) + " of the " +
                     std::to_string(dem.points.size()) + " points of " + fields_path +
                     " are points of this model: the two files come from different meshes (solve on the mesh the fields "
                     "were coarse-grained on: continuum.mesh_file = coarse's mesh_file)");
  return index;
}

PointFields reindex(const PointFields& from, const std::vector<int>& index, std::size_t size) {
  PointFields out;
  out.source = from.source;
  out.points.resize(size);
  for (const auto& [name, values] : from.values) {
    std::vector<double> v(size, 0.0);
    std::vector<char> ok(size, 0);
    for (std::size_t k = 0; k < size; ++k)
      if (index[k] >= 0) {
        v[k] = values[index[k]];
        ok[k] = from.valid.at(name)[index[k]];
      }
    out.set(name, std::move(v), std::move(ok));
  }
  for (std::size_t k = 0; k < size; ++k)
    if (index[k] >= 0) out.points[k] = from.points[index[k]];
  return out;
}

}  // namespace pilelab::compare
