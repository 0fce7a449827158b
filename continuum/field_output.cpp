#include "continuum/field_output.h"

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <cmath>
#include <limits>
#include <filesystem>
#include <fstream>

#include <deal.II/base/mpi.h>

#include "common/atomic_file.h"
#include "common/hdf5_file.h"
#include "common/error.h"

namespace pilelab::continuum {

using namespace dealii;

std::string write_vtu(DataOut<2>& data_out, const std::string& out_dir, const std::string& name,
                      MPI_Comm comm) {
  namespace fs = std::filesystem;
  // No date and time in the file: the same scene gives the same bytes.
  DataOutBase::VtkFlags flags;
  flags.print_date_and_time = false;
  data_out.set_flags(flags);
  const unsigned rank = Utilities::MPI::this_mpi_process(comm);
  const unsigned n_ranks = Utilities::MPI::n_mpi_processes(comm);
  // deal.II reports a failed stream (a full disk) by an exception whose text names neither the
  // file nor the cause: say both.
  auto write_with = [](const std::string& path, const std::function<void(std::ostream&)>& write) {
    write_atomically(path, [&](const std::string& tmp) {
      const auto failed = [&] {
        return InputError(path + ": cannot write the file: " +
                          (errno ? std::string(std::strerror(errno)) : std::string("the stream failed (is the disk full?)")));
      };
      errno = 0;
      std::ofstream out(tmp);
      if (!out) throw failed();
      try {
        write(out);
      } catch (const ExceptionBase&) {
        throw failed();
      }
      out.close();
      if (!out) throw failed();
    });
  };
  if (n_ranks == 1) {
    const std::string path = (fs::path(out_dir) / (name + ".vtu")).string();
    write_with(path, [&](std::ostream& out) { data_out.write_vtu(out); });
    std::error_code ignored;
    fs::remove(fs::path(out_dir) / (name + ".pvtu"), ignored);
    return path;
  }
  std::vector<std::string> pieces;
  for (unsigned r = 0; r < n_ranks; ++r) pieces.push_back(name + "_rank" + std::to_string(r) + ".vtu");
  write_with((fs::path(out_dir) / pieces[rank]).string(), [&](std::ostream& out) { data_out.write_vtu(out); });
  // The record goes last, once every piece is in place.
  MPI_Barrier(comm);
  const std::string path = (fs::path(out_dir) / (name + ".pvtu")).string();
  if (rank == 0) {
    write_with(path, [&](std::ostream& out) { data_out.write_pvtu_record(out, pieces); });
    std::error_code ignored;
    fs::remove(fs::path(out_dir) / (name + ".vtu"), ignored);
  }
  return path;
}

namespace {

// The x-extent of the domain along y = y0: where the horizontal line crosses the boundary.
// At the base (y0 at the lowest level) the base edges themselves give it.
std::pair<double, double> width_at(const Triangulation<2>& tria, double y0) {
  double lo = 1e300, hi = -1e300;
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto f : cell->face_indices()) {
      const auto face = cell->face(f);
      if (!face->at_boundary()) continue;
      const Point<2> a = face->vertex(0), b = face->vertex(1);
      if (a[1] == y0 && b[1] == y0) {
        lo = std::min({lo, a[0], b[0]});
        hi = std::max({hi, a[0], b[0]});
      } else if ((a[1] - y0) * (b[1] - y0) <= 0 && a[1] != b[1]) {
        const double x = a[0] + (y0 - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
    }
  return {lo, hi};
}

}  // namespace

std::vector<ProfileValue> sample_profiles(const Triangulation<2>& tria, const PileGeometry& pile,
                                        const std::vector<double>& heights, int n_points, const std::string& source,
                                        const std::vector<std::string>& field_names, const PointEvaluator& fields,
                                        double rho_g_h, MPI_Comm comm) {
  // Which fields become which profile quantity, and with which factor.
  std::vector<std::string> names;
  std::vector<double> factor;
  for (const std::string& f : field_names) {
    if (f.rfind("principal_stress", 0) == 0) {
      names.emplace_back();
      factor.push_back(0.0);
    } else if (f.rfind("stress_", 0) == 0 && f.size() == 9 && f.find_first_of("xy", 7) == 7) {
      names.push_back("sigma_" + f.substr(7));  // stress_xx -> sigma_xx, compression positive
      factor.push_back(-1.0 / rho_g_h);
    } else if (f == "pressure") {
      names.push_back(f);
      factor.push_back(1.0 / rho_g_h);
    } else {
      names.push_back(f);
      factor.push_back(1.0);
    }
  }
  const std::size_t nq = field_names.size();
  std::vector<ProfileValue> rows;
  for (const double eta : heights) {
    const double y = eta * pile.height_m;
    const auto [x0, x1] = width_at(tria, y);
    if (!(x1 > x0)) continue;  // the cut misses the domain
    const std::vector<double> xs = profile_points(x0, x1, n_points);
    std::vector<Point<2>> points;
    for (double x : xs) points.emplace_back(x, y);
    const auto values = evaluate_at_points(points, nq, fields, comm);
    for (int i = 0; i < n_points; ++i) {
      if (std::isnan(values[0][i])) continue;  // outside the mesh (a notch in the outline): no row
      for (std::size_t q = 0; q < nq; ++q)
        if (!names[q].empty()) rows.push_back({source, names[q], eta, xs[i], factor[q] * values[q][i], 0.0, false});
    }
  }
  return rows;
}

std::vector<std::vector<double>> evaluate_at_points(const std::vector<Point<2>>& points, std::size_t nq,
                                                    const PointEvaluator& evaluate, MPI_Comm comm) {
  // Each point is evaluated by the ranks that own a cell around it. A point on the border of
  // two ranks' cells (a vertex, as every models.h5 point is) is found by both: the lowest of
  // them gives its value, so that each point has exactly one value, whatever the partition
  // (a sum of both made such points NaN). A point no rank finds is outside the mesh: NaN.
  const std::size_t n = points.size();
  const int rank = static_cast<int>(Utilities::MPI::this_mpi_process(comm));
  const int nobody = static_cast<int>(Utilities::MPI::n_mpi_processes(comm));
  std::vector<double> local_values(nq * n, 0.0);
  std::vector<int> local_owner(n, nobody), owner(n);
  std::vector<double> v(nq);
  for (std::size_t i = 0; i < n; ++i)
    if (evaluate(points[i], v)) {
      local_owner[i] = rank;
      for (std::size_t q = 0; q < nq; ++q) local_values[nq * i + q] = v[q];
    }
  MPI_Allreduce(local_owner.data(), owner.data(), static_cast<int>(n), MPI_INT, MPI_MIN, comm);
  for (std::size_t i = 0; i < n; ++i)
    if (owner[i] != rank)
      for (std::size_t q = 0; q < nq; ++q) local_values[nq * i + q] = 0.0;
  std::vector<double> global(nq * n);
  MPI_Allreduce(local_values.data(), global.data(), static_cast<int>(global.size()), MPI_DOUBLE, MPI_SUM, comm);
  std::vector<std::vector<double>> out(nq, std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t q = 0; q < nq; ++q)
      out[q][i] = owner[i] < nobody ? global[nq * i + q] : std::numeric_limits<double>::quiet_NaN();
  return out;
}

std::vector<Point<2>> model_output_points(const Triangulation<2>& tria) {
  std::vector<Point<2>> points;
  const auto& vertices = tria.get_vertices();
  const auto& used = tria.get_used_vertices();
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (used[i]) points.push_back(vertices[i]);
  for (const auto& cell : tria.active_cell_iterators()) points.push_back(cell->center());
  return points;
}

void write_models_h5(const std::string& path, const Triangulation<2>& tria, const std::vector<Point<2>>& points,
                     const std::vector<ModelFields>& models, double rho_g_h, double height_m) {
  // The vertices in the order model_output_points lists them, and the triangles in those indices.
  const auto& used = tria.get_used_vertices();
  std::vector<std::int64_t> output_index(used.size(), -1);
  std::int64_t vertex_count = 0;
  for (std::size_t i = 0; i < used.size(); ++i)
    if (used[i]) output_index[i] = vertex_count++;
  std::vector<std::int64_t> triangles;
  for (const auto& cell : tria.active_cell_iterators())
    for (unsigned int k = 0; k < cell->n_vertices(); ++k) triangles.push_back(output_index[cell->vertex_index(k)]);
  const std::uint64_t corners = tria.n_active_cells() ? triangles.size() / tria.n_active_cells() : 3;
  write_atomically(path, [&](const std::string& tmp) {
    H5File f = H5File::create(tmp);
    f.set_attribute("/", "format", std::string("pilelab-models"));
    f.set_attribute("/", "format_version", std::int64_t(1));
    f.set_attribute("/", "rho_g_h_N_per_m", rho_g_h);
    f.set_attribute("/", "height_m", height_m);
    f.set_attribute("/", "vertex_count", vertex_count);
    f.write("/mesh/triangles", triangles, {tria.n_active_cells(), corners});
    f.set_attribute("/", "note", std::string("stress_* tension positive (N/m, 2D); pressure and principal "
                                             "stresses compression positive; NaN: point outside the mesh"));
    std::vector<double> xy;
    for (const auto& p : points) xy.insert(xy.end(), {p[0], p[1]});
    for (const ModelFields& m : models) {
      f.write("/" + m.model + "/points", xy, {points.size(), 2}, "m");
      for (std::size_t q = 0; q < m.names.size(); ++q)
        f.write("/" + m.model + "/" + m.names[q], m.values[q], {points.size()}, m.units[q]);
      for (const auto& [key, value] : m.attributes) f.set_attribute("/" + m.model, key, value);
    }
    f.close();
  });
}

}  // namespace pilelab::continuum
