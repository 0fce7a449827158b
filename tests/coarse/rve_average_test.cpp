// RVE averages (paper eq. 12-19) on synthetic packings with exactly known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "coarse/rve_average.h"
#include "coarse/rve_study.h"
#include "dem/shape.h"

using namespace pilelab::coarse;
using pilelab::dem::Vec2;

namespace {

// A random packing: hexagons of one size scattered over a box, contacts between close pairs
// and with a floor, arbitrary forces. The tensors' algebra does not care about equilibrium.
struct Synthetic {
  pilelab::dem::Shape hexagon;
  Packing packing;
};

Synthetic random_packing(unsigned seed, int n = 400, double box = 0.2) {
  Synthetic s;
  std::vector<Vec2> corners;
  for (int k = 0; k < 6; ++k) corners.emplace_back(0.004 * std::cos(k * M_PI / 3), 0.004 * std::sin(k * M_PI / 3));
  s.hexagon = pilelab::dem::make_polygon(corners);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < n; ++i) {
    Grain g;
    g.body = i + 5;
    g.centre = {box * u(rng) - box / 2, box * u(rng)};
    g.angle = 2 * M_PI * u(rng);
    g.area = s.hexagon.area;
    g.mass = 5000 * g.area;
    g.shape = &s.hexagon;
    s.packing.grains.push_back(g);
  }
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Vec2 d = s.packing.grains[j].centre - s.packing.grains[i].centre;
      if (d.norm() > 0.012) continue;
      Contact c;
      c.a = i;
      c.b = j;
      c.point = s.packing.grains[i].centre + (0.3 + 0.4 * u(rng)) * d;
      c.force_on_a = {u(rng) - 0.5, -u(rng)};
      s.packing.contacts.push_back(c);
    }
  return s;
}

// Exact area of the disc (c, R) covered by squares of side 2 h centred on the integer lattice,
// computed independently of coarse/ by slicing: with x = cx + R sin t, the material length of
// the vertical chord at x is L(cy + R cos t) - L(cy - R cos t), where L(y) is the material
// length of the y-lattice below y, piecewise linear: L(y) = A + b y with b = 1 on a square and 0
// in a gap. Between the angles where x or a chord end crosses a square's edge, A and b are
// constant, so the integral over dx = R cos t dt is C1 R int cos + C2 R^2 int cos^2, in closed form.
double lattice_area_in_disc(const Vec2& c, double R, double h) {
  auto in_square = [&](double y) { return std::abs(y - std::round(y)) <= h; };
  auto L = [&](double y) {
    const double n = std::floor(y + 0.5);
    return 2 * h * n + std::clamp(y - n, -h, h);
  };
  std::vector<double> cuts = {-M_PI / 2, M_PI / 2};
  for (long i = std::lround(std::floor(c.x() - R)) - 1; i <= std::lround(std::ceil(c.x() + R)) + 1; ++i)
    for (double e : {i - h, i + h})
      if (std::abs(e - c.x()) < R) cuts.push_back(std::asin((e - c.x()) / R));
  for (long j = std::lround(std::floor(c.y() - R)) - 1; j <= std::lround(std::ceil(c.y() + R)) + 1; ++j)
    for (double e : {j - h, j + h})
      for (double cos_t : {(e - c.y()) / R, (c.y() - e) / R})  // upper and lower chord ends
        if (cos_t > 0 && cos_t < 1) cuts.insert(cuts.end(), {std::acos(cos_t), -std::acos(cos_t)});
  std::sort(cuts.begin(), cuts.end());
  double area = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double a = cuts[k], b = cuts[k + 1], m = 0.5 * (a + b);
    if (!(b > a) || !in_square(c.x() + R * std::sin(m))) continue;
    const double hi = c.y() + R * std::cos(m), lo = c.y() - R * std::cos(m);
    const double b_hi = in_square(hi), b_lo = in_square(lo);
    const double A_hi = L(hi) - b_hi * hi, A_lo = L(lo) - b_lo * lo;
    const double c1 = A_hi - A_lo + (b_hi - b_lo) * c.y(), c2 = b_hi + b_lo;
    area += c1 * R * (std::sin(b) - std::sin(a)) + c2 * R * R * (0.5 * (b - a) + 0.25 * (std::sin(2 * b) - std::sin(2 * a)));
  }
  return area;
}

Tensor rotation(double angle) {
  Tensor q;
  q << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return q;
}

}  // namespace

// Cambou's fit is exact on affine fields: u = H x + c gives back H, whatever the packing.
TEST(RveAverage, AffineDisplacementGivesItsGradientExactly) {
  Synthetic s = random_packing(1);
  Tensor H;
  H << 1.3e-3, -0.7e-3, 2.1e-3, -0.4e-3;
  const Vec2 shift(1e-4, -3e-4);
  Packing later = s.packing;
  for (Grain& g : later.grains) g.centre = g.centre + H * g.centre + shift;
  RveAverager rve(s.packing);
  rve.set_displacements(later);
  for (const Vec2& p : {Vec2(0, 0.1), Vec2(-0.05, 0.05), Vec2(0.07, 0.15)}) {
    const RveSample sample = rve.average(p, 0.03);
    ASSERT_TRUE(sample.has_strain);
    EXPECT_LT((sample.displacement_gradient - H).norm(), 1e-12) << p.transpose();
    EXPECT_LT(sample.strain_fit_residual, 1e-10);
    EXPECT_NEAR(sample.rotation(), 0.5 * (H(1, 0) - H(0, 1)), 1e-12);
  }
}

// Rotating the packing rotates every tensor: sigma' = Q sigma Q^T, and scalars do not change.
TEST(RveAverage, RotatedPackingGivesRotatedTensors) {
  Synthetic s = random_packing(2);
  const double angle = 0.7;
  const Tensor Q = rotation(angle);
  Packing turned = s.packing;
  for (Grain& g : turned.grains) {
    g.centre = Q * g.centre;
    g.angle += angle;
  }
  for (Contact& c : turned.contacts) {
    c.point = Q * c.point;
    c.force_on_a = Q * c.force_on_a;
  }
  RveAverager a(s.packing), b(turned);
  const Vec2 p(0.01, 0.1);
  const RveSample x = a.average(p, 0.04), y = b.average(Q * p, 0.04);
  ASSERT_EQ(x.grain_count, y.grain_count);
  const double scale = x.stress.norm();
  EXPECT_LT((Q * x.stress * Q.transpose() - y.stress).norm(), 1e-12 * scale);
  EXPECT_LT((Q * x.fabric * Q.transpose() - y.fabric).norm(), 1e-12 * x.fabric.norm());
  EXPECT_NEAR(x.volume_fraction, y.volume_fraction, 1e-12);
  EXPECT_EQ(x.coordination, y.coordination);
}

// Monodisperse grains: tr<F> = (1/V) sum V^p c^p = (N a / V) C; the volume fraction from the
// outlines differs from N a / V only by grains cut by the RVE circle, all within a bounding
// radius b of it, so |tr F - v C| <= C * (area of the annulus R +- b) / V.
TEST(RveAverage, FabricTraceIsVolumeFractionTimesCoordinationForEqualGrains) {
  Synthetic s = random_packing(3, 600);
  RveAverager rve(s.packing);
  const double b = s.hexagon.bounding_radius;
  for (double R : {0.02, 0.04, 0.06}) {
    const RveSample x = rve.average({0, 0.1}, R);
    ASSERT_GT(x.grain_count, 10);
    const double bound = x.coordination * (M_PI * ((R + b) * (R + b) - (R - b) * (R - b))) / x.volume;
    EXPECT_NEAR(x.fabric.trace(), x.volume_fraction * x.coordination, bound) << R;
    // and exactly with the centre-based volume fraction:
    EXPECT_NEAR(x.fabric.trace(), x.grain_count * s.hexagon.area / x.volume * x.coordination, 1e-12);
  }
}

// Grains of a perfect square lattice with unit spacing and touching neighbours: known
// volume fraction (grain area per cell) deep inside, coordination 4, fabric isotropic.
TEST(RveAverage, SquareLatticeOfSquaresHasKnownDensityAndFabric) {
  pilelab::dem::Shape sq = pilelab::dem::make_polygon({{-0.4, -0.4}, {0.4, -0.4}, {0.4, 0.4}, {-0.4, 0.4}});
  Packing p;
  const int n = 40;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      Grain g;
      g.body = j * n + i;
      g.centre = {i - n / 2.0, static_cast<double>(j)};
      g.area = sq.area;
      g.shape = &sq;
      p.grains.push_back(g);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int k = j * n + i;
      if (i + 1 < n) p.contacts.push_back({k, k + 1, p.grains[k].centre + Vec2(0.5, 0), {-1, 0}});
      if (j + 1 < n) p.contacts.push_back({k, k + n, p.grains[k].centre + Vec2(0, 0.5), {0, -1}});
    }
  RveAverager rve(p);
  const Vec2 centre(0.3, 20.2);
  const RveSample x = rve.average(centre, 8.0);
  // The outline-based fraction counts the cut grains' parts inside the disc exactly, so it
  // equals the lattice's exact material area over the disc's, up to rounding (~1e-15 per term
  // over a few hundred terms). Dropping the cut grains would lose about 0.64 * 2 pi R * 0.5.
  ASSERT_NEAR(x.volume, M_PI * 64.0, 1e-12);
  const double exact = lattice_area_in_disc(centre, 8.0, 0.4);
  EXPECT_NEAR(x.volume_fraction, exact / x.volume, 1e-11);
  // The slicing itself, on discs with known answers: inside one square, and a disc over many
  // cells whose fraction tends to 0.64.
  EXPECT_NEAR(lattice_area_in_disc({3.05, -2.0}, 0.3, 0.4), M_PI * 0.09, 1e-14);
  EXPECT_NEAR(lattice_area_in_disc({0.5, 0.5}, 0.1, 0.4), 0.0, 1e-15);  // in a gap
  EXPECT_NEAR(lattice_area_in_disc({0.3, 0.7}, 200.0, 0.4) / (M_PI * 4e4), 0.64, 2 * 2 * M_PI * 200 * 0.5 / (M_PI * 4e4));
  EXPECT_EQ(x.coordination, 4.0);
  const double per_area = x.grain_count * 0.64 / x.volume;
  EXPECT_NEAR(x.fabric(0, 0), 2 * per_area, 1e-12);
  EXPECT_NEAR(x.fabric(1, 1), 2 * per_area, 1e-12);
  EXPECT_NEAR(x.fabric(0, 1), 0.0, 1e-12);
  // Unit compressive contact forces, both directions: sigma = -(N/V) * 0.5 * 2 * I... each
  // grain has 4 contacts of force 1 at distance 0.5: sum x F = -1 per direction.
  EXPECT_NEAR(x.stress(0, 0), -x.grain_count / x.volume, 1e-12);
  EXPECT_NEAR(x.stress(1, 1), -x.grain_count / x.volume, 1e-12);
}

TEST(RveAverage, EmptyRveHasNoData) {
  Synthetic s = random_packing(4);
  RveAverager rve(s.packing);
  const RveSample x = rve.average({5.0, 5.0}, 0.01);
  EXPECT_FALSE(x.has_data());
  EXPECT_EQ(x.stress, Tensor::Zero());
  EXPECT_FALSE(x.has_strain);
}

// Contacts along one line cannot determine a 2D gradient: the fit is refused, not NaN.
TEST(RveAverage, CollinearContactsGiveNoStrain) {
  Packing p;
  for (int i = 0; i < 5; ++i) {
    Grain g;
    g.body = i;
    g.centre = {0.01 * i, 0.0};
    g.area = 1e-5;
    p.grains.push_back(g);
  }
  for (int i = 0; i + 1 < 5; ++i) p.contacts.push_back({i, i + 1, {0.01 * i + 0.005, 0.0}, {-1, 0}});
  Packing later = p;
  for (Grain& g : later.grains) g.centre.x() *= 1.001;
  RveAverager rve(p);
  rve.set_displacements(later);
  const RveSample x = rve.average({0.02, 0}, 0.1);
  EXPECT_TRUE(x.has_data());
  EXPECT_FALSE(x.has_strain);
  EXPECT_TRUE(std::isfinite(x.displacement_gradient.norm()));
}

// The RVE volume is clipped to the domain: on a base, half the disc.
TEST(RveAverage, VolumeIsClippedToTheDomain) {
  Synthetic s = random_packing(5);
  Domain half_plane;  // y >= 0, a large square with its lower edge on y = 0 (counter-clockwise)
  half_plane.edges = {{{-10, 0}, {10, 0}}, {{10, 0}, {10, 20}}, {{10, 20}, {-10, 20}}, {{-10, 20}, {-10, 0}}};
  RveAverager rve(s.packing, half_plane);
  EXPECT_NEAR(rve.average({0.0, 0.0}, 0.03).volume, M_PI * 0.03 * 0.03 / 2, 1e-15);
  EXPECT_NEAR(rve.average({0.0, 0.1}, 0.03).volume, M_PI * 0.03 * 0.03, 1e-15);
}

// The study grows the radius until a grain count or a radius is reached; a start radius of
// NaN (0/0 from a pile without grains) or 0 reaches neither, so it is refused, not looped on.
TEST(RveStudy, RefusesRadiiThatNeverGrow) {
  Synthetic s = random_packing(6);
  RveAverager rve(s.packing);
  const std::vector<Vec2> points = {{0.0, 0.1}};
  RveStudySettings ok;
  ok.first_radius_m = 0.01;
  ok.max_radius_m = 0.2;
  EXPECT_GT(rve_size_study(rve, points, ok).chosen_grain_count, 0.0);
  for (double r : {double(NAN), 0.0, -0.01, double(INFINITY)}) {
    RveStudySettings bad = ok;
    bad.first_radius_m = r;
    EXPECT_THROW(rve_size_study(rve, points, bad), std::invalid_argument) << r;
  }
  RveStudySettings no_growth = ok;
  no_growth.growth = 1.0;
  EXPECT_THROW(rve_size_study(rve, points, no_growth), std::invalid_argument);
  RveStudySettings nan_limit = ok;
  nan_limit.max_radius_m = NAN;
  EXPECT_THROW(rve_size_study(rve, points, nan_limit), std::invalid_argument);
}

TEST(TensorSummary, PrincipalValuesAndOrientation) {
  // A compressive stress with its major axis 30 degrees above the horizontal.
  const Tensor Q = rotation(30 * M_PI / 180);
  Tensor d = Tensor::Zero();
  d(0, 0) = -3.0;
  d(1, 1) = -1.0;
  const TensorSummary s = summarise(Q * d * Q.transpose(), -1.0);
  EXPECT_NEAR(s.major, 3.0, 1e-14);
  EXPECT_NEAR(s.minor, 1.0, 1e-14);
  EXPECT_NEAR(s.mean, 2.0, 1e-14);
  EXPECT_NEAR(s.anisotropy, 0.5, 1e-14);
  EXPECT_NEAR(s.orientation_deg, 30.0, 1e-12);
  // Orientation is an axis: -150 degrees is reported as 30, -30 as 150.
  const TensorSummary t = summarise(rotation(-150 * M_PI / 180) * d * rotation(-150 * M_PI / 180).transpose(), -1.0);
  EXPECT_NEAR(t.orientation_deg, 30.0, 1e-12);
  const TensorSummary u = summarise(rotation(-30 * M_PI / 180) * d * rotation(-30 * M_PI / 180).transpose(), -1.0);
  EXPECT_NEAR(u.orientation_deg, 150.0, 1e-12);
}
