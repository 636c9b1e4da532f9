// SPDX-License-Identifier: GPL-3.0-or-later
// Local fits of the denoising variant (paper Sec. 2.5): the weighted
// least-squares plane of a smooth vertex (Eq. 12-13) and the crease line.
#pragma once

#include "geometry.h"
#include "../params.h"
#include "topology.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace sodt {

/// A fitted plane (point, unit normal) or line (point, unit direction).
struct FittedFrame {
  bool ok = false;
  Vec3 point = Vec3(0, 0, 0);
  Vec3 dir = Vec3(0, 0, 0);
};

/// Weighted centroid of the points and the unit eigenvector of their weighted
/// scatter matrix for the smallest (axis 0) or largest (axis 2) eigenvalue,
/// turned to point along `hint`. ok = false for non-finite results.
inline FittedFrame principalFit(const std::vector<std::pair<Vec3, double>>& pts, int axis, const Vec3& hint) {
  FittedFrame f;
  Vec3 c(0, 0, 0);
  double ws = 0;
  for (const auto& pw : pts) {
    c += pw.first * pw.second;
    ws += pw.second;
  }
  if (!(ws > 0)) return f;
  c /= ws;
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (const auto& pw : pts) {
    const Vec3 d = pw.first - c;
    const Eigen::Vector3d e(d[0], d[1], d[2]);
    M += pw.second * e * e.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M);  // ascending eigenvalues
  const Eigen::Vector3d v = es.eigenvectors().col(axis);
  Vec3 dir(v[0], v[1], v[2]);
  if (dir * hint < 0) dir = -dir;
  if (!isFinite(dir) || !isFinite(c) || dir.SquaredNorm() == 0) return f;
  f.ok = true;
  f.point = c;
  f.dir = dir.Normalize();
  return f;
}

/// Area-weighted unit normal of every Interior vertex (zero for the others).
inline std::vector<Vec3> vertexNormals(const RingTopology& topo, const std::vector<Vec3>& pos, int threads = 1) {
  std::vector<Vec3> nrm(pos.size(), Vec3(0, 0, 0));
  forEachInterior(topo, threads, [&](int i) {
    const int b = topo.ringBegin[i], n = topo.ringSize(i);
    Vec3 s(0, 0, 0);
    for (int k = 0; k < n; ++k)
      s += doubleAreaVector(pos[i], pos[topo.ringIdx[b + k]], pos[topo.ringIdx[b + (k + 1) % n]]);
    const double len = s.Norm();
    if (len > 0) nrm[i] = s / len;
  });
  return nrm;
}

/// The weight L(r) of Eq. 12: linear from 0 at r = cos(pi/4) to 1 at r = 1.
inline double normalAgreementWeight(double r) {
  const double c = std::sqrt(0.5);
  return std::min(1.0, std::max(0.0, (r - c) / (1.0 - c)));
}

/// Weighted least-squares plane of Eq. 12-13 through vertex i and its ring:
/// weights 1 for i and L(n_i . n_k) for neighbour k; the point is the weighted
/// centroid and the normal the eigenvector of the smallest eigenvalue of the
/// weighted scatter matrix, oriented like n_i. It needs three neighbours
/// with a weight: the vertex and two neighbours span the plane of one
/// triangle, a plane of no least squares, and one that stands upright on
/// the surface where the two lie on a line with the vertex (a rim of
/// needles, or a crease, whose sides' normals disagree with the vertex's).
/// Without a plane the vertex keeps its Algorithm 2 move.
inline FittedFrame fitPlane(int i, const RingTopology& topo, const std::vector<Vec3>& pos,
                            const std::vector<Vec3>& nrm) {
  FittedFrame f;
  const Vec3& n0 = nrm[i];
  if (n0.SquaredNorm() == 0) return f;
  // Reused by each thread: this runs once per vertex, possibly in parallel.
  static thread_local std::vector<std::pair<Vec3, double>> pts;
  pts.clear();
  pts.emplace_back(pos[i], 1.0);
  for (int k = topo.ringBegin[i]; k < topo.ringBegin[i + 1]; ++k) {
    const int j = topo.ringIdx[k];
    const double w = nrm[j].SquaredNorm() > 0 ? normalAgreementWeight(n0 * nrm[j]) : 0.0;
    if (w > 0) pts.emplace_back(pos[j], w);
  }
  if (pts.size() < 4) return f;
  return principalFit(pts, 0, n0);
}

/// Least-squares line through vertex i of class Crease and up to two feature
/// (crease or corner) vertices on each side of it along the crease direction
/// e: on each side, the feature neighbour closest to the line (x_i, e), then
/// that vertex's feature neighbour that continues furthest along e. Only
/// feature vertices are used, so a line never bends towards the faces next
/// to a crease. Fails (ok = false) with fewer than one vertex on each side.
inline FittedFrame fitCreaseLine(int i, const Vec3& e, const RingTopology& topo, const std::vector<Vec3>& pos,
                                 const std::vector<VertexClass>& cls) {
  FittedFrame f;
  auto isFeature = [&](int j) { return cls[j] == VertexClass::Crease || cls[j] == VertexClass::Corner; };
  // Distance from the line, relative to the distance along it: smaller is better aligned.
  auto offLine = [&](const Vec3& x, double along) {
    const Vec3 d = x - pos[i];
    return (d - e * (d * e)).Norm() / std::abs(along);
  };
  static thread_local std::vector<std::pair<Vec3, double>> pts;
  pts.clear();
  pts.emplace_back(pos[i], 1.0);
  int sides = 0;
  for (double sign : {1.0, -1.0}) {
    int first = -1;
    double best = 0;
    for (int k = topo.ringBegin[i]; k < topo.ringBegin[i + 1]; ++k) {
      const int j = topo.ringIdx[k];
      const double along = sign * ((pos[j] - pos[i]) * e);
      if (!isFeature(j) || !(along > 0)) continue;
      const double q = offLine(pos[j], along);
      if (first < 0 || q < best) first = j, best = q;
    }
    if (first < 0) continue;
    ++sides;
    pts.emplace_back(pos[first], 1.0);
    if (topo.kind[first] != VertexKind::Interior) continue;
    const double reach = sign * ((pos[first] - pos[i]) * e);
    int second = -1;
    double best2 = 0;
    for (int k = topo.ringBegin[first]; k < topo.ringBegin[first + 1]; ++k) {
      const int j = topo.ringIdx[k];
      const double along = sign * ((pos[j] - pos[i]) * e);
      if (j == i || !isFeature(j) || !(along > reach)) continue;
      const double q = offLine(pos[j], along);
      if (second < 0 || q < best2) second = j, best2 = q;
    }
    if (second >= 0) pts.emplace_back(pos[second], 1.0);
  }
  if (sides < 2) return f;
  return principalFit(pts, 2, e);
}

}  // namespace sodt
