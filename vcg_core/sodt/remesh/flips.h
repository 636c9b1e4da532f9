// SPDX-License-Identifier: GPL-3.0-or-later
// Edge flips that run between S-ODT sweeps: an interior edge between two nearly
// coplanar triangles is flipped when that raises the smaller angle of the pair.
#pragma once

#include "../guards/cover.h"
#include "../guards/deviation.h"
#include "../maths/geometry.h"
#include "../maths/local_solve.h"
#include "../params.h"
#include "../maths/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

namespace sodt {

/// Smallest interior angle of the two triangles, in radians.
inline double pairMinAngle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e,
                           const Vec3& f) {
  return std::min(triangleMinAngle(a, b, c), triangleMinAngle(d, e, f));
}

/// An edge between two feature vertices runs along the crease when it lies
/// within this angle of the crease direction e3 of a crease end: wide enough
/// for the zigzag of a crease across a coarse mesh, narrow enough to let
/// the slivers that cross a flat face from one feature line to another flip.
constexpr double kCreaseEdgeMaxDeg = 30.0;

/// Options of a flip pass.
struct FlipRules {
  /// Only flip edges whose faces' normals differ by less (default: SodtParams).
  double maxDihedralRad = SodtParams{}.flipMaxDihedralDeg * kPi / 180.0;
  /// Per vertex, may be null: with it, the feature edges along creases are
  /// kept (see featureEdge).
  const std::vector<VertexClass>* cls = nullptr;
  /// Per vertex, the unit crease direction e3 of the Crease vertices of cls
  /// (Classification::creaseDir). Null: every edge between two crease or
  /// corner vertices counts as a feature edge.
  const std::vector<Vec3>* creaseDir = nullptr;
  double minGainRad = 1e-9;                       ///< a flip must raise the pair's min angle by more
  /// Deviation guard (may be null): the new edge and faces must stay within
  /// the bound of the input surface, like the vertex moves.
  const InputSurface* input = nullptr;
  /// The other direction (with input; may be null): the input points the
  /// pair covers must stay within the bound of the new faces.
  InputCover* cover = nullptr;
  /// Turn guard (with a refNormal): each new face must keep within the
  /// angle of maxTurnCos2 (Star::maxTurnCos2; 0: 90 degrees) of the pair's
  /// merged input normal, which it takes as its own, like a moved face of
  /// its input normal. Off without a bound (Guard::None, Denoise, 90 degrees).
  bool keepTurn = false;
  double maxTurnCos2 = 0;
};

/// True when the surface made by flipping a-b into c-d stays within input's
/// bound: the midpoint of c-d, the point of c-d closest to the old edge a-b
/// (where the pair's two surfaces lie farthest apart) and the centroids of
/// the new faces must each lie near the input patch of one of a, b, c, d.
inline bool flipKeepsInput(const InputSurface& in, const std::vector<Vec3>& pos, int a, int b, int c, int d) {
  const int vs[4] = {c, d, a, b};
  bool any = false;
  for (int v : vs) any = any || in.topo->kind[v] == VertexKind::Interior;
  if (!any) return true;
  // Closest point of segment c-d to line a-b.
  const Vec3 u = pos[d] - pos[c], w = pos[b] - pos[a], r = pos[c] - pos[a];
  const double uu = u * u, uw = u * w, ww = w * w, ur = u * r, wr = w * r;
  const double den = uu * ww - uw * uw;
  double t = den > 0 ? (uw * wr - ww * ur) / den : 0.5;
  t = std::min(1.0, std::max(0.0, t));
  const Vec3 pts[4] = {(pos[c] + pos[d]) * 0.5, pos[c] + u * t, (pos[a] + pos[d] + pos[c]) / 3.0,
                       (pos[d] + pos[b] + pos[c]) / 3.0};
  for (const Vec3& q : pts) {
    bool ok = false;
    for (int v : vs)
      if (in.topo->kind[v] == VertexKind::Interior && in.near(v, q, -1)) { ok = true; break; }
    if (!ok) return false;
  }
  return true;
}

/// True when the edge v-o follows the crease through v: it lies within
/// kCreaseEdgeMaxDeg of dir, v's crease direction, and no other neighbour
/// of v on the same side of v (along dir) is better aligned with dir. The
/// second test tells the crease's own edge from a flat edge nearly
/// parallel to it, such as the long edge of a sliver spanning a flat face
/// between two parallel feature lines. True for a zero dir or a
/// zero-length edge (the safe side). around: see featureEdge.
template <class Around>
bool alongCrease(const std::vector<Vec3>& pos, int v, int o, const Vec3& dir, const Around& around) {
  const double c = std::cos(kCreaseEdgeMaxDeg * kPi / 180.0);
  const Vec3 e = pos[o] - pos[v];
  const double ee = e.SquaredNorm(), dd = dir.SquaredNorm(), ed = e * dir;
  if (!(ee > 0) || !(dd > 0)) return true;
  // |cos(e, dir)| >= c, without a square root.
  if (ed * ed < c * c * ee * dd) return false;
  bool best = true;
  around(v, [&](int u) {
    if (u == o || !best) return;
    const Vec3 w = pos[u] - pos[v];
    const double wd = w * dir, ww = w.SquaredNorm();
    // Same side, and cos^2(w, dir) > cos^2(e, dir).
    if (wd * ed > 0 && wd * wd * ee > ed * ed * ww) best = false;
  });
  return best;
}

/// True when the edge a-b runs along a crease, as classified: both ends
/// are crease or corner vertices, and the edge lies within
/// kCreaseEdgeMaxDeg of the crease direction of a crease end (of either:
/// near a corner or where two creases meet, one end following its crease
/// is enough to keep the edge, the safe side) and is the edge of that end
/// best aligned with its crease on its side (alongCrease). A corner
/// has no direction, so an edge between two corners always counts (with
/// no way to tell the feature edge that joins two corners from one across
/// a face, it is kept, as flips always did); a corner-crease edge counts
/// when it follows the crease end. A crease end without a direction (zero
/// e3, or no creaseDir at all) and a zero-length edge count too.
///
/// around(v, visit) calls visit(u) for every neighbour u of v.
template <class Around>
bool featureEdge(const FlipRules& rules, const std::vector<Vec3>& pos, int a, int b, const Around& around) {
  if (!rules.cls) return false;
  const VertexClass ca = (*rules.cls)[a], cb = (*rules.cls)[b];
  const auto feature = [](VertexClass c) { return c == VertexClass::Crease || c == VertexClass::Corner; };
  if (!feature(ca) || !feature(cb)) return false;
  if (!rules.creaseDir || (ca == VertexClass::Corner && cb == VertexClass::Corner)) return true;
  for (int v : {a, b})
    if ((*rules.cls)[v] == VertexClass::Crease && alongCrease(pos, v, v == a ? b : a, (*rules.creaseDir)[v], around))
      return true;
  return false;
}

namespace detail {

/// Half-edge a -> b of face `face`, kept in the list of its start a.
struct FlipHalf {
  int to, face;
};

/// Upper bound of the rounding error of triangleMinAngleCos2 (a few units
/// in the last place of values at most 1), with a wide safety factor.
constexpr double kCos2Slack = 1e-12;

/// True when the pair's smallest angle certainly does not grow by more than
/// minGain: the squared cosines of the smallest angles before (faces t1, t2)
/// and after (u1, u2) show the angle falling by more than their rounding.
/// False says nothing (the exact test decides). Needs minGain >= 0, and
/// squared cosines from the trigonometric corner (dot > 0, lengths > 0): the
/// smallest angle of a triangle is the one opposite its shortest edge, which
/// both this and triangleMinAngle pick by the same comparisons.
inline bool flipCannotGain(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double minGain) {
  if (!(minGain >= 0)) return false;
  const double t1 = triangleMinAngleCos2(a, b, c), t2 = triangleMinAngleCos2(b, a, d);
  const double u1 = triangleMinAngleCos2(a, d, c), u2 = triangleMinAngleCos2(d, b, c);
  // 0 and 1 are also what degenerate corners give: no verdict from those.
  const auto plain = [](double x) { return x > 0 && x < 1; };
  if (!plain(t1) || !plain(t2) || !plain(u1) || !plain(u2)) return false;
  // cos^2 falls as the angle grows (angles below 90 degrees).
  return std::max(u1, u2) > std::max(t1, t2) + kCos2Slack;
}

}  // namespace detail

/// One pass over all interior edges; flips every edge that qualifies, at most
/// one edge per face per pass. An edge a-b shared by faces (a, b, c) and
/// (b, a, d) becomes c-d, with faces (a, d, c) and (d, b, c), when
/// - both faces are live and flippable, c != d, and the edge c-d does not exist;
/// - the faces' normals differ by less than rules.maxDihedralRad;
/// - a-b is not a feature edge along a crease (featureEdge);
/// - both new faces keep the orientation of the pair (no fold);
/// - with rules.keepTurn and a refNormal, both new faces keep within the
///   turn of rules.maxTurnCos2 of the merged input normal (see below);
/// - the smallest angle of the pair grows by more than rules.minGainRad.
/// Edges are taken in the order of (a, b) with a < b, and what a flip changes
/// (the two faces it made, the edge c-d it made) is seen by the edges after
/// it in the same pass: the flips of a pass depend on that order.
/// refNormal (per face, may be empty) is updated for the two new faces: both
/// get the normalised sum of the two old faces' (zero when it vanishes).
/// flipped (may be null) gets a, b, c, d of every flip appended.
///
/// seed (per vertex, may be null) limits the pass to the edges with a seed
/// among a, b, c, d. Seeded with the vertices of the flips of the pass
/// before, on the same positions, it flips what a whole pass would: an edge
/// that pass did not flip, with neither face made by it nor c-d flipped away
/// by it, is judged the same again (its faces, the vertices, the existing
/// edges that block it and the positions are all unchanged), and every edge
/// that a flip changed in one of those ways has a flipped vertex among a, b,
/// c, d.
/// \return the number of flips.
inline int flipPass(FaceList& faces, const std::vector<Vec3>& pos, const FlipRules& rules,
                    std::vector<Vec3>* refNormal = nullptr, std::vector<int>* flipped = nullptr,
                    const std::vector<char>* seed = nullptr) {
  using detail::FlipHalf;
  const int nv = static_cast<int>(pos.size());
  // The half-edges grouped by their start, each group sorted by end: a
  // counting sort over the starts (no global sort, O(1) lookups by start).
  std::vector<int> begin(nv + 1, 0);
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    for (int v : faces.tri[f]) ++begin[v + 1];
  }
  for (int v = 0; v < nv; ++v) begin[v + 1] += begin[v];
  std::vector<FlipHalf> half(begin[nv]);
  {
    std::vector<int> fill(begin.begin(), begin.end() - 1);
    for (std::size_t f = 0; f < faces.tri.size(); ++f) {
      if (!faces.live[f]) continue;
      const auto& t = faces.tri[f];
      for (int j = 0; j < 3; ++j) half[fill[t[j]]++] = {t[(j + 1) % 3], static_cast<int>(f)};
    }
  }
  const auto byEnd = [](const FlipHalf& x, const FlipHalf& y) { return x.to < y.to; };
  for (int v = 0; v < nv; ++v) {
    FlipHalf* lo = half.data() + begin[v];
    FlipHalf* hi = half.data() + begin[v + 1];
    if (hi - lo <= 16) {
      for (FlipHalf* i = lo + 1; i < hi; ++i)  // insertion sort: groups are a valence long
        for (FlipHalf* j = i; j > lo && byEnd(*j, *(j - 1)); --j) std::swap(*j, *(j - 1));
    } else {
      std::sort(lo, hi, byEnd);
    }
  }
  // The half-edges a -> b of the list (several for a non-manifold edge).
  const auto range = [&](int a, int b) {
    return std::equal_range(half.data() + begin[a], half.data() + begin[a + 1], FlipHalf{b, -1}, byEnd);
  };
  const auto exists = [&](int a, int b) {
    const auto r = range(a, b);
    return r.first != r.second;
  };
  auto third = [&faces](int f, int a, int b) {
    for (int v : faces.tri[f])
      if (v != a && v != b) return v;
    return -1;
  };
  const double cosMax = std::cos(rules.maxDihedralRad);
  std::vector<char> touched(faces.tri.size(), 0);
  std::set<std::pair<int, int>> created;  // edges made by this pass (the grouped list is stale for them)
  int flips = 0;
  for (int a = 0; a < nv; ++a) {
    for (int h = begin[a]; h < begin[a + 1]; ++h) {
      const int b = half[h].to, f1 = half[h].face;
      if (a > b) continue;  // each edge once, from its lower end
      // Its faces must be untouched by this pass: the list still holds them.
      if (touched[f1] || !faces.flippable[f1]) continue;
      if ((h > begin[a] && half[h - 1].to == b) || (h + 1 < begin[a + 1] && half[h + 1].to == b))
        continue;  // a -> b in two faces: non-manifold
      const auto o = range(b, a);
      if (o.second - o.first != 1) continue;  // border or non-manifold edge
      const int f2 = o.first->face;
      if (f1 == f2 || touched[f2] || !faces.flippable[f2]) continue;
      const int c = third(f1, a, b), d = third(f2, a, b);
      if (c < 0 || d < 0 || c == d) continue;
      if (seed && !(*seed)[a] && !(*seed)[b] && !(*seed)[c] && !(*seed)[d]) continue;
      const Vec3 &pa = pos[a], &pb = pos[b], &pc = pos[c], &pd = pos[d];
      const Vec3 n1 = doubleAreaVector(pa, pb, pc), n2 = doubleAreaVector(pb, pa, pd);
      const double l1 = n1.Norm(), l2 = n2.Norm();
      if (!(l1 > 0) || !(l2 > 0) || !((n1 * n2) > cosMax * l1 * l2)) continue;
      const Vec3 m1 = doubleAreaVector(pa, pd, pc), m2 = doubleAreaVector(pd, pb, pc);
      const Vec3 pair = n1 / l1 + n2 / l2;
      if (!(m1 * pair > 0) || !(m2 * pair > 0)) continue;
      if (detail::flipCannotGain(pa, pb, pc, pd, rules.minGainRad)) continue;
      const double before = pairMinAngle(pa, pb, pc, pb, pa, pd);
      const double after = pairMinAngle(pa, pd, pc, pd, pb, pc);
      if (!(after > before + rules.minGainRad)) continue;
      if (exists(c, d) || exists(d, c) || created.count({std::min(c, d), std::max(c, d)})) continue;
      if (featureEdge(rules, pos, a, b, [&](int v, const auto& visit) {
            for (int k = begin[v]; k < begin[v + 1]; ++k) visit(half[k].to);
          }))
        continue;
      if (rules.input && !flipKeepsInput(*rules.input, pos, a, b, c, d)) continue;
      const bool haveRef = refNormal && !refNormal->empty();
      Vec3 merged(0, 0, 0);
      if (haveRef) {
        merged = (*refNormal)[f1] + (*refNormal)[f2];
        const double len = merged.Norm();
        merged = len > 0 ? merged / len : Vec3(0, 0, 0);
        // The moves' guard tests every face against its input normal: a
        // new face beyond the bound would freeze its vertices.
        if (rules.keepTurn &&
            (turnsBeyond(m1, merged, rules.maxTurnCos2) || turnsBeyond(m2, merged, rules.maxTurnCos2)))
          continue;
      }
      if (rules.cover && !rules.cover->coveredAfterFlip(f1, f2, {a, d, c}, {d, b, c})) continue;
      faces.tri[f1] = {a, d, c};
      faces.tri[f2] = {d, b, c};
      if (rules.cover) rules.cover->commitFlip(f1, f2);
      touched[f1] = touched[f2] = 1;
      created.insert({std::min(c, d), std::max(c, d)});
      if (haveRef) (*refNormal)[f1] = (*refNormal)[f2] = merged;
      if (flipped) flipped->insert(flipped->end(), {a, b, c, d});
      ++flips;
    }
  }
  return flips;
}

}  // namespace sodt
