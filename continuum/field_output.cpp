#include "continuum/field_output.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <deal.II/base/mpi.h>

#include "common/atomic_file.h"
#include "common/error.h"

namespace pilelab::continuum {

using namespace dealii;

std::string write_vtu(const DataOut<2>& data_out, const std::string& out_dir, const std::string& name,
                      MPI_Comm comm) {
  namespace fs = std::filesystem;
  const unsigned rank = Utilities::MPI::this_mpi_process(comm);
  const unsigned n_ranks = Utilities::MPI::n_mpi_processes(comm);
  auto write_with = [](const std::string& path, const std::function<void(std::ostream&)>& write) {
    write_atomically(path, [&](const std::string& tmp) {
      std::ofstream out(tmp);
      write(out);
      out.close();
      if (!out) throw InputError(path + ": cannot write the file");
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

std::vector<ProfileRow> sample_profiles(const Triangulation<2>& tria, const PileGeometry& pile,
                                        const std::vector<double>& heights, int n_points, const std::string& source,
                                        const std::vector<std::string>& quantities, const PointEvaluator& evaluate,
                                        MPI_Comm comm) {
  const std::size_t nq = quantities.size();
  std::vector<ProfileRow> rows;
  std::vector<double> values(nq);
  for (const double eta : heights) {
    const double y = eta * pile.height_m;
    const auto [x0, x1] = width_at(tria, y);
    if (!(x1 > x0)) continue;  // the cut misses the domain
    // Gather: each point is evaluated by the one rank owning its cell; sums over ranks.
    std::vector<double> local((nq + 1) * n_points, 0.0);
    std::vector<double> xs(n_points);
    for (int i = 0; i < n_points; ++i) {
      xs[i] = x0 + (x1 - x0) * (i + 0.5) / n_points;
      if (evaluate(Point<2>(xs[i], y), values)) {
        local[(nq + 1) * i] = 1.0;
        for (std::size_t q = 0; q < nq; ++q) local[(nq + 1) * i + 1 + q] = values[q];
      }
    }
    std::vector<double> global(local.size());
    MPI_Allreduce(local.data(), global.data(), static_cast<int>(local.size()), MPI_DOUBLE, MPI_SUM, comm);
    for (int i = 0; i < n_points; ++i) {
      if (global[(nq + 1) * i] != 1.0) continue;  // outside the mesh (a notch in the outline)
      for (std::size_t q = 0; q < nq; ++q)
        rows.push_back({source, quantities[q], eta, xs[i], global[(nq + 1) * i + 1 + q]});
    }
  }
  return rows;
}

void write_profiles_csv(const std::string& csv_path, const std::vector<ProfileRow>& rows) {
  std::set<std::string> replaced;
  for (const auto& r : rows) replaced.insert(r.source);
  std::ostringstream out;
  const std::string header = "source,quantity,y_over_h,x_m,value,stderr";
  out << header << "\n";
  if (std::filesystem::exists(csv_path)) {
    std::istringstream in(read_text_file(csv_path));
    std::string line;
    std::getline(in, line);
    if (line != header)
      throw InputError(csv_path + ": unexpected header \"" + line + "\" (expected \"" + header + "\")");
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      if (!replaced.count(line.substr(0, line.find(',')))) out << line << "\n";
    }
  }
  char buf[256];
  for (const auto& r : rows) {
    std::snprintf(buf, sizeof buf, "%s,%s,%.6g,%.9g,%.9g,\n", r.source.c_str(), r.quantity.c_str(), r.y_over_h,
                  r.x_m, r.value);
    out << buf;
  }
  write_text_atomically(csv_path, out.str());
}

}  // namespace pilelab::continuum
