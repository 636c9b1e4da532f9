// SPDX-License-Identifier: GPL-3.0-or-later
// The deviation guard: a moved vertex and the faces around it must stay close
// to the input surface near that vertex (its input one-ring faces and the
// faces of its neighbours' one-rings that lie around it).
#pragma once

#include "../maths/geometry.h"
#include "../maths/local_solve.h"
#include "../maths/topology.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace sodt {

/// The input mesh, read by index: the faces of vertex v's input one-ring and
/// of its neighbours' one-rings form the surface patch v must stay near.
/// From a neighbour u with more than kPatchWindow faces around it, the patch
/// takes the kPatchWindow faces of u's star centred on the edge uv (those
/// beside v around u), not all of them: a vertex next to one of valence
/// 100000 would otherwise search 100000 faces per rejected point, and a
/// sweep would cost the square of that valence. A smaller patch only makes
/// the guard stricter (the distance to fewer faces is never smaller), and
/// stars of up to kPatchWindow faces, nearly every star of a mesh, are
/// taken whole. The patch of v then has at most (kPatchWindow + 1) times
/// v's valence faces. Nothing is copied per visit; the structures must
/// outlive this view.
struct InputSurface {
  /// The most faces of a neighbour's star in a vertex's patch (even).
  static constexpr int kPatchWindow = 32;

  const FaceList* faces = nullptr;
  const RingTopology* topo = nullptr;
  const std::vector<Vec3>* pos = nullptr;
  double limit = 0;  ///< distance bound
  double limit2 = 0;  ///< its square

  /// Per face: an upper bound of the distance from its first corner to its
  /// other two, so that far faces are skipped without the exact distance.
  std::vector<float> reach;

  /// Per ring entry k of an interior vertex v (see RingTopology), the index
  /// j into the ring of u = ringIdx[k] with ringIdx[j] == v, when u is
  /// interior and its star has more than kPatchWindow faces; -1 otherwise.
  /// Empty when no star has more than kPatchWindow faces.
  std::vector<int> mirror;

  /// The margin of every checked point of the input itself (see Margins):
  /// the vertices are corners of their own patches and the centroids and
  /// edge midpoints of their star triangles lie on input faces, so their
  /// distance to the input is the rounding of their coordinates at most.
  /// Negative when that rounding is not small against the bound.
  float inputMargin = -1;

  /// Sets the bound and precomputes reach and inputMargin; faces, topo and
  /// pos must be set.
  void prepare(double distanceLimit) {
    limit = distanceLimit;
    limit2 = limit * limit;
    reach.assign(faces->tri.size(), 0.f);
    const std::vector<Vec3>& P = *pos;
    // A midpoint (a + b) * 0.5 and a centroid (a + b + c) / 3 computed in
    // double are off the exact point by a few units in the last place of
    // the largest coordinate per axis: 16 of them, on every axis, is ample.
    double largest = 0;
    for (const Vec3& q : P)
      for (int j = 0; j < 3; ++j) largest = std::max(largest, std::abs(q[j]));
    const double rounding = 16 * std::sqrt(3.0) * std::numeric_limits<double>::epsilon() * largest;
    inputMargin = rounding < limit ? floatBelow(limit - rounding) : -1.f;
    for (std::size_t f = 0; f < faces->tri.size(); ++f) {
      if (!faces->live[f]) continue;
      const std::array<int, 3>& t = faces->tri[f];
      const double r = std::sqrt(std::max((P[t[1]] - P[t[0]]).SquaredNorm(), (P[t[2]] - P[t[0]]).SquaredNorm()));
      // Rounded up to float, and a little more, so the bound stays an upper bound.
      reach[f] = static_cast<float>(r * (1 + 1e-6)) * (1 + 1e-6f);
    }
    setMirror();
  }

  /// Fills mirror in time linear in the ring entries: the entries pointing
  /// at a large star are bucketed by that star's centre, whose ring then
  /// gives each of them its position in one pass. Without a large star,
  /// mirror stays empty (and is never read).
  void setMirror() {
    const RingTopology& T = *topo;
    mirror.clear();
    if (T.ringBegin.empty()) return;
    const int nv = static_cast<int>(T.ringBegin.size()) - 1;
    const auto large = [&](int u) { return T.kind[u] == VertexKind::Interior && T.ringSize(u) > kPatchWindow; };
    std::vector<int> begin(nv + 1, 0);
    bool any = false;
    for (int v = 0; v < nv; ++v) {
      if (T.kind[v] != VertexKind::Interior) continue;
      for (int k = T.ringBegin[v]; k < T.ringBegin[v + 1]; ++k)
        if (large(T.ringIdx[k])) {
          ++begin[T.ringIdx[k] + 1];
          any = true;
        }
    }
    if (!any) return;
    mirror.assign(T.ringIdx.size(), -1);
    for (int u = 0; u < nv; ++u) begin[u + 1] += begin[u];
    // Per large star, the ring entries (k, owner v) that point at it.
    std::vector<std::pair<int, int>> entry(begin[nv]);
    std::vector<int> next(begin.begin(), begin.end() - 1);
    for (int v = 0; v < nv; ++v) {
      if (T.kind[v] != VertexKind::Interior) continue;
      for (int k = T.ringBegin[v]; k < T.ringBegin[v + 1]; ++k)
        if (large(T.ringIdx[k])) entry[next[T.ringIdx[k]]++] = {k, v};
    }
    std::vector<int> where(nv, -1);  // per vertex its position in the current star's ring
    for (int u = 0; u < nv; ++u) {
      if (begin[u] == begin[u + 1]) continue;
      for (int j = T.ringBegin[u + 1] - 1; j >= T.ringBegin[u]; --j) where[T.ringIdx[j]] = j;  // the first of repeats
      for (int e = begin[u]; e < begin[u + 1]; ++e) mirror[entry[e].first] = where[entry[e].second];
      for (int j = T.ringBegin[u]; j < T.ringBegin[u + 1]; ++j) where[T.ringIdx[j]] = -1;
    }
  }

  /// The cheap part of the face test: outside a ball around the face or
  /// farther than the bound from its plane (Far), or over the face within
  /// the bound of its plane (Near, *dist as for nearFace); Unsure otherwise.
  enum class Quick { Far, Near, Unsure };
  Quick quickTest(int f, const Vec3& q, double* dist) const {
    const std::array<int, 3>& t = faces->tri[f];
    const std::vector<Vec3>& P = *pos;
    const Vec3& a = P[t[0]];
    const Vec3 qa = q - a;
    const double r = reach[f] + limit;
    if (qa.SquaredNorm() > r * r) return Quick::Far;  // outside a ball holding the face and its margin
    const Vec3& b = P[t[1]];
    const Vec3& c = P[t[2]];
    const Vec3 ab = b - a, ac = c - a;
    const Vec3 n = ab ^ ac;
    const double nn = n.SquaredNorm();
    // The plane tests need a normal that is not made of rounding errors, as
    // that of a face with (nearly) collinear corners is.
    if (!(nn > 1e-12 * ab.SquaredNorm() * ac.SquaredNorm())) return Quick::Unsure;
    // Farther than the bound from the face's plane: farther from the face.
    const double h = qa * n;
    if (h * h > limit2 * nn) return Quick::Far;
    // Over the face (on the inner side of its three edges): the distance is
    // the plane distance, already within the bound. With e the edge and n
    // the normal, (e x (q - corner)) . n is |e| |n| times q's signed
    // distance from the edge's line within the plane.
    const Vec3 bc = c - b, ca = a - c;
    const double s[3] = {(ab ^ qa) * n, (bc ^ (q - b)) * n, (ca ^ (q - c)) * n};
    if (s[0] >= 0 && s[1] >= 0 && s[2] >= 0) {
      if (dist) *dist = std::abs(h) / std::sqrt(nn) + 1e-9 * r;
      return Quick::Near;
    }
    // Farther than the bound outside an edge's line: farther from the face.
    const Vec3* edge[3] = {&ab, &bc, &ca};
    for (int i = 0; i < 3; ++i)
      if (s[i] < 0 && s[i] * s[i] > limit2 * edge[i]->SquaredNorm() * nn * (1 + 1e-9)) return Quick::Far;
    return Quick::Unsure;
  }

  /// The exact face test, by the closest point of the face.
  bool exactTest(int f, const Vec3& q, double* dist) const {
    const std::array<int, 3>& t = faces->tri[f];
    const std::vector<Vec3>& P = *pos;
    const double d2 = pointTriangleDistance2(q, P[t[0]], P[t[1]], P[t[2]]);
    if (!(d2 <= limit2)) return false;
    if (dist) *dist = std::sqrt(d2) + 1e-9 * (reach[f] + limit);
    return true;
  }

  /// True when q lies within the bound of input face f; then *dist (when
  /// not null) gets an upper bound of q's distance to f (exceeding it by
  /// about 1e-9 of the face's size at most).
  bool nearFace(int f, const Vec3& q, double* dist = nullptr) const {
    const Quick r = quickTest(f, q, dist);
    return r == Quick::Unsure ? exactTest(f, q, dist) : r == Quick::Near;
  }

  /// A face of v's input patch within sqrt(limit2) of q, or -1 when there is
  /// none; *dist as for nearFace. The face hints (-1 for none) are tried
  /// first, both by the cheap test before either by the exact one (an edge
  /// midpoint is usually over one of the two faces beside its edge), then
  /// the patch, v's own faces from face *cursor of its input star on (0
  /// without a cursor); *cursor is set to the own face found. Points taken
  /// around a star in order lie over its faces in order, so that with a
  /// cursor kept between them the search around a vertex of valence N costs
  /// N steps in all, not N per point. Whether a face is found does not
  /// depend on the hints or the cursor, only the time does.
  int nearFaceOf(int v, const Vec3& q, int hint, int hint2 = -1, double* dist = nullptr, int* cursor = nullptr) const {
    if (hint2 == hint) hint2 = -1;
    const Quick r1 = hint >= 0 ? quickTest(hint, q, dist) : Quick::Far;
    if (r1 == Quick::Near) return hint;
    const Quick r2 = hint2 >= 0 ? quickTest(hint2, q, dist) : Quick::Far;
    if (r2 == Quick::Near) return hint2;
    if (r1 == Quick::Unsure && exactTest(hint, q, dist)) return hint;
    if (r2 == Quick::Unsure && exactTest(hint2, q, dist)) return hint2;
    int found = -1;
    forEachPatchFace(
        v,
        [&](int f, int at) {
          if (f == hint || f == hint2 || !nearFace(f, q, dist)) return false;
          found = f;
          if (cursor && at >= 0) *cursor = at;
          return true;
        },
        cursor ? *cursor : 0);
    return found;
  }

  /// Calls visit(f, at) for each face f of interior vertex v's patch (see
  /// InputSurface) until visit returns true; true then. First v's own
  /// faces, from face start of its input star on (modulo the star's size),
  /// with at their position in the star; then the others, with at = -1. A
  /// face in two neighbours' windows may be visited twice.
  template <class Visit>
  bool forEachPatchFace(int v, Visit&& visit, int start = 0) const {
    const RingTopology& T = *topo;
    const int b = T.ringBegin[v], e = T.ringBegin[v + 1];
    const int n = e - b;
    const int s = n > 0 ? (start % n + n) % n : 0;
    for (int c = 0, at = s; c < n; ++c, at = at + 1 < n ? at + 1 : 0)
      if (visit(T.ringFace[b + at], at)) return true;
    for (int k = b; k < e; ++k) {
      const int u = T.ringIdx[k];
      if (T.kind[u] != VertexKind::Interior) continue;
      const int ub = T.ringBegin[u], n = T.ringBegin[u + 1] - ub;
      // The whole star, or the window of faces around the edge uv: faces
      // at - w .. at + w - 1 of u's ring with w = kPatchWindow / 2, where
      // faces at - 1 and at are the two with v in them.
      int first = 0, count = n;
      if (n > kPatchWindow && mirror[k] >= 0) {
        first = mirror[k] - ub - kPatchWindow / 2;
        count = kPatchWindow;
      }
      for (int c = 0; c < count; ++c) {
        const int rel = ((first + c) % n + n) % n;
        const int j = ub + rel;
        // Face j of u's star is (u, ring j, ring j + 1): one with v in it
        // is one of v's own faces, visited above.
        if (T.ringIdx[j] == v || T.ringIdx[rel + 1 < n ? j + 1 : ub] == v) continue;
        if (visit(T.ringFace[j], -1)) return true;
      }
    }
    return false;
  }

  /// True when q lies within sqrt(limit2) of a face of v's input patch.
  bool near(int v, const Vec3& q, int hint, double* dist = nullptr) const {
    return nearFaceOf(v, q, hint, -1, dist) >= 0;
  }

  /// Margins left inside the bound by a vertex's last accepted move, from
  /// which keeps() answers without distance queries: for the
  /// vertex itself, and per star triangle k for its centroid and the
  /// midpoint of the edge to ring vertex k (the smaller of the two).
  /// Negative: none. Stored rounded down, so they stay lower bounds.
  struct Margins {
    float point = -1;
    float* slot = nullptr;  ///< star-size entries
  };

  /// A float below x (by about 1e-6 of it), so that a stored margin stays a
  /// lower bound; the largest float above that range, minus infinity below
  /// it (and NaN for NaN).
  static float floatBelow(double x) {
    const double y = x > 0 ? x * (1 - 1e-6) : x * (1 + 1e-6) - 1e-30;
    if (y >= std::numeric_limits<float>::max()) return std::numeric_limits<float>::max();
    if (y <= -std::numeric_limits<float>::max()) return -std::numeric_limits<float>::infinity();
    return static_cast<float>(y);
  }

  /// How far the centroid of star triangle k and the midpoint of its edge
  /// to ring vertex k can have moved since the margins were taken, the
  /// larger of the two (see keeps); k1 is the triangle after k.
  static double slotMove(double step, const double* drift, std::size_t k, std::size_t k1) {
    return std::max((step + drift[k]) / 2, (step + drift[k] + drift[k1]) / 3);
  }

  /// keeps' answer for vertex v with a star of n triangles when the margins
  /// answer every point without a distance query: then true, with next and
  /// reused as keeps sets them. False when some point would need a query
  /// (next may be partly written then).
  bool keepsByMargins(int v, std::size_t n, double step, const double* drift, const Margins& last, Margins& next,
                      long long& reused) const {
    if (topo->kind[v] != VertexKind::Interior) return false;  // keeps answers those in no time
    if (!(step <= last.point)) return false;
    for (std::size_t k = 0; k < n; ++k) {
      const double moved = slotMove(step, drift, k, k + 1 < n ? k + 1 : 0);
      if (!(moved <= last.slot[k])) return false;
      next.slot[k] = floatBelow(last.slot[k] - moved);
    }
    next.point = floatBelow(last.point - step);
    reused += 1 + 2 * static_cast<long long>(n);
    return true;
  }

  /// True when, with vertex v (the centre of st) at p, p and the centroids
  /// and edge midpoints of the star's triangles at p lie within
  /// sqrt(limit2) of v's input patch. Where the input is locally flat, the
  /// distance to it is convex and the farthest point of a star triangle is
  /// one of its corners; the centroids and midpoints catch triangles and
  /// edges that cut across a crease or a bend. A vertex that is not interior
  /// in the input is not restricted.
  ///
  /// hints, when not null, gives per star triangle an input face to try
  /// first for its centroid (-1 for none), and is set to the face found
  /// there; the midpoint of the edge to ring vertex k tries the faces of
  /// triangles k and k - 1 first. pointHint does the same for p. Hints only
  /// save time: any input face index (or -1) gives the same answer.
  ///
  /// last holds the margins of the vertex's last accepted move (or none):
  /// the distance to the input is 1-Lipschitz; since that move the vertex
  /// moves by step and ring vertex k has moved by at most drift[k], so the
  /// midpoint to ring vertex k moves by (step + drift[k]) / 2 and the
  /// centroid of star triangle k by (step + drift[k] + drift[k + 1]) / 3. A
  /// point whose margin covers its movement is within the bound without a
  /// distance query; the others are queried. The answer does not depend on
  /// the margins. After a true answer, next holds the margins of the new
  /// position (next.slot must have star-size entries). Adds the points it
  /// queried and those it answered from the margins to the counts.
  bool keeps(int v, const Star& st, const Vec3& p, int* hints, int& pointHint, double step,
             const double* drift, const Margins& last, Margins& next, long long& queried, long long& reused) const {
    const std::size_t n = st.size();
    if (topo->kind[v] != VertexKind::Interior) {  // unrestricted
      next.point = -1;
      std::fill(next.slot, next.slot + n, -1.f);
      return true;
    }
    double d = 0;
    int cursor = 0;  // see nearFaceOf
    if (step <= last.point) {
      ++reused;
      next.point = floatBelow(last.point - step);
    } else {
      ++queried;
      const int f = nearFaceOf(v, p, pointHint >= 0 ? pointHint : (hints ? hints[0] : -1), -1, &d, &cursor);
      if (f < 0) return false;
      pointHint = f;
      next.point = floatBelow(limit - d);
    }
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t k1 = k + 1 < n ? k + 1 : 0;
      const double moved = slotMove(step, drift, k, k1);
      if (moved <= last.slot[k]) {
        reused += 2;
        next.slot[k] = floatBelow(last.slot[k] - moved);
        continue;
      }
      queried += 2;
      double dc = 0, dm = 0;
      const int fc = nearFaceOf(v, (p + st.ring[k] + st.at(k + 1)) / 3.0, hints ? hints[k] : -1, -1, &dc, &cursor);
      if (fc < 0) return false;
      if (hints) hints[k] = fc;
      const int before = hints ? hints[k == 0 ? n - 1 : k - 1] : -1;
      if (nearFaceOf(v, (p + st.ring[k]) * 0.5, fc, before, &dm, &cursor) < 0) return false;
      next.slot[k] = floatBelow(limit - std::max(dc, dm));
    }
    return true;
  }
};

}  // namespace sodt
