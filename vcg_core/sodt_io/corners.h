// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Sharp corners between features: where two feature lines or border edges
// meet at an angle below a target, no triangle of the corner can do better
// than that angle while the features stay, so a smallest-angle target is
// measured on the other triangles.

#include <sodt/maths/corners.h>
#include <sodt/maths/geometry.h>
#include "metrics.h"

#include <array>
#include <vector>

namespace sodt {

/// The corners of protectedAngles().
struct ProtectedAngles {
  /// Corners: runs of faces around a vertex between two feature edges (or
  /// a whole border fan) whose angles at the vertex add up to less than
  /// the target.
  int corners = 0;
  double smallestDeg = 0;  ///< the smallest of their angles (0 when there is none)
  /// Faces whose smallest angle is at such a corner.
  long long faces = 0;
  /// The smallest angle of every other live face (180 when there is none).
  double minAngleElsewhereDeg = 180;
};

/// The corners of m where features meet at less than targetDeg
/// (protectedCorners() on its live faces).
template <class MeshType>
ProtectedAngles protectedAngles(const MeshType& m, double featureDeg, double targetDeg) {
  ProtectedAngles r;
  const double kDeg = 180 / kPi;
  std::vector<std::array<int, 3>> tri;
  for (const auto& f : m.face)
    if (!f.IsD())
      tri.push_back({{int(f.cV(0) - &m.vert[0]), int(f.cV(1) - &m.vert[0]), int(f.cV(2) - &m.vert[0])}});
  if (tri.empty()) return r;
  std::vector<Vec3> pos(m.vert.size());
  for (std::size_t v = 0; v < m.vert.size(); ++v) pos[v] = detail::toVec3<MeshType>(m.vert[v].cP());
  const CornerView c = protectedCorners(tri, pos, featureDeg / kDeg, targetDeg / kDeg);
  r.corners = c.corners;
  r.smallestDeg = c.smallestRad * kDeg;
  for (char a : c.atCorner) r.faces += a;
  r.minAngleElsewhereDeg = c.minAngleElsewhere * kDeg;
  return r;
}

}  // namespace sodt
