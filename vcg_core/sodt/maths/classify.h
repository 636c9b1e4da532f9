// SPDX-License-Identifier: GPL-3.0-or-later
// Smooth / crease / corner classification of vertices by the eigenvalues of
// the normal tensor of their one-ring (paper Eq. 9-10).
#pragma once

#include "geometry.h"
#include "../params.h"
#include "topology.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <vector>

namespace sodt {

/// Eigen-analysis of one vertex's normal tensor.
struct TensorClass {
  VertexClass cls = VertexClass::Fixed;
  Vec3 creaseDir = Vec3(0, 0, 0);  ///< unit e3 (eigenvector of the smallest eigenvalue)
  double nu[3] = {0, 0, 0};        ///< eigenvalues, nu[0] >= nu[1] >= nu[2]
};

/// Class from the eigenvalues nu1 >= nu2 >= nu3 of the normal tensor (Eq. 10):
/// the largest of nu1 - nu2 (smooth), epsilon (nu2 - nu3) (crease) and
/// epsilon eta nu3 (corner). Ties go to the earlier, less constrained class.
inline VertexClass classifyEigenvalues(double nu1, double nu2, double nu3, double epsilon, double eta) {
  const double ss = nu1 - nu2, se = epsilon * (nu2 - nu3), sc = epsilon * eta * nu3;
  if (ss >= se && ss >= sc) return VertexClass::Smooth;
  if (se >= sc) return VertexClass::Crease;
  return VertexClass::Corner;
}

/// Normal tensor T = sum_k w_k n_k n_k^T of the star of centre x0 (Eq. 9),
/// w_k = (S_k / S_max) exp(-g_k / sigma) with S_k the area of triangle k, g_k
/// the distance from x0 to its barycentre and sigma the mean edge length of
/// the mesh, then its class (Eq. 10). Degenerate triangles get no weight; a
/// star without any area is Smooth.
/// \param ring one-ring positions in face order; triangle k is (x0, ring[k], ring[k+1]).
inline TensorClass classifyStar(const Vec3& x0, const std::vector<Vec3>& ring, double sigma, double epsilon,
                                double eta) {
  TensorClass out;
  const std::size_t n = ring.size();
  double smax = 0;
  for (std::size_t k = 0; k < n; ++k)
    smax = std::max(smax, 0.5 * doubleAreaVector(x0, ring[k], ring[(k + 1) % n]).Norm());
  if (!(smax > 0)) {
    out.cls = VertexClass::Smooth;
    return out;
  }
  Eigen::Matrix3d T = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& a = ring[k];
    const Vec3& b = ring[(k + 1) % n];
    const Vec3 av = doubleAreaVector(x0, a, b);
    const double len = av.Norm();
    if (!(len > 0)) continue;
    const Vec3 nk = av / len;
    const double gk = (x0 - (x0 + a + b) / 3.0).Norm();
    const double wk = (0.5 * len / smax) * std::exp(-gk / sigma);
    const Eigen::Vector3d e(nk[0], nk[1], nk[2]);
    T += wk * e * e.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(T);  // ascending eigenvalues
  const Eigen::Vector3d ev = es.eigenvalues();
  out.nu[0] = ev[2];
  out.nu[1] = ev[1];
  out.nu[2] = std::max(0.0, ev[0]);
  const Eigen::Vector3d e3 = es.eigenvectors().col(0);
  out.creaseDir = Vec3(e3[0], e3[1], e3[2]);
  out.cls = classifyEigenvalues(out.nu[0], out.nu[1], out.nu[2], epsilon, eta);
  return out;
}

/// Mean length of the edges of the live faces (each edge counted once per face side).
template <class MeshType>
double meanEdgeLength(const MeshType& m) {
  double sum = 0;
  long long cnt = 0;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    for (int j = 0; j < 3; ++j) {
      sum += vcg::Distance(vcg::Point3d::Construct(f.cP(j)), vcg::Point3d::Construct(f.cP((j + 1) % 3)));
      ++cnt;
    }
  }
  return cnt ? sum / double(cnt) : 0.0;
}

/// Classification of every vertex of a mesh.
struct Classification {
  std::vector<VertexClass> cls;  ///< per vertex (index in m.vert); Fixed for non-interior vertices
  std::vector<Vec3> creaseDir;   ///< unit crease direction e3 for Crease vertices (zero for the others)
  int count[4] = {0, 0, 0, 0};   ///< vertices per class, indexed by VertexClass

  int smooth() const { return count[0]; }
  int crease() const { return count[1]; }
  int corner() const { return count[2]; }
  int fixed() const { return count[3]; }
};

/// Classifies the vertices with the given positions (indexed like the
/// topology). Vertices that are not Interior (border, non-manifold, isolated,
/// deleted) are Fixed; deleted ones are not counted.
inline Classification classifyRings(const RingTopology& topo, const std::vector<Vec3>& pos, double sigma,
                                    double epsilon, double eta, int threads = 1) {
  Classification c;
  const long nv = static_cast<long>(topo.kind.size());
  c.cls.assign(nv, VertexClass::Fixed);
  c.creaseDir.assign(nv, Vec3(0, 0, 0));
  forEachInterior(topo, threads, [&](int i) {
    static thread_local std::vector<Vec3> ring;  // reused by each thread
    ring.clear();
    for (int k = topo.ringBegin[i]; k < topo.ringBegin[i + 1]; ++k) ring.push_back(pos[topo.ringIdx[k]]);
    const TensorClass t = classifyStar(pos[i], ring, sigma, epsilon, eta);
    c.cls[i] = t.cls;
    c.creaseDir[i] = t.creaseDir;
  });
  for (long i = 0; i < nv; ++i)
    if (topo.kind[i] != VertexKind::Deleted) ++c.count[static_cast<int>(c.cls[i])];
  return c;
}

/// Bounding box [lo, hi] of the vertices of faces (neither isolated nor
/// deleted), and its diagonal: the mesh's size, which an unreferenced vertex
/// does not change. Without such vertices, the box is the origin.
inline double surfaceBox(const std::vector<Vec3>& pos, const RingTopology& topo, Vec3& lo, Vec3& hi) {
  lo = hi = Vec3(0, 0, 0);
  bool any = false;
  for (std::size_t i = 0; i < pos.size(); ++i) {
    if (topo.kind[i] == VertexKind::Deleted || topo.kind[i] == VertexKind::Isolated) continue;
    for (int k = 0; k < 3; ++k) {
      lo[k] = any ? std::min(lo[k], pos[i][k]) : pos[i][k];
      hi[k] = any ? std::max(hi[k], pos[i][k]) : pos[i][k];
    }
    any = true;
  }
  return any ? (hi - lo).Norm() : 0.0;
}

/// The diagonal of surfaceBox.
inline double surfaceDiagonal(const std::vector<Vec3>& pos, const RingTopology& topo) {
  Vec3 lo, hi;
  return surfaceBox(pos, topo, lo, hi);
}

/// Classifies every vertex of m (Eq. 9-10) with sensitivities epsilon and eta.
/// \throw InvalidInput for epsilon or eta not positive, or a mesh outside the
///        sizes of checkMeshSize().
template <class MeshType>
Classification classifyVertices(const MeshType& m, double epsilon, double eta) {
  if (!(epsilon > 0) || !(eta > 0)) throw InvalidInput("epsilon and eta must be positive");
  const RingTopology topo = buildRingTopology(m);
  std::vector<Vec3> pos(m.vert.size());
  for (std::size_t i = 0; i < m.vert.size(); ++i)
    if (!m.vert[i].IsD()) pos[i] = Vec3::Construct(m.vert[i].cP());
  checkMeshSize(surfaceDiagonal(pos, topo));
  return classifyRings(topo, pos, meanEdgeLength(m), epsilon, eta);
}

}  // namespace sodt
