#pragma once
// The closed loop of a stress-strain fit, as one plain value handed from the comparison
// (compare/, which builds it from the fit and the fields) to the continuum models (continuum/,
// which solve it): the gravity change the DEM's strains come from, on the fields' mesh, for
// isotropic elasticity (plane strain, rough base) with the fitted constants.
#include <string>

namespace pilelab {

struct GravityChangeProblem {
  std::string mesh_file;
  double lame_lambda_N_per_m = 0.0, shear_modulus_N_per_m = 0.0;
  double gravity_change = 0.0;  ///< relative change of g
  double density_kg_per_m2 = 0.0, gravity_m_per_s2 = 0.0;
};

}  // namespace pilelab
