// SPDX-License-Identifier: GPL-3.0-or-later
// The deviation bound's other direction: points of the input (its vertices,
// edge midpoints and face centroids) must stay within the bound of the output.
#pragma once

#include "../maths/geometry.h"
#include "../maths/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace sodt {

/// The cover's limit in units of the deviation bound (see InputCover). At
/// 1.0 the min angle dropped further (basic with flips: bunny_closed 6.65 to
/// 5.90 degrees, spot_badquality 15.9 to 12.2); at 1.25 the sampled two-way
/// distance of every shared-mesh run stays within 1.5 bounds.
constexpr double kCoverLimitFactor = 1.25;

/// The slack of a face that covers no point (see InputCover).
constexpr double kCoverNoPoints = std::numeric_limits<double>::infinity();

/// The input's sample points, each held by one face of the working mesh that
/// lies within the bound of it (its cover). deviation.h bounds the distance
/// from the output to the input; this bounds the distance from the input's
/// vertices, edge midpoints and face centroids to the output, so that a tip,
/// a thin fin or a sharp rim cannot slide away from under the output.
///
/// Every point starts on its own face (distance 0). A move of vertex v
/// changes only the faces of v's star, so only the points they cover can be
/// uncovered: each must then lie within the bound of a face of v's star at
/// the new position (its own cover first), or the move is refused. An
/// accepted move hands each point whose cover left the bound to the
/// nearest face of the star. A flip does the same with the pair's two faces.
///
/// A face keeps a slack, how far inside the limit its points lie at least: a
/// move of one of its corners by less leaves them covered, and is passed
/// without a distance query (every run takes the same shortcuts, so the
/// result does not depend on threads, lanes or margins). Points are kept in one intrusive list
/// per face. A move writes only the
/// lists of its star's faces, which no vertex of the same colour shares, so
/// the sweeps stay parallel; whether a move is accepted does not depend on
/// the order of the lists, and which face takes a point depends on the
/// positions alone, so the result is the same for every thread count.
class InputCover {
 public:
  /// Takes the input's points (pos and faces as they are now). faces, topo
  /// and pos are the working mesh's, read at every test (flips change faces
  /// and topo; they must outlive this); limit is the distance the points
  /// must keep to the output (kCoverLimitFactor times the bound in a run).
  void prepare(const FaceList& faces, const RingTopology& topo, const std::vector<Vec3>& pos, double limit) {
    faces_ = &faces;
    topo_ = &topo;
    pos_ = &pos;
    limit2_ = limit * limit;
    const std::size_t nf = faces.tri.size();
    head_.assign(nf, -1);
    point_.clear();
    face_.clear();
    next_.clear();
    std::vector<char> seen(pos.size(), 0);
    std::vector<std::pair<long long, int>> edges;  // (a * n + b) with a < b, face
    for (std::size_t f = 0; f < nf; ++f) {
      if (!faces.live[f]) continue;
      const std::array<int, 3>& t = faces.tri[f];
      add((pos[t[0]] + pos[t[1]] + pos[t[2]]) / 3.0, static_cast<int>(f));
      for (int j = 0; j < 3; ++j) {
        const int a = t[j], b = t[(j + 1) % 3];
        if (!seen[a]) {
          seen[a] = 1;
          add(pos[a], static_cast<int>(f));
        }
        edges.push_back({static_cast<long long>(std::min(a, b)) * static_cast<long long>(pos.size()) + std::max(a, b),
                         static_cast<int>(f)});
      }
    }
    slack_.assign(nf, kCoverNoPoints);
    limit_ = limit;
    std::sort(edges.begin(), edges.end());
    const long long nv = static_cast<long long>(pos.size());
    for (std::size_t k = 0; k < edges.size(); ++k) {
      if (k > 0 && edges[k].first == edges[k - 1].first) continue;
      const int a = static_cast<int>(edges[k].first / nv), b = static_cast<int>(edges[k].first % nv);
      // The quarter points too: on a long edge across a bend the midpoint
      // alone left the input 1.7 bounds from the output (spot_badquality).
      for (double t : {0.25, 0.5, 0.75}) add(pos[a] * (1 - t) + pos[b] * t, edges[k].second);
    }
    for (std::size_t q = 0; q < point_.size(); ++q)
      slack_[face_[q]] = std::min(slack_[face_[q]], slackOf(distance2(static_cast<int>(q), faces.tri[face_[q]])));
  }

  /// The number of input points kept covered.
  std::size_t points() const { return point_.size(); }

  /// True when, with vertex v at p, every point covered by a face of v's
  /// star lies within the bound of one of the star's faces.
  bool coveredAfterMove(int v, const Vec3& p) const { return coveredAfterMove(v, p, ringFaces(v)); }

  /// The same for a vertex whose star is the given faces (a border vertex's
  /// open fan, which the ring topology does not hold).
  bool coveredAfterMove(int v, const Vec3& p, const std::vector<int>& star) const {
    return coveredAfterMove(v, p, FaceSpan{star.data(), star.data() + star.size()});
  }

  /// After vertex v moved from `from` to p (coveredAfterMove(v, p) true,
  /// with v still at `from`): each point of v's star whose cover left the
  /// bound goes to the star's nearest face, and the faces' slacks follow.
  void commitMove(int v, const Vec3& from, const Vec3& p) { commitMove(v, from, p, ringFaces(v)); }

  /// The same for a star given by its faces (see coveredAfterMove).
  void commitMove(int v, const Vec3& from, const Vec3& p, const std::vector<int>& star) {
    commitMove(v, from, p, FaceSpan{star.data(), star.data() + star.size()});
  }

  /// True when the faces f1 and f2, made into t1 and t2 by a flip, still
  /// cover every point they cover now (at the current positions).
  bool coveredAfterFlip(int f1, int f2, const std::array<int, 3>& t1, const std::array<int, 3>& t2) const {
    for (int f : {f1, f2})
      for (int q = head_[f]; q >= 0; q = next_[q])
        if (!(distance2(q, t1) <= limit2_) && !(distance2(q, t2) <= limit2_)) return false;
    return true;
  }

  /// After the flip of faces f1 and f2 (their corners already changed):
  /// every point either covered goes to the nearer of the two.
  void commitFlip(int f1, int f2) {
    int chain = -1;  // both lists, detached
    for (int f : {f1, f2}) {
      for (int q = head_[f]; q >= 0;) {
        const int after = next_[q];
        next_[q] = chain;
        chain = q;
        q = after;
      }
      head_[f] = -1;
    }
    const std::array<int, 3>& t1 = faces_->tri[f1];
    const std::array<int, 3>& t2 = faces_->tri[f2];
    slack_[f1] = slack_[f2] = kCoverNoPoints;
    while (chain >= 0) {
      const int q = chain;
      chain = next_[q];
      const double d1 = distance2(q, t1), d2 = distance2(q, t2);
      const int f = d1 <= d2 ? f1 : f2;
      link(q, f);
      slack_[f] = std::min(slack_[f], slackOf(std::min(d1, d2)));
    }
  }

  /// The largest distance from a point to its cover (for tests).
  double largestDistance() const {
    double d2 = 0;
    for (std::size_t q = 0; q < point_.size(); ++q)
      d2 = std::max(d2, distance2(static_cast<int>(q), faces_->tri[face_[q]]));
    return std::sqrt(d2);
  }

 private:
  /// The faces of a star, as indices into the face list (negative: none).
  struct FaceSpan {
    const int* first;
    const int* last;
    const int* begin() const { return first; }
    const int* end() const { return last; }
  };

  FaceSpan ringFaces(int v) const {
    const RingTopology& T = *topo_;
    const int* base = T.ringFace.data();
    return FaceSpan{base + T.ringBegin[v], base + T.ringBegin[v + 1]};
  }

  bool coveredAfterMove(int v, const Vec3& p, FaceSpan star) const {
    const double step = stepOf(v, p);
    for (int f : star) {
      if (f < 0 || step <= slack_[f]) continue;  // no point of f moves out of reach
      for (int q = head_[f]; q >= 0; q = next_[q])
        if (!(distance2(q, f, v, p) <= limit2_) && nearestInStar(q, v, p, star).second > limit2_) return false;
    }
    return true;
  }

  void commitMove(int v, const Vec3& from, const Vec3& p, FaceSpan star) {
    const double step = (p - from).Norm() * (1 + 1e-12);
    for (int f : star) {
      if (f < 0) continue;
      if (step <= slack_[f]) {  // every point of f stays within the bound of it
        slack_[f] -= step;
        continue;
      }
      double worst = -1;  // the largest squared distance of a point kept by f (-1: none)
      int prev = -1;
      for (int q = head_[f]; q >= 0;) {
        const int after = next_[q];
        const double d2 = distance2(q, f, v, p);
        const std::pair<int, double> to = d2 <= limit2_ ? std::make_pair(f, d2) : nearestInStar(q, v, p, star);
        if (to.first == f || to.first < 0 || !(to.second <= limit2_)) {
          prev = q;
          worst = std::max(worst, d2);
        } else {
          (prev < 0 ? head_[f] : next_[prev]) = after;  // unlink
          link(q, to.first);
          slack_[to.first] = std::min(slack_[to.first], slackOf(to.second));
        }
        q = after;
      }
      slack_[f] = worst < 0 ? kCoverNoPoints : slackOf(worst);  // of f's new shape
    }
  }

  /// How far a point at squared distance d2 from a face can move (or the
  /// face move under it) and stay within the limit: a lower bound, by 1e-9
  /// of the limit, so that the shortcut it gives never passes a point the
  /// exact test would refuse by rounding.
  double slackOf(double d2) const { return limit_ * (1 - 1e-9) - std::sqrt(d2); }

  /// The length of v's move to p, rounded up.
  double stepOf(int v, const Vec3& p) const { return (p - (*pos_)[v]).Norm() * (1 + 1e-12); }

  void add(const Vec3& x, int f) {
    point_.push_back(x);
    face_.push_back(-1);
    next_.push_back(-1);
    link(static_cast<int>(point_.size()) - 1, f);
  }

  void link(int q, int f) {
    face_[q] = f;
    next_[q] = head_[f];
    head_[f] = q;
  }

  /// Squared distance from point q to triangle t at the current positions.
  double distance2(int q, const std::array<int, 3>& t) const {
    const std::vector<Vec3>& P = *pos_;
    return pointTriangleDistance2(point_[q], P[t[0]], P[t[1]], P[t[2]]);
  }

  /// Squared distance from point q to face f, with vertex v at p.
  double distance2(int q, int f, int v, const Vec3& p) const {
    const std::array<int, 3>& t = faces_->tri[f];
    const std::vector<Vec3>& P = *pos_;
    const auto at = [&](int j) -> const Vec3& { return t[j] == v ? p : P[t[j]]; };
    return pointTriangleDistance2(point_[q], at(0), at(1), at(2));
  }

  /// The face of v's star nearest to point q with v at p (the first in ring
  /// order among equals), and the squared distance.
  std::pair<int, double> nearestInStar(int q, int v, const Vec3& p, FaceSpan star) const {
    std::pair<int, double> best(-1, std::numeric_limits<double>::infinity());
    for (int f : star) {
      if (f < 0) continue;
      const double d2 = distance2(q, f, v, p);
      if (d2 < best.second) best = {f, d2};
    }
    return best;
  }

  const FaceList* faces_ = nullptr;
  const RingTopology* topo_ = nullptr;
  const std::vector<Vec3>* pos_ = nullptr;
  double limit2_ = 0;
  std::vector<Vec3> point_;  ///< the input points (constant)
  std::vector<int> face_;    ///< per point, its cover
  std::vector<int> next_;    ///< per point, the next of its cover's list (-1: none)
  std::vector<int> head_;    ///< per face, its first point (-1: none)
  /// Per face, a lower bound of how far inside the limit its points lie
  /// (limit minus their largest distance to it): a move of a corner by less
  /// leaves every point of the face covered by it, with no distance query.
  /// Only the moves of the face's corners change it, and each updates it.
  std::vector<double> slack_;
  double limit_ = 0;
};

}  // namespace sodt
