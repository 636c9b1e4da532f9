// SPDX-License-Identifier: GPL-3.0-or-later
// Topology and quality report of a triangle mesh for the mesh generator:
// closedness, edge/vertex manifoldness, orientation, components, angles.
#pragma once

#include <sodt/maths/geometry.h>
#include <sodt_io/metrics.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

namespace sodt {
namespace tools {

/// Everything the generator asserts about a mesh it writes. Edge counts are
/// over undirected edges of the live faces.
struct MeshCheck {
  int vertices = 0;            ///< live vertices
  int faces = 0;               ///< live faces
  long long edges = 0;         ///< undirected edges
  long long boundaryEdges = 0;     ///< edges with one face
  long long nonManifoldEdges = 0;  ///< edges with more than two faces
  long long misorientedEdges = 0;  ///< two-face edges traversed twice in the same direction
  int nonManifoldVertices = 0;     ///< vertices whose faces form more than one fan
  int isolatedVertices = 0;        ///< live vertices no live face references
  int degenerateIndexFaces = 0;    ///< faces with a repeated vertex index
  int zeroAreaFaces = 0;           ///< faces whose area is exactly zero in double
  int components = 0;             ///< vertex-connected components (isolated vertices excluded)
  int boundaryLoops = 0;           ///< cycles of boundary edges (edge-manifold meshes only)
  double volume = 0;               ///< signed enclosed volume; 0 unless closed and oriented
  AngleStats angles;               ///< corner angles in degrees (sodt_io/metrics.h)
  long long anglesBelow1Deg = 0;   ///< corner angles below 1 degree

  bool closedManifold() const {
    return faces > 0 && boundaryEdges == 0 && nonManifoldEdges == 0 && misorientedEdges == 0 &&
           nonManifoldVertices == 0 && degenerateIndexFaces == 0;
  }
  bool openManifold() const {
    return faces > 0 && boundaryEdges > 0 && nonManifoldEdges == 0 && misorientedEdges == 0 &&
           nonManifoldVertices == 0 && degenerateIndexFaces == 0;
  }
  int eulerCharacteristic() const { return vertices - static_cast<int>(edges) + faces; }
};

namespace detail {

/// Minimal union-find over [0, n).
class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(int a, int b) { parent_[find(a)] = find(b); }

 private:
  std::vector<int> parent_;
};

}  // namespace detail

/// Computes the report for the live elements of m. Vertex indices are
/// positions in m.vert.
template <class MeshType>
MeshCheck checkMesh(const MeshType& m) {
  MeshCheck c;
  const int nv = static_cast<int>(m.vert.size());
  auto index = [&m](const typename MeshType::VertexType* p) { return static_cast<int>(p - &m.vert[0]); };

  std::vector<std::pair<int, int>> half;        // directed edges of the live faces
  std::vector<std::vector<std::pair<int, int>>> fan(nv);  // per vertex: (a, b) of its faces (v, a, b)
  std::vector<char> referenced(nv, 0);
  detail::DisjointSets comps(nv);
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    ++c.faces;
    const int v[3] = {index(f.cV(0)), index(f.cV(1)), index(f.cV(2))};
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) {
      ++c.degenerateIndexFaces;
      continue;
    }
    const Vec3 p0(f.cP(0)[0], f.cP(0)[1], f.cP(0)[2]);
    const Vec3 p1(f.cP(1)[0], f.cP(1)[1], f.cP(1)[2]);
    const Vec3 p2(f.cP(2)[0], f.cP(2)[1], f.cP(2)[2]);
    if (doubleAreaVector(p0, p1, p2).SquaredNorm() == 0.0) ++c.zeroAreaFaces;
    for (int j = 0; j < 3; ++j) {
      half.emplace_back(v[j], v[(j + 1) % 3]);
      fan[v[j]].emplace_back(v[(j + 1) % 3], v[(j + 2) % 3]);
      referenced[v[j]] = 1;
      comps.unite(v[j], v[(j + 1) % 3]);
    }
  }
  for (int i = 0; i < nv; ++i) {
    if (m.vert[i].IsD()) continue;
    ++c.vertices;
    if (!referenced[i]) ++c.isolatedVertices;
  }

  // Undirected edges: count faces per edge and the directions they use.
  std::vector<std::pair<int, int>> undirected;
  undirected.reserve(half.size());
  for (const auto& h : half) undirected.emplace_back(std::min(h.first, h.second), std::max(h.first, h.second));
  std::sort(half.begin(), half.end());
  std::sort(undirected.begin(), undirected.end());
  std::vector<int> boundaryNext(nv, -1);  // boundary half-edge a -> b, for loop counting
  for (std::size_t i = 0; i < undirected.size();) {
    std::size_t j = i;
    while (j < undirected.size() && undirected[j] == undirected[i]) ++j;
    const long long n = static_cast<long long>(j - i);
    ++c.edges;
    const std::pair<int, int> e = undirected[i];
    const auto forward = std::equal_range(half.begin(), half.end(), e);
    const auto backward = std::equal_range(half.begin(), half.end(), std::make_pair(e.second, e.first));
    const long long nf = forward.second - forward.first, nb = backward.second - backward.first;
    if (n == 1) {
      ++c.boundaryEdges;
      const std::pair<int, int> h = nf == 1 ? e : std::make_pair(e.second, e.first);
      boundaryNext[h.first] = boundaryNext[h.first] == -1 ? h.second : -2;
    } else if (n > 2) {
      ++c.nonManifoldEdges;
    } else if (nf != 1 || nb != 1) {
      ++c.misorientedEdges;
    }
    i = j;
  }

  // A vertex is manifold when the opposite edges of its faces link up into
  // one fan (a cycle when interior, a path on the boundary).
  for (int i = 0; i < nv; ++i) {
    if (fan[i].empty()) continue;
    std::vector<int> ids;
    for (const auto& ab : fan[i]) {
      ids.push_back(ab.first);
      ids.push_back(ab.second);
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    detail::DisjointSets local(static_cast<int>(ids.size()));
    auto at = [&ids](int x) { return static_cast<int>(std::lower_bound(ids.begin(), ids.end(), x) - ids.begin()); };
    for (const auto& ab : fan[i]) local.unite(at(ab.first), at(ab.second));
    int fans = 0;
    for (int k = 0; k < static_cast<int>(ids.size()); ++k) fans += local.find(k) == k;
    if (fans != 1) ++c.nonManifoldVertices;
  }

  for (int i = 0; i < nv; ++i)
    if (referenced[i] && comps.find(i) == i) ++c.components;

  if (c.nonManifoldEdges == 0 && c.nonManifoldVertices == 0) {
    std::vector<char> seen(nv, 0);
    for (int i = 0; i < nv; ++i) {
      if (boundaryNext[i] < 0 || seen[i]) continue;
      ++c.boundaryLoops;
      for (int k = i; k >= 0 && !seen[k]; k = boundaryNext[k]) seen[k] = 1;
    }
  }

  c.angles = computeAngleStats(m);
  c.anglesBelow1Deg = c.angles.histogram[0];  // bin 0 holds [0, 1) degrees
  if (c.closedManifold()) c.volume = enclosedVolume(m).volume;
  return c;
}

/// One markdown table row: name | V | F | closed | boundary loops | components
/// | genus or chi | volume | min | max | % < 30 | # < 1 deg | zero-area faces.
inline std::string formatRow(const std::string& name, const MeshCheck& c) {
  char buf[512];
  const bool closed = c.closedManifold();
  std::snprintf(buf, sizeof buf, "| %s | %d | %d | %s | %d | %d | %d | %.4g | %.3f | %.2f | %.1f | %lld | %d |",
                name.c_str(), c.vertices, c.faces, closed ? "yes" : "no", c.boundaryLoops, c.components,
                c.eulerCharacteristic(), c.volume, c.angles.minDeg, c.angles.maxDeg, 100.0 * c.angles.fracBelow30,
                c.anglesBelow1Deg, c.zeroAreaFaces);
  return buf;
}

inline const char* tableHeader() {
  return "| file | V | F | closed | bnd loops | comps | chi | volume | min deg | max deg | % < 30 | # < 1 deg | "
         "zero-area F |\n|---|---:|---:|:-:|---:|---:|---:|---:|---:|---:|---:|---:|---:|";
}

}  // namespace tools
}  // namespace sodt
