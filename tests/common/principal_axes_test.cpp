// Principal axes of a 2D tensor: exact on tensors built from known axes, and the one anisotropy
// definition shared by coarse/, continuum/ and compare/.
#include <cmath>

#include <gtest/gtest.h>

#include "common/principal_axes.h"

using namespace pilelab;

namespace {
// Q diag(major, minor) Q^T with Q the rotation by theta: the tensor whose major axis is at theta.
struct Sym {
  double xx, yy, xy;
};
Sym from_axes(double major, double minor, double theta_deg) {
  const double t = theta_deg * M_PI / 180.0, c = std::cos(t), s = std::sin(t);
  return {major * c * c + minor * s * s, major * s * s + minor * c * c, (major - minor) * s * c};
}
}  // namespace

TEST(PrincipalAxes, RecoversTheAxesATensorWasBuiltFrom) {
  for (double theta : {0.0, 17.0, 45.0, 89.0, 90.0, 120.0, 179.0}) {
    const Sym t = from_axes(3.0, 1.0, theta);
    const PrincipalAxes p = principal_axes(t.xx, t.yy, t.xy);
    EXPECT_NEAR(p.major, 3.0, 1e-14) << theta;
    EXPECT_NEAR(p.minor, 1.0, 1e-14) << theta;
    EXPECT_NEAR(p.mean, 2.0, 1e-14) << theta;
    EXPECT_NEAR(p.anisotropy, 0.5, 1e-14) << theta;
    EXPECT_NEAR(p.orientation_deg, theta, 1e-12) << theta;
  }
}

TEST(PrincipalAxes, OrientationIsAnAxisInZeroTo180) {
  // theta and theta + 180 are the same axis; -30 reads 150.
  const Sym t = from_axes(2.0, -1.0, -30.0);
  EXPECT_NEAR(principal_axes(t.xx, t.yy, t.xy).orientation_deg, 150.0, 1e-12);
  const Sym u = from_axes(2.0, -1.0, 210.0);
  EXPECT_NEAR(principal_axes(u.xx, u.yy, u.xy).orientation_deg, 30.0, 1e-12);
}

TEST(PrincipalAxes, AnisotropyIsBoundedWhereTheSignsDiffer) {
  // (major - minor) / (|major| + |minor|): 1 for pure shear, where |major + minor| would be 0.
  const PrincipalAxes shear = principal_axes(0.0, 0.0, 2.0);
  EXPECT_NEAR(shear.anisotropy, 1.0, 1e-15);
  EXPECT_NEAR(shear.orientation_deg, 45.0, 1e-12);
  const Sym t = from_axes(3.0, -1.0, 10.0);
  EXPECT_NEAR(principal_axes(t.xx, t.yy, t.xy).anisotropy, 1.0, 1e-14);
}

TEST(PrincipalAxes, ZeroTensorHasNoAnisotropy) {
  const PrincipalAxes zero = principal_axes(0.0, 0.0, 0.0);
  EXPECT_EQ(zero.anisotropy, 0.0);
  // No major axis: the convention is the vertical, whatever the signs of the zeros.
  EXPECT_EQ(zero.orientation_deg, 90.0);
  EXPECT_EQ(principal_axes(-0.0, -0.0, -0.0).orientation_deg, 90.0);
  EXPECT_EQ(principal_axes(2.0, 2.0, 0.0).orientation_deg, 90.0);
  // Below zero_scale a tensor counts as zero; above it, it does not.
  EXPECT_EQ(principal_axes(2e-12, 1e-12, 0.0, 1e-9).anisotropy, 0.0);
  EXPECT_NEAR(principal_axes(2e-6, 1e-6, 0.0, 1e-9).anisotropy, 1.0 / 3.0, 1e-12);
}
