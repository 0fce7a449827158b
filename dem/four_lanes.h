#pragma once
// Four doubles in the lanes of one 256-bit vector (GCC's and Clang's vector extension), for the
// kernels that treat four contacts at once. Each lane is rounded exactly as the scalar
// operation is (no FMA: the build sets -ffp-contract=off), so a kernel that performs a scalar
// function's operations in the same order gives its bits in every lane, on any x86-64: the
// compiler emits AVX where a kernel is cloned for it, pairs of SSE2 registers otherwise.
#include <cmath>
#include <cstdint>

// A function compiled twice, for AVX2 and for plain SSE2, the processor choosing one when the
// program starts (GCC's function multi-versioning). Both perform the same IEEE operations in
// the same order, so they give the same bits. PILELAB_SSE2_ONLY builds the SSE2 code alone: the
// test that both give the same files runs such a build beside the usual one.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(PILELAB_SSE2_ONLY)
#define PILELAB_AVX2_AND_SSE2 __attribute__((target_clones("avx2", "default")))
#else
#define PILELAB_AVX2_AND_SSE2
#endif

namespace pilelab::dem {

// The helpers below take and return vectors by value. They are inlined by force into each clone
// of a kernel, compiled for its own instruction set, so no call crosses the difference in
// calling convention with and without AVX that GCC warns of.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

using Double4 = double __attribute__((vector_size(32)));
using Mask4 = std::int64_t __attribute__((vector_size(32)));  ///< a comparison's lanes: -1 true, 0 false

/// std::sqrt lane by lane (correctly rounded, as the scalar one).
[[gnu::always_inline]] inline Double4 lane_sqrt(Double4 x) {
  for (int k = 0; k < 4; ++k) x[k] = std::sqrt(x[k]);
  return x;
}
/// std::abs: the sign bit cleared.
[[gnu::always_inline]] inline Double4 lane_abs(Double4 x) { return (Double4)((Mask4)x & INT64_MAX); }
/// std::copysign(magnitude, sign): magnitude's bits with sign's sign bit.
[[gnu::always_inline]] inline Double4 lane_copysign(Double4 magnitude, Double4 sign) {
  return (Double4)(((Mask4)magnitude & INT64_MAX) | ((Mask4)sign & INT64_MIN));
}
/// std::max(a, b) and std::min(a, b), which return a unless b is strictly larger (smaller).
[[gnu::always_inline]] inline Double4 lane_max(Double4 a, Double4 b) { return a < b ? b : a; }
[[gnu::always_inline]] inline Double4 lane_min(Double4 a, Double4 b) { return b < a ? b : a; }
/// std::isinf.
[[gnu::always_inline]] inline Mask4 lane_isinf(Double4 x) { return lane_abs(x) == INFINITY; }
/// The vector of value(0), value(1), value(2), value(3): four lanes gathered from wherever
/// they lie.
template <class Value>
[[gnu::always_inline]] inline Double4 lanes_of(Value&& value) {
  return Double4{value(0), value(1), value(2), value(3)};
}

#pragma GCC diagnostic pop

}  // namespace pilelab::dem
