// The material's conversions are one another's inverses, and its stress law has the textbook
// responses: a pure shear takes 2 mu, an equibiaxial strain in plane strain 2 (lambda + mu), and
// plane stress's reduced lambda* = E nu / (1 - nu^2).
#include <cmath>

#include <gtest/gtest.h>

#include "common/isotropic_material.h"

using pilelab::IsotropicMaterial;

TEST(IsotropicMaterial, LameRoundTrip) {
  for (double nu : {-0.9, 0.0, 0.3, 0.49}) {
    const IsotropicMaterial m{2.5e6, nu};
    const IsotropicMaterial back = IsotropicMaterial::from_lame(m.lame_lambda(), m.shear_modulus());
    EXPECT_NEAR(back.youngs_modulus_N_per_m, m.youngs_modulus_N_per_m, 1e-12 * m.youngs_modulus_N_per_m);
    EXPECT_NEAR(back.poisson_ratio, nu, 1e-12);
    EXPECT_NEAR(m.shear_modulus(), m.youngs_modulus_N_per_m / (2 * (1 + nu)), 1e-9);
    EXPECT_TRUE(m.stable());
  }
  EXPECT_FALSE((IsotropicMaterial{1e6, 0.5}).stable());
  EXPECT_FALSE((IsotropicMaterial{1e6, -1.0}).stable());
}

TEST(IsotropicMaterial, PlaneStressReducesLambda) {
  const IsotropicMaterial m{3e6, 0.25};
  EXPECT_NEAR(m.lambda_2d(true), 3e6 * 0.25 / (1 - 0.25 * 0.25), 1e-9 * 3e6);
  EXPECT_EQ(m.lambda_2d(false), m.lame_lambda());
}

TEST(IsotropicMaterial, StressLaw) {
  const IsotropicMaterial m{1e7, 0.3};
  const double mu = m.shear_modulus(), lambda = m.lame_lambda(), e = 1e-4;
  const auto shear = m.stress({0, 0, e}, false);
  EXPECT_NEAR(shear[2], 2 * mu * e, 1e-12 * mu * e);
  EXPECT_EQ(shear[0], 0.0);
  const auto bulk = m.stress({e, e, 0}, false);
  EXPECT_NEAR(bulk[0], 2 * (lambda + mu) * e, 1e-12 * mu * e);
  EXPECT_NEAR(bulk[1], bulk[0], 1e-12 * mu * e);
  // Uniaxial stress in plane stress: eps_yy = -nu eps_xx gives sigma_yy = 0, sigma_xx = E eps_xx.
  const auto uniaxial = m.stress({e, -0.3 * e, 0}, true);
  EXPECT_NEAR(uniaxial[1], 0.0, 1e-12 * mu * e);
  EXPECT_NEAR(uniaxial[0], 1e7 * e, 1e-9 * 1e7 * e);
}
