#pragma once
// 2D vectors and tensors used everywhere in granflow.
#include <Eigen/Core>

namespace granflow {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

// z-component of the 2D cross product a × b.
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
// Unit vector rotated +90°: the tangent t̂ = ẑ × n̂.
inline Vec2 perp(const Vec2& n) { return Vec2(-n.y(), n.x()); }

}  // namespace granflow
