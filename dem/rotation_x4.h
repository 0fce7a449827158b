#pragma once
// The rotation of four bodies at once: rotation_sincos (common/portable_math.h) in the four lanes
// of a vector. Placing every grain's corners every step is a fifth of a DEM step, and most of it
// is the two series of rotation_sincos, a chain of dependent multiplications and additions that
// leaves the processor waiting; four grains in lanes take about the time of one.

namespace pilelab::dem {

/// s[k], c[k] = sin(x[k]), cos(x[k]) with the bits of rotation_sincos for each k.
void rotation_sincos_x4(const double x[4], double s[4], double c[4]);

}  // namespace pilelab::dem
