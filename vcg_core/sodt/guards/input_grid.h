// SPDX-License-Identifier: GPL-3.0-or-later
// The input surface for local repair: a hashed uniform grid of its faces,
// answering "is q within r of the input?" and "where is the input point
// closest to q?". Unlike InputSurface (deviation.h), which reads the input
// by vertex index, it needs no correspondence between the input and the
// current mesh, so it still answers after vertices are added or removed.
#pragma once

#include "../maths/box_tree.h"
#include "../maths/geometry.h"
#include "../maths/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
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
  /// Copies the live faces of faces over pos. cell: about the mean edge
  /// length, the scale of the rounding margin of the boxes.
  InputGrid(const std::vector<Vec3>& pos, const FaceList& faces, double cell) {
    double largest = 0;
    for (std::size_t f = 0; f < faces.tri.size(); ++f) {
      if (!faces.live[f]) continue;
      const auto& t = faces.tri[f];
      tri_.push_back({pos[t[0]], pos[t[1]], pos[t[2]]});
      for (int v : t)
        for (int k = 0; k < 3; ++k) largest = std::max(largest, std::abs(pos[v][k]));
    }
    (void)cell;
    tree_.build(static_cast<int>(tri_.size()), [this](int k, int j) { return tri_[k][j]; }, 1e-12 * largest);
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

 private:
  static constexpr int kRecent = 4;
  std::vector<std::array<Vec3, 3>> tri_;
  BoxTree tree_;
  mutable int recent_[kRecent] = {-1, -1, -1, -1};  ///< the last triangles within() found (not thread-safe)
  mutable int next_ = 0;
};

}  // namespace sodt
