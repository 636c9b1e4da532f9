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

/// A triangle collapses when the sine of its smallest angle is below this,
/// roughly: its doubled area is at most kCollapse times its longest edge
/// squared. The one threshold of every fold and collapse test, scalar and
/// AVX2 (local_solve.h, lanes.h).
constexpr double kCollapse = 1e-12;

/// A 2x2 system, or a quadratic along a line, is singular in practice when
/// its determinant (its curvature) is below this fraction of the sum of the
/// magnitudes of its terms: the closed-form solves of local_solve.h and
/// their AVX2 forms in lanes.h.
constexpr double kSingularRel = 1e-12;

/// Twice the area vector of triangle (a, b, c): (b - a) x (c - a).
inline Vec3 doubleAreaVector(const Vec3& a, const Vec3& b, const Vec3& c) {
  return (b - a) ^ (c - a);
}

/// Angle in radians between vectors u and v, accurate near 0 and pi.
/// Returns 0 when either vector is zero.
inline double angleBetween(const Vec3& u, const Vec3& v) {
  return std::atan2((u ^ v).Norm(), u * v);
}

/// Smallest of the three interior angles of triangle (a, b, c), in radians:
/// the angle opposite the shortest edge (law of sines), one atan2 only.
inline double triangleMinAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = (b - a).SquaredNorm(), bc = (c - b).SquaredNorm(), ca = (a - c).SquaredNorm();
  if (bc <= ab && bc <= ca) return angleBetween(b - a, c - a);
  if (ca <= ab) return angleBetween(c - b, a - b);
  return angleBetween(a - c, b - c);
}

/// Squared cosine of the smallest interior angle of triangle (a, b, c): a
/// trigonometry-free quality measure that decreases as that angle grows
/// (the smallest angle is at most 60 degrees, so its cosine is positive).
/// A triangle with a zero-length edge gets 1 (angle 0).
inline double triangleMinAngleCos2(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = (b - a).SquaredNorm(), bc = (c - b).SquaredNorm(), ca = (a - c).SquaredNorm();
  double dot, l1, l2;  // the corner opposite the shortest edge, and its two edges
  if (bc <= ab && bc <= ca) {
    dot = (b - a) * (c - a), l1 = ab, l2 = ca;
  } else if (ca <= ab) {
    dot = (c - b) * (a - b), l1 = bc, l2 = ab;
  } else {
    dot = (a - c) * (b - c), l1 = ca, l2 = bc;
  }
  const double den = l1 * l2;
  if (!(den > 0)) return 1.0;
  return dot <= 0 ? 0.0 : std::min(1.0, dot * dot / den);
}

/// Squared distance from p to the closest point of triangle (a, b, c),
/// by the Voronoi regions of its vertices, edges and face.
inline double pointTriangleDistance2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Squared distance to the point o + e t of an edge.
  const auto toEdge = [&p](const Vec3& o, const Vec3& e, double t) { return (p - (o + e * t)).SquaredNorm(); };
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab * ap, d2 = ac * ap;
  if (d1 <= 0 && d2 <= 0) return ap.SquaredNorm();
  const Vec3 bp = p - b;
  const double d3 = ab * bp, d4 = ac * bp;
  if (d3 >= 0 && d4 <= d3) return bp.SquaredNorm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return toEdge(a, ab, d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab * cp, d6 = ac * cp;
  if (d6 >= 0 && d5 <= d6) return cp.SquaredNorm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return toEdge(a, ac, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return toEdge(b, c - b, (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double den = va + vb + vc;
  if (!(den > 0)) {  // degenerate triangle: closest of its edges
    auto seg = [&p](const Vec3& u, const Vec3& v) {
      const Vec3 d = v - u;
      const double l = d.SquaredNorm();
      const double t = l > 0 ? std::min(1.0, std::max(0.0, ((p - u) * d) / l)) : 0.0;
      return (p - (u + d * t)).SquaredNorm();
    };
    return std::min({seg(a, b), seg(b, c), seg(c, a)});
  }
  const double v = vb / den, w = vc / den;
  return (p - (a + ab * v + ac * w)).SquaredNorm();
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
  s *= 1.0 / s.Norm();  // |n x e| >= sqrt(2/3) for a unit n and the least aligned axis e
  t = n ^ s;
}

/// x rounded to the nearest value of the scalar type S, as a double: what a
/// mesh with S coordinates stores for x. The rounded value is read back
/// through a volatile so that no optimiser can drop the rounding: GCC 12.2
/// at -O2 does drop it when its SLP vectorizer pairs two neighbouring
/// double -> float -> double conversions (then x and y of a point stay
/// unrounded while z is rounded).
template <class S>
inline double roundedTo(double x) {
  const volatile S s = static_cast<S>(x);
  return static_cast<double>(s);
}
template <>
inline double roundedTo<double>(double x) {
  return x;
}

/// roundedTo for every coordinate of p.
template <class S>
inline Vec3 roundedTo(const Vec3& p) {
  return Vec3(roundedTo<S>(p[0]), roundedTo<S>(p[1]), roundedTo<S>(p[2]));
}

/// True when every coordinate is finite.
inline bool isFinite(const Vec3& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

}  // namespace sodt
