// SPDX-License-Identifier: GPL-3.0-or-later
// Compact one-ring topology built once per run from the face list: for every
// vertex its neighbours in cyclic face order, or why it has no closed ring.
#pragma once

#include "geometry.h"

#include <vcg/complex/complex.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
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
/// ringFace[ringBegin[i] + k] is the index in the face list of that k-th face.
struct RingTopology {
  std::vector<VertexKind> kind;
  std::vector<int> ringBegin;
  std::vector<int> ringIdx;
  std::vector<int> ringFace;

  int ringSize(int v) const { return ringBegin[v + 1] - ringBegin[v]; }
};

/// Calls f(i) for every Interior vertex i, split in equal shares between
/// threads; f may write only what belongs to vertex i.
template <class F>
void forEachInterior(const RingTopology& topo, int threads, F f) {
  const long nv = static_cast<long>(topo.kind.size());
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
#else
  (void)threads;
#endif
  for (long i = 0; i < nv; ++i)
    if (topo.kind[i] == VertexKind::Interior) f(static_cast<int>(i));
}

/// Triangles as vertex-index triples (indices into the mesh's vertex vector).
struct FaceList {
  std::vector<std::array<int, 3>> tri;
  std::vector<char> live;       ///< false for deleted faces
  std::vector<char> flippable;  ///< the selection allows flipping this face
};

/// Per vertex, the live faces around it (index lists in CSR form).
struct IncidentFaces {
  std::vector<int> begin, face;
  IncidentFaces(const FaceList& faces, int nv) : begin(static_cast<std::size_t>(nv) + 1, 0) {
    for (std::size_t f = 0; f < faces.tri.size(); ++f)
      if (faces.live[f])
        for (int v : faces.tri[f]) ++begin[static_cast<std::size_t>(v) + 1];
    for (int v = 0; v < nv; ++v) begin[v + 1] += begin[v];
    face.resize(begin[nv]);
    std::vector<int> fill(begin.begin(), begin.end() - 1);
    for (std::size_t f = 0; f < faces.tri.size(); ++f)
      if (faces.live[f])
        for (int v : faces.tri[f]) face[fill[v]++] = static_cast<int>(f);
  }
};

/// The faces of m as index triples; with selectedOnly a face is flippable
/// only when it is selected or all its vertices are.
template <class MeshType>
FaceList makeFaceList(const MeshType& m, bool selectedOnly = false) {
  FaceList fl;
  fl.tri.resize(m.face.size());
  fl.live.assign(m.face.size(), 0);
  fl.flippable.assign(m.face.size(), 0);
  for (std::size_t f = 0; f < m.face.size(); ++f) {
    const auto& F = m.face[f];
    if (F.IsD()) continue;
    for (int j = 0; j < 3; ++j) fl.tri[f][j] = static_cast<int>(F.cV(j) - &m.vert[0]);
    fl.live[f] = 1;
    fl.flippable[f] = !selectedOnly || F.IsS() || (F.cV(0)->IsS() && F.cV(1)->IsS() && F.cV(2)->IsS());
  }
  return fl;
}

/// Faces whose smallest angle is below this have a normal that says
/// little about the surface: moving a vertex by a hundredth of an edge
/// length turns a 3-degree sliver by about 10 degrees.
constexpr double kSliverNormalDeg = 3.0;

/// Per vertex, the sum of the area vectors of the live faces around it
/// (faces with a non-finite area left out): the surface's orientation at
/// the vertex, in which slivers weigh little.
inline std::vector<Vec3> vertexAreaSums(const FaceList& faces, const std::vector<Vec3>& pos) {
  std::vector<Vec3> around(pos.size(), Vec3(0, 0, 0));
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    const std::array<int, 3>& t = faces.tri[f];
    const Vec3 a = doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]);
    if (isFinite(a))
      for (int v : t) around[v] += a;
  }
  return around;
}

/// For each live face folded against the surface at its corners (its
/// normal more than 90 degrees from the sum of vertexAreaSums at its three
/// vertices, which its neighbours outweigh): the unit normal of that
/// surface; zero for every other face. Such a face is a fold of the
/// surface, not a side of it: a sliver whose normal rounding or a move
/// turned, or a face that noise or a bad hole fill turned over. Its own
/// orientation is no reference for which side a face over it should face;
/// moves and a denoising filter may unfold it into the surface.
inline std::vector<Vec3> foldedFaceSurfaceNormals(const FaceList& faces, const std::vector<Vec3>& pos) {
  std::vector<Vec3> normal(faces.tri.size(), Vec3(0, 0, 0));
  const std::vector<Vec3> around = vertexAreaSums(faces, pos);
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    const std::array<int, 3>& t = faces.tri[f];
    const Vec3 a = doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]);
    if (!(a.SquaredNorm() > 0) || !isFinite(a)) continue;
    const Vec3 mean = around[t[0]] + around[t[1]] + around[t[2]];
    const double len = mean.Norm();
    if (len > 0 && std::isfinite(len) && mean * a < 0) normal[f] = mean / len;
  }
  return normal;
}

namespace detail {

/// Edge a -> b opposite a vertex in one of its faces.
struct FanEdge {
  int a, b, face;
  bool operator<(const FanEdge& o) const { return a < o.a || (a == o.a && b < o.b); }
};

/// Fans up to this size are checked by pairwise comparison, larger ones
/// after sorting; both give the same result.
constexpr int kSmallFan = 16;

/// After a walk of `steps` edges appended from position `before`: Interior
/// when it went round all n edges of the fan, else NonManifold (several
/// fans) with the walk removed again.
inline VertexKind keepWholeRing(RingTopology& topo, std::size_t before, int steps, int n) {
  if (steps == n) return VertexKind::Interior;
  topo.ringIdx.resize(before);
  topo.ringFace.resize(before);
  return VertexKind::NonManifold;
}

/// Classifies the fan of n edges of one vertex (see buildRingTopology) and,
/// when it is one closed fan, appends its ring to topo, starting at the
/// smallest edge start and following the edges. Two edges with the same
/// start or the same end: NonManifold; a start that ends no edge: Boundary;
/// a cycle shorter than n: NonManifold (several fans).
inline VertexKind closeSmallFan(const FanEdge* fan, int n, RingTopology& topo) {
  for (int k = 1; k < n; ++k)
    for (int j = 0; j < k; ++j)
      if (fan[j].a == fan[k].a || fan[j].b == fan[k].b) return VertexKind::NonManifold;
  int first = 0;
  for (int k = 0; k < n; ++k) {
    bool isEnd = false;
    for (int j = 0; j < n && !isEnd; ++j) isEnd = fan[j].b == fan[k].a;
    if (!isEnd) return VertexKind::Boundary;
    if (fan[k].a < fan[first].a) first = k;
  }
  // Every start is an end and no two share either: following the edges is a
  // permutation of the starts; its cycle through the first must hold all n.
  const std::size_t before = topo.ringIdx.size();
  int k = first, steps = 0;
  do {
    topo.ringIdx.push_back(fan[k].a);
    topo.ringFace.push_back(fan[k].face);
    const int next = fan[k].b;
    k = 0;
    while (fan[k].a != next) ++k;
    ++steps;
  } while (k != first);
  return keepWholeRing(topo, before, steps, n);
}

/// closeSmallFan for any n, by sorting (edges and ends are scratch space).
inline VertexKind closeFan(const FanEdge* fan, int n, std::vector<FanEdge>& edges, std::vector<int>& ends,
                           RingTopology& topo) {
  edges.assign(fan, fan + n);
  std::sort(edges.begin(), edges.end());
  for (int k = 1; k < n; ++k)
    if (edges[k].a == edges[k - 1].a) return VertexKind::NonManifold;  // two faces leave the same edge
  ends.clear();
  for (const FanEdge& ed : edges) ends.push_back(ed.b);
  std::sort(ends.begin(), ends.end());
  for (int k = 1; k < n; ++k)
    if (ends[k] == ends[k - 1]) return VertexKind::NonManifold;
  for (int k = 0; k < n; ++k)
    if (!std::binary_search(ends.begin(), ends.end(), edges[k].a)) return VertexKind::Boundary;
  const auto find = [&edges](int a) {
    return std::lower_bound(edges.begin(), edges.end(), FanEdge{a, -1, -1});  // present: every end starts an edge
  };
  const std::size_t before = topo.ringIdx.size();
  const int start = edges[0].a;
  int cur = start, steps = 0;
  do {
    const FanEdge& ed = *find(cur);
    topo.ringIdx.push_back(cur);
    topo.ringFace.push_back(ed.face);
    cur = ed.b;
    ++steps;
  } while (cur != start);
  return keepWholeRing(topo, before, steps, n);
}

}  // namespace detail

/// Flips faces so that every edge shared by exactly two live faces is used
/// by them in opposite directions. Each component (faces joined through
/// such edges) that has a conflict (an edge both faces run the same way)
/// gets one winding: when it is closed (each of its faces has three such
/// edges), the one that gives it a positive signed volume (outward
/// normals); else that of the majority of its faces (of its first face on
/// a tie). Components without a conflict keep their winding, even a closed
/// one that faces inwards. Two faces on the same three vertices (a face
/// given twice) are not joined, so duplicates are never a conflict.
/// Components that cannot be oriented (a Moebius band) and faces around
/// edges with three or more faces keep theirs. The half-edges are grouped
/// by their lower vertex (a counting sort), so the cost is linear in the
/// faces. pos: the vertex positions (pos.size() vertices).
/// \return the number of faces flipped.
inline int orientCoherently(FaceList& faces, const std::vector<Vec3>& pos) {
  struct Half {
    int hi, face;
    bool up;  ///< the face runs the edge from its lower to its higher vertex
  };
  const int nv = static_cast<int>(pos.size());
  const std::size_t nf = faces.tri.size();
  std::vector<int> begin(static_cast<std::size_t>(nv) + 1, 0);
  for (std::size_t f = 0; f < nf; ++f)
    if (faces.live[f])
      for (int j = 0; j < 3; ++j) {
        const int a = faces.tri[f][j], b = faces.tri[f][(j + 1) % 3];
        if (a != b) ++begin[static_cast<std::size_t>(std::min(a, b)) + 1];
      }
  for (int v = 0; v < nv; ++v) begin[v + 1] += begin[v];
  std::vector<Half> half(static_cast<std::size_t>(begin[nv]));
  std::vector<int> fill(begin.begin(), begin.end() - 1);
  for (std::size_t f = 0; f < nf; ++f)
    if (faces.live[f])
      for (int j = 0; j < 3; ++j) {
        const int a = faces.tri[f][j], b = faces.tri[f][(j + 1) % 3];
        if (a != b) half[static_cast<std::size_t>(fill[std::min(a, b)]++)] = Half{std::max(a, b), int(f), a < b};
      }
  const auto sameVertices = [&faces](int f, int g) {
    std::array<int, 3> a = faces.tri[f], b = faces.tri[g];
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    return a == b;
  };
  // Faces joined by a two-face edge, and whether that edge asks one of them
  // to turn over (both run it the same way).
  std::vector<std::vector<std::pair<int, bool>>> next(nf);
  bool mixed = false;
  for (int v = 0; v < nv; ++v) {
    std::sort(half.begin() + begin[v], half.begin() + begin[v + 1],
              [](const Half& x, const Half& y) { return x.hi != y.hi ? x.hi < y.hi : x.face < y.face; });
    for (int h = begin[v]; h < begin[v + 1];) {
      int e = h + 1;
      while (e < begin[v + 1] && half[e].hi == half[h].hi) ++e;
      if (e - h == 2 && half[h].face != half[h + 1].face && !sameVertices(half[h].face, half[h + 1].face)) {
        const bool same = half[h].up == half[h + 1].up;
        mixed = mixed || same;
        next[half[h].face].emplace_back(half[h + 1].face, same);
        next[half[h + 1].face].emplace_back(half[h].face, same);
      }
      h = e;
    }
  }
  if (!mixed) return 0;
  std::vector<signed char> parity(nf, -1);  // relative to the component's first face
  std::vector<int> component, queue;
  int flipped = 0;
  for (std::size_t seed = 0; seed < nf; ++seed) {
    if (!faces.live[seed] || parity[seed] >= 0) continue;
    component.clear();
    queue.assign(1, int(seed));
    parity[seed] = 0;
    bool orientable = true, closed = true;
    int ones = 0;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int f = queue[q];
      component.push_back(f);
      ones += parity[f];
      closed = closed && next[f].size() == 3;
      for (const auto& nb : next[f]) {
        const signed char want = static_cast<signed char>(parity[f] ^ (nb.second ? 1 : 0));
        if (parity[nb.first] < 0) {
          parity[nb.first] = want;
          queue.push_back(nb.first);
        } else if (parity[nb.first] != want) {
          orientable = false;
        }
      }
    }
    if (!orientable || ones == 0) continue;  // a Moebius band, or no conflict
    const int zeros = static_cast<int>(component.size()) - ones;
    signed char turn = ones > zeros ? 0 : 1;  // the minority turns over
    if (closed) {
      // The signed volume with the faces of parity 0 as they are, about
      // the component's mean vertex (against cancellation).
      Vec3 c(0, 0, 0);
      for (int f : component)
        for (int v : faces.tri[f]) c += pos[v];
      c /= 3.0 * double(component.size());
      double volume = 0;
      for (int f : component) {
        const std::array<int, 3>& t = faces.tri[f];
        const double v = (pos[t[0]] - c) * ((pos[t[1]] - c) ^ (pos[t[2]] - c));
        volume += parity[f] ? -v : v;
      }
      if (volume != 0 && std::isfinite(volume)) turn = volume > 0 ? 1 : 0;
    }
    for (int f : component)
      if (parity[f] == turn) {
        std::swap(faces.tri[f][1], faces.tri[f][2]);
        ++flipped;
      }
  }
  return flipped;
}

/// Builds the ring topology of the faces over nv vertices (deleted[i] marks
/// deleted vertices). Dead faces and faces with a repeated vertex are
/// ignored, but the vertices of a face with a repeated vertex are marked
/// NonManifold so that they stay fixed.
inline RingTopology buildRingTopology(const FaceList& faces, const std::vector<char>& deleted) {
  const int nv = static_cast<int>(deleted.size());
  RingTopology topo;
  topo.kind.assign(nv, VertexKind::Isolated);
  for (int i = 0; i < nv; ++i)
    if (deleted[i]) topo.kind[i] = VertexKind::Deleted;

  // Directed edges (a -> b) opposite to each vertex in its faces: the face
  // (v, a, b) contributes a -> b to v's fan.
  std::vector<int> count(nv + 1, 0);
  std::vector<char> badFace(nv, 0);
  for (std::size_t fi = 0; fi < faces.tri.size(); ++fi) {
    if (!faces.live[fi]) continue;
    const int* v = faces.tri[fi].data();
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      for (int j = 0; j < 3; ++j) badFace[v[j]] = 1;
      continue;
    }
    for (int j = 0; j < 3; ++j) ++count[v[j] + 1];
  }
  for (int i = 0; i < nv; ++i) count[i + 1] += count[i];
  using detail::FanEdge;
  std::vector<FanEdge> fan(count[nv]);
  std::vector<int> fill(count.begin(), count.end() - 1);
  for (std::size_t fi = 0; fi < faces.tri.size(); ++fi) {
    if (!faces.live[fi]) continue;
    const int* v = faces.tri[fi].data();
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
    for (int j = 0; j < 3; ++j)
      fan[fill[v[j]]++] = {v[(j + 1) % 3], v[(j + 2) % 3], static_cast<int>(fi)};
  }

  topo.ringBegin.assign(nv + 1, 0);
  topo.ringIdx.reserve(count[nv]);
  topo.ringFace.reserve(count[nv]);
  std::vector<FanEdge> edges;
  std::vector<int> ends;
  for (int i = 0; i < nv; ++i) {
    topo.ringBegin[i] = static_cast<int>(topo.ringIdx.size());
    if (topo.kind[i] == VertexKind::Deleted) continue;
    if (badFace[i]) {  // in a face with a repeated vertex, whatever else it is in
      topo.kind[i] = VertexKind::NonManifold;
      continue;
    }
    const int b = count[i], e = count[i + 1];
    if (b == e) continue;  // Isolated
    topo.kind[i] = e - b <= detail::kSmallFan ? detail::closeSmallFan(fan.data() + b, e - b, topo)
                                              : detail::closeFan(fan.data() + b, e - b, edges, ends, topo);
  }
  topo.ringBegin[nv] = static_cast<int>(topo.ringIdx.size());
  return topo;
}

/// The order in which a sweep visits its vertices, in phases: no two
/// vertices of one phase are ring neighbours, so a phase's visits read only
/// positions that stay fixed while it is swept, and can run in any order or
/// in parallel with the same result.
struct SweepPlan {
  std::vector<int> order;
  std::vector<int> phaseBegin;  ///< phase p is order[phaseBegin[p] .. phaseBegin[p + 1])
  /// With tiles: tile t (in plan order) is phases tileBegin[t] ..
  /// tileBegin[t + 1], and group g is tiles groupBegin[g] ..
  /// groupBegin[g + 1]. No vertex of a tile has a ring neighbour in another
  /// tile of its group, so the tiles of a group can be swept at once, each
  /// phase by phase, with the result of sweeping them one after the other.
  /// Empty without tiles.
  std::vector<int> tileBegin;
  std::vector<int> groupBegin;
};

/// Plans a sweep of the given vertices. They are coloured greedily (in
/// ascending index order, each gets the smallest colour none of its ring
/// neighbours among them has; only ring adjacency counts: vertices outside
/// the list never move). With tile 0 each phase is one colour, colour by
/// colour. With tile > 0 the indices are cut into tiles of `tile`
/// consecutive indices and each phase is one colour within one tile, tile by
/// tile: when indices follow the surface (breadth-first order), a sweep then
/// works on one tile's data at a time instead of crossing the whole mesh once
/// per colour. The tiles are coloured too (greedily in index order; two
/// tiles are adjacent when a vertex of one is a ring neighbour of a vertex
/// of the other), and go group by group, one group per tile colour, in
/// index order within a group: the tiles of a group can then be swept in
/// parallel with a wait only between groups, where one wait per phase made
/// a thread held up by another program stall the others thousands of times
/// per sweep. Within a phase, ascending index; empty phases are left out.
/// Deterministic.
inline SweepPlan colourVertices(const RingTopology& topo, const std::vector<int>& vertices, int tile = 0) {
  const int nv = static_cast<int>(topo.kind.size());
  std::vector<int> colour(nv, -1);
  std::vector<int> seenAt;  // seenAt[c] == v: colour c is taken by a neighbour of v
  int colours = 0;
  for (int v : vertices) {
    for (int k = topo.ringBegin[v]; k < topo.ringBegin[v + 1]; ++k) {
      const int c = colour[topo.ringIdx[k]];
      if (c >= 0) seenAt[c] = v;
    }
    int c = 0;
    while (c < colours && seenAt[c] == v) ++c;
    if (c == colours) {
      ++colours;
      seenAt.push_back(-1);
    }
    colour[v] = c;
  }
  const std::size_t tiles = tile > 0 ? static_cast<std::size_t>(nv) / tile + 1 : 1;
  // The tiles' colours, and their places in plan order: by colour, then
  // index.
  std::vector<int> tileColour(tiles, 0);
  std::vector<std::size_t> tileRank(tiles, 0);
  if (tile > 0) {
    std::vector<char> member(nv, 0);
    for (int v : vertices) member[v] = 1;
    std::fill(tileColour.begin(), tileColour.end(), -1);
    std::vector<int> seenTile;  // seenTile[c] == t: tile colour c is taken by a neighbour of tile t
    int tileColours = 0;
    std::vector<int> sorted(vertices);
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < sorted.size();) {
      const std::size_t t = static_cast<std::size_t>(sorted[i] / tile);
      std::size_t j = i;
      for (; j < sorted.size() && static_cast<std::size_t>(sorted[j] / tile) == t; ++j) {
        const int v = sorted[j];
        for (int k = topo.ringBegin[v]; k < topo.ringBegin[v + 1]; ++k) {
          const int u = topo.ringIdx[k];
          if (!member[u] || static_cast<std::size_t>(u / tile) == t) continue;
          const int c = tileColour[u / tile];
          if (c >= 0) seenTile[c] = static_cast<int>(t);
        }
      }
      int c = 0;
      while (c < tileColours && seenTile[c] == static_cast<int>(t)) ++c;
      if (c == tileColours) {
        ++tileColours;
        seenTile.push_back(-1);
      }
      tileColour[t] = c;
      i = j;
    }
    std::vector<std::size_t> count(tileColours + 1, 0);
    for (std::size_t k = 0; k < tiles; ++k)
      if (tileColour[k] >= 0) ++count[tileColour[k] + 1];
    for (int c = 0; c < tileColours; ++c) count[c + 1] += count[c];
    for (std::size_t k = 0; k < tiles; ++k)
      if (tileColour[k] >= 0) tileRank[k] = count[tileColour[k]]++;
  }
  // Phase key of a vertex: its tile's place, then its colour.
  const auto key = [&](int v) {
    return (tile > 0 ? tileRank[static_cast<std::size_t>(v / tile)] * colours : 0) + static_cast<std::size_t>(colour[v]);
  };
  std::vector<int> start(tiles * colours + 1, 0);
  for (int v : vertices) ++start[key(v) + 1];
  SweepPlan plan;
  plan.phaseBegin.push_back(0);
  int lastTile = -1, lastGroup = -1;
  for (std::size_t k = 0; k + 1 < start.size(); ++k) {
    if (start[k + 1] > 0) {
      if (tile > 0) {
        const int rank = static_cast<int>(k / colours);
        if (rank != lastTile) {
          plan.tileBegin.push_back(static_cast<int>(plan.phaseBegin.size()) - 1);
          lastTile = rank;
        }
      }
      plan.phaseBegin.push_back(plan.phaseBegin.back() + start[k + 1]);
    }
    start[k + 1] += start[k];
  }
  plan.order.resize(vertices.size());
  for (int v : vertices) plan.order[start[key(v)]++] = v;
  if (tile > 0) {
    plan.tileBegin.push_back(static_cast<int>(plan.phaseBegin.size()) - 1);
    // Groups: runs of tiles of one colour, in plan order.
    for (std::size_t t = 0; t + 1 < plan.tileBegin.size(); ++t) {
      const int first = plan.order[plan.phaseBegin[plan.tileBegin[t]]];
      const int g = tileColour[static_cast<std::size_t>(first / tile)];
      if (g != lastGroup) {
        plan.groupBegin.push_back(static_cast<int>(t));
        lastGroup = g;
      }
    }
    plan.groupBegin.push_back(static_cast<int>(plan.tileBegin.size()) - 1);
  }
  return plan;
}

/// The vertices in breadth-first order over the faces: entry i is the
/// original index of the i-th vertex. Each connected part is walked from its
/// lowest-index vertex, neighbours in face order; deleted vertices go last.
/// A one-ring then lies within a few breadth-first layers, close in memory,
/// whatever order the mesh stores its vertices in (subdivision and merged
/// parts scatter them), and the order depends only on the connectivity.
inline std::vector<int> breadthFirstOrder(const FaceList& faces, const std::vector<char>& deleted) {
  const int nv = static_cast<int>(deleted.size());
  std::vector<int> begin(nv + 1, 0);
  for (std::size_t f = 0; f < faces.tri.size(); ++f)
    if (faces.live[f])
      for (int v : faces.tri[f]) ++begin[v + 1];
  for (int i = 0; i < nv; ++i) begin[i + 1] += begin[i];
  std::vector<int> incident(begin[nv]);
  {
    std::vector<int> fill(begin.begin(), begin.end() - 1);
    for (std::size_t f = 0; f < faces.tri.size(); ++f)
      if (faces.live[f])
        for (int v : faces.tri[f]) incident[fill[v]++] = static_cast<int>(f);
  }
  std::vector<int> order;
  order.reserve(nv);
  std::vector<char> seen(deleted.begin(), deleted.end());
  for (int seed = 0; seed < nv; ++seed) {
    if (seen[seed]) continue;
    seen[seed] = 1;
    std::size_t head = order.size();
    order.push_back(seed);
    for (; head < order.size(); ++head) {
      const int v = order[head];
      for (int k = begin[v]; k < begin[v + 1]; ++k)
        for (int u : faces.tri[incident[k]])
          if (!seen[u]) {
            seen[u] = 1;
            order.push_back(u);
          }
    }
  }
  for (int i = 0; i < nv; ++i)
    if (deleted[i]) order.push_back(i);
  return order;
}

/// Reorders the faces by their smallest vertex index (ties keep their
/// order), dead faces last, and returns the previous index of each face.
/// With vertices in breadth-first order the faces of a star then lie close
/// together in memory too, so per-face data read per visit (reference
/// normals, the deviation guard's input faces) is near in the cache. The
/// ring topology and everything built on it do not depend on face order.
inline std::vector<int> sortFacesByVertex(FaceList& faces, int nv) {
  const std::size_t nf = faces.tri.size();
  std::vector<int> begin(static_cast<std::size_t>(nv) + 2, 0);  // key nv: dead faces
  const auto key = [&](std::size_t f) {
    if (!faces.live[f]) return nv;
    const std::array<int, 3>& t = faces.tri[f];
    return std::min(t[0], std::min(t[1], t[2]));
  };
  for (std::size_t f = 0; f < nf; ++f) ++begin[key(f) + 1];
  for (int k = 0; k <= nv; ++k) begin[k + 1] += begin[k];
  std::vector<int> previous(nf);
  for (std::size_t f = 0; f < nf; ++f) previous[begin[key(f)]++] = static_cast<int>(f);
  FaceList sorted;
  sorted.tri.resize(nf);
  sorted.live.resize(nf);
  sorted.flippable.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    sorted.tri[f] = faces.tri[previous[f]];
    sorted.live[f] = faces.live[previous[f]];
    sorted.flippable[f] = faces.flippable[previous[f]];
  }
  faces = std::move(sorted);
  return previous;
}

/// Builds the ring topology of m (see the FaceList overload). Needs no vcg adjacency.
template <class MeshType>
RingTopology buildRingTopology(const MeshType& m) {
  std::vector<char> deleted(m.vert.size(), 0);
  for (std::size_t i = 0; i < m.vert.size(); ++i) deleted[i] = m.vert[i].IsD();
  return buildRingTopology(makeFaceList(m), deleted);
}

}  // namespace sodt
