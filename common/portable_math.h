// Sine, cosine and arctangent that give the same bits on every machine.
//
// glibc picks its sin, cos and atan at load time by the CPU's instruction set (FMA, AVX2), and
// the variants can differ in the last bit. A granular pile is chaotic: one such bit in a grain's
// orientation grows until the pile settles differently. The same build poured the 160-grain
// test pile to a height of 43.1 mm on this machine's CPU and 47.7 mm with FMA and AVX2 masked
// (GLIBC_TUNABLES), so the same scene and seed did not give the same result on another
// machine. These functions use only +, -, * and /, which IEEE 754 rounds correctly, and
// operations that are exact (fmod, nearbyint, frexp, ldexp, copysign), in a fixed order (the
// build sets -ffp-contract=off), so they give the same bits everywhere.
//
// Accuracy: faithful (within one ulp). Each result is rounded once from a value carried in
// double-double (the argument reduction, the table of arctangents, the quotient's residual),
// which costs half an ulp; the kernels' own roundings cost up to 0.36 ulp more (measured),
// the series' truncation nothing. tests/common/portable_math_test.cpp checks faithfulness
// against long double.
// sin and cos reduce exactly for |x| < 2e8 rad; beyond, deterministically, with an absolute
// error of about 4e-17 |x|.
#pragma once

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>

// The error-free transformations below (two_sum, two_product) need each operation rounded
// to double as written: no fast-math reassociation, no excess precision, no contraction.
#if defined(__FAST_MATH__)
#error "common/portable_math.h needs IEEE arithmetic as written: do not build with -ffast-math"
#endif
#if FLT_EVAL_METHOD != 0
#error "common/portable_math.h needs double operations evaluated in double (FLT_EVAL_METHOD 0)"
#endif
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

namespace pilelab {

namespace portable_math_detail {
// pi/2 = p1 + p2 + p3 + p4 to 135 bits; p1..p3 carry at most 26 significant bits, so k * p_i is
// exact for the |k| <= 2^27 + 4 the reduction meets, and x - k pi/2 is computed without
// cancellation error (Cody and Waite).
constexpr double two_over_pi = 0x1.45f306dc9c883p-1;
constexpr double pio2_1 = 0x1.921fb58000000p+0;
constexpr double pio2_2 = -0x1.dde9740000000p-27;
constexpr double pio2_3 = 0x1.1a62630000000p-54;
constexpr double pio2_4 = 0x1.8a2e03707344ap-81;
constexpr double pio2_hi = 0x1.921fb54442d18p+0, pio2_lo = 0x1.1a62633145c07p-54;
constexpr double pi_hi = 0x1.921fb54442d18p+1, pi_lo = 0x1.1a62633145c07p-53;

// A value carried as hi + lo with |lo| <= ulp(hi)/2: twice the precision of a double.
struct Wide {
  double hi, lo;
};

// s + e = a + b exactly (Knuth's two-sum).
inline Wide two_sum(double a, double b) {
  const double s = a + b, bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}

// p + e = a * b exactly (Dekker's product with Veltkamp's split; no fused multiply-add).
// Needs |a|, |b| below 2^996 and a product far from underflow; callers scale to stay there.
inline Wide two_product(double a, double b) {
  constexpr double split = 0x1p27 + 1.0;
  const double ta = split * a, ah = ta - (ta - a), al = a - ah;
  const double tb = split * b, bh = tb - (tb - b), bl = b - bh;
  const double p = a * b;
  return {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
}

// sin and cos of r + dr, |r| <= pi/4 + rounding, |dr| <= ulp(r). Taylor series: the first
// omitted terms, r^19/19! and r^20/20!, are below 1e-19 relative, far under half an ulp; dr
// enters to first order, sin(r + dr) = sin r + dr cos r, with cos r ~ 1 - r^2/2 (the next
// term is below 2^-106 relative).
inline double sin_kernel(double r, double dr) {
  const double z = r * r;
  const double p = -1.0 / 6 + z * (1.0 / 120 + z * (-1.0 / 5040 + z * (1.0 / 362880 + z * (-1.0 / 39916800 +
                   z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0 + z * (1.0 / 355687428096000.0)))))));
  return r + (z * (r * p - 0.5 * dr) + dr);
}

inline double cos_kernel(double r, double dr) {
  const double z = r * r;
  const double q = 1.0 / 24 + z * (-1.0 / 720 + z * (1.0 / 40320 + z * (-1.0 / 3628800 + z * (1.0 / 479001600.0 +
                   z * (-1.0 / 87178291200.0 + z * (1.0 / 20922789888000.0 + z * (-1.0 / 6402373705728000.0)))))));
  // 1 - z/2 loses the low bits of z/2; (1 - w) - z/2 gets them back, exactly, before the tail.
  const double half_z = 0.5 * z, w = 1.0 - half_z;
  return w + ((((1.0 - w) - half_z) + z * z * q) - r * dr);
}

// atan(j/16), j = 0..16, as hi + lo.
constexpr Wide atan_table[17] = {
    {0x0.0p+0, 0x0.0p+0},
    {0x1.ff55bb72cfdeap-5, -0x1.c934d86d23f1dp-60}, {0x1.fd5ba9aac2f6ep-4, -0x1.cd37686760c17p-59},
    {0x1.7b97b4bce5b02p-3, 0x1.347b0b4f881cap-58},  {0x1.f5b75f92c80ddp-3, 0x1.8ab6e3cf7afbdp-57},
    {0x1.362773707ebccp-2, -0x1.963a544b672d8p-57}, {0x1.6f61941e4def1p-2, -0x1.c63aae6f6e918p-56},
    {0x1.a64eec3cc23fdp-2, -0x1.24dec1b50b7ffp-56}, {0x1.dac670561bb4fp-2, 0x1.a2b7f222f65e2p-56},
    {0x1.0657e94db30d0p-1, -0x1.d5b495f6349e6p-56}, {0x1.1e00babdefeb4p-1, -0x1.928df287a668fp-58},
    {0x1.345f01cce37bbp-1, 0x1.1021137c71102p-55},  {0x1.4978fa3269ee1p-1, 0x1.2419a87f2a458p-56},
    {0x1.5d58987169b18p-1, 0x1.0028e4bc5e7cap-57},  {0x1.700a7c5784634p-1, -0x1.8c34d25aadef6p-56},
    {0x1.819d0b7158a4dp-1, -0x1.bf76229d3b917p-56}, {0x1.921fb54442d18p-1, 0x1.1a62633145c07p-55}};

// atan(q + dq) for 0 <= q <= 1, as hi + lo (not normalised). Below 7/64 a series in q itself;
// above, atan(q) = atan(c) + atan((q - c) / (1 + q c)) with c = j/16 the nearest table point,
// which leaves |u| <= 1/32 (q - c is exact, as q and c lie within a factor 2). The first
// omitted terms, (7/64)^25/25 and u^17/17, are below 1e-25.
inline Wide atan_unit(double q, double dq) {
  if (q < 7.0 / 64) {
    const double z = q * q;
    const double p = -1.0 / 3 + z * (1.0 / 5 + z * (-1.0 / 7 + z * (1.0 / 9 + z * (-1.0 / 11 + z * (1.0 / 13 +
                     z * (-1.0 / 15 + z * (1.0 / 17 + z * (-1.0 / 19 + z * (1.0 / 21 + z * (-1.0 / 23))))))))));
    return {q, q * z * p + dq * (1.0 - z)};
  }
  const int j = static_cast<int>(q * 16.0 + 0.5);
  const double c = j / 16.0;
  const Wide qc = two_product(q, c);
  const double u = ((q - c) + dq) / ((1.0 + qc.hi) + qc.lo);
  const double z = u * u;
  const double s = u * z * (-1.0 / 3 + z * (1.0 / 5 + z * (-1.0 / 7 + z * (1.0 / 9 + z * (-1.0 / 11 +
                   z * (1.0 / 13 + z * (-1.0 / 15)))))));
  const Wide head = two_sum(atan_table[j].hi, u);
  return {head.hi, head.lo + (atan_table[j].lo + s)};
}

// atan(a / b) for 0 <= a <= b, b > 0 finite, as hi + lo: the quotient's rounding error is
// carried into the series, so it costs no accuracy.
inline Wide atan_ratio(double a, double b) {
  const double q = a / b;  // one correctly rounded division, subnormal results included
  if (q < 0x1p-600) return {q, 0.0};  // atan q = q to far below an ulp; no residual needed
  // Scale both by a power of two (exact: b lands in [1/2, 1) and a >= 2^-601 stays normal), so
  // that the product in the residual neither overflows nor underflows.
  int e;
  std::frexp(b, &e);
  a = std::ldexp(a, -e), b = std::ldexp(b, -e);
  const Wide qb = two_product(q, b);
  return atan_unit(q, ((a - qb.hi) - qb.lo) / b);
}
}  // namespace portable_math_detail

/// sin(x) and cos(x) together, the same bits on every IEEE 754 machine.
inline void portable_sincos(double x, double& s, double& c) {
  namespace d = portable_math_detail;
  if (!std::isfinite(x)) {
    s = c = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  if (std::abs(x) < 0x1p-27) {  // sin x = x and cos x = 1 to within a quarter ulp; keeps -0
    s = x, c = 1.0;
    return;
  }
  // Beyond |x| = 2^27 pi/2 the products k p_i are no longer exact. fmod is exact, so taking
  // out whole turns of the double nearest 2 pi keeps the result deterministic; its error,
  // 3.9e-17 |x|, is what an angle that large is worth anyway.
  if (std::abs(x) >= 0x1p27 * d::pio2_1) x = std::fmod(x, 2.0 * d::pi_hi);
  // k = nearbyint(x 2/pi), rounded to nearest with ties to even, as adding and subtracting
  // 1.5 * 2^52 rounds any |y| < 2^51 (exact, and without a library call in the hot loop).
  constexpr double round_shift = 0x1.8p52;
  const double k = (x * d::two_over_pi + round_shift) - round_shift;
  // r = x - k pi/2 as r + dr: x - k p1 is exact (the two are close); the rest are summed
  // with their rounding errors kept.
  const d::Wide a = d::two_sum(x - k * d::pio2_1, -(k * d::pio2_2));
  const d::Wide b = d::two_sum(a.hi, -(k * d::pio2_3));
  const d::Wide r = d::two_sum(b.hi, (a.lo + b.lo) - k * d::pio2_4);
  const double sr = d::sin_kernel(r.hi, r.lo), cr = d::cos_kernel(r.hi, r.lo);
  // k mod 4 picks the quadrant: (s, c) = (sr, cr), (cr, -sr), (-sr, -cr) or (-cr, sr), read
  // from a table rather than chosen by a branch, which the DEM's random angles would mispredict.
  const int quadrant = static_cast<int>(static_cast<std::int64_t>(k) & 3);  // |k| < 2^28: exact; & 3 is k mod 4
  const double turn[4] = {sr, cr, -sr, -cr};
  s = turn[quadrant];
  c = turn[(quadrant + 1) & 3];
}

/// sin(x) and cos(x) of a body's angle, which places its corners: the same bits on every IEEE
/// 754 machine, like portable_sincos, but within two ulp (plus 1e-18) rather than faithful, at
/// less than half the cost (the DEM places every grain's corners every step). The same
/// Cody-Waite reduction in plain doubles: x - k p1 and the products k p_i are exact, the two
/// subtractions round (an ulp of r in all), and pi/2 is carried to 80 bits, so the part left
/// out, 1.54 k 2^-81, stays below 1e-18 for |x| < 2^20. Then the same Taylor series, without the
/// low parts carried. Every placement of a grain's corners from its angle (the
/// World, the VTK writer, the coarse-graining's and the mesh's outlines) uses it, so that all
/// put a corner at the same bits. |x| >= 2^20 rad, infinities and NaN, and |x| < 2^-27 (where
/// sin x = x keeps the sign of a zero): portable_sincos.
inline void rotation_sincos(double x, double& s, double& c) {
  namespace d = portable_math_detail;
  if (!(std::abs(x) < 0x1p20) || std::abs(x) < 0x1p-27) {
    portable_sincos(x, s, c);
    return;
  }
  constexpr double round_shift = 0x1.8p52;
  const double k = (x * d::two_over_pi + round_shift) - round_shift;
  const double r = ((x - k * d::pio2_1) - k * d::pio2_2) - k * d::pio2_3;
  const double z = r * r;
  const double p = -1.0 / 6 + z * (1.0 / 120 + z * (-1.0 / 5040 + z * (1.0 / 362880 + z * (-1.0 / 39916800 +
                   z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0 + z * (1.0 / 355687428096000.0)))))));
  const double q = 1.0 / 24 + z * (-1.0 / 720 + z * (1.0 / 40320 + z * (-1.0 / 3628800 + z * (1.0 / 479001600.0 +
                   z * (-1.0 / 87178291200.0 + z * (1.0 / 20922789888000.0 + z * (-1.0 / 6402373705728000.0)))))));
  const double sr = r + r * z * p;
  // 1 - z/2 loses the low bits of z/2; (1 - w) - z/2 gets them back exactly.
  const double half_z = 0.5 * z, w = 1.0 - half_z;
  const double cr = w + (((1.0 - w) - half_z) + z * z * q);
  const int quadrant = static_cast<int>(static_cast<std::int64_t>(k) & 3);
  const double turn[4] = {sr, cr, -sr, -cr};
  s = turn[quadrant];
  c = turn[(quadrant + 1) & 3];
}

inline double portable_sin(double x) {
  double s, c;
  portable_sincos(x, s, c);
  return s;
}

inline double portable_cos(double x) {
  double s, c;
  portable_sincos(x, s, c);
  return c;
}

/// atan2(y, x), the angle of (x, y) in [-pi, pi], the same bits on every IEEE 754 machine.
/// Signed zeros and infinities follow C's atan2.
inline double portable_atan2(double y, double x) {
  namespace d = portable_math_detail;
  // x + y would carry a payload and sign that differ between machines.
  if (std::isnan(x) || std::isnan(y)) return std::numeric_limits<double>::quiet_NaN();
  const double ax = std::abs(x), ay = std::abs(y);
  double angle;
  if (std::isinf(ax) && std::isinf(ay)) {  // C's values for infinite arguments
    angle = std::signbit(x) ? 3.0 * d::atan_table[16].hi : d::atan_table[16].hi;
  } else if (std::isinf(ax)) {
    angle = std::signbit(x) ? d::pi_hi : 0.0;
  } else if (std::isinf(ay)) {
    angle = d::pio2_hi;
  } else if (ay == 0.0) {
    angle = std::signbit(x) ? d::pi_hi : 0.0;
  } else if (ax == 0.0) {
    angle = d::pio2_hi;
  } else {
    // The angle of (|x|, |y|) is t or pi/2 - t, t = atan of the smaller over the larger; the
    // angle of (x, y) with x < 0 is pi minus that. The constants' low parts join the sum
    // before its one final rounding.
    const d::Wide t = ay <= ax ? d::atan_ratio(ay, ax) : d::atan_ratio(ax, ay);
    const bool steep = ay > ax, left = std::signbit(x);
    // angle = base + sign * t, base in {0, pi/2, pi}
    const double sign = steep == left ? 1.0 : -1.0;
    const d::Wide base = steep ? d::Wide{d::pio2_hi, d::pio2_lo} : left ? d::Wide{d::pi_hi, d::pi_lo} : d::Wide{0.0, 0.0};
    const d::Wide head = d::two_sum(base.hi, sign * t.hi);
    angle = head.hi + (head.lo + (base.lo + sign * t.lo));
  }
  return std::copysign(angle, y);
}

/// atan(t), the same bits on every IEEE 754 machine.
inline double portable_atan(double t) { return portable_atan2(t, 1.0); }

}  // namespace pilelab
