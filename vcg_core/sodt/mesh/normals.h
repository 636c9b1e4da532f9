// SPDX-License-Identifier: GPL-3.0-or-later
// Face and vertex normals of a smoothed mesh, from the smoother's own
// working arrays (vertices in breadth-first order), on several threads.
#pragma once

#include "../maths/geometry.h"
#include "../maths/topology.h"

#include <vcg/complex/complex.h>

#include <vector>

namespace sodt {

/// Writes unit normals into m where it has them: per face, its area vector
/// normalised; per vertex, the sum of the area vectors of its faces (area
/// weighting, as vcglib's PerVertexNormalizedPerFace), normalised. Computed
/// in double from the working positions pos (working index i is
/// m.vert[order[i]]; faces.tri[f] is m.face[faceOrder[f]] in working
/// indices) and rounded once. A zero sum gives a zero normal. Vertices that
/// no live face references, and deleted ones, keep their normal.
template <class MeshType>
void writeNormals(MeshType& m, const FaceList& faces, const RingTopology& topo, const std::vector<Vec3>& pos,
                  const std::vector<int>& order, const std::vector<int>& faceOrder, int threads) {
  using FaceNormal = typename MeshType::FaceType::NormalType;
  using VertexNormal = typename MeshType::VertexType::NormalType;
  using FaceScalar = typename FaceNormal::ScalarType;
  using VertexScalar = typename VertexNormal::ScalarType;
  const auto unit = [](const Vec3& a) {
    const double len = a.Norm();
    return len > 0 ? a / len : Vec3(0, 0, 0);
  };
  const long nf = static_cast<long>(faces.tri.size()), nv = static_cast<long>(pos.size());
  const auto area = [&](long f) {
    const std::array<int, 3>& t = faces.tri[f];
    return doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]);
  };
  (void)threads;
  if (vcg::tri::HasPerFaceNormal(m)) {
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
#endif
    for (long f = 0; f < nf; ++f) {
      if (!faces.live[f]) continue;
      const Vec3 n = unit(area(f));
      m.face[faceOrder[f]].N() = FaceNormal(FaceScalar(n[0]), FaceScalar(n[1]), FaceScalar(n[2]));
    }
  }
  if (!vcg::tri::HasPerVertexNormal(m)) return;
  const auto store = [&](long i, const Vec3& sum) {
    const Vec3 n = unit(sum);
    m.vert[order[i]].N() = VertexNormal(VertexScalar(n[0]), VertexScalar(n[1]), VertexScalar(n[2]));
  };
  // An interior vertex's faces are its star: (centre, ring k, ring k + 1).
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
#endif
  for (long i = 0; i < nv; ++i) {
    if (topo.kind[i] != VertexKind::Interior) continue;
    const int b = topo.ringBegin[i], e = topo.ringBegin[i + 1];
    const Vec3& c = pos[i];
    Vec3 sum(0, 0, 0);
    for (int k = b; k < e; ++k)
      sum += (pos[topo.ringIdx[k]] - c) ^ (pos[topo.ringIdx[k + 1 < e ? k + 1 : b]] - c);
    store(i, sum);
  }
  // The others (borders, non-manifold vertices): over the faces.
  std::vector<int> slot(nv, -1);
  std::vector<long> others;
  for (long i = 0; i < nv; ++i)
    if (topo.kind[i] == VertexKind::Boundary || topo.kind[i] == VertexKind::NonManifold) {
      slot[i] = static_cast<int>(others.size());
      others.push_back(i);
    }
  if (others.empty()) return;
  std::vector<Vec3> sum(others.size(), Vec3(0, 0, 0));
  for (long f = 0; f < nf; ++f) {
    if (!faces.live[f]) continue;
    const std::array<int, 3>& t = faces.tri[f];
    if (slot[t[0]] < 0 && slot[t[1]] < 0 && slot[t[2]] < 0) continue;
    const Vec3 a = area(f);
    for (int v : t)
      if (slot[v] >= 0) sum[slot[v]] += a;
  }
  for (std::size_t k = 0; k < others.size(); ++k) store(others[k], sum[k]);
}

}  // namespace sodt
