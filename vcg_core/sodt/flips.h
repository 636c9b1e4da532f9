// SPDX-License-Identifier: GPL-3.0-or-later
// Edge flips that run between S-ODT sweeps: an interior edge between two nearly
// coplanar triangles is flipped when that raises the smaller angle of the pair.
#pragma once

#include "deviation.h"
#include "geometry.h"
#include "params.h"
#include "topology.h"

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

/// Options of a flip pass.
struct FlipRules {
  double maxDihedralRad = 20.0 * kPi / 180.0;  ///< only flip edges whose faces' normals differ by less
  const std::vector<VertexClass>* cls = nullptr;  ///< feature edges (both ends crease/corner) are kept
  double minGainRad = 1e-9;                       ///< a flip must raise the pair's min angle by more
  /// Deviation guard (may be null): the new edge and faces must stay within
  /// the bound of the input surface, like the vertex moves.
  const InputSurface* input = nullptr;
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

/// One pass over all interior edges; flips every edge that qualifies, at most
/// one edge per face per pass. An edge a-b shared by faces (a, b, c) and
/// (b, a, d) becomes c-d, with faces (a, d, c) and (d, b, c), when
/// - both faces are live and flippable, c != d, and the edge c-d does not exist;
/// - the faces' normals differ by less than rules.maxDihedralRad;
/// - a and b are not both crease/corner vertices (a feature edge);
/// - both new faces keep the orientation of the pair (no fold);
/// - the smallest angle of the pair grows by more than rules.minGainRad.
/// refNormal (per face, may be empty) is updated for the two new faces.
/// \return the number of flips.
inline int flipPass(FaceList& faces, const std::vector<Vec3>& pos, const FlipRules& rules,
                    std::vector<Vec3>* refNormal = nullptr) {
  struct HalfEdge {
    int a, b, face;
    bool operator<(const HalfEdge& o) const { return a < o.a || (a == o.a && b < o.b); }
  };
  std::vector<HalfEdge> he;
  he.reserve(faces.tri.size() * 3);
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    const auto& t = faces.tri[f];
    for (int j = 0; j < 3; ++j) he.push_back({t[j], t[(j + 1) % 3], static_cast<int>(f)});
  }
  std::sort(he.begin(), he.end());
  auto find = [&he](int a, int b) -> const HalfEdge* {
    auto it = std::lower_bound(he.begin(), he.end(), HalfEdge{a, b, -1});
    return (it != he.end() && it->a == a && it->b == b) ? &*it : nullptr;
  };
  auto multiplicity = [&he](int a, int b) {
    auto r = std::equal_range(he.begin(), he.end(), HalfEdge{a, b, -1});
    return static_cast<int>(r.second - r.first);
  };
  auto isFeature = [&rules](int v) {
    if (!rules.cls) return false;
    const VertexClass c = (*rules.cls)[v];
    return c == VertexClass::Crease || c == VertexClass::Corner;
  };
  auto third = [&faces](int f, int a, int b) {
    for (int v : faces.tri[f])
      if (v != a && v != b) return v;
    return -1;
  };
  const double cosMax = std::cos(rules.maxDihedralRad);
  std::vector<char> touched(faces.tri.size(), 0);
  std::set<std::pair<int, int>> created;  // edges made by this pass (the sorted list is stale for them)
  int flips = 0;
  for (const HalfEdge& e : he) {
    if (e.a > e.b) continue;  // each edge once, from its lower end
    const int f1 = e.face;
    if (multiplicity(e.a, e.b) != 1 || multiplicity(e.b, e.a) != 1) continue;  // border or non-manifold edge
    const HalfEdge* o = find(e.b, e.a);
    if (!o) continue;
    const int f2 = o->face;
    if (f1 == f2 || touched[f1] || touched[f2] || !faces.flippable[f1] || !faces.flippable[f2]) continue;
    const int a = e.a, b = e.b, c = third(f1, a, b), d = third(f2, a, b);
    if (c < 0 || d < 0 || c == d) continue;
    if (find(c, d) || find(d, c) || created.count({std::min(c, d), std::max(c, d)})) continue;  // exists already
    if (isFeature(a) && isFeature(b)) continue;
    const Vec3 n1 = doubleAreaVector(pos[a], pos[b], pos[c]), n2 = doubleAreaVector(pos[b], pos[a], pos[d]);
    const double l1 = n1.Norm(), l2 = n2.Norm();
    if (!(l1 > 0) || !(l2 > 0) || !((n1 * n2) > cosMax * l1 * l2)) continue;
    const Vec3 m1 = doubleAreaVector(pos[a], pos[d], pos[c]), m2 = doubleAreaVector(pos[d], pos[b], pos[c]);
    const Vec3 pair = n1 / l1 + n2 / l2;
    if (!(m1 * pair > 0) || !(m2 * pair > 0)) continue;
    const double before = pairMinAngle(pos[a], pos[b], pos[c], pos[b], pos[a], pos[d]);
    const double after = pairMinAngle(pos[a], pos[d], pos[c], pos[d], pos[b], pos[c]);
    if (!(after > before + rules.minGainRad)) continue;
    if (rules.input && !flipKeepsInput(*rules.input, pos, a, b, c, d)) continue;
    faces.tri[f1] = {a, d, c};
    faces.tri[f2] = {d, b, c};
    touched[f1] = touched[f2] = 1;
    created.insert({std::min(c, d), std::max(c, d)});
    if (refNormal && !refNormal->empty()) {
      Vec3 r = (*refNormal)[f1] + (*refNormal)[f2];
      const double len = r.Norm();
      r = len > 0 ? r / len : Vec3(0, 0, 0);
      (*refNormal)[f1] = (*refNormal)[f2] = r;
    }
    ++flips;
  }
  return flips;
}

}  // namespace sodt
