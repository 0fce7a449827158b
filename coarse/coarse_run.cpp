#include "coarse/coarse_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <sstream>

#include "coarse/coarse_scene.h"
#include "coarse/kernel_average.h"
#include "coarse/quantities.h"
#include "coarse/rve_study.h"
#include "coarse/virial_identity.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "common/fields_attributes.h"
#include "common/hdf5_file.h"
#include "common/profiles_csv.h"
#include "common/triangle_vtu.h"
#include "common/report.h"
#include "common/scene_tables.h"
#include "mesh/pile_mesh.h"

namespace pilelab::coarse {

namespace {

using Clock = std::chrono::steady_clock;

// One pile: its packing at the averaged snapshot, the later one for strains, the averager.
struct Pile {
  std::string path;
  std::unique_ptr<Packing> packing, later;
  std::unique_ptr<RveAverager> rve, rve_later;        ///< rve_later: stress at the later snapshot
  std::unique_ptr<KernelAverager> kernel, kernel_later;
  double height = 0.0;      ///< top of the highest grain [m]
  double grain_area = 0.0;  ///< sum of grain areas [m^2]
  double mass = 0.0;        ///< [kg]
  double time = 0.0;        ///< simulated time of the snapshot [s]
};

double top_of(const Grain& g) {
  if (!g.shape) return g.centre.y();
  if (g.shape->kind == dem::ShapeKind::disc) return g.centre.y() + g.shape->radius;
  double top = -INFINITY;
  for (const Vec2& v : world_outline(g)) top = std::max(top, v.y());
  return top;
}

Domain domain_of(const mesh::TriangleMesh& m) {
  // Boundary edges, oriented as in their triangle (counter-clockwise around the material).
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  Domain d;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (count[{std::min(a, b), std::max(a, b)}] == 1) d.edges.emplace_back(m.nodes[a], m.nodes[b]);
    }
  return d;
}

// x extent of the domain along the horizontal line at height y (from its boundary edges).
std::pair<double, double> x_range_at(const Domain& d, double y) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& [a, b] : d.edges) {
    if (a.y() == y) lo = std::min(lo, a.x()), hi = std::max(hi, a.x());
    if (b.y() == y) lo = std::min(lo, b.x()), hi = std::max(hi, b.x());
    if ((a.y() - y) * (b.y() - y) < 0) {
      const double x = a.x() + (y - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
      lo = std::min(lo, x), hi = std::max(hi, x);
    }
  }
  return {lo, hi};
}

// Mean and standard error of the values present (NaN marks "no data in this pile").
struct Stat {
  double mean = 0, stderr_ = 0;
  int n = 0;
};
Stat stat_of(const std::vector<double>& v) {
  Stat s;
  double sum = 0;
  for (double x : v)
    if (!std::isnan(x)) sum += x, ++s.n;
  if (s.n == 0) return s;
  s.mean = sum / s.n;
  if (s.n > 1) {
    double ss = 0;
    for (double x : v)
      if (!std::isnan(x)) ss += (x - s.mean) * (x - s.mean);
    s.stderr_ = std::sqrt(ss / (s.n - 1) / s.n);
  }
  return s;
}

// The sampled fields of all piles at a list of points: value[q][point] over piles.
struct Samples {
  std::vector<std::vector<Stat>> stats;  ///< [quantity][point]
  /// Ensembles: each pile's own values of the fit's quantities, [name][pile][point] (NaN: no
  /// data), so that fits can be bootstrapped over piles.
  std::map<std::string, std::vector<std::vector<double>>> per_pile;
};

// The quantities kept per pile in ensembles: what a stress-strain fit resamples over piles, what
// the comparison's jackknife re-averages (stresses, displacements, strains), and the packing's
// scalars, so that any statistic of the ensemble (a ratio, a position of a maximum) can be
// recomputed pile by pile or with one pile left out.
const std::vector<std::string> pile_quantities = {"stress_change_xx", "stress_change_yy", "stress_change_xy",
                                                  "strain_xx", "strain_yy", "strain_xy", "fabric_xx",
                                                  "fabric_yy", "fabric_xy", "pressure", "stress_xx",
                                                  "stress_yy", "stress_xy", "displacement_x", "displacement_y",
                                                  "volume_fraction", "coordination", "grain_count"};

void write_vtu(const std::string& path, const mesh::TriangleMesh& m, bool on_nodes, const Samples& samples,
               bool with_stderr, double time_s) {
  std::vector<VtuField> fields;
  const std::size_t n = samples.stats[0].size();
  auto add = [&](const std::string& name, auto value_of) {
    VtuField f{name, std::vector<double>(n)};
    for (std::size_t i = 0; i < n; ++i) f.values[i] = value_of(i);
    fields.push_back(std::move(f));
  };
  const auto& qs = quantities();
  add("has_data", [&](std::size_t i) { return samples.stats[1][i].n > 0 ? 1.0 : 0.0; });
  for (std::size_t q = 0; q < qs.size(); ++q) {
    add(qs[q].name, [&](std::size_t i) { return samples.stats[q][i].mean; });
    if (with_stderr) add(qs[q].name + "_stderr", [&](std::size_t i) { return samples.stats[q][i].stderr_; });
  }
  // Vectors for ParaView's Glyph and Warp: the displacement, and the principal axes of the
  // mean stress (compressive, compression positive) and of the fabric, each scaled by its
  // principal value (an axis has no sign: the arrow's direction is arbitrary up to +-).
  const auto index_of = [&](const std::string& name) {
    for (std::size_t q = 0; q < qs.size(); ++q)
      if (qs[q].name == name) return static_cast<int>(q);
    return -1;
  };
  const auto mean = [&](int q, std::size_t i) { return q < 0 ? 0.0 : samples.stats[q][i].mean; };
  const auto add_vector = [&](const std::string& name, auto vector_of) {
    VtuField f{name, std::vector<double>(3 * n), 3};
    for (std::size_t i = 0; i < n; ++i) {
      const std::array<double, 2> v = vector_of(i);
      f.values[3 * i] = v[0];
      f.values[3 * i + 1] = v[1];
    }
    fields.push_back(std::move(f));
  };
  // Principal pair of the symmetric tensor [[a, c], [c, b]]: the larger eigenvalue (first) and
  // the smaller, each with its unit eigenvector.
  const auto principal = [](double a, double b, double c, bool major) -> std::array<double, 2> {
    const double centre = 0.5 * (a + b), radius = std::hypot(0.5 * (a - b), c);
    const double lambda = major ? centre + radius : centre - radius;
    const double theta = 0.5 * std::atan2(2.0 * c, a - b) + (major ? 0.0 : 0.5 * M_PI);
    return {lambda * std::cos(theta), lambda * std::sin(theta)};
  };
  const int ux = index_of("displacement_x"), uy = index_of("displacement_y");
  if (ux >= 0 && uy >= 0) add_vector("displacement", [&](std::size_t i) { return std::array<double, 2>{mean(ux, i), mean(uy, i)}; });
  const int sxx = index_of("stress_xx"), syy = index_of("stress_yy"), sxy = index_of("stress_xy");
  for (const bool major : {true, false})
    add_vector(major ? "stress_major_axis" : "stress_minor_axis", [&](std::size_t i) {
      return principal(-mean(sxx, i), -mean(syy, i), -mean(sxy, i), major);  // of the compression
    });
  const int fxx = index_of("fabric_xx"), fyy = index_of("fabric_yy"), fxy = index_of("fabric_xy");
  add_vector("fabric_major_axis", [&](std::size_t i) { return principal(mean(fxx, i), mean(fyy, i), mean(fxy, i), true); });

  std::vector<std::array<double, 2>> nodes;
  for (const auto& p : m.nodes) nodes.push_back({p.x(), p.y()});
  if (on_nodes) write_triangle_vtu(path, nodes, m.triangles, fields, {}, time_s);
  else write_triangle_vtu(path, nodes, m.triangles, {}, fields, time_s);
}

void write_fields_h5(const std::string& path, const mesh::TriangleMesh& m, bool on_nodes,
                     const std::vector<Vec2>& points, const Samples& samples, const FieldsAttributes& attributes) {
  write_atomically(path, [&](const std::string& tmp) {
    H5File f = H5File::create(tmp);
    write_fields_attributes(f, attributes);
    std::vector<double> xy;
    for (const auto& p : m.nodes) xy.push_back(p.x()), xy.push_back(p.y());
    f.write("/mesh/nodes", xy, {m.nodes.size(), 2}, "m");
    std::vector<std::int64_t> tri;
    for (const auto& t : m.triangles) tri.insert(tri.end(), t.begin(), t.end());
    f.write("/mesh/triangles", tri, {m.triangles.size(), 3});
    std::vector<double> pxy;
    for (const auto& p : points) pxy.push_back(p.x()), pxy.push_back(p.y());
    f.write("/fields/points", pxy, {points.size(), 2}, "m");
    f.set_attribute("/fields", "location", std::string(on_nodes ? "nodes" : "cells"));
    const auto& qs = quantities();
    std::vector<std::int64_t> has(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) has[i] = samples.stats[1][i].n;
    f.write("/fields/piles_with_data", has);
    for (std::size_t q = 0; q < qs.size(); ++q) {
      std::vector<double> mean(points.size()), err(points.size());
      std::vector<std::int64_t> count(points.size());
      for (std::size_t i = 0; i < points.size(); ++i) {
        mean[i] = samples.stats[q][i].mean;
        err[i] = samples.stats[q][i].stderr_;
        count[i] = samples.stats[q][i].n;
      }
      f.write("/fields/" + qs[q].name, mean, {}, qs[q].unit);
      f.write("/fields/" + qs[q].name + "_stderr", err, {}, qs[q].unit);
      f.write("/fields/" + qs[q].name + "_count", count);
    }
    for (const auto& [name, piles] : samples.per_pile)
      for (std::size_t k = 0; k < piles.size(); ++k) f.write("/piles/" + std::to_string(k) + "/" + name, piles[k], {}, "");
    f.close();
  });
}

}  // namespace

namespace {

// --- The steps of the coarse-graining ---------------------------------------------------------

// The piles to average (one, or an ensemble's members), read at the averaged snapshot and, where
// present, the later one for strains; with what the sizes and scales below are derived from.
struct PileSet {
  std::vector<Pile> piles;
  int piles_with_strains = 0;
  double gravity_change = 0.0;   ///< g(strain_to) / g(snapshot) - 1, of the first pile with both
  double mean_height = 0.0;      ///< [m]
  double gravity = 0.0;          ///< [m/s^2]
  double bulk_fraction = 0.0;    ///< grain area over pile (mesh) area
  double rho_bulk = 0.0;         ///< mean grain mass over mesh area [kg/m^2]
  double grain_size_area = 0.0;  ///< mean area of a grain [m^2]
  double snapshot_time = 0.0;    ///< the snapshots' mean simulated time [s]
  double diameter() const { return 2 * std::sqrt(grain_size_area / M_PI); }
  /// The RVE radius that holds `count` grains on average.
  double radius_for(double count) const { return std::sqrt(count * grain_size_area / (M_PI * bulk_fraction)); }
};

// A pile must lie on the mesh that coarse-grains it. A mesh of another pile or scene left the
// fields empty and the volume fraction meaningless (grain area over a mesh that holds none of
// it: 3209 was seen). So the grains whose centres lie in the mesh must cover at least a quarter
// of its area: a settled 2D packing covers about 0.8, and a mesh three quarters empty is not
// this pile's. A mesh of part of the pile (its core, say) passes: the grains outside are left out.
void require_pile_on_mesh(const Pile& pile, double mesh_area, const std::string& mesh_file) {
  double area_inside = 0;  // of the grains the averager keeps: centres in the mesh
  for (std::size_t p = 0; p < pile.packing->grains.size(); ++p)
    if (pile.rve->grain_in_domain(p)) area_inside += pile.packing->grains[p].area;
  if (area_inside < 0.25 * mesh_area) {
    std::ostringstream m;
    m << pile.path << ": " << pile.rve->grains_outside_domain() << " of its " << pile.packing->grains.size()
      << " grains lie outside the mesh " << mesh_file << " (coarse.mesh_file), and those inside cover "
      << 100 * area_inside / mesh_area << " % of its area: expected a mesh of this pile (pilelab mesh on its dem.h5)";
    throw InputError(m.str());
  }
}

PileSet read_piles(const CoarseSettings& settings, double mesh_area) {
  PileSet set;
  for (const std::string& path : settings.dem_files) {
    Pile pile;
    pile.path = path;
    const dem::DemFile file = dem::read_dem_file(path);
    const dem::Snapshot snapshot = file.snapshot(settings.snapshot);
    pile.time = snapshot.time;
    pile.packing = std::make_unique<Packing>(packing_from_snapshot(file, snapshot));
    // Every size below (grain diameter, RVE radius, kernel width) is derived from the grains;
    // without any they would be 0/0.
    if (pile.packing->grains.empty())
      throw InputError(path + ": snapshot '" + settings.snapshot +
                       "' (coarse.snapshot) has no grains; coarse-graining needs a poured pile");
    if (file.has_snapshot(settings.strain_to)) {
      pile.later = std::make_unique<Packing>(packing_from_snapshot(file, file.snapshot(settings.strain_to)));
      if (set.piles_with_strains++ == 0)
        set.gravity_change = pile.later->gravity.norm() / pile.packing->gravity.norm() - 1.0;
    }
    for (const Grain& g : pile.packing->grains) {
      pile.height = std::max(pile.height, top_of(g));
      pile.grain_area += g.area;
      pile.mass += g.mass;
    }
    set.piles.push_back(std::move(pile));
  }
  double mean_mass = 0, mean_grain_area = 0, grains = 0;
  const double n = static_cast<double>(set.piles.size());
  for (const Pile& p : set.piles) {
    set.mean_height += p.height / n;
    set.snapshot_time += p.time / n;
    mean_mass += p.mass / n;
    mean_grain_area += p.grain_area / n;
    grains += static_cast<double>(p.packing->grains.size()) / n;
  }
  set.gravity = set.piles.front().packing->gravity.norm();
  set.bulk_fraction = mean_grain_area / mesh_area;
  set.rho_bulk = mean_mass / mesh_area;
  set.grain_size_area = mean_grain_area / grains;
  return set;
}

// The points of the RVE-size study: the scene's, else three at a quarter of the height (on the
// axis through the apex and half-way to either flank).
std::vector<Vec2> rve_study_points(const CoarseSettings& settings, const mesh::TriangleMesh& mesh, const Domain& domain,
                                   double height) {
  std::vector<Vec2> points;
  for (std::size_t i = 0; i < settings.study_x_m.size(); ++i)
    points.emplace_back(settings.study_x_m[i], settings.study_y_over_h[i] * height);
  if (!points.empty()) return points;
  const double y = 0.25 * height;
  const auto [lo, hi] = x_range_at(domain, y);
  double axis = 0.5 * (lo + hi), top = -INFINITY;  // the vertical through the apex
  for (const Vec2& n : mesh.nodes)
    if (n.y() > top) top = n.y(), axis = n.x();
  return {{axis, y}, {0.5 * (lo + axis), y}, {0.5 * (axis + hi), y}};
}

// The fields of every pile at any point, averaged over the piles: RVE (paper eq. 12-19) or
// kernel windows of one size, with the stress change to the later snapshot in the same window
// (the increment that goes with the strain).
class EnsembleSampler {
 public:
  EnsembleSampler(const std::vector<Pile>& piles, double rve_radius) : piles_(piles), radius_(rve_radius) {}

  /// Each quantity at each point: the value of the ensemble-mean sample (tensors averaged,
  /// then derived), and the standard error of the per-pile values (axes unwrapped to within
  /// 90 degrees of the mean before their spread is taken); with keep_piles, an ensemble's
  /// per-pile values of pile_quantities too.
  Samples sample(const std::vector<Vec2>& points, bool keep_piles) const {
    const auto& qs = quantities();
    Samples out;
    out.stats.assign(qs.size(), std::vector<Stat>(points.size()));
    std::vector<std::size_t> kept;  // indices into qs of the per-pile quantities
    if (keep_piles && piles_.size() > 1)
      for (std::size_t q = 0; q < qs.size(); ++q)
        if (std::find(pile_quantities.begin(), pile_quantities.end(), qs[q].name) != pile_quantities.end()) {
          kept.push_back(q);
          out.per_pile[qs[q].name].assign(piles_.size(), std::vector<double>(points.size(), NAN));
        }
#pragma omp parallel for schedule(dynamic, 64)
    for (std::size_t i = 0; i < points.size(); ++i) {
      std::vector<RveSample> per_pile;
      for (const Pile& p : piles_) per_pile.push_back(sample_pile(p, points[i]));
      const RveSample mean = mean_sample(per_pile);
      for (std::size_t q : kept)
        for (std::size_t k = 0; k < per_pile.size(); ++k)
          if (const auto v = qs[q].value(per_pile[k])) out.per_pile[qs[q].name][k][i] = *v;
      for (std::size_t q = 0; q < qs.size(); ++q) {
        const auto m = qs[q].value(mean);
        std::vector<double> values;
        for (const RveSample& s : per_pile) {
          auto v = qs[q].value(s);
          if (!v) continue;
          if (qs[q].is_axis && m) *v += 180.0 * std::round((*m - *v) / 180.0);
          values.push_back(*v);
        }
        Stat st = stat_of(values);
        if (!m || values.empty()) st = Stat{};
        else st.mean = *m;
        out.stats[q][i] = st;
      }
    }
    return out;
  }

 private:
  RveSample sample_pile(const Pile& p, const Vec2& x) const {
    RveSample s = p.kernel ? p.kernel->average(x) : p.rve->average(x, radius_);
    if (s.has_data() && (p.kernel_later || p.rve_later)) {
      const RveSample later = p.kernel ? p.kernel_later->average(x) : p.rve_later->average(x, radius_);
      if (later.has_data()) {
        s.stress_change = later.stress - s.stress;
        s.has_stress_change = true;
      }
    }
    return s;
  }

  const std::vector<Pile>& piles_;
  double radius_;
};

// Profiles along horizontal cuts at the scene's heights, stresses over rho g h and compression
// positive: the rows of profiles.csv (source "dem").
std::vector<ProfileValue> profile_rows(const CoarseSettings& settings, const Domain& domain, const EnsembleSampler& sampler,
                                       double height, double stress_scale) {
  std::vector<ProfileValue> rows;
  for (double f : settings.profile_heights) {
    const double y = f * height;
    auto [lo, hi] = x_range_at(domain, y);
    if (!(lo < hi)) continue;
    std::vector<Vec2> cut;
    for (double x : profile_points(lo, hi, settings.profile_points)) cut.emplace_back(x, y);
    const Samples s = sampler.sample(cut, false);
    const auto& qs = quantities();
    for (std::size_t q = 0; q < qs.size(); ++q) {
      const bool stress = qs[q].is_stress || qs[q].name == "pressure";
      const double scale = stress ? (qs[q].is_stress ? -1.0 : 1.0) / stress_scale : 1.0;
      const std::string name = qs[q].is_stress ? "sigma_" + qs[q].name.substr(7) : qs[q].name;
      for (std::size_t i = 0; i < cut.size(); ++i) {
        if (s.stats[q][i].n == 0) continue;  // no data here: no row
        rows.push_back({"dem", name, f, cut[i].x(), scale * s.stats[q][i].mean, std::abs(scale) * s.stats[q][i].stderr_, true});
      }
    }
  }
  return rows;
}

// The virial identity of each pile (sum of grain stresses = gravity + wall terms - settling
// residual): a check of the stresses that needs no mesh.
nlohmann::json virial_identities(const std::vector<Pile>& piles) {
  nlohmann::json identity = nlohmann::json::array();
  for (const Pile& p : piles) {
    const VirialIdentity v = virial_identity(*p.packing);
    identity.push_back({{"dem_file", p.path},
                        {"virial_yy_N_m", v.grain_sum(1, 1)},
                        {"gravity_yy_N_m", v.gravity(1, 1)},
                        {"wall_yy_N_m", v.wall(1, 1)},
                        {"settling_residual_yy_N_m", v.residual(1, 1)},
                        {"relative_mismatch", v.relative_mismatch()},
                        {"relative_mismatch_yy",
                         std::abs(v.grain_sum(1, 1) - v.wall(1, 1) - v.gravity(1, 1)) / std::abs(v.gravity(1, 1))},
                        {"relative_mismatch_with_residual", v.relative_mismatch_with_residual()}});
  }
  return identity;
}

// Over the field points: how many have no data, the mean grain count of a window, and Madadi's
// g2 = tr<F> / (v C) (paper eq. 23) averaged over the points with data.
struct FieldSummary {
  int points_without_data = 0;
  double mean_grain_count = 0.0, fabric_g2 = 0.0;
};
FieldSummary summarise_fields(const Samples& fields) {
  const auto& qs = quantities();
  auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find_if(qs.begin(), qs.end(), [&](const Quantity& q) { return q.name == name; }) - qs.begin());
  };
  const std::size_t trace_q = column("fabric_trace"), nu_q = column("volume_fraction"), c_q = column("coordination");
  const std::size_t n = fields.stats[0].size();
  FieldSummary out;
  int g2_points = 0;
  double g2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (fields.stats[1][i].n == 0) ++out.points_without_data;
    out.mean_grain_count += fields.stats[0][i].mean / n;
    const double vc = fields.stats[nu_q][i].mean * fields.stats[c_q][i].mean;
    if (fields.stats[trace_q][i].n > 0 && vc > 0) g2 += fields.stats[trace_q][i].mean / vc, ++g2_points;
  }
  out.fabric_g2 = g2_points ? g2 / g2_points : 0.0;
  return out;
}

}  // namespace

namespace {

// The kernel's branch quadrature (5 points along a branch about a diameter long) holds only
// when the kernel is smooth on that scale, w >= d; a smaller w also gives a grain grid of
// (pile size / w)^2 cells. Checked where d is first known: an explicit width before the RVE
// study, the default (the RVE radius) once the study has chosen it.
void check_kernel_width(double w, const std::string& origin, const CoarseSettings& settings, double diameter,
                        const std::string& scene_path) {
  if (settings.method == CoarseSettings::Method::rve || w >= diameter) return;
  std::ostringstream m;
  m << scene_path << ": coarse.kernel_width_m" << origin << " is " << w
    << " m, but the kernel averages need a width of at least the mean grain diameter of "
    << (settings.dem_files.size() > 1 ? "the piles in coarse.dem_files" : settings.dem_files.front())
    << " (snapshot '" << settings.snapshot << "'): allowed: >= " << diameter << " m, or 0 for the RVE radius";
  throw InputError(m.str());
}

// An RVE must hold grains: below one grain diameter most windows hold no grain's centre and the
// fields are empty (the paper's RVEs hold 100-200). One larger than the pile averages the whole
// pile at every point: finite, uniform, and said so.
void check_rve_radius(const CoarseSettings& settings, double diameter, double pile_height, const std::string& scene_path) {
  if (settings.rve_radius_m > 0 && settings.rve_radius_m < diameter) {
    std::ostringstream m;
    m << scene_path << ": coarse.rve_radius_m is " << settings.rve_radius_m
      << " m, smaller than the mean grain diameter " << diameter
      << " m: such an RVE holds a few grains at most (the paper's hold 100-200); allowed: >= " << diameter
      << " m, or 0 to size it by coarse.rve_grain_count";
    throw InputError(m.str());
  }
  if (settings.rve_radius_m > pile_height)
    std::fprintf(stderr,
                 "warning: coarse.rve_radius_m = %g m exceeds the pile's height %g m: the RVEs reach beyond the pile, "
                 "and far from the pile's centre each averages most of it, so the fields are smoothed flat\n",
                 settings.rve_radius_m, pile_height);
}

// What fields.h5 says of how its fields were made (common/fields_attributes.h).
FieldsAttributes fields_attributes(const CoarseSettings& settings, const PileSet& set, double radius, double kernel_width) {
  FieldsAttributes a;
  a.method = settings.method == CoarseSettings::Method::rve ? std::string("rve") : settings.kernel;
  a.rve_radius_m = radius;
  a.kernel_width_m = settings.method == CoarseSettings::Method::rve ? 0.0 : kernel_width;
  a.piles = static_cast<std::int64_t>(set.piles.size());
  a.snapshot = settings.snapshot;
  a.strain_to = set.piles_with_strains ? settings.strain_to : std::string("");
  a.gravity_change = set.gravity_change;
  a.height_m = set.mean_height;
  a.rho_bulk_kg_per_m2 = set.rho_bulk;
  a.gravity_m_per_s2 = set.gravity;
  a.snapshot_time_s = set.snapshot_time;
  return a;
}

}  // namespace

nlohmann::json run_coarse(const CoarseRunOptions& opt) {
  const auto start = Clock::now();
  SceneReader reader = SceneReader::from_file(opt.scene_path);
  CoarseSettings settings =
      read_coarse_scene(reader, std::filesystem::path(opt.scene_path).parent_path().string(), opt.out_dir);
  reader.reject_unknown({"coarse"}, scene_tables());
  if (!opt.dem_files.empty() && !reader.has("coarse.dem_files")) settings.dem_files = opt.dem_files;
  prepare_output_directory(opt.out_dir);
  const auto out = [&](const char* file) { return (std::filesystem::path(opt.out_dir) / file).string(); };

  // 1. The mesh and the piles.
  const mesh::TriangleMesh mesh = mesh::read_triangle_mesh(settings.mesh_file);
  const Domain domain = domain_of(mesh);
  PileSet set = read_piles(settings, mesh::mesh_area(mesh));
  std::vector<Pile>& piles = set.piles;
  for (Pile& p : piles) {
    p.rve = std::make_unique<RveAverager>(*p.packing, domain, settings.clip_volume);
    if (p.later) {
      p.rve->set_displacements(*p.later);
      p.rve_later = std::make_unique<RveAverager>(*p.later, domain, settings.clip_volume);
    }
    require_pile_on_mesh(p, mesh::mesh_area(mesh), settings.mesh_file);
  }
  const double diameter = set.diameter();
  if (settings.kernel_width_m > 0) check_kernel_width(settings.kernel_width_m, "", settings, diameter, opt.scene_path);
  check_rve_radius(settings, diameter, set.mean_height, opt.scene_path);

  // 2. RVE-size study (paper Figs. 5-6): at each point, each quantity against the grain count;
  // it chooses the window's size unless the scene sets it.
  RveStudySettings study_settings;
  study_settings.first_radius_m = 0.75 * diameter;
  study_settings.max_grain_count = settings.study_max_grain_count;
  study_settings.max_radius_m = 4 * set.mean_height;
  study_settings.tolerance = settings.study_tolerance;
  const RveStudy study =
      rve_size_study(*piles.front().rve, rve_study_points(settings, mesh, domain, set.mean_height), study_settings);
  const double chosen_count = study.chosen_grain_count;
  write_text_atomically(out("rve_study.csv"), study.csv);
  const double grain_count_target = settings.rve_grain_count > 0 ? settings.rve_grain_count : chosen_count;
  const double radius = settings.rve_radius_m > 0 ? settings.rve_radius_m : set.radius_for(grain_count_target);
  // Default kernel width: the RVE radius, so that both windows average over as many grains.
  const double kernel_width = settings.kernel_width_m > 0 ? settings.kernel_width_m : radius;
  check_kernel_width(kernel_width, " (0: the RVE radius, from coarse.rve_radius_m or rve_grain_count)", settings, diameter,
                     opt.scene_path);
  if (settings.method == CoarseSettings::Method::kernel) {
    const Kernel kernel(kernel_shape(settings.kernel), kernel_width);
    for (Pile& p : piles) {
      p.kernel = std::make_unique<KernelAverager>(*p.packing, kernel, domain, settings.clip_volume);
      if (p.later) {
        p.kernel->set_displacements(*p.later);
        p.kernel_later = std::make_unique<KernelAverager>(*p.later, kernel, domain, settings.clip_volume);
      }
    }
  }
  const EnsembleSampler sampler(piles, radius);

  // 3. The fields on the mesh (at its nodes or triangle centroids), averaged over the piles.
  const bool on_nodes = settings.location == CoarseSettings::Location::nodes;
  std::vector<Vec2> points;
  if (on_nodes) points = mesh.nodes;
  else
    for (const auto& t : mesh.triangles) points.push_back((mesh.nodes[t[0]] + mesh.nodes[t[1]] + mesh.nodes[t[2]]) / 3.0);
  const auto fields_start = Clock::now();
  const Samples fields = sampler.sample(points, true);
  const double fields_seconds = std::chrono::duration<double>(Clock::now() - fields_start).count();

  // 4. Profiles along horizontal cuts.
  const double stress_scale = set.rho_bulk * set.gravity * set.mean_height;
  write_profile_values(out("profiles.csv"), profile_rows(settings, domain, sampler, set.mean_height, stress_scale));

  // 5. The files and the report.
  const FieldsAttributes attributes = fields_attributes(settings, set, radius, kernel_width);
  write_fields_h5(out("fields.h5"), mesh, on_nodes, points, fields, attributes);
  write_vtu(out("fields.vtu"), mesh, on_nodes, fields, piles.size() > 1, set.snapshot_time);

  const FieldSummary summary = summarise_fields(fields);
  nlohmann::json section = attributes.to_json();
  section["dem_files"] = settings.dem_files;
  section["mesh_file"] = settings.mesh_file;
  section["location"] = on_nodes ? "nodes" : "cells";
  section["rve_volume"] = settings.clip_volume ? "clipped" : "full";
  section["rve_grain_count_target"] = grain_count_target;
  section["mean_grain_count"] = summary.mean_grain_count;
  section["points"] = points.size();
  section["points_without_data"] = summary.points_without_data;
  section["strains"] = set.piles_with_strains > 0;
  section["piles_with_strains"] = set.piles_with_strains;
  section["fabric_g2"] = summary.fabric_g2;
  int outside = 0;
  for (const Pile& p : piles) outside = std::max(outside, p.rve->grains_outside_domain());
  section["grains_outside_mesh"] = outside;
  section["bulk_volume_fraction"] = set.bulk_fraction;
  section["stress_scale_rho_g_h_N_per_m"] = stress_scale;
  section["rve_study"] = {{"tolerance", settings.study_tolerance},
                          {"chosen_grain_count", chosen_count},
                          {"chosen_radius_m", set.radius_for(chosen_count)},
                          {"points", study.points}};
  section["virial_identity"] = virial_identities(piles);
  section["fields_wall_time_s"] = fields_seconds;
  section["wall_time_s"] = std::chrono::duration<double>(Clock::now() - start).count();
  write_report_section(out("report.json"), "coarse", section);
  return section;
}

}  // namespace pilelab::coarse
