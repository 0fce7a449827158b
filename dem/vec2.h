#pragma once
// 2D vector helpers on top of Eigen's fixed-size vector.
#include <Eigen/Core>

namespace pilelab::dem {

using Vec2 = Eigen::Vector2d;

/// z-component of the 3D cross product of two in-plane vectors.
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
/// omega e_z x r: the velocity of a point at r from the centre of a body spinning at omega.
inline Vec2 cross(double omega, const Vec2& r) { return {-omega * r.y(), omega * r.x()}; }
/// The vector turned by +90 degrees.
inline Vec2 perp(const Vec2& a) { return {-a.y(), a.x()}; }
/// Rotation of a body-frame vector by angle (cos, sin given).
inline Vec2 rotate(const Vec2& a, double c, double s) { return {c * a.x() - s * a.y(), s * a.x() + c * a.y()}; }

}  // namespace pilelab::dem
