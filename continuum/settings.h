#pragma once
// Settings of the continuum stage: the scene's [continuum] table as plain structs with units
// in the names, defaults and ranges (docs/SCENES.md lists every key). No deal.II here, so the
// command-line front end compiles without it.
#include <string>
#include <vector>

#include "common/scene_reader.h"

namespace pilelab::continuum {

/// How a linear system is solved. Both report their iteration count (1 for direct).
struct SolverSettings {
  enum class Kind { iterative, direct } kind = Kind::iterative;
  double relative_tolerance = 1e-10;  ///< |r| <= tol |b| for the iterative solvers
  int max_iterations = 5000;
};

/// Isotropic linear elasticity, two-dimensional. Moduli are per unit depth (N/m), like the
/// DEM's contact stiffness; stresses come out in N/m.
struct ElasticSettings {
  double youngs_modulus_N_per_m = 1.0e7;
  double poisson_ratio = 0.3;
  enum class Plane { strain, stress } plane = Plane::strain;
  enum class Base { rough, smooth } base = Base::rough;  ///< rough: u = 0; smooth: u_y = 0
  int degree = 2;                                        ///< FE_SimplexP degree, 1 or 2
  double gravity_change = -0.1;                          ///< relative change of g (DEM relaxation)
  SolverSettings solver;

  /// Lame's first parameter and the shear modulus of the 2D problem: for plane stress the
  /// effective lambda* = 2 lambda mu / (lambda + 2 mu) replaces lambda.
  double lambda_2d() const;
  double mu() const;
};

/// The fixed-principal-axes closure (Wittmer, Cates, Claudin). psi = pi/4 - phi/2 per side.
struct FpaSettings {
  double left_repose_angle_deg = 28.0;
  double right_repose_angle_deg = 28.0;
  /// true: the angles are the DEM pile's, read from the "dem" section of OUT/report.json
  /// (apply_dem_repose_angles), not from the scene.
  bool angles_from_dem = false;
  int degree = 1;
  /// Traction-free flanks: "strong" imposes sigma = 0 there (what traction-free plus the
  /// closure imply, see docs/CONTINUUM.md), "weak" adds surface_weight/h_F * |sigma n|^2 on
  /// the flanks to the least-squares functional.
  enum class Surface { strong, weak } surface = Surface::strong;
  double surface_weight = 10.0;
  /// Direct by default: the least-squares matrix of a hyperbolic operator is strongly
  /// anisotropic along the characteristics, which algebraic multigrid handles poorly
  /// (docs/CONTINUUM.md has the iteration counts); MUMPS's Cholesky factorisation does not care.
  SolverSettings solver{SolverSettings::Kind::direct};
};

struct ContinuumSettings {
  bool elastic = true;
  bool fpa = true;
  std::string mesh_file;  ///< empty: OUT/pile.msh if it exists, else generated from [mesh]
  bool has_mesh_table = false;
  double density_kg_per_m2 = 4100.0;   ///< bulk areal density (grains 5000 kg/m^2 at packing 0.82)
  double gravity_m_per_s2 = 9.81;
  std::vector<double> profile_heights = {0.0, 0.1, 0.2, 0.3, 0.5, 0.7};  ///< y / h, as [coarse]
  int profile_points = 61;             ///< points per horizontal cut, flank to flank, as [coarse]
  ElasticSettings elastic_model;
  FpaSettings fpa_model;
};

/// Reads [continuum] (and checks that it holds no unknown keys). Relative file names are taken
/// relative to scene_dir. Throws InputError naming the file and the key.
ContinuumSettings read_continuum_scene(SceneReader& reader, const std::string& scene_dir);

/// For angles_from_dem: takes repose_angle_left_deg and repose_angle_right_deg from the "dem"
/// section of report_path. InputError naming the file and key if absent or outside (0, 45).
void apply_dem_repose_angles(FpaSettings& fpa, const std::string& report_path);

}  // namespace pilelab::continuum
