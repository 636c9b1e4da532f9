// SPDX-License-Identifier: GPL-3.0-or-later
// Compact one-ring topology built once per run from the face list: for every
// vertex its neighbours in cyclic face order, or why it has no closed ring.
#pragma once

#include <vcg/complex/complex.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace sodt {

/// Why a vertex can or cannot be moved.
enum class VertexKind : std::uint8_t {
  Interior = 0,     ///< its faces form one closed, consistently oriented fan
  Boundary = 1,     ///< its fan is open (it lies on a border of the mesh)
  NonManifold = 2,  ///< several fans, an edge with more than two faces, or inconsistent winding
  Isolated = 3,     ///< no face references it
  Deleted = 4,      ///< flagged deleted in the mesh
};

/// One-rings in compressed form. Vertex i (its index in m.vert) has kind[i];
/// when Interior, its ring is ringIdx[ringBegin[i] .. ringBegin[i+1]) and the
/// faces of its star are (i, ring[k], ring[k+1]) in the mesh's orientation;
/// ringFace[ringBegin[i] + k] is the index in m.face of that k-th face.
struct RingTopology {
  std::vector<VertexKind> kind;
  std::vector<int> ringBegin;
  std::vector<int> ringIdx;
  std::vector<int> ringFace;

  int ringSize(int v) const { return ringBegin[v + 1] - ringBegin[v]; }
};

/// Builds the ring topology of m. Deleted faces and faces with a repeated
/// vertex are ignored, but the vertices of a face with a repeated vertex are
/// marked NonManifold so that they stay fixed. Needs no vcg adjacency.
template <class MeshType>
RingTopology buildRingTopology(const MeshType& m) {
  const int nv = static_cast<int>(m.vert.size());
  RingTopology topo;
  topo.kind.assign(nv, VertexKind::Isolated);
  for (int i = 0; i < nv; ++i)
    if (m.vert[i].IsD()) topo.kind[i] = VertexKind::Deleted;

  // Directed edges (a -> b) opposite to each vertex in its faces: the face
  // (v, a, b) contributes a -> b to v's fan.
  std::vector<int> count(nv + 1, 0);
  std::vector<char> badFace(nv, 0);
  auto vindex = [&m](const typename MeshType::VertexType* p) {
    return static_cast<int>(p - &m.vert[0]);
  };
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    const int v[3] = {vindex(f.cV(0)), vindex(f.cV(1)), vindex(f.cV(2))};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      for (int j = 0; j < 3; ++j) badFace[v[j]] = 1;
      continue;
    }
    for (int j = 0; j < 3; ++j) ++count[v[j] + 1];
  }
  for (int i = 0; i < nv; ++i) count[i + 1] += count[i];
  struct FanEdge {
    int a, b, face;
    bool operator<(const FanEdge& o) const { return a < o.a || (a == o.a && b < o.b); }
  };
  std::vector<FanEdge> fan(count[nv]);
  std::vector<int> fill(count.begin(), count.end() - 1);
  for (std::size_t fi = 0; fi < m.face.size(); ++fi) {
    const auto& f = m.face[fi];
    if (f.IsD()) continue;
    const int v[3] = {vindex(f.cV(0)), vindex(f.cV(1)), vindex(f.cV(2))};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
    for (int j = 0; j < 3; ++j)
      fan[fill[v[j]]++] = {v[(j + 1) % 3], v[(j + 2) % 3], static_cast<int>(fi)};
  }

  topo.ringBegin.assign(nv + 1, 0);
  topo.ringIdx.reserve(count[nv]);
  topo.ringFace.reserve(count[nv]);
  std::vector<FanEdge> edges;
  for (int i = 0; i < nv; ++i) {
    topo.ringBegin[i] = static_cast<int>(topo.ringIdx.size());
    if (topo.kind[i] == VertexKind::Deleted) continue;
    const int b = count[i], e = count[i + 1];
    if (b == e) continue;  // Isolated
    if (badFace[i]) {
      topo.kind[i] = VertexKind::NonManifold;
      continue;
    }
    edges.assign(fan.begin() + b, fan.begin() + e);
    std::sort(edges.begin(), edges.end());
    const int n = e - b;
    bool manifold = true;
    for (int k = 1; k < n && manifold; ++k)
      if (edges[k].a == edges[k - 1].a) manifold = false;  // two faces leave the same edge
    if (!manifold) {
      topo.kind[i] = VertexKind::NonManifold;
      continue;
    }
    auto find = [&edges](int a) -> const FanEdge* {
      auto it = std::lower_bound(edges.begin(), edges.end(), FanEdge{a, -1, -1});
      return (it != edges.end() && it->a == a) ? &*it : nullptr;
    };
    // A closed single fan has every edge start also as an edge end; an open fan
    // starts at a vertex that ends no edge.
    std::vector<int> ends;
    ends.reserve(n);
    for (const auto& ed : edges) ends.push_back(ed.b);
    std::sort(ends.begin(), ends.end());
    bool open = false, dupEnd = false;
    for (int k = 0; k < n; ++k) {
      if (k > 0 && ends[k] == ends[k - 1]) dupEnd = true;
      if (!std::binary_search(ends.begin(), ends.end(), edges[k].a)) open = true;
    }
    if (dupEnd) {
      topo.kind[i] = VertexKind::NonManifold;
      continue;
    }
    if (open) {
      topo.kind[i] = VertexKind::Boundary;
      continue;
    }
    // Closed: walk one cycle; if it is shorter than n there are several fans.
    const int start = edges[0].a;
    int cur = start, steps = 0;
    const int before = static_cast<int>(topo.ringIdx.size());
    do {
      const FanEdge* ed = find(cur);
      topo.ringIdx.push_back(cur);
      topo.ringFace.push_back(ed->face);
      cur = ed->b;
      ++steps;
    } while (cur != start && find(cur) && steps <= n);
    if (cur != start || steps != n) {
      topo.ringIdx.resize(before);
      topo.ringFace.resize(before);
      topo.kind[i] = VertexKind::NonManifold;
      continue;
    }
    topo.kind[i] = VertexKind::Interior;
  }
  topo.ringBegin[nv] = static_cast<int>(topo.ringIdx.size());
  return topo;
}

}  // namespace sodt
