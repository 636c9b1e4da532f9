// SPDX-License-Identifier: GPL-3.0-or-later
// A hierarchy of oriented boxes over triangles, for closest-point and
// "is anything within r?" searches where a uniform grid does not work: a
// grid cell holds every triangle whose box meets it, and the box of a long
// needle meets a number of cells that grows with the mesh (a fan of N
// needles around one vertex puts about N^2 / 4 triangles into cells). Here
// each triangle is in one leaf, so the memory is linear in the triangles,
// and a node is bounded by a box along the principal axes of its corners,
// which stays thin around a bundle of needles where an axis-aligned box
// would be as wide as the bundle is long. The triangles are split at the
// median of their centroids along the widest axis of the centroids' box, as
// a bounding-volume hierarchy is usually built; the tree has about
// log2(n / 4) levels.
#pragma once

#include "geometry.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace sodt {

class BoxTree {
 public:
  /// Indexes triangles 0 .. n-1 with corners corner(k, j) (a Vec3, j =
  /// 0..2). slack: an absolute margin added to every box, to cover rounding
  /// in the projections.
  template <class Corner>
  void build(int n, Corner corner, double slack) {
    nodes_.clear();
    item_.clear();
    if (n <= 0) return;
    std::vector<Vec3> centroid(n);
    for (int k = 0; k < n; ++k) centroid[k] = (corner(k, 0) + corner(k, 1) + corner(k, 2)) / 3.0;
    item_.resize(n);
    for (int k = 0; k < n; ++k) item_[k] = k;
    nodes_.reserve(2 * (n / kLeaf + 1));
    nodes_.emplace_back();
    struct Range {
      int node, begin, end;
    };
    std::vector<Range> todo{{0, 0, n}};
    while (!todo.empty()) {
      const Range r = todo.back();
      todo.pop_back();
      bound(nodes_[r.node], corner, r.begin, r.end, slack);
      if (r.end - r.begin <= kLeaf) {
        nodes_[r.node].begin = r.begin;
        nodes_[r.node].end = r.end;
        continue;
      }
      Vec3 lo = centroid[item_[r.begin]], hi = lo;
      for (int k = r.begin; k < r.end; ++k)
        for (int i = 0; i < 3; ++i) {
          lo[i] = std::min(lo[i], centroid[item_[k]][i]);
          hi[i] = std::max(hi[i], centroid[item_[k]][i]);
        }
      const Vec3 d = hi - lo;
      const int axis = d[0] >= d[1] && d[0] >= d[2] ? 0 : (d[1] >= d[2] ? 1 : 2);
      const int mid = r.begin + (r.end - r.begin) / 2;
      std::nth_element(item_.begin() + r.begin, item_.begin() + mid, item_.begin() + r.end, [&](int a, int b) {
        return centroid[a][axis] < centroid[b][axis] || (centroid[a][axis] == centroid[b][axis] && a < b);
      });
      const int left = static_cast<int>(nodes_.size());
      nodes_[r.node].left = left;
      nodes_.emplace_back();
      nodes_.emplace_back();
      todo.push_back({left + 1, mid, r.end});
      todo.push_back({left, r.begin, mid});
    }
  }

  bool empty() const { return nodes_.empty(); }

  /// Calls visit(k) for every triangle k whose leaf's box is within
  /// sqrt(reach2()) of q, nearer subtrees first, until visit returns true;
  /// reach2 is asked again before each node, so a visit that finds a
  /// closer triangle narrows the search. Returns false when it stopped
  /// because it had opened maxNodes nodes (no limit by default).
  template <class Reach2, class Visit>
  bool search(const Vec3& q, Reach2&& reach2, Visit&& visit,
              long maxNodes = std::numeric_limits<long>::max()) const {
    if (nodes_.empty()) return true;
    struct Entry {
      int node;
      double d2;
    };
    Entry stack[128];
    int top = 0;
    stack[top++] = {0, distance2(nodes_[0], q)};
    for (long opened = 0; top > 0;) {
      const Entry e = stack[--top];
      if (e.d2 > reach2()) continue;
      if (++opened > maxNodes) return false;
      const Node& nd = nodes_[e.node];
      if (nd.left < 0) {
        for (int k = nd.begin; k < nd.end; ++k)
          if (visit(item_[k])) return true;
        continue;
      }
      const double a = distance2(nodes_[nd.left], q), b = distance2(nodes_[nd.left + 1], q);
      // The nearer child is searched first: it goes on top.
      if (a <= b) {
        stack[top++] = {nd.left + 1, b};
        stack[top++] = {nd.left, a};
      } else {
        stack[top++] = {nd.left, a};
        stack[top++] = {nd.left + 1, b};
      }
    }
    return true;
  }

 private:
  static constexpr int kLeaf = 4;  ///< most triangles in a leaf

  struct Node {
    Vec3 centre;
    Vec3 axis[3];            ///< orthonormal
    double half[3];          ///< half extents along axis, with the slack
    int left = -1;           ///< children left and left + 1; -1 for a leaf
    int begin = 0, end = 0;  ///< a leaf's triangles in item_
  };

  /// Squared distance from q to the node's box (0 inside).
  static double distance2(const Node& nd, const Vec3& q) {
    const Vec3 d = q - nd.centre;
    double s = 0;
    for (int i = 0; i < 3; ++i) {
      const double e = std::max(std::abs(d * nd.axis[i]) - nd.half[i], 0.0);
      s += e * e;
    }
    return s;
  }

  /// The box of the corners of triangles item_[b, e): along the principal
  /// axes of those corners (the axes of the world when they are not finite).
  template <class Corner>
  void bound(Node& nd, Corner& corner, int b, int e, double slack) const {
    const Vec3 ref = corner(item_[b], 0);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double count = 0;
    for (int k = b; k < e; ++k)
      for (int j = 0; j < 3; ++j) {
        const Vec3 d = corner(item_[k], j) - ref;
        const Eigen::Vector3d x(d[0], d[1], d[2]);
        sum += x;
        cov += x * x.transpose();
        count += 1;
      }
    const Eigen::Vector3d mean = sum / count;
    cov = cov / count - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    Eigen::Matrix3d V = eig.eigenvectors();
    if (eig.info() != Eigen::Success || !V.allFinite()) V = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 3; ++i) nd.axis[i] = Vec3(V(0, i), V(1, i), V(2, i));
    // Orthonormal to rounding; the extents below are measured along these
    // very axes, so the box holds the corners whatever the axes are.
    double lo[3], hi[3];
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::numeric_limits<double>::infinity();
      hi[i] = -lo[i];
    }
    for (int k = b; k < e; ++k)
      for (int j = 0; j < 3; ++j) {
        const Vec3 d = corner(item_[k], j) - ref;
        for (int i = 0; i < 3; ++i) {
          const double t = d * nd.axis[i];
          lo[i] = std::min(lo[i], t);
          hi[i] = std::max(hi[i], t);
        }
      }
    nd.centre = ref;
    for (int i = 0; i < 3; ++i) {
      nd.centre += nd.axis[i] * (0.5 * (lo[i] + hi[i]));
      nd.half[i] = 0.5 * (hi[i] - lo[i]) * (1 + 1e-9) + slack;
    }
  }

  std::vector<Node> nodes_;
  std::vector<int> item_;  ///< triangles in leaf order
};

}  // namespace sodt
