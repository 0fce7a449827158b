// compare/ on synthetic files: a field made from a known elastic law is fitted back to its
// constants through fields.h5; a model identical to the DEM differs from it by zero.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <vector>

#include "common/hdf5_file.h"
#include "common/report.h"
#include "common/error.h"
#include "compare/compare_run.h"
#include "compare/point_fields.h"

using namespace pilelab;

namespace {

struct Synthetic {
  std::vector<double> xy;                 // node coordinates
  std::vector<std::int64_t> triangles;
  std::map<std::string, std::vector<double>> fields;
};

// A square [-0.5, 0.5] x [0, 1] (n x n cells): strain varying in space, the stress change of
// plane-strain isotropic elasticity (lambda, mu), a gravity stress, an isotropic fabric.
Synthetic elastic_field(double lambda, double mu, int n = 24) {
  Synthetic s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.xy.insert(s.xy.end(), {-0.5 + double(i) / n, double(j) / n});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::int64_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      s.triangles.insert(s.triangles.end(), {a, b, c, a, c, d});
    }
  const std::size_t k = s.xy.size() / 2;
  auto& f = s.fields;
  for (const char* q : {"strain_xx", "strain_yy", "strain_xy", "stress_change_xx", "stress_change_yy",
                        "stress_change_xy", "fabric_xx", "fabric_yy", "fabric_xy", "pressure", "stress_xx",
                        "stress_yy", "stress_xy", "stress_orientation_deg", "displacement_x", "displacement_y"})
    f[q].resize(k);
  for (std::size_t p = 0; p < k; ++p) {
    const double x = s.xy[2 * p], y = s.xy[2 * p + 1];
    const double exx = 1e-4 * (1 + x), eyy = 2e-4 * (1 - 0.5 * y), exy = 0.5e-4 * x * y;
    f["strain_xx"][p] = exx, f["strain_yy"][p] = eyy, f["strain_xy"][p] = exy;
    f["stress_change_xx"][p] = lambda * (exx + eyy) + 2 * mu * exx;
    f["stress_change_yy"][p] = lambda * (exx + eyy) + 2 * mu * eyy;
    f["stress_change_xy"][p] = 2 * mu * exy;
    f["fabric_xx"][p] = 1.5, f["fabric_yy"][p] = 1.5, f["fabric_xy"][p] = 0.0;
    f["stress_yy"][p] = -1000 * (1 - y), f["stress_xx"][p] = -400 * (1 - y), f["stress_xy"][p] = 0.0;
    f["pressure"][p] = 700 * (1 - y);
    f["stress_orientation_deg"][p] = 90.0;
    f["displacement_x"][p] = 1e-4 * (x + 0.5 * x * x), f["displacement_y"][p] = 2e-4 * (y - 0.25 * y * y);
  }
  return s;
}

// fields.h5 as coarse/ writes it; an ensemble's piles go to /piles/K as well.
// with_change = false: a DEM without a later snapshot, so no displacement or strain data and a
// gravity change of 0 (as coarse writes it then).
void write_fields(const std::string& path, const Synthetic& s, const std::vector<const Synthetic*>& piles = {},
                  bool with_change = true) {
  H5File h = H5File::create(path);
  h.set_attribute("/", "format", std::string("pilelab-fields"));
  h.set_attribute("/", "format_version", std::int64_t(1));
  h.set_attribute("/", "rve_radius_m", 0.1);
  h.set_attribute("/", "height_m", 1.0);
  h.set_attribute("/", "rho_bulk_kg_per_m2", 1000.0 / 9.81);
  h.set_attribute("/", "gravity_m_per_s2", 9.81);
  h.set_attribute("/", "gravity_change", with_change ? -0.1 : 0.0);
  h.set_attribute("/", "snapshot_time_s", 2.5);
  const std::uint64_t k = s.xy.size() / 2;
  h.write("/mesh/nodes", s.xy, {k, 2}, "m");
  h.write("/mesh/triangles", s.triangles, {s.triangles.size() / 3, 3});
  h.write("/fields/points", s.xy, {k, 2}, "m");
  h.set_attribute("/fields", "location", std::string("nodes"));
  const auto count = static_cast<std::int64_t>(std::max<std::size_t>(piles.size(), 1));
  for (const auto& [name, v] : s.fields) {
    const bool change_field = name.rfind("displacement", 0) == 0 || name.rfind("strain", 0) == 0 ||
                              name.rfind("stress_change", 0) == 0;
    h.write("/fields/" + name, change_field && !with_change ? std::vector<double>(v.size(), NAN) : v);
    h.write("/fields/" + name + "_count",
            std::vector<std::int64_t>(v.size(), change_field && !with_change ? 0 : count));
    for (std::size_t k = 0; k < piles.size(); ++k) h.write("/piles/" + std::to_string(k) + "/" + name, piles[k]->fields.at(name));
  }
}

// fields.h5 with one part damaged, as a truncated copy or a hand edit would leave it.
enum class Damage { nodes_shape, triangle_index, negative_index, points_count, degenerate_triangle, counted_nan,
                    orphan_count, later_version };
void write_damaged_fields(const std::string& path, const Synthetic& s, Damage damage) {
  H5File h = H5File::create(path);
  h.set_attribute("/", "format", std::string("pilelab-fields"));
  h.set_attribute("/", "format_version", std::int64_t(damage == Damage::later_version ? 9 : 1));
  const std::uint64_t k = s.xy.size() / 2;
  if (damage == Damage::nodes_shape) {
    std::vector<double> xyz(3 * k, 0.0);
    h.write("/mesh/nodes", xyz, {k, 3}, "m");
  } else {
    h.write("/mesh/nodes", s.xy, {k, 2}, "m");
  }
  auto tri = s.triangles;
  if (damage == Damage::triangle_index) tri[7] = static_cast<std::int64_t>(k);
  if (damage == Damage::negative_index) tri[7] = -1;
  if (damage == Damage::degenerate_triangle) tri[5] = tri[4];  // a triangle with a repeated node
  h.write("/mesh/triangles", tri, {tri.size() / 3, 3});
  const std::uint64_t points = damage == Damage::points_count ? k - 1 : k;
  const std::vector<double> xy(s.xy.begin(), s.xy.begin() + 2 * points);
  h.write("/fields/points", xy, {points, 2}, "m");
  h.set_attribute("/fields", "location", std::string("nodes"));
  std::vector<double> stress(points, 1.0);
  if (damage == Damage::counted_nan) stress[3] = NAN;
  if (damage != Damage::orphan_count) h.write("/fields/stress_yy", stress);
  h.write("/fields/stress_yy_count", std::vector<std::int64_t>(points, 1));
}

std::string temp_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d.string();
}

}  // namespace

TEST(CompareRun, ElasticFieldIsFittedBackToItsConstants) {
  const std::string dir = temp_dir("pilelab_fit_run");
  const double lambda = 3.0e6, mu = 1.2e6;
  write_fields(dir + "/fields.h5", elastic_field(lambda, mu));
  compare::FitOptions opt;
  opt.fields_path = dir + "/fields.h5";
  opt.out_dir = dir;
  opt.resamples = 20;
  const auto fit = compare::run_fit(opt);
  const auto& iso = fit["models"]["isotropic"];
  EXPECT_NEAR(iso["lambda_N_per_m"].get<double>(), lambda, 1e-8 * lambda);
  EXPECT_NEAR(iso["mu_N_per_m"].get<double>(), mu, 1e-8 * mu);
  EXPECT_NEAR(iso["r2"].get<double>(), 1.0, 1e-12);
  EXPECT_GE(fit["samples"].get<int>(), 50);  // thinned to 0.1 m on a unit square
  std::filesystem::remove_all(dir);
}

// An ensemble of two piles with the same strains and moduli lambda_1, lambda_2: resampling
// whole piles draws {1,1}, {2,2} or {1,2} (a quarter of the time each extreme), so the 95 %
// interval of lambda runs exactly from lambda_1 to lambda_2.
TEST(CompareRun, EnsembleFitsAreBootstrappedOverPiles) {
  const std::string dir = temp_dir("pilelab_fit_piles");
  const double mu = 1.0e6, l1 = 2.0e6, l2 = 4.0e6;
  const Synthetic a = elastic_field(l1, mu), b = elastic_field(l2, mu);
  const Synthetic mean = elastic_field(0.5 * (l1 + l2), mu);
  write_fields(dir + "/with_piles.h5", mean, {&a, &b});
  compare::FitOptions opt;
  opt.fields_path = dir + "/with_piles.h5";
  opt.out_dir = dir;
  opt.resamples = 400;
  const auto fit = compare::run_fit(opt);
  EXPECT_EQ(fit["bootstrap_over"].get<std::string>(), "piles");
  const auto& iso = fit["models"]["isotropic"];
  EXPECT_NEAR(iso["lambda_N_per_m"].get<double>(), 0.5 * (l1 + l2), 1e-6 * l2);
  EXPECT_NEAR(iso["lambda_N_per_m_ci95"][0].get<double>(), l1, 1e-6 * l2);
  EXPECT_NEAR(iso["lambda_N_per_m_ci95"][1].get<double>(), l2, 1e-6 * l2);
  EXPECT_NEAR(iso["mu_N_per_m_ci95"][0].get<double>(), mu, 1e-6 * mu);
  std::filesystem::remove_all(dir);
}

// models.h5 with the DEM's fields as one model, solved with rho g = rho_g_factor times the
// DEM's and a gravity change change_factor times the DEM's: its stresses scaled by rho_g_factor,
// its displacements and strains by rho_g_factor * change_factor (a linear model).
void write_models(const std::string& path, const Synthetic& s, double rho_g_factor, double change_factor,
                  bool with_change = true, bool with_height = true) {
  H5File m = H5File::create(path);
  m.set_attribute("/", "format_version", std::int64_t(1));
  m.set_attribute("/", "rho_g_h_N_per_m", 1000.0 * rho_g_factor);  // the DEM's rho g is 1000 N/m^2, h = 1 m
  if (with_height) m.set_attribute("/", "height_m", 1.0);
  m.write("/same/points", s.xy, {s.xy.size() / 2, 2}, "m");
  for (const char* q : {"stress_xx", "stress_yy", "stress_xy"}) {
    std::vector<double> v = s.fields.at(q);
    for (double& x : v) x *= rho_g_factor;
    m.write(std::string("/same/") + q, v);
  }
  for (const char* q : {"strain_xx", "strain_yy", "strain_xy", "displacement_x", "displacement_y"}) {
    std::vector<double> v = s.fields.at(q);
    for (double& x : v) x *= rho_g_factor * change_factor;
    m.write(std::string("/same/") + q, v);
  }
  if (with_change) m.set_attribute("/same", "gravity_change", -0.1 * change_factor);
}

// Compare run in dir, on the fields.h5 and models.h5 written there, with a scene of its own.
nlohmann::json run_compare_in(const std::string& dir) {
  std::ofstream(dir + "/scene.toml") << "[compare]\nfit_resamples = 10\n";
  return compare::run_compare({dir + "/scene.toml", dir, std::nullopt, {}});
}

// The same fields as the DEM, differing only by rounding once put on the DEM's scale.
void expect_same_fields(const nlohmann::json& same, std::size_t points) {
  EXPECT_EQ(same["matched_points"].get<std::size_t>(), points);
  for (const char* q : {"relative_l2_stress_xx", "relative_l2_stress_yy", "relative_l2_strain_xx", "relative_l2_strain_yy",
                        "relative_l2_strain_xy", "relative_l2_displacement", "relative_l2_lower_half_stress_yy"})
    EXPECT_NEAR(same[q].get<double>(), 0.0, 1e-14) << q;
  EXPECT_NEAR(same["principal_axis_angle_mean_deg"].get<double>(), 0.0, 1e-6);
}

TEST(CompareRun, IdenticalModelDiffersByZero) {
  const std::string dir = temp_dir("pilelab_compare_run");
  const Synthetic s = elastic_field(3e6, 1e6);
  write_fields(dir + "/fields.h5", s);
  write_models(dir + "/models.h5", s, 1.0, 1.0);
  const auto c = run_compare_in(dir);
  expect_same_fields(c["models"]["same"], s.xy.size() / 2);
  EXPECT_NEAR(c["stress_scale_dem_over_model"].get<double>(), 1.0, 1e-15);
  EXPECT_NEAR(c["models"]["same"]["displacement_scale_dem_over_model"].get<double>(), 1.0, 1e-15);
  std::filesystem::remove_all(dir);
}

// A model solved with 2.5 times the DEM's rho g and 3 times its gravity change has 2.5 times
// its stresses and 7.5 times its displacements and strains: rescaled by the DEM's rho g (and
// rho g Delta) over the model's, the difference vanishes; unscaled it would be 150 % and 650 %.
TEST(CompareRun, ModelWithAnotherDensityAndGravityChangeIsRescaled) {
  const std::string dir = temp_dir("pilelab_compare_rescaled");
  const Synthetic s = elastic_field(3e6, 1e6);
  write_fields(dir + "/fields.h5", s);
  write_models(dir + "/models.h5", s, 2.5, 3.0);
  const auto c = run_compare_in(dir);
  expect_same_fields(c["models"]["same"], s.xy.size() / 2);
  EXPECT_NEAR(c["stress_scale_dem_over_model"].get<double>(), 1 / 2.5, 1e-15);
  EXPECT_NEAR(c["models"]["same"]["displacement_scale_dem_over_model"].get<double>(), 1 / 7.5, 1e-15);
  // The closed loop's comparison scales the same way.
  const auto d = compare::compare_displacements(dir + "/fields.h5", dir + "/models.h5", "same");
  EXPECT_NEAR(d["relative_l2_displacement"].get<double>(), 0.0, 1e-14);
  EXPECT_NEAR(d["relative_l2_strain_yy"].get<double>(), 0.0, 1e-14);
  std::filesystem::remove_all(dir);
}

// Runs f, which must throw InputError whose message holds every one of words.
template <class F>
void expect_refused(F f, const std::vector<std::string>& words, const char* what) {
  try {
    f();
    ADD_FAILURE() << what;
  } catch (const InputError& e) {
    for (const std::string& word : words) EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
}

// A model solved on another mesh than the fields' (a 20 x 20 square against the fields' 24 x 24:
// only their shared corner and edge points coincide) is refused naming both files, where it was
// compared over the few points they share, or over none.
TEST(CompareRun, ModelsFromAnotherMeshAreRefused) {
  const std::string dir = temp_dir("pilelab_compare_other_mesh");
  write_fields(dir + "/fields.h5", elastic_field(3e6, 1e6));
  write_models(dir + "/models.h5", elastic_field(3e6, 1e6, 20), 1.0, 1.0);
  const std::vector<std::string> words = {dir + "/models.h5", dir + "/fields.h5", "/same/points", "different meshes"};
  expect_refused([&] { run_compare_in(dir); }, words, "a model on another mesh was compared");
  expect_refused([&] { compare::compare_displacements(dir + "/fields.h5", dir + "/models.h5", "same"); }, words,
                 "a model on another mesh was compared in the closed loop");
  std::filesystem::remove_all(dir);
}

// A model's value that is not a number is damage (its points are its own mesh's vertices, all
// inside): refused naming the dataset and the row, not a point quietly left out of every norm.
TEST(CompareRun, NonFiniteModelValueIsNamed) {
  const std::string dir = temp_dir("pilelab_compare_nan_model");
  const Synthetic s = elastic_field(3e6, 1e6);
  write_fields(dir + "/fields.h5", s);
  Synthetic damaged = s;
  damaged.fields["stress_yy"][7] = std::numeric_limits<double>::infinity();
  write_models(dir + "/models.h5", damaged, 1.0, 1.0);
  expect_refused([&] { run_compare_in(dir); }, {dir + "/models.h5", "/same/stress_yy", "value 7 is infinite"},
                 "an infinite model value was compared");
  std::filesystem::remove_all(dir);
}

// compare.vtu carries the DEM's pressure and its vertical stress as the figures draw it,
// -sigma_yy / rho g h (here rho g = 1000 N/m^2, h = 1 m, sigma_yy = -1000 (1 - y): exactly 1 - y at
// every node), and the snapshot's time for ParaView, in the file and in compare.pvd.
TEST(CompareRun, CompareVtuHasTheDemPressureTheScaledStressAndTheTime) {
  const std::string dir = temp_dir("pilelab_compare_vtu");
  const Synthetic s = elastic_field(3e6, 1e6);
  write_fields(dir + "/fields.h5", s);
  write_models(dir + "/models.h5", s, 1.0, 1.0);
  run_compare_in(dir);
  std::ifstream in(dir + "/compare.vtu");
  const std::string vtu((std::istreambuf_iterator<char>(in)), {});
  const auto values_of = [&](const std::string& name) {
    const std::size_t at = vtu.find("Name=\"" + name + "\"");
    EXPECT_NE(at, std::string::npos) << name;
    std::istringstream numbers(vtu.substr(vtu.find('>', at) + 1));
    std::vector<double> v(s.xy.size() / 2);
    for (double& x : v) numbers >> x;
    return v;
  };
  const std::vector<double> sigma = values_of("dem_sigma_yy_over_rho_g_h"), pressure = values_of("dem_pressure");
  for (std::size_t i = 0; i < sigma.size(); ++i) {
    EXPECT_NEAR(sigma[i], 1 - s.xy[2 * i + 1], 1e-9) << i;  // the file's 10 digits
    EXPECT_NEAR(pressure[i], s.fields.at("pressure")[i], 1e-9 * 700) << i;
  }
  EXPECT_NE(vtu.find("Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">2.5<"), std::string::npos);
  std::ifstream pvd(dir + "/compare.pvd");
  EXPECT_NE(std::string((std::istreambuf_iterator<char>(pvd)), {}).find("timestep=\"2.5\""), std::string::npos);
  std::filesystem::remove_all(dir);
}

// A change of g of 0 on one side (strains from a snapshot at the same g) gives no scale: the
// displacements and strains are left out, with the reason, and the stresses still compare.
TEST(CompareRun, ZeroGravityChangeLeavesDisplacementsOut) {
  const std::string dir = temp_dir("pilelab_compare_zero_change");
  const Synthetic s = elastic_field(3e6, 1e6);
  write_fields(dir + "/fields.h5", s);
  write_models(dir + "/models.h5", s, 1.0, 0.0);
  const auto c = run_compare_in(dir);
  const auto& same = c["models"]["same"];
  EXPECT_TRUE(same.contains("displacement_comparison_skipped"));
  EXPECT_FALSE(same.contains("relative_l2_displacement"));
  EXPECT_FALSE(same.contains("relative_l2_strain_yy"));
  EXPECT_NEAR(same["relative_l2_stress_yy"].get<double>(), 0.0, 1e-14);
  std::filesystem::remove_all(dir);
}

TEST(CompareRun, DemWithoutALaterSnapshotLeavesDisplacementsOut) {
  // No relaxation snapshot: the DEM's displacement and strain fields are empty and its gravity
  // change is 0. The stresses still compare; the model's displacements are not compared.
  const std::string dir = temp_dir("pilelab_compare_no_dem_change");
  const Synthetic s = elastic_field(3e6, 1e6);
  write_fields(dir + "/fields.h5", s, {}, false);
  write_models(dir + "/models.h5", s, 1.0, 1.0);
  const auto c = run_compare_in(dir);
  const auto& same = c["models"]["same"];
  // Absent, or NaN (written as null): never a number that pretends to measure something.
  EXPECT_TRUE(!same.contains("relative_l2_displacement") || std::isnan(same["relative_l2_displacement"].get<double>()));
  EXPECT_NEAR(same["relative_l2_stress_yy"].get<double>(), 0.0, 1e-14);
  std::filesystem::remove_all(dir);
}

// Without the model's gravity change (or its height, for rho g) there is no scale to compare
// by: an error naming the file and the attribute, not a silent factor of 1.
TEST(CompareRun, ModelWithoutItsScaleIsAnError) {
  const std::string dir = temp_dir("pilelab_compare_unscaled");
  const Synthetic s = elastic_field(3e6, 1e6);
  write_fields(dir + "/fields.h5", s);
  const std::pair<bool, const char*> cases[] = {{true, "gravity_change"}, {false, "height_m"}};
  for (const auto& [no_change, attribute] : cases) {
    std::filesystem::remove(dir + "/models.h5");
    write_models(dir + "/models.h5", s, 1.0, 1.0, !no_change, no_change);
    try {
      run_compare_in(dir);
      ADD_FAILURE() << "no error without " << attribute;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("models.h5"), std::string::npos) << m;
      EXPECT_NE(m.find(attribute), std::string::npos) << m;
    }
  }
  std::filesystem::remove_all(dir);
}

// The DEM's section of report.json may lack the repose angles (an older or hand-made report)
// or hold null (a flank too short to fit): compare then has no FPA angle to set beside the
// fit, and says so with repose_angle_deg = 0 instead of reading a missing key.
TEST(CompareRun, ReportWithoutReposeAnglesGivesNoFpaAngle) {
  const std::string dir = temp_dir("pilelab_compare_repose");
  write_fields(dir + "/fields.h5", elastic_field(3e6, 1e6));
  for (const char* dem : {R"({})", R"({"repose_angle_left_deg": 30.0})", R"({"repose_angle_left_deg": 30.0,
                           "repose_angle_right_deg": null})", R"(5)"}) {
    std::ofstream(dir + "/report.json") << "{\"dem\": " << dem << "}\n";
    const auto c = run_compare_in(dir);
    // No angle: no FPA angle to set beside the fit (null, not a misleading 0).
    EXPECT_TRUE(c["fpa_angle"]["repose_angle_deg"].is_null()) << dem;
    EXPECT_TRUE(c["fpa_angle"]["psi_fpa_deg"].is_null()) << dem;
  }
  // Both present: their mean, and psi = 45 - phi/2.
  std::ofstream(dir + "/report.json") << R"({"dem": {"repose_angle_left_deg": 30.0, "repose_angle_right_deg": 34.0}})";
  const auto c = run_compare_in(dir);
  EXPECT_DOUBLE_EQ(c["fpa_angle"]["repose_angle_deg"].get<double>(), 32.0);
  EXPECT_DOUBLE_EQ(c["fpa_angle"]["psi_fpa_deg"].get<double>(), 29.0);
  std::filesystem::remove_all(dir);
}

// A damaged fields.h5 is an InputError naming the file and the dataset, never a read past the
// end of an array in the integrals.
TEST(CompareRun, DamagedMeshInFieldsFileIsNamed) {
  const std::string dir = temp_dir("pilelab_compare_damaged");
  const Synthetic s = elastic_field(3e6, 1e6, 4);
  const std::pair<Damage, const char*> cases[] = {{Damage::nodes_shape, "/mesh/nodes"},
                                                  {Damage::triangle_index, "/mesh/triangles"},
                                                  {Damage::negative_index, "/mesh/triangles"},
                                                  {Damage::points_count, "/fields/points"},
                                                  {Damage::degenerate_triangle, "/mesh/triangles row 1"},
                                                  {Damage::counted_nan, "/fields/stress_yy row 3"},
                                                  {Damage::orphan_count, "/fields/stress_yy_count:"},
                                                  {Damage::later_version, "format_version = 9"}};
  for (const auto& [damage, dataset] : cases) {
    const std::string path = dir + "/damaged.h5";
    std::filesystem::remove(path);
    write_damaged_fields(path, s, damage);
    compare::Triangulation mesh;
    try {
      compare::read_dem_fields(path, &mesh);
      ADD_FAILURE() << "no error for " << dataset;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(path), std::string::npos) << m;
      EXPECT_NE(m.find(dataset), std::string::npos) << m;
    }
  }
  std::filesystem::remove_all(dir);
}

// An ensemble whose piles' stresses are the model's times (1 + e_k): with pile k left out the
// mean is the model's times (1 + e_(k)), e_(k) the mean of the other e, so the relative L2
// difference is |e_(k)| / (1 + e_(k)) exactly, and its jackknife standard error follows from
// the e alone. The axes agree in every pile, so the angle's error is zero.
TEST(CompareRun, EnsembleDifferencesCarryTheirJackknifeErrors) {
  const std::string dir = temp_dir("pilelab_compare_jackknife");
  const Synthetic model = elastic_field(3e6, 1e6);
  const std::vector<double> e = {0.1, -0.05, 0.2, 0.02};
  const auto scaled = [&](double factor) {
    Synthetic s = model;
    for (const char* q : {"stress_xx", "stress_yy", "stress_xy"})
      for (double& v : s.fields[q]) v *= factor;
    return s;
  };
  std::vector<Synthetic> piles;
  double e_mean = 0;
  for (double ek : e) piles.push_back(scaled(1 + ek)), e_mean += ek / e.size();
  std::vector<const Synthetic*> pile_pointers;
  for (const Synthetic& p : piles) pile_pointers.push_back(&p);
  write_fields(dir + "/fields.h5", scaled(1 + e_mean), pile_pointers);
  write_models(dir + "/models.h5", model, 1.0, 1.0);
  const auto c = run_compare_in(dir);
  const auto& same = c["models"]["same"];

  const double n = e.size();
  std::vector<double> theta;
  for (std::size_t k = 0; k < e.size(); ++k) {
    const double left_out = (e_mean * n - e[k]) / (n - 1);
    theta.push_back(std::abs(left_out) / (1 + left_out));
  }
  double theta_mean = 0, ss = 0;
  for (double t : theta) theta_mean += t / n;
  for (double t : theta) ss += (t - theta_mean) * (t - theta_mean);
  const double expected = std::sqrt((n - 1) / n * ss);
  ASSERT_GT(expected, 1e-3);
  for (const char* q : {"relative_l2_stress_yy", "relative_l2_stress_xx", "relative_l2_lower_half_stress_yy"}) {
    EXPECT_NEAR(same[q].get<double>(), e_mean / (1 + e_mean), 1e-12) << q;
    ASSERT_TRUE(same.contains(std::string(q) + "_stderr")) << same.dump(1);
    EXPECT_NEAR(same[std::string(q) + "_stderr"].get<double>(), expected, 1e-12) << q;
  }
  EXPECT_NEAR(same["principal_axis_angle_mean_deg_stderr"].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(same["relative_l2_displacement_stderr"].get<double>(), 0.0, 1e-14);
  EXPECT_NEAR(c["fpa_angle"]["psi_fit_right_deg_stderr"].get<double>(), 0.0, 1e-9);  // the apex is a corner: one flank
  std::filesystem::remove_all(dir);
}

// A single pile has no spread to resample: no errors are claimed.
TEST(CompareRun, SinglePileClaimsNoErrors) {
  const std::string dir = temp_dir("pilelab_compare_single");
  const Synthetic s = elastic_field(3e6, 1e6);
  write_fields(dir + "/fields.h5", s);
  write_models(dir + "/models.h5", s, 1.0, 1.0);
  const auto c = run_compare_in(dir);
  EXPECT_FALSE(c["models"]["same"].contains("relative_l2_stress_yy_stderr"));
  std::filesystem::remove_all(dir);
}
