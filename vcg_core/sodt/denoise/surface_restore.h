// SPDX-License-Identifier: GPL-3.0-or-later
// Filtered's last step: the sweeps move each smooth vertex in the tangent
// plane of its star, which on a curved surface leaves it off the surface by
// about kappa d^2 / 2 after a tangential travel d (inwards on a convex
// part). On the coarse benchmark torus (a face turns 22 degrees per ring)
// the sweeps added 1.4% of the noise to the distance between the denoised
// and the clean surface. So before the sweeps each smooth vertex gets the
// quadric of the denoised surface through it,
//
//   z = a u^2 + b u v + c v^2 + d u + e v
//
// in the frame of its normal, fitted to its ring by least squares (the
// linear terms absorb the tilt of the area-weighted normal), and after them
// its height over its old tangent plane is set back on that quadric. Only where the surface is smooth around the vertex: its star's
// face normals and those of each neighbour's star lie within half the
// feature angle of their vertex normals, so no quadric is fitted across a
// sharp edge or over one (on the noisy spot, fits beside its sharp edges
// moved their faces and cost a degree of dihedral error).
#pragma once

#include "../guards/deviation.h"
#include "../maths/fitting.h"
#include "../maths/geometry.h"
#include "../maths/topology.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <vector>

namespace sodt {

/// Local quadrics of a surface at its smooth vertices (see the file
/// comment).
class SurfaceQuadrics {
 public:
  /// Fits at every vertex in `which` whose neighbourhood is smooth: the
  /// faces of its star and of its neighbours' stars within acos(flatCos)
  /// of the normals of their centres.
  void fit(const RingTopology& topo, const std::vector<Vec3>& pos, const std::vector<int>& which, double flatCos,
           int threads) {
    const int nv = static_cast<int>(pos.size());
    const std::vector<Vec3> normal = vertexNormals(topo, pos, threads);
    std::vector<char> flat(nv, 0);
    forEachInterior(topo, threads, [&](int i) { flat[i] = starIsFlat(topo, pos, normal[i], i, flatCos); });
    frame_.assign(nv, Frame());
    for (int i : which) {
      if (topo.kind[i] != VertexKind::Interior || !flat[i]) continue;
      bool around = true;
      for (int k = topo.ringBegin[i]; k < topo.ringBegin[i + 1] && around; ++k) around = flat[topo.ringIdx[k]];
      if (around) frame_[i] = fitAt(topo, pos, normal[i], i);
    }
  }

  /// Where x, a position of vertex i, lies on i's quadric: the same place
  /// over the tangent plane, at the quadric's height. False when i has no
  /// quadric or x is farther than `reach` from its fitted position along
  /// the plane (the quadric describes the surface near the vertex only).
  bool onQuadric(int i, const Vec3& x, double reach, Vec3& y) const {
    const Frame& f = frame_[i];
    if (!f.ok) return false;
    const Vec3 d = x - f.origin;
    const double u = d * f.e1, v = d * f.e2;
    if (u * u + v * v > reach * reach) return false;
    y = f.origin + f.e1 * u + f.e2 * v + f.n * (f.a * u * u + f.b * u * v + f.c * v * v + f.d * u + f.e * v);
    return isFinite(y);
  }

  bool has(int i) const { return frame_[i].ok; }

 private:
  struct Frame {
    bool ok = false;
    Vec3 origin, n, e1, e2;
    double a = 0, b = 0, c = 0, d = 0, e = 0;
  };

  static bool starIsFlat(const RingTopology& topo, const std::vector<Vec3>& pos, const Vec3& n, int i,
                         double flatCos) {
    if (n.SquaredNorm() == 0) return false;
    const int b = topo.ringBegin[i], m = topo.ringSize(i);
    for (int k = 0; k < m; ++k) {
      const Vec3 a = doubleAreaVector(pos[i], pos[topo.ringIdx[b + k]], pos[topo.ringIdx[b + (k + 1) % m]]);
      const double len = a.Norm();
      if (!(len > 0) || (a / len) * n < flatCos) return false;
    }
    return true;
  }

  static Frame fitAt(const RingTopology& topo, const std::vector<Vec3>& pos, const Vec3& n, int i) {
    Frame f;
    if (topo.ringSize(i) < 3) return f;
    const Vec3 seed = std::fabs(n[0]) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    f.e1 = (seed - n * (seed * n)).Normalize();
    f.e2 = n ^ f.e1;
    f.n = n;
    f.origin = pos[i];
    Eigen::Matrix<double, 5, 5> M = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> r = Eigen::Matrix<double, 5, 1>::Zero();
    for (int k = topo.ringBegin[i]; k < topo.ringBegin[i + 1]; ++k) {
      const Vec3 d = pos[topo.ringIdx[k]] - pos[i];
      const double u = d * f.e1, v = d * f.e2;
      Eigen::Matrix<double, 5, 1> row;
      row << u * u, u * v, v * v, u, v;
      M += row * row.transpose();
      r += row * (d * n);
    }
    // The least-squares solution of least norm: a ring that does not
    // determine every coefficient (the four neighbours of a vertex of
    // valence 4 in a grid say nothing about b) gets 0 for what it leaves
    // open.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> es(M);  // ascending eigenvalues
    const double top = es.eigenvalues()[4];
    if (!(top > 0)) return f;
    Eigen::Matrix<double, 5, 1> s = Eigen::Matrix<double, 5, 1>::Zero();
    for (int k = 0; k < 5; ++k)
      if (es.eigenvalues()[k] > 1e-9 * top)
        s += es.eigenvectors().col(k) * (es.eigenvectors().col(k).dot(r) / es.eigenvalues()[k]);
    if (!s.allFinite()) return f;
    f.a = s[0];
    f.b = s[1];
    f.c = s[2];
    f.d = s[3];
    f.e = s[4];
    f.ok = true;
    return f;
  }

  std::vector<Frame> frame_;
};

/// Sets every vertex of `which` that has a quadric back on it (see
/// SurfaceQuadrics::onQuadric), one vertex after the other, where that
/// turns none of its star's faces against faceNormal, with quality leaves
/// the star's smallest angle no smaller, and with a bound (bound not null)
/// keeps the vertex and its star's centroids within it. Returns the
/// vertices moved.
inline int restoreOnQuadrics(const SurfaceQuadrics& q, const RingTopology& topo, const std::vector<Vec3>& faceNormal,
                             bool quality, const InputSurface* bound, double reach, const std::vector<int>& which,
                             std::vector<Vec3>& pos) {
  int moved = 0;
  for (int i : which) {
    Vec3 y;
    if (topo.kind[i] != VertexKind::Interior || !q.has(i) || !q.onQuadric(i, pos[i], reach, y)) continue;
    const int b = topo.ringBegin[i], m = topo.ringSize(i);
    double before = 0, after = 0;  // the star's largest squared cosine of a smallest angle
    bool ok = !bound || bound->near(i, y, -1);
    for (int k = 0; k < m && ok; ++k) {
      const Vec3& p = pos[topo.ringIdx[b + k]];
      const Vec3& r = pos[topo.ringIdx[b + (k + 1) % m]];
      ok = doubleAreaVector(y, p, r) * faceNormal[topo.ringFace[b + k]] > 0 &&
           (!bound || bound->near(i, (y + p + r) / 3.0, -1));
      before = std::max(before, triangleMinAngleCos2(pos[i], p, r));
      after = std::max(after, triangleMinAngleCos2(y, p, r));
    }
    if (!ok || (quality && after > before)) continue;
    pos[i] = y;
    ++moved;
  }
  return moved;
}

}  // namespace sodt
