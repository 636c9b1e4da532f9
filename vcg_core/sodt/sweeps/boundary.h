// SPDX-License-Identifier: GPL-3.0-or-later
// Border vertices that slide along the border (SodtParams::slideBoundary):
// their open fans, the input border polyline each one stays on, and one
// guarded visit (the S-ODT minimiser along the border, Eq. 5 on the open fan).
#pragma once

#include "../guards/deviation.h"
#include "../maths/geometry.h"
#include "../guards/guarded_move.h"
#include "../maths/local_solve.h"
#include "../params.h"
#include "../maths/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace sodt {

/// A border vertex where the border turns by more than this (the angle
/// between its two border edges' directions, in degrees) is a corner of the
/// border and stays fixed, like the corners of a square patch. 30 degrees
/// keeps every polygon corner with up to 12 sides fixed, while a border
/// sampled at 12 or more vertices per full turn slides.
constexpr double kBoundaryCornerDeg = 30.0;

/// A border vertex with more faces than this stays fixed too: it is the
/// apex of a fan-triangulated polygon or of a cone's cap, and a slide
/// would read its whole fan for each of its faces' sample points (O(n^2)
/// per visit for a fan of n faces).
constexpr int kMaxSlidingFan = 64;

/// The open fan of a border vertex v: faces (v, ring[k], ring[k+1]) for k <
/// faces.size(), in the mesh's orientation. The border runs ring.back() ->
/// v -> ring.front().
struct OpenFan {
  std::vector<int> ring;   ///< faces.size() + 1 vertices
  std::vector<int> faces;  ///< indices into the face list
};

/// The open fan of v when its faces form exactly one chain (two border
/// edges at v); false otherwise (a closed ring, or several fans: more than
/// two border edges, which keeps v fixed).
inline bool openFan(int v, const FaceList& faces, const IncidentFaces& inc, OpenFan& fan) {
  struct Edge {
    int a, b, face;
  };
  std::vector<Edge> edges;
  for (int k = inc.begin[v]; k < inc.begin[v + 1]; ++k) {
    const std::array<int, 3>& t = faces.tri[inc.face[k]];
    const int j = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    edges.push_back({t[(j + 1) % 3], t[(j + 2) % 3], inc.face[k]});
  }
  const std::size_t n = edges.size();
  int start = -1;
  for (std::size_t k = 0; k < n; ++k) {
    bool isEnd = false;
    for (std::size_t j = 0; j < n; ++j) {
      if (j != k && (edges[j].a == edges[k].a || edges[j].b == edges[k].b)) return false;  // non-manifold
      isEnd = isEnd || edges[j].b == edges[k].a;
    }
    if (isEnd) continue;
    if (start >= 0) return false;  // a second chain
    start = static_cast<int>(k);
  }
  if (start < 0) return false;  // closed
  fan.ring.assign(1, edges[start].a);
  fan.faces.clear();
  for (int k = start; k >= 0 && fan.faces.size() < n;) {
    fan.faces.push_back(edges[k].face);
    fan.ring.push_back(edges[k].b);
    int next = -1;
    for (std::size_t j = 0; j < n && next < 0; ++j)
      if (edges[j].a == edges[k].b) next = static_cast<int>(j);
    k = next;
  }
  return fan.faces.size() == n;
}

/// The sliding border vertices of a run and what their visits read: the
/// input border polyline each one stays on, the input faces its deviation
/// guard checks against, and its current open fan (rebuilt after flips).
struct BoundarySlide {
  /// Points of the input border around a sliding vertex: the border
  /// neighbours' neighbours, the neighbours, the vertex, in border order
  /// (prev prev, prev, v, next, next next). It ends early (a repeated point)
  /// at a neighbour that does not slide, so that no vertex passes a fixed one.
  using Path = std::array<Vec3, 5>;

  std::vector<int> vertex;  ///< the sliding vertices, ascending
  std::vector<Path> path;   ///< per sliding vertex
  std::vector<int> patchBegin, patch;  ///< per sliding vertex, input faces (CSR) of its deviation patch
  std::vector<OpenFan> fan;  ///< per sliding vertex, its current open fan
  int corners = 0;           ///< border vertices kept fixed as corners (turn, or more than two border edges)

  bool empty() const { return vertex.empty(); }

  /// Moves the sliding vertices from stats.fixedBoundary to
  /// stats.activeVertices, and counts them and the corners.
  void count(SodtStats& stats) const {
    const int n = static_cast<int>(vertex.size());
    stats.fixedBoundary -= n;
    stats.activeVertices += n;
    stats.slidingBoundary = n;
    stats.boundaryCorners = corners;
  }

  /// The sliding vertices whose position in pos differs from start's (the
  /// positions of vertex, in order).
  int movedFrom(const std::vector<Vec3>& start, const std::vector<Vec3>& pos) const {
    int moved = 0;
    for (std::size_t s = 0; s < vertex.size(); ++s) moved += !(pos[vertex[s]] == start[s]);
    return moved;
  }

  /// The positions of the sliding vertices in pos, in order.
  std::vector<Vec3> positions(const std::vector<Vec3>& pos) const {
    std::vector<Vec3> out;
    for (int v : vertex) out.push_back(pos[v]);
    return out;
  }

  /// Finds the sliding vertices among the border vertices of topo (selected
  /// ones with p.selectedOnly: a selection's border is not the mesh's, its
  /// vertices are interior and move as such), from the input faces and
  /// positions.
  void prepare(const SodtParams& p, const FaceList& faces, const RingTopology& topo, const std::vector<Vec3>& pos,
               const std::vector<char>& selected) {
    const int nv = static_cast<int>(pos.size());
    const IncidentFaces inc(faces, nv);
    std::vector<int> slot(nv, -1);
    std::vector<OpenFan> all;
    std::vector<int> candidates;
    const double cosCorner = std::cos(kBoundaryCornerDeg * kPi / 180.0);
    for (int v = 0; v < nv; ++v) {
      if (topo.kind[v] != VertexKind::Boundary) continue;
      OpenFan f;
      if (inc.begin[v + 1] - inc.begin[v] > kMaxSlidingFan || !openFan(v, faces, inc, f)) {
        ++corners;
        continue;
      }
      const Vec3 in = pos[v] - pos[f.ring.back()], out = pos[f.ring.front()] - pos[v];
      const double li = in.Norm(), lo = out.Norm();
      if (!(li > 0 && lo > 0) || !(in * out >= cosCorner * li * lo)) {
        ++corners;
        continue;
      }
      if (p.selectedOnly && !selected[v]) continue;
      slot[v] = static_cast<int>(candidates.size());
      candidates.push_back(v);
      all.push_back(std::move(f));
    }
    vertex = candidates;
    fan = all;
    path.resize(vertex.size());
    for (std::size_t s = 0; s < vertex.size(); ++s) {
      const int v = vertex[s], prev = fan[s].ring.back(), next = fan[s].ring.front();
      // The neighbours' own border neighbours, when those slide too.
      const int prev2 = slot[prev] >= 0 ? fan[slot[prev]].ring.back() : prev;
      const int next2 = slot[next] >= 0 ? fan[slot[next]].ring.front() : next;
      path[s] = Path{pos[prev2], pos[prev], pos[v], pos[next], pos[next2]};
    }
    preparePatches(topo, inc);
  }

  /// The deviation patch of each sliding vertex: its input faces and those
  /// around its input neighbours (a neighbour with more than kMaxPatchStar
  /// faces gives none: a smaller patch only makes the guard stricter).
  void preparePatches(const RingTopology& topo, const IncidentFaces& inc) {
    constexpr int kMaxPatchStar = 64;
    patchBegin.assign(1, 0);
    patch.clear();
    std::vector<int> mine;
    for (std::size_t s = 0; s < vertex.size(); ++s) {
      mine.clear();
      const int v = vertex[s];
      for (int k = inc.begin[v]; k < inc.begin[v + 1]; ++k) mine.push_back(inc.face[k]);
      for (int u : fan[s].ring) {
        if (topo.kind[u] != VertexKind::Interior && topo.kind[u] != VertexKind::Boundary) continue;
        if (inc.begin[u + 1] - inc.begin[u] > kMaxPatchStar) continue;
        for (int k = inc.begin[u]; k < inc.begin[u + 1]; ++k) mine.push_back(inc.face[k]);
      }
      std::sort(mine.begin(), mine.end());
      mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
      patch.insert(patch.end(), mine.begin(), mine.end());
      patchBegin.push_back(static_cast<int>(patch.size()));
    }
  }

  /// After flips: the open fans of the current faces (border edges never
  /// flip, so every sliding vertex keeps one open fan and its border).
  void rebuildFans(const FaceList& faces, int nv) {
    const IncidentFaces inc(faces, nv);
    for (std::size_t s = 0; s < vertex.size(); ++s) openFan(vertex[s], faces, inc, fan[s]);
  }

  /// The parameter of the vertex itself on its path (see pointAt): the
  /// length of the path's first two segments.
  double startArc(std::size_t s) const {
    const Path& P = path[s];
    return (P[1] - P[0]).Norm() + (P[2] - P[1]).Norm();
  }

  /// The point of path s at parameter a, the length along the polyline from
  /// its first point (clamped to its ends), on the cubic Hermite curve
  /// through the path's points with finite-difference tangents: a border
  /// sampled from a smooth curve keeps nearly its length when its vertices
  /// slide along it, where sliding along the polyline cuts every corner
  /// (on aneurysm_open, 0.16 % of the border length in 20 sweeps). Where a
  /// coordinate is the same at the segment's ends and tangents, it is taken
  /// as is, so that a straight border along an axis stays exactly on it.
  Vec3 pointAt(std::size_t s, double a) const {
    const Path& P = path[s];
    double len[4];
    for (int k = 0; k < 4; ++k) len[k] = (P[k + 1] - P[k]).Norm();
    // Unit-length tangent at point k, from its neighbours along the path.
    const auto tangent = [&](int k) {
      const int lo = k > 0 && len[k - 1] > 0 ? k - 1 : k, hi = k < 4 && len[k] > 0 ? k + 1 : k;
      const double l = (lo < k ? len[k - 1] : 0) + (hi > k ? len[k] : 0);
      return l > 0 ? (P[hi] - P[lo]) / l : Vec3(0, 0, 0);
    };
    if (!(a > 0)) return P[0];
    for (int k = 0; k < 4; ++k) {
      if (!(a <= len[k] && len[k] > 0)) {
        a -= len[k];
        continue;
      }
      const double t = a / len[k], t2 = t * t, t3 = t2 * t;
      const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = 3 * t2 - 2 * t3, h11 = t3 - t2;
      const Vec3 m0 = tangent(k) * len[k], m1 = tangent(k + 1) * len[k];
      Vec3 y;
      for (int j = 0; j < 3; ++j)
        y[j] = P[k][j] == P[k + 1][j] && m0[j] == 0 && m1[j] == 0
                   ? P[k][j]
                   : h00 * P[k][j] + h10 * m0[j] + h01 * P[k + 1][j] + h11 * m1[j];
      return y;
    }
    return P[4];
  }
};

/// The star of a sliding vertex: its centre, the open fan's ring (one more
/// vertex than faces) and the input normals of the fan's faces.
struct OpenStar {
  Vec3 center;
  std::vector<Vec3> ring;
  std::vector<Vec3> refNormal;  ///< per face; empty without a guard
  std::size_t faces() const { return ring.size() - 1; }
};

/// The S-ODT energy of Eq. 5 over the open fan as a quadratic relative to
/// the centre (as sodtQuadratic, summing over the fan's faces only). Exact
/// on every line whose direction is orthogonal to (last - first) x n: the
/// cubic term -2 |p|^2 p.W of an open fan, W = sum_k e_k x n = (ring.back()
/// - ring.front()) x n, vanishes there, and the border direction
/// (front - back) is such a line.
inline StarQuadratic openFanQuadratic(const OpenStar& st, const Vec3& n) {
  return fanQuadratic(st.center, st.faces(), [&st](std::size_t k) -> const Vec3& { return st.ring[k]; }, n);
}

/// The unit normal of the open fan (the normalised sum of its faces' area
/// vectors), or zero.
inline Vec3 openFanNormal(const OpenStar& st) {
  Vec3 sum(0, 0, 0);
  for (std::size_t k = 0; k < st.faces(); ++k) sum += (st.ring[k] - st.center) ^ (st.ring[k + 1] - st.center);
  const double len = sum.Norm();
  return len > 0 && std::isfinite(len) ? sum / len : Vec3(0, 0, 0);
}

/// Where a sliding vertex wants to go along the border direction e (unit,
/// from the previous border neighbour to the next): the signed distance d
/// of the minimiser of Eq. 5 on the line centre + d e (false when the open
/// fan's energy is not convex along it), and of the fallback, the midpoint
/// of the two border neighbours (the border's own Laplacian).
inline bool borderSteps(const OpenStar& st, Algorithm a, Vec3& e, double& d, double& fallback) {
  const Vec3 chord = st.ring.front() - st.ring.back();
  const double len = chord.Norm();
  const Vec3 n = openFanNormal(st);
  if (!(len > 0) || n.SquaredNorm() == 0) return false;
  e = chord / len;
  fallback = ((st.ring.front() + st.ring.back()) * 0.5 - st.center) * e;
  if (a == Algorithm::Laplacian) {
    d = fallback;
    return std::isfinite(d);
  }
  Vec3 p;
  if (!minimizeOnLine(openFanQuadratic(st, n), Vec3(0, 0, 0), e, p)) return false;
  d = p * e;
  return std::isfinite(d) && std::isfinite(fallback);
}

/// The fold and angle guard of moveAllowed for an open fan: moving the
/// centre to y may not flip a face against its area vector now (against n
/// for a face degenerate now) or its input normal, nor collapse one, nor
/// (quality) give one a smaller smallest angle than cos2Limit's.
inline bool openFanAllows(const OpenStar& st, const Vec3& y, const Vec3& n, bool quality, double cos2Limit) {
  const bool haveRef = st.refNormal.size() == st.faces();
  for (std::size_t k = 0; k < st.faces(); ++k) {
    const Vec3 &a = st.ring[k], &b = st.ring[k + 1];
    const Vec3 now = (a - st.center) ^ (b - st.center);
    const double l2now =
        std::max({(a - st.center).SquaredNorm(), (b - st.center).SquaredNorm(), (b - a).SquaredNorm()});
    const Vec3 cur = now.Norm() > kCollapse * l2now ? now : n;
    const Vec3 next = (a - y) ^ (b - y);
    if (!(next * cur > 0) || (haveRef && next * st.refNormal[k] < 0)) return false;
    const double l2 = std::max({(a - y).SquaredNorm(), (b - y).SquaredNorm(), (b - a).SquaredNorm()});
    if (!(next.SquaredNorm() > kCollapse * kCollapse * l2 * l2)) return false;
    if (quality && triangleMinAngleCos2(y, a, b) > cos2Limit) return false;
  }
  return true;
}

/// The largest squared cosine of a smallest angle over the open fan's faces
/// with the centre at y (see triangleMinAngleCos2).
inline double openFanMinAngleCos2(const OpenStar& st, const Vec3& y) {
  double c = 0;
  for (std::size_t k = 0; k < st.faces(); ++k) c = std::max(c, triangleMinAngleCos2(y, st.ring[k], st.ring[k + 1]));
  return c;
}

/// The deviation guard of a sliding vertex at y: y, the centroids of its
/// fan's faces and the midpoints of its edges lie within the bound of
/// its input patch (BoundarySlide::patch), as keeps() asks of interior
/// vertices (without remembered margins: border vertices are few).
inline bool openFanKeeps(const InputSurface& in, const BoundarySlide& b, std::size_t s, const OpenStar& st,
                         const Vec3& y, long long& queried) {
  const auto near = [&](const Vec3& q) {
    ++queried;
    for (int k = b.patchBegin[s]; k < b.patchBegin[s + 1]; ++k)
      if (in.nearFace(b.patch[k], q)) return true;
    return false;
  };
  if (!near(y)) return false;
  for (std::size_t k = 0; k < st.ring.size(); ++k) {
    if (!near((y + st.ring[k]) * 0.5)) return false;
    if (k < st.faces() && !near((y + st.ring[k] + st.ring[k + 1]) / 3.0)) return false;
  }
  return true;
}

/// One visit of sliding vertex s (BoundarySlide::vertex[s]), the centre of
/// st, at x, on a mesh that stores coordinates as Scalar: the border step
/// (borderSteps) taken along the curve through the input border
/// (BoundarySlide::pointAt; arc is the vertex's parameter there, updated
/// with the move), so the vertex never leaves the input border, shortened by halvings under the guards of an
/// interior visit (fold, quality, reach, deviation both ways), else the fallback step
/// likewise. Scalar code only: the same result with and without the lane
/// kernel.
template <class Scalar>
Outcome slideVisit(const VisitContext& c, const BoundarySlide& b, std::size_t s, const OpenStar& st, Vec3& x,
                   double& arc, long long& queried) {
  const SodtParams& p = c.move.p;
  Vec3 e;
  double d = 0, fallback = 0;
  if (!borderSteps(st, p.algorithm, e, d, fallback)) return Outcome::Failed;
  const double a0 = arc;
  if (p.guard == Guard::None) {
    const Outcome o = GuardedMove<Scalar>::commitUnguarded(b.pointAt(s, a0 + d), x);
    if (moves(o)) arc = a0 + d;
    return o;
  }
  const Vec3 n = openFanNormal(st);
  const bool quality = p.guard == Guard::Quality;
  const double before = quality ? openFanMinAngleCos2(st, st.center) : 1.0;
  // The number of halvings used, -1 when every length was vetoed, -2 when
  // the step rounds to no move (as GuardedMove::tryStep).
  const auto tryArc = [&](double step) {
    double f = 1.0;
    for (int j = 0; j <= p.maxBacktracks; ++j, f *= 0.5) {
      const Vec3 y = GuardedMove<Scalar>::representable(b.pointAt(s, a0 + step * f));
      if (!isFinite(y)) continue;
      if (y == x) return j == 0 ? -2 : -1;
      if (!openFanAllows(st, y, n, quality, before)) continue;
      if (!withinReach(c, st.center, y, st.ring.size(), [&](std::size_t k) -> const Vec3& { return st.ring[k]; }))
        continue;
      if (c.input && !openFanKeeps(*c.input, b, s, st, y, queried)) continue;
      if (c.cover && !c.cover->coveredAfterMove(b.vertex[s], y, b.fan[s].faces)) continue;
      x = y;
      arc = a0 + step * f;
      return j;
    }
    return -1;
  };
  const int r = tryArc(d);
  if (r == 0) return Outcome::Moved;
  if (r > 0) return Outcome::Backtracked;
  if (p.laplacianFallback && tryArc(fallback) >= 0) return Outcome::Fallback;
  return r == -2 ? Outcome::Unchanged : Outcome::Rejected;
}

}  // namespace sodt
