// SPDX-License-Identifier: GPL-3.0-or-later
// Pure double-precision kernels on points: triangle normals and angles, the
// tangent frame of a plane. Nothing here sees a mesh.
#pragma once

#include <vcg/space/point3.h>

#include <algorithm>
#include <cmath>

namespace sodt {

using Vec3 = vcg::Point3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;

/// Twice the area vector of triangle (a, b, c): (b - a) x (c - a).
inline Vec3 doubleAreaVector(const Vec3& a, const Vec3& b, const Vec3& c) {
  return (b - a) ^ (c - a);
}

/// Angle in radians between vectors u and v, accurate near 0 and pi.
/// Returns 0 when either vector is zero.
inline double angleBetween(const Vec3& u, const Vec3& v) {
  return std::atan2((u ^ v).Norm(), u * v);
}

/// Smallest of the three interior angles of triangle (a, b, c), in radians.
inline double triangleMinAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double aa = angleBetween(b - a, c - a);
  const double ab = angleBetween(c - b, a - b);
  const double ac = kPi - aa - ab;  // exact sum keeps the three consistent
  return std::min(std::min(aa, ab), std::max(ac, 0.0));
}

/// Fills s and t so that (s, t, n) is a right-handed orthonormal frame.
/// \pre n has unit length.
inline void tangentFrame(const Vec3& n, Vec3& s, Vec3& t) {
  // Cross with the coordinate axis least aligned with n: well conditioned.
  const double ax = std::abs(n[0]), ay = std::abs(n[1]), az = std::abs(n[2]);
  Vec3 e(0, 0, 0);
  if (ax <= ay && ax <= az)
    e[0] = 1;
  else if (ay <= az)
    e[1] = 1;
  else
    e[2] = 1;
  s = n ^ e;
  s.Normalize();
  t = n ^ s;
}

/// True when every coordinate is finite.
inline bool isFinite(const Vec3& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

}  // namespace sodt
