#pragma once
// The rotation of four bodies at once: rotation_sincos (common/portable_math.h) in the four lanes
// of a vector. Placing every grain's corners every step is a fifth of a DEM step, and most of it
// is the two series of rotation_sincos, a chain of dependent multiplications and additions that
// leaves the processor waiting: four grains in lanes, and several groups of four in flight.

namespace pilelab::dem {

/// s[k], c[k] = sin(x[k]), cos(x[k]) with the bits of rotation_sincos, for k < count. The
/// lanes take four angles at a time; the groups of four are independent, so the processor
/// overlaps their chains: give it many angles at once.
void rotation_sincos_x4(const double* x, double* s, double* c, int count);

}  // namespace pilelab::dem
