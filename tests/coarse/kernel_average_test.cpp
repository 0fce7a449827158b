// Kernel coarse-graining: normalised kernels and the exact momentum balance it is chosen for.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coarse/kernel_average.h"

using namespace pilelab::coarse;
using pilelab::dem::Vec2;

// Both kernels integrate to one over the plane (midpoint rule in polar coordinates).
TEST(KernelAverage, KernelsAreNormalised) {
  for (Kernel k : {Kernel::gaussian, Kernel::lucy}) {
    const double w = 0.7, R = kernel_support(k, w);
    const int n = 20000;
    double integral = 0;
    for (int i = 0; i < n; ++i) {
      const double r = (i + 0.5) * R / n;
      integral += kernel_value(k, r, w) * 2 * M_PI * r * R / n;
    }
    // The Gaussian is cut at 3w, which drops exp(-9) of its mass.
    EXPECT_NEAR(integral, k == Kernel::gaussian ? 1 - std::exp(-9.0) : 1.0, 1e-7);
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
  KernelAverager kernel(p, Kernel::lucy, w);
  const double h = 1e-4;
  for (const Vec2& x : {Vec2(0.5, 0.5), Vec2(0.3, 0.6), Vec2(0.62, 0.41)}) {
    const Tensor sx = (kernel.average(x + Vec2(h, 0)).stress - kernel.average(x - Vec2(h, 0)).stress) / (2 * h);
    const Tensor sy = (kernel.average(x + Vec2(0, h)).stress - kernel.average(x - Vec2(0, h)).stress) / (2 * h);
    const Vec2 div(sx(0, 0) + sy(0, 1), sx(1, 0) + sy(1, 1));
    Vec2 expected = Vec2::Zero();
    double scale = 0;
    for (int i = 0; i < n; ++i) {
      expected += kernel_value(Kernel::lucy, (x - p.grains[i].centre).norm(), w) * net[i];
      scale += kernel_value(Kernel::lucy, (x - p.grains[i].centre).norm(), w) * net[i].norm();
    }
    EXPECT_LT((div - expected).norm(), 1e-4 * scale) << x.transpose();
  }
}
