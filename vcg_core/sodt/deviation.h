// SPDX-License-Identifier: GPL-3.0-or-later
// The deviation guard: a moved vertex and the faces around it must stay close
// to the input surface near that vertex (its input one- and two-ring faces).
#pragma once

#include "geometry.h"
#include "local_solve.h"
#include "topology.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sodt {

/// The input mesh, read by index: the faces of vertex v's input one-ring and
/// of its neighbours' one-rings form the surface patch v must stay near.
/// Nothing is copied per visit; the structures must outlive this view.
struct InputSurface {
  const FaceList* faces = nullptr;
  const RingTopology* topo = nullptr;
  const std::vector<Vec3>* pos = nullptr;
  double limit = 0;  ///< distance bound
  double limit2 = 0;  ///< its square
  /// Per face: an upper bound of the distance from its first corner to its
  /// other two, so that far faces are skipped without the exact distance.
  std::vector<float> reach;

  /// Sets the bound and precomputes reach; faces, topo and pos must be set.
  void prepare(double distanceLimit) {
    limit = distanceLimit;
    limit2 = limit * limit;
    reach.assign(faces->tri.size(), 0.f);
    const std::vector<Vec3>& P = *pos;
    for (std::size_t f = 0; f < faces->tri.size(); ++f) {
      if (!faces->live[f]) continue;
      const std::array<int, 3>& t = faces->tri[f];
      const double r = std::sqrt(std::max((P[t[1]] - P[t[0]]).SquaredNorm(), (P[t[2]] - P[t[0]]).SquaredNorm()));
      // Rounded up to float, and a little more, so the bound stays an upper bound.
      reach[f] = static_cast<float>(r * (1 + 1e-6)) * (1 + 1e-6f);
    }
  }

  bool nearFace(int f, const Vec3& q) const {
    const std::array<int, 3>& t = faces->tri[f];
    const std::vector<Vec3>& P = *pos;
    const Vec3& a = P[t[0]];
    const Vec3 qa = q - a;
    const double r = reach[f] + limit;
    if (qa.SquaredNorm() > r * r) return false;  // outside a ball holding the face and its margin
    const Vec3& b = P[t[1]];
    const Vec3& c = P[t[2]];
    const Vec3 ab = b - a, ac = c - a;
    const Vec3 n = ab ^ ac;
    const double nn = n.SquaredNorm();
    if (nn > 0) {
      // Farther than the bound from the face's plane: farther from the face.
      const double h = qa * n;
      if (h * h > limit2 * nn) return false;
      // Over the face (on the inner side of its three edges): the distance
      // is the plane distance, already within the bound.
      if (((ab ^ qa) * n) >= 0 && (((c - b) ^ (q - b)) * n) >= 0 && (((a - c) ^ (q - c)) * n) >= 0) return true;
    }
    return pointTriangleDistance2(q, a, b, c) <= limit2;
  }

  /// A face of v's input patch within sqrt(limit2) of q, or -1 when there is
  /// none. The face hints (-1 for none) are tried first; whether a face is
  /// found does not depend on them, only the time does.
  int nearFaceOf(int v, const Vec3& q, int hint, int hint2 = -1) const {
    if (hint >= 0 && nearFace(hint, q)) return hint;
    if (hint2 >= 0 && hint2 != hint && nearFace(hint2, q)) return hint2;
    const RingTopology& T = *topo;
    const int b = T.ringBegin[v], e = T.ringBegin[v + 1];
    for (int k = b; k < e; ++k)
      if (T.ringFace[k] != hint && T.ringFace[k] != hint2 && nearFace(T.ringFace[k], q)) return T.ringFace[k];
    for (int k = b; k < e; ++k) {
      const int u = T.ringIdx[k];
      if (T.kind[u] != VertexKind::Interior) continue;
      for (int j = T.ringBegin[u]; j < T.ringBegin[u + 1]; ++j)
        if (nearFace(T.ringFace[j], q)) return T.ringFace[j];
    }
    return -1;
  }

  /// True when q lies within sqrt(limit2) of a face of v's input patch.
  bool near(int v, const Vec3& q, int hint) const { return nearFaceOf(v, q, hint) >= 0; }

  /// True when, with vertex v (the centre of st) at p, p and the midpoints of
  /// the star's edges at p lie within sqrt(limit2) of v's input patch. Where
  /// the input is locally flat, the distance to it is convex and the farthest
  /// point of a star triangle is one of its corners; the edge midpoints catch
  /// edges that cut across a crease or a bend. hints, when not null, gives per
  /// star triangle the input face it came from (valid while the connectivity
  /// is the input's). pointHint is a face to try first for p (-1 for none);
  /// it is set to the face found. A vertex that is not interior in the input
  /// is not restricted.
  bool keeps(int v, const Star& st, const Vec3& p, const int* hints, int& pointHint) const {
    if (topo->kind[v] != VertexKind::Interior) return true;
    const int f = nearFaceOf(v, p, pointHint >= 0 ? pointHint : (hints ? hints[0] : -1));
    if (f < 0) return false;
    pointHint = f;
    for (std::size_t k = 0; k < st.size(); ++k) {
      if (!near(v, (p + st.ring[k] + st.at(k + 1)) / 3.0, hints ? hints[k] : -1)) return false;
      if (!near(v, (p + st.ring[k]) * 0.5, hints ? hints[k] : -1)) return false;
    }
    return true;
  }
};

}  // namespace sodt
