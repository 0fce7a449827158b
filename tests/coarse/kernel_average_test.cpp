// Kernel coarse-graining: normalised kernels and the exact momentum balance it is chosen for.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "coarse/kernel_average.h"

using namespace pilelab::coarse;
using pilelab::dem::Vec2;

// Every registered kernel integrates to one over the plane (midpoint rule in polar
// coordinates, error O(1/n^2), below 1e-7 at n = 20000).
TEST(KernelAverage, EveryKernelIntegratesToOne) {
  ASSERT_GE(kernel_shapes().size(), 4u);
  for (const KernelShape* shape : kernel_shapes()) {
    const Kernel k(*shape, 0.7);
    const double R = k.support();
    const int n = 20000;
    double integral = 0;
    for (int i = 0; i < n; ++i) {
      const double r = (i + 0.5) * R / n;
      integral += k.value(r) * 2 * M_PI * r * R / n;
    }
    EXPECT_NEAR(integral, 1.0, 1e-7) << shape->name;
    EXPECT_EQ(k.value(R * (1 + 1e-12)), 0.0) << shape->name << ": nothing beyond the support";
    // The mass within r, 2 pi r^2 mass_within_over_r2(r), against the same midpoint rule.
    for (double f : {0.2, 0.5, 0.9}) {
      double within = 0;
      for (int i = 0; i < n; ++i) {
        const double r = (i + 0.5) * f * R / n;
        within += k.value(r) * 2 * M_PI * r * f * R / n;
      }
      EXPECT_NEAR(2 * M_PI * f * R * f * R * k.mass_within_over_r2(f * R), within, 1e-7) << shape->name << " at " << f;
    }
  }
}

// Each registered kernel by name; an unknown name is refused naming the known ones.
TEST(KernelAverage, KernelsAreFoundByName) {
  for (const char* name : {"gaussian", "lucy", "heaviside", "linear"}) EXPECT_STREQ(kernel_shape(name).name, name);
  try {
    kernel_shape("cubic");
    FAIL() << "an unknown kernel was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no coarse-graining kernel 'cubic' (known: gaussian, lucy, heaviside, linear)"),
              std::string::npos)
        << e.what();
  }
}

// Cambou's fit weighted by any kernel is exact on affine fields: u = H x + c gives back H at
// points whose kernel lies inside the packing.
TEST(KernelAverage, EveryKernelGivesTheExactStrainOfAnAffineDisplacement) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Packing p;
  for (int i = 0; i < 400; ++i) {
    Grain g;
    g.body = i;
    g.centre = {u(rng), u(rng)};
    g.mass = g.area = 1e-3;
    p.grains.push_back(g);
  }
  for (int i = 0; i < 400; ++i)
    for (int j = i + 1; j < 400; ++j)
      if ((p.grains[j].centre - p.grains[i].centre).norm() < 0.08)
        p.contacts.push_back({i, j, 0.5 * (p.grains[i].centre + p.grains[j].centre), Vec2(0.1, -0.2)});
  Tensor H;
  H << 1.3e-3, -0.7e-3, 2.1e-3, -0.4e-3;
  Packing later = p;
  for (Grain& g : later.grains) g.centre = g.centre + H * g.centre + Vec2(1e-4, -3e-4);
  for (const KernelShape* shape : kernel_shapes()) {
    KernelAverager kernel(p, Kernel(*shape, 0.1));
    kernel.set_displacements(later);
    for (const Vec2& x : {Vec2(0.5, 0.5), Vec2(0.4, 0.6)}) {
      const RveSample sample = kernel.average(x);
      ASSERT_TRUE(sample.has_strain) << shape->name;
      EXPECT_LT((sample.displacement_gradient - H).norm(), 1e-12) << shape->name << " at " << x.transpose();
    }
  }
}

// div sigma = sum_p phi(r - r_p) F_p - sum_walls f_c phi(r - x_c) for ANY packing (F_p: the
// sum of contact forces on p), because each branch integral differentiates to the kernel at
// its ends. Checked by central differences (error O(h^2)) against the 5-point Gauss rule's
// error on a branch shorter than the kernel width.
TEST(KernelAverage, DivergenceOfStressIsTheNetContactForceDensity) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Packing p;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    Grain g;
    g.body = i;
    g.centre = {u(rng), u(rng)};
    g.mass = 1.0;
    g.area = 1e-3;
    p.grains.push_back(g);
  }
  std::vector<Vec2> net(n, Vec2::Zero());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if ((p.grains[j].centre - p.grains[i].centre).norm() < 0.03) {
        const Vec2 f(u(rng) - 0.5, u(rng) - 0.5);
        p.contacts.push_back({i, j, 0.5 * (p.grains[i].centre + p.grains[j].centre), f});
        net[i] += f;
        net[j] -= f;
      }
  const double w = 0.15;
  const Kernel lucy(kernel_shape("lucy"), w);
  KernelAverager kernel(p, lucy);
  const double h = 1e-4;
  for (const Vec2& x : {Vec2(0.5, 0.5), Vec2(0.3, 0.6), Vec2(0.62, 0.41)}) {
    const Tensor sx = (kernel.average(x + Vec2(h, 0)).stress - kernel.average(x - Vec2(h, 0)).stress) / (2 * h);
    const Tensor sy = (kernel.average(x + Vec2(0, h)).stress - kernel.average(x - Vec2(0, h)).stress) / (2 * h);
    const Vec2 div(sx(0, 0) + sy(0, 1), sx(1, 0) + sy(1, 1));
    Vec2 expected = Vec2::Zero();
    double scale = 0;
    for (int i = 0; i < n; ++i) {
      expected += lucy.value((x - p.grains[i].centre).norm()) * net[i];
      scale += lucy.value((x - p.grains[i].centre).norm()) * net[i].norm();
    }
    EXPECT_LT((div - expected).norm(), 1e-4 * scale) << x.transpose();
  }
}

namespace {
// A closed polygon (counter-clockwise corners) as a domain.
Domain polygon_domain(const std::vector<Vec2>& corners) {
  Domain d;
  for (std::size_t i = 0; i < corners.size(); ++i) d.edges.emplace_back(corners[i], corners[(i + 1) % corners.size()]);
  return d;
}
}  // namespace

// A radial kernel centred on a corner of angle alpha, its support inside the corner's two
// edges, has alpha / 2 pi of its mass inside: exactly, whatever the kernel. On a straight
// edge (alpha = pi) that is one half; deep inside, all.
TEST(KernelAverage, MassFractionAtCornersIsTheirAngleOver2Pi) {
  const double w = 0.1;
  for (const KernelShape* shape : kernel_shapes()) {
    const Kernel k(*shape, w);
    const double L = 10 * k.support();
    const Domain square = polygon_domain({{0, 0}, {L, 0}, {L, L}, {0, L}});
    EXPECT_NEAR(kernel_mass_fraction_in(square, k, {0, 0}), 0.25, 1e-12);           // a right angle
    EXPECT_NEAR(kernel_mass_fraction_in(square, k, {0.5 * L, 0}), 0.5, 1e-12);      // a straight edge
    EXPECT_EQ(kernel_mass_fraction_in(square, k, {0.5 * L, 0.5 * L}), 1.0);         // deep inside
    EXPECT_EQ(kernel_mass_fraction_in(square, k, {2 * L, 0.5 * L}), 0.0);           // far outside
    // The apex of a pile-like wedge: flanks at 25 degrees to the base, interior angle 130.
    const double a = 25 * M_PI / 180;
    const Domain wedge = polygon_domain({{-L * std::cos(a), 0}, {L * std::cos(a), 0}, {0, L * std::sin(a)}});
    EXPECT_NEAR(kernel_mass_fraction_in(wedge, k, {0, L * std::sin(a)}), (M_PI - 2 * a) / (2 * M_PI), 1e-12);
    EXPECT_NEAR(kernel_mass_fraction_in(polygon_domain({}), k, {0, 0}), 1.0, 0.0);  // no domain: the plane
  }
}

// At a distance y0 from a straight edge the Gaussian kernel, were it not cut, would have
// 1 - erfc(y0 / w) / 2 of its mass inside; the cut at 3 w changes a fraction by at most
// e^-9 / (1 - e^-9) = 1.2e-4. And complementary domains share the kernel's mass.
TEST(KernelAverage, MassFractionNearAnEdgeIsTheErfOfTheDistance) {
  const double w = 0.1, L = 5.0;
  const Domain upper = polygon_domain({{-L, 0}, {L, 0}, {L, L}, {-L, L}});
  const Domain lower = polygon_domain({{-L, -L}, {L, -L}, {L, 0}, {-L, 0}});
  for (double y0 : {0.01, 0.05, 0.1, 0.2}) {
    const double f = kernel_mass_fraction_in(upper, Kernel(kernel_shape("gaussian"), w), {0.3, y0});
    EXPECT_NEAR(f, 1 - 0.5 * std::erfc(y0 / w), 1.3e-4) << y0;
    for (const KernelShape* shape : kernel_shapes())
      EXPECT_NEAR(kernel_mass_fraction_in(upper, Kernel(*shape, w), {0.3, y0}) +
                      kernel_mass_fraction_in(lower, Kernel(*shape, w), {0.3, y0}),
                  1.0, 1e-12);
  }
}

// The Lucy kernel's mass beyond a line at distance y0 < w, summed independently by a nested
// midpoint rule over the cut-off cap (error O(1/n^2): below 1e-6 at n = 1000).
TEST(KernelAverage, LucyMassFractionNearAnEdgeMatchesDirectQuadrature) {
  const double w = 0.1, L = 5.0;
  const Domain upper = polygon_domain({{-L, 0}, {L, 0}, {L, L}, {-L, L}});
  const int n = 1000;
  for (double y0 : {0.001, 0.02, 0.05, 0.08}) {
    double outside = 0;
    for (int i = 0; i < n; ++i) {
      const double y = y0 + (w - y0) * (i + 0.5) / n, half = std::sqrt(w * w - y * y);
      for (int j = 0; j < n; ++j) {
        const double x = -half + 2 * half * (j + 0.5) / n;
        outside += Kernel(kernel_shape("lucy"), w).value(std::hypot(x, y)) * (2 * half / n) * ((w - y0) / n);
      }
    }
    EXPECT_NEAR(kernel_mass_fraction_in(upper, Kernel(kernel_shape("lucy"), w), {0.3, y0}), 1 - outside, 1e-6) << y0;
  }
}

// Near a corner, with the corner and both edges inside the kernel's support and the point on
// neither: the Gauss pieces that stop at the support, at the corner and at each edge's point
// nearest to the point, against a nested midpoint rule over the quadrant (error O(1/n^2):
// below 1e-6 at n = 1000 for the Lucy kernel, which is smooth up to its support).
TEST(KernelAverage, MassFractionNearACornerMatchesDirectQuadrature) {
  const double w = 0.1, L = 5.0;
  const Domain square = polygon_domain({{0, 0}, {L, 0}, {L, L}, {0, L}});
  const int n = 1000;
  for (const Vec2& x : {Vec2(0.03, 0.04), Vec2(0.001, 0.07), Vec2(0.06, 0.012)}) {
    const double x0 = std::max(0.0, x.x() - w), x1 = x.x() + w, y0 = std::max(0.0, x.y() - w), y1 = x.y() + w;
    double inside = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const Vec2 y(x0 + (x1 - x0) * (i + 0.5) / n, y0 + (y1 - y0) * (j + 0.5) / n);
        inside += Kernel(kernel_shape("lucy"), w).value((y - x).norm());
      }
    inside *= (x1 - x0) * (y1 - y0) / (double(n) * n);
    EXPECT_NEAR(kernel_mass_fraction_in(square, Kernel(kernel_shape("lucy"), w), x), inside, 1e-6) << x.transpose();
  }
}

// A material filling a rectangle uniformly (grains on a square lattice of spacing s, area a
// each: volume fraction a / s^2). Near its edge the plain kernel sum is diluted by the part of
// the kernel outside; clipped to the domain it is the bulk value again, up to the lattice's
// midpoint-rule error, O((s / w)^2) (here s = w / 50: about 1e-3 at most).
TEST(KernelAverage, ClippedToTheDomainADensityIsNotDilutedAtTheBoundary) {
  const double w = 0.05, s = w / 50, a = 0.5 * s * s, L = 0.4;
  Packing p;
  for (int i = 0; i * s < L; ++i)
    for (int j = 0; j * s < L; ++j) {
      Grain g;
      g.body = static_cast<int>(p.grains.size());
      g.centre = {(i + 0.5) * s, (j + 0.5) * s};
      g.mass = a;
      g.area = a;
      p.grains.push_back(g);
    }
  // Each grain pressed by its right-hand neighbour with 1 N along the row: sigma_xx = -1 / s
  // (one contact of branch s per cell of area s^2), the same at the base as inside, since the
  // rows run along the base.
  const int per_row = static_cast<int>(std::lround(std::sqrt(double(p.grains.size()))));  // the loops' count
  ASSERT_EQ(std::size_t(per_row) * per_row, p.grains.size());
  for (int i = 0; i + 1 < per_row; ++i)
    for (int j = 0; j < per_row; ++j) {
      const int a = i * per_row + j, b = (i + 1) * per_row + j;
      p.contacts.push_back({a, b, 0.5 * (p.grains[a].centre + p.grains[b].centre), Vec2(-1.0, 0.0)});
    }
  const double extent = per_row * s;
  const Domain box = polygon_domain({{0, 0}, {extent, 0}, {extent, extent}, {0, extent}});
  for (const char* name : {"lucy", "gaussian"}) {
    const Kernel k(kernel_shape(name), w);
    const KernelAverager clipped(p, k, box, true), plain(p, k, box, false);
    const Vec2 at_base(0.5 * extent, 0.2 * w), inside(0.5 * extent, 0.5 * extent);
    EXPECT_NEAR(clipped.average(inside).volume_fraction, 0.5, 2e-3);
    EXPECT_NEAR(clipped.average(at_base).volume_fraction, 0.5, 2e-3);
    EXPECT_NEAR(clipped.average(inside).stress(0, 0) * s, -1.0, 4e-3);
    EXPECT_NEAR(clipped.average(at_base).stress(0, 0) * s, -1.0, 4e-3);
    EXPECT_LT(plain.average(at_base).volume_fraction, 0.5 * 0.9);  // the dilution the clip removes
    EXPECT_NEAR(clipped.average(at_base).volume_fraction,
                plain.average(at_base).volume_fraction / kernel_mass_fraction_in(box, k, at_base), 1e-12);
  }
}
