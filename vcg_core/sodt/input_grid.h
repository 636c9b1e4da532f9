// SPDX-License-Identifier: GPL-3.0-or-later
// The input surface for local repair: a hashed uniform grid of its faces,
// answering "is q within r of the input?" and "where is the input point
// closest to q?". Unlike InputSurface (deviation.h), which reads the input
// by vertex index, it needs no correspondence between the input and the
// current mesh, so it still answers after vertices are added or removed.
#pragma once

#include "geometry.h"
#include "topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
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

/// A copy of a triangle mesh with its faces hashed into cubic cells.
class InputGrid {
 public:
  /// Copies the live faces of faces over pos; cell is the cell's edge
  /// length (> 0), about the mean edge length.
  InputGrid(const std::vector<Vec3>& pos, const FaceList& faces, double cell) : cell_(cell) {
    for (std::size_t f = 0; f < faces.tri.size(); ++f) {
      if (!faces.live[f]) continue;
      const auto& t = faces.tri[f];
      tri_.push_back({pos[t[0]], pos[t[1]], pos[t[2]]});
    }
    stamp_.assign(tri_.size(), 0);
    for (std::size_t f = 0; f < tri_.size(); ++f) {
      Vec3 lo = tri_[f][0], hi = tri_[f][0];
      for (const Vec3& q : tri_[f])
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], q[k]), hi[k] = std::max(hi[k], q[k]);
      forCells(lo, hi, [&](std::int64_t key) { cells_[key].push_back(static_cast<int>(f)); });
    }
  }

  /// True when some input point lies within r of q.
  bool within(const Vec3& q, double r) const {
    bool found = false;
    visit(q, r, [&](const std::array<Vec3, 3>& t) {
      found = pointTriangleDistance2(q, t[0], t[1], t[2]) <= r * r;
      return found;
    });
    return found;
  }

  /// The input point closest to q among those within r; false if none.
  bool closest(const Vec3& q, double r, Vec3& out) const {
    double best = r * r;
    bool found = false;
    visit(q, r, [&](const std::array<Vec3, 3>& t) {
      const Vec3 c = closestPointOnTriangle(q, t[0], t[1], t[2]);
      const double d = (c - q).SquaredNorm();
      if (d <= best) best = d, out = c, found = true;
      return false;
    });
    return found;
  }

 private:
  /// Calls f with the key of every cell that meets the box [lo, hi]. Boxes
  /// far larger than a cell (a sliver across a whole CAD face) still get
  /// every cell: the caller's budget of such faces is small.
  template <class F>
  void forCells(const Vec3& lo, const Vec3& hi, F f) const {
    std::int64_t a[3], b[3];
    for (int k = 0; k < 3; ++k) a[k] = coord(lo[k]), b[k] = coord(hi[k]);
    for (std::int64_t x = a[0]; x <= b[0]; ++x)
      for (std::int64_t y = a[1]; y <= b[1]; ++y)
        for (std::int64_t z = a[2]; z <= b[2]; ++z) f(key(x, y, z));
  }

  std::int64_t coord(double x) const { return static_cast<std::int64_t>(std::floor(x / cell_)); }
  static std::int64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
    return ((x & 0x1FFFFF) << 42) | ((y & 0x1FFFFF) << 21) | (z & 0x1FFFFF);
  }

  /// Calls f(triangle) once for every face in the cells within r of q,
  /// until f returns true.
  template <class F>
  void visit(const Vec3& q, double r, F f) const {
    ++epoch_;
    bool stop = false;
    forCells(q - Vec3(r, r, r), q + Vec3(r, r, r), [&](std::int64_t k) {
      if (stop) return;
      const auto it = cells_.find(k);
      if (it == cells_.end()) return;
      for (int t : it->second) {
        if (stop || stamp_[t] == epoch_) continue;
        stamp_[t] = epoch_;
        stop = f(tri_[t]);
      }
    });
  }

  double cell_;
  std::vector<std::array<Vec3, 3>> tri_;
  std::unordered_map<std::int64_t, std::vector<int>> cells_;
  mutable std::vector<std::uint32_t> stamp_;  ///< faces seen by the current query
  mutable std::uint32_t epoch_ = 0;
};

}  // namespace sodt
