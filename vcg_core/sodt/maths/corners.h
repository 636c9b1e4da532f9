// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Sharp corners between features: where two feature lines or border edges
// meet at an angle below a target, no triangle of the corner can do better
// than that angle while the features stay, so a smallest-angle target is
// measured on the other triangles. Shared by the report (sodt_io) and the
// repair, which ranks its states by the same measure.

#include "geometry.h"
#include "topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <vector>

namespace sodt {

/// The corners of protectedCorners().
struct CornerView {
  /// Corners: runs of faces around a vertex between two feature edges (or
  /// a whole border fan) whose angles at the vertex add up to less than
  /// the target.
  int corners = 0;
  double smallestRad = 0;  ///< the smallest of their angles (0 when there is none)
  /// Per face, whether its smallest angle is at such a corner (then it is
  /// not counted against the target).
  std::vector<char> atCorner;
  /// The smallest angle of every other face with an area (pi when there is none).
  double minAngleElsewhere = kPi;
};

namespace detail {

/// Union-find over a fixed number of items.
class Components {
 public:
  explicit Components(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::size_t(0)); }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace detail

/// The corners of the faces tri (indices into pos) where features meet at
/// less than targetRad. An edge is a feature when it is a border or
/// non-manifold edge, or when the normals of its two faces differ by more
/// than featureRad and neither face is a sliver (smallest angle below
/// kSliverNormalDeg): a sliver's normal is nearly arbitrary, so the angle
/// across its edges says nothing, and a sliver is never taken for a
/// feature's corner unless a border bounds it. Around each vertex, the
/// faces between two consecutive feature edges form one corner, whose
/// angle is the sum of their angles at the vertex; a vertex without a
/// feature edge has one corner of 360 degrees. Faces with a zero-length
/// edge have no angle of their own and are measured with the others.
/// Every edge may be a feature (protectedCorners' default).
struct AnyEdge {
  bool operator()(int, int) const { return true; }
};

/// The corners of the faces tri (indices into pos) where features meet at
/// less than targetRad; an edge between two faces is a feature only when
/// mayBe(lo, hi) holds for its ends too (lo < hi), so that a caller that
/// changes the mesh can keep to the features it started from.
template <class MayBe = AnyEdge>
CornerView protectedCorners(const std::vector<std::array<int, 3>>& tri, const std::vector<Vec3>& pos,
                            double featureRad, double targetRad, const MayBe& mayBe = MayBe()) {
  CornerView r;
  const std::size_t nf = tri.size();
  r.atCorner.assign(nf, 0);
  if (nf == 0) return r;
  std::vector<std::array<double, 3>> angle(nf);
  std::vector<Vec3> normal(nf);
  std::vector<char> sliver(nf);
  const double sliverRad = kSliverNormalDeg * kPi / 180;
  for (std::size_t f = 0; f < nf; ++f) {
    const Vec3 p[3] = {pos[std::size_t(tri[f][0])], pos[std::size_t(tri[f][1])], pos[std::size_t(tri[f][2])]};
    for (int j = 0; j < 3; ++j) angle[f][j] = angleBetween(p[(j + 1) % 3] - p[j], p[(j + 2) % 3] - p[j]);
    normal[f] = doubleAreaVector(p[0], p[1], p[2]);
    const double smallest = *std::min_element(angle[f].begin(), angle[f].end());
    sliver[f] = !(smallest >= sliverRad) || !(normal[f].Norm() > 0);
  }
  // The sides of the faces, sorted by edge: a run of one side is a border,
  // of three or more non-manifold.
  struct Side {
    int lo, hi;
    std::size_t face;
  };
  std::vector<Side> sides;
  sides.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j) {
      const int a = tri[f][j], b = tri[f][(j + 1) % 3];
      sides.push_back({std::min(a, b), std::max(a, b), f});
    }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return x.lo < y.lo || (x.lo == y.lo && (x.hi < y.hi || (x.hi == y.hi && x.face < y.face)));
  });
  // Corners (face f, its vertex j) are items 3 f + j; a non-feature edge
  // joins the two corners of its faces at each of its ends.
  const double cosFeature = std::cos(featureRad);
  const auto cornerOf = [&](std::size_t f, int v) {
    for (int j = 0; j < 3; ++j)
      if (tri[f][j] == v) return 3 * f + std::size_t(j);
    return std::size_t(0);  // not reached: v is a corner of f
  };
  detail::Components corner(3 * nf);
  for (std::size_t k = 0; k < sides.size();) {
    std::size_t e = k + 1;
    while (e < sides.size() && sides[e].lo == sides[k].lo && sides[e].hi == sides[k].hi) ++e;
    if (e - k == 2) {
      const std::size_t f1 = sides[k].face, f2 = sides[k + 1].face;
      const double l = normal[f1].Norm() * normal[f2].Norm();
      const bool feature = !sliver[f1] && !sliver[f2] && normal[f1] * normal[f2] < cosFeature * l &&
                           mayBe(sides[k].lo, sides[k].hi);
      if (!feature)
        for (int v : {sides[k].lo, sides[k].hi}) corner.join(cornerOf(f1, v), cornerOf(f2, v));
    }
    k = e;
  }
  std::vector<double> sum(3 * nf, 0.0);
  for (std::size_t c = 0; c < 3 * nf; ++c) sum[corner.find(c)] += angle[c / 3][c % 3];
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < 3 * nf; ++c)
    if (corner.find(c) == c && sum[c] < targetRad) {
      ++r.corners;
      smallest = std::min(smallest, sum[c]);
    }
  if (r.corners > 0) r.smallestRad = smallest;
  for (std::size_t f = 0; f < nf; ++f) {
    const int j = int(std::min_element(angle[f].begin(), angle[f].end()) - angle[f].begin());
    if (normal[f].Norm() > 0 && sum[corner.find(3 * f + std::size_t(j))] < targetRad)
      r.atCorner[f] = 1;
    else
      r.minAngleElsewhere = std::min(r.minAngleElsewhere, angle[f][j]);
  }
  return r;
}

}  // namespace sodt
