// SPDX-License-Identifier: GPL-3.0-or-later
// The input surface for local repair and for the measures of a mesh whose
// faces changed: a tree of its faces, answering "is q within r of the
// input?", "where is the input point closest to q?" and "which way does the
// input face under q face?". Unlike InputSurface (deviation.h), which reads
// the input by vertex index, it needs no correspondence between the input
// and the current mesh, so it still answers after vertices are added or
// removed.
#pragma once

#include "../maths/box_tree.h"
#include "../maths/geometry.h"
#include "../maths/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace sodt {

/// Closest point to p on triangle (a, b, c) (same regions as
/// pointTriangleDistance2).
inline Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab * ap, d2 = ac * ap;
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab * bp, d4 = ac * bp;
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab * cp, d6 = ac * cp;
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double den = va + vb + vc;
  if (!(den > 0)) {  // degenerate: the nearest of its corners is close enough for a projection target
    const double da = (p - a).SquaredNorm(), db = (p - b).SquaredNorm(), dc = (p - c).SquaredNorm();
    return da <= db && da <= dc ? a : db <= dc ? b : c;
  }
  return a + ab * (vb / den) + ac * (vc / den);
}

/// A copy of a triangle mesh's faces in a BoxTree, which answers in time
/// that does not grow with the valence of a vertex (a uniform grid holds
/// all n faces around a vertex of valence n in its cell, and every query
/// there would read them all). Queries on one object must not run
/// concurrently (within() remembers its last answers).
class InputGrid {
 public:
  /// Copies the live faces of faces over pos. faceNormal (per face of
  /// faces, or empty): the orientation under() answers for each face, a
  /// unit vector or zero for none; when empty, each face's own unit normal
  /// (zero for a face without area).
  InputGrid(const std::vector<Vec3>& pos, const FaceList& faces, const std::vector<Vec3>& faceNormal = {}) {
    double largest = 0;
    for (std::size_t f = 0; f < faces.tri.size(); ++f) {
      if (!faces.live[f]) continue;
      const auto& t = faces.tri[f];
      tri_.push_back({pos[t[0]], pos[t[1]], pos[t[2]]});
      if (faceNormal.empty()) {
        const Vec3 a = doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]);
        const double len = a.Norm();
        normal_.push_back(len > 0 && std::isfinite(len) ? a / len : Vec3(0, 0, 0));
      } else {
        normal_.push_back(faceNormal[f]);
      }
      for (int v : t)
        for (int k = 0; k < 3; ++k) largest = std::max(largest, std::abs(pos[v][k]));
    }
    tree_.build(static_cast<int>(tri_.size()), [this](int k, int j) { return tri_[k][j]; }, 1e-12 * largest);
    tie2_ = 1e-20 * largest * largest;
  }

  /// A query opens at most this many nodes of the tree (an ordinary one
  /// opens a few dozen). Only where hundreds of needles meet near q does it
  /// reach it; it then answers as if nothing were near, which refuses the
  /// change that asked (the callers' safe side), so that a vertex of
  /// valence n costs O(1) per query there, not O(n).
  static constexpr long kMaxNodes = 256;

  /// True when some input point lies within r of q (false also when the
  /// query gave up, see kMaxNodes).
  bool within(const Vec3& q, double r) const {
    // The triangles that answered the last queries answer most of the
    // next ones (a repair asks about a few points of one neighbourhood in
    // a row): tried first, they spare the walk down the tree. The answer
    // is the same either way.
    for (int t : recent_)
      if (t >= 0 && pointTriangleDistance2(q, tri_[t][0], tri_[t][1], tri_[t][2]) <= r * r) return true;
    int hit = -1;
    tree_.search(q, [r] { return r * r; }, [&](int t) {
      if (pointTriangleDistance2(q, tri_[t][0], tri_[t][1], tri_[t][2]) <= r * r) hit = t;
      return hit >= 0;
    }, kMaxNodes);
    if (hit < 0) return false;
    recent_[next_] = hit;
    next_ = (next_ + 1) % kRecent;
    return true;
  }

  /// The input point closest to q among those within r; false if none (or
  /// when the query gave up, see kMaxNodes).
  bool closest(const Vec3& q, double r, Vec3& out) const {
    double best = r * r;
    bool found = false;
    const bool complete = tree_.search(q, [&best] { return best; }, [&](int t) {
      const Vec3 c = closestPointOnTriangle(q, tri_[t][0], tri_[t][1], tri_[t][2]);
      const double d = (c - q).SquaredNorm();
      if (d <= best) best = d, out = c, found = true;
      return false;
    }, kMaxNodes);
    return found && complete;
  }

  /// Calls visit(k) for every input triangle k within r of q (its corners:
  /// triangle(k)). False when the query gave up after opening maxNodes
  /// nodes: the list is then incomplete.
  template <class Visit>
  bool forEachNear(const Vec3& q, double r, Visit&& visit, long maxNodes = kMaxNodes) const {
    const double r2 = r * r;
    return tree_.search(q, [r2] { return r2; }, [&](int t) {
      if (pointTriangleDistance2(q, tri_[t][0], tri_[t][1], tri_[t][2]) <= r2) visit(t);
      return false;
    }, maxNodes);
  }
  /// Calls visit(k) for every input triangle k whose box is within r of q:
  /// every triangle within r and some beyond, for a caller that measures
  /// them itself. Same limit as forEachNear.
  template <class Visit>
  bool forEachCandidate(const Vec3& q, double r, Visit&& visit, long maxNodes = kMaxNodes) const {
    const double r2 = r * r;
    return tree_.search(q, [r2] { return r2; }, [&](int t) {
      const auto& c = tri_[t];
      double d2 = 0;
      for (int i = 0; i < 3; ++i) {
        const double lo = std::min({c[0][i], c[1][i], c[2][i]}), hi = std::max({c[0][i], c[1][i], c[2][i]});
        const double out = q[i] < lo ? lo - q[i] : q[i] > hi ? q[i] - hi : 0.0;
        d2 += out * out;
      }
      if (d2 <= r2) visit(t);
      return false;
    }, maxNodes);
  }
  const std::array<Vec3, 3>& triangle(int k) const { return tri_[k]; }
  int size() const { return static_cast<int>(tri_.size()); }

  /// The input face under a point: the one nearest it. Where several are
  /// nearest (up to rounding: the point lies over their common edge or
  /// corner), the one whose orientation is best aligned with the face
  /// asking.
  struct Under {
    bool found = false;  ///< false: no face with an orientation within reach (or the query gave up)
    Vec3 normal;         ///< its orientation (unit)
    int face = -1;       ///< its position among the live faces the grid was made from
  };

  /// The input face under q (see Under) among those within reach of q
  /// (infinity for any distance); dir: the area vector of the face asking.
  /// Faces without orientation (zero normal) are passed over. Opens at most
  /// maxNodes nodes of the tree (see kMaxNodes);
  /// answers nothing found when it stops there. Safe to call concurrently.
  Under under(const Vec3& q, const Vec3& dir, double reach, long maxNodes = kMaxNodes) const {
    // The nearest distance, with a margin for the rounding of distances
    // that are equal in exact arithmetic.
    const auto window = [this](double d2) { return d2 + 1e-9 * d2 + tie2_; };
    double best = std::numeric_limits<double>::infinity();
    const double reach2 = reach * reach;
    std::vector<std::pair<double, int>> near;  // oriented faces within the window of best when seen
    const bool complete = tree_.search(q, [&] { return std::min(window(best), reach2); }, [&](int t) {
      const double d2 = pointTriangleDistance2(q, tri_[t][0], tri_[t][1], tri_[t][2]);
      if (d2 > reach2 || normal_[t].SquaredNorm() == 0) return false;
      if (d2 <= window(best)) {
        best = std::min(best, d2);
        near.push_back({d2, t});
      }
      return false;
    }, maxNodes);
    Under u;
    if (!complete || near.empty()) return u;
    double aligned = -std::numeric_limits<double>::infinity();
    for (const auto& c : near)
      if (c.first <= window(best) && normal_[c.second] * dir > aligned) {
        aligned = normal_[c.second] * dir;
        u.normal = normal_[c.second];
        u.face = c.second;
      }
    u.found = true;
    return u;
  }

 private:
  static constexpr int kRecent = 4;
  std::vector<std::array<Vec3, 3>> tri_;
  std::vector<Vec3> normal_;  ///< per triangle of tri_, its orientation for under()
  double tie2_ = 0;           ///< squared distances closer than this are equal (rounding)
  BoxTree tree_;
  mutable int recent_[kRecent] = {-1, -1, -1, -1};  ///< the last triangles within() found (not thread-safe)
  mutable int next_ = 0;
};

}  // namespace sodt
