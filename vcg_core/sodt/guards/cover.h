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

/// The smallest key of a face that covers no point (see InputCover).
constexpr double kCoverNoPoints = std::numeric_limits<double>::infinity();

/// What coveredAfterMove measured, handed to the commitMove of the same
/// move so that it measures nothing twice: per point it queried, in the
/// order it queried them, the squared distance to its cover and, when that
/// left the limit, the nearest face of the star and its squared distance.
/// Holds at most the capacity reserve() gave it (a visit must not
/// allocate); commitMove measures the points beyond that itself.
struct CoverScratch {
  struct Entry {
    int point;
    int to;  ///< the nearest face of the star, or -1 when the cover kept the point
    double d2, d2to;
  };
  void reserve(std::size_t n) { entry.reserve(n); }

  int vertex = -1;  ///< the move measured (-1: none)
  Vec3 at;
  std::vector<Entry> entry;
};

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
/// Each point keeps a margin, how far inside the limit it lies at least, and
/// a face the smallest margin of its points: a move of a corner by less
/// leaves the point (or all of the face's points) covered, and is passed
/// without a distance query. Those shortcuts only skip queries whose answer
/// they know, so the result does not depend on them (nor on threads, lanes
/// or margins). Points are kept in one intrusive list per face, laid out
/// face by face at the start so that a face's points share cache lines. A
/// move writes only the lists of its star's faces, which no vertex of the
/// same colour shares, so the sweeps stay parallel; whether a move is
/// accepted does not depend on the order of the lists, and which face takes
/// a point depends on the positions alone, so the result is the same for
/// every thread count.
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
    limit_ = limit;
    limit2_ = limit * limit;
    const std::size_t nf = faces.tri.size();
    // Which face takes which point: the centroid its own face, a vertex the
    // first face that has it, an edge's three points the first of its two
    // faces. First counted per face, then laid out face by face.
    std::vector<std::pair<long long, int>> edges;  // (a * n + b) with a < b, face
    edges.reserve(3 * nf);
    const long long nv = static_cast<long long>(pos.size());
    for (std::size_t f = 0; f < nf; ++f) {
      if (!faces.live[f]) continue;
      const std::array<int, 3>& t = faces.tri[f];
      for (int j = 0; j < 3; ++j) {
        const int a = t[j], b = t[(j + 1) % 3];
        edges.push_back({std::min(a, b) * nv + std::max(a, b), static_cast<int>(f)});
      }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end(),
                            [](const std::pair<long long, int>& x, const std::pair<long long, int>& y) {
                              return x.first == y.first;
                            }),
                edges.end());
    std::vector<char> seen(pos.size(), 0);
    std::vector<std::size_t> begin(nf + 1, 0);
    for (std::size_t f = 0; f < nf; ++f) {
      if (!faces.live[f]) continue;
      begin[f + 1] = 1;
      for (int a : faces.tri[f])
        if (!seen[a]) {
          seen[a] = 1;
          ++begin[f + 1];
        }
    }
    for (const auto& e : edges) begin[e.second + 1] += 3;
    for (std::size_t f = 0; f < nf; ++f) begin[f + 1] += begin[f];
    point_.assign(begin[nf], Point());
    face_.assign(begin[nf], -1);
    cover_.assign(nf, FaceCover());
    // The points are on their faces up to the rounding of a centroid or of
    // a point between two corners, a few units in the last place of the
    // largest coordinate: 16 of them on every axis is ample.
    double largest = 0;
    for (const Vec3& q : pos)
      for (int j = 0; j < 3; ++j) largest = std::max(largest, std::abs(q[j]));
    const float key = keyOfMargin(slackOf(0) - 16 * std::sqrt(3.0) * std::numeric_limits<double>::epsilon() * largest, 0);
    std::vector<std::size_t> fill(begin.begin(), begin.end() - 1);
    const auto add = [&](const Vec3& x, int f) {
      const std::size_t q = fill[f]++;
      point_[q] = Point{x, key, q + 1 < begin[f + 1] ? static_cast<int>(q + 1) : -1};
      face_[q] = f;
    };
    std::fill(seen.begin(), seen.end(), 0);
    for (std::size_t f = 0; f < nf; ++f) {
      if (!faces.live[f]) continue;
      const std::array<int, 3>& t = faces.tri[f];
      add((pos[t[0]] + pos[t[1]] + pos[t[2]]) / 3.0, static_cast<int>(f));
      for (int a : t)
        if (!seen[a]) {
          seen[a] = 1;
          add(pos[a], static_cast<int>(f));
        }
    }
    for (const auto& e : edges) {
      const int a = static_cast<int>(e.first / nv), b = static_cast<int>(e.first % nv);
      // The quarter points too: on a long edge across a bend the midpoint
      // alone left the input 1.7 bounds from the output (spot_badquality).
      for (double t : {0.25, 0.5, 0.75}) add(pos[a] * (1 - t) + pos[b] * t, e.second);
    }
    for (std::size_t f = 0; f < nf; ++f)
      if (begin[f] < begin[f + 1]) {
        cover_[f].head = static_cast<int>(begin[f]);
        cover_[f].minKey = key;
      }
  }

  /// The number of input points kept covered.
  std::size_t points() const { return point_.size(); }

  /// True when, with vertex v at p, every point covered by a face of v's
  /// star lies within the bound of one of the star's faces. scratch, when
  /// not null, keeps what was measured for commitMove.
  bool coveredAfterMove(int v, const Vec3& p, CoverScratch* scratch = nullptr) const {
    return coveredAfterMove(v, p, ringFaces(v), scratch);
  }

  /// The same for a vertex whose star is the given faces (a border vertex's
  /// open fan, which the ring topology does not hold).
  bool coveredAfterMove(int v, const Vec3& p, const std::vector<int>& star) const {
    return coveredAfterMove(v, p, FaceSpan{star.data(), star.data() + star.size()}, nullptr);
  }

  /// After vertex v moved from `from` to p (coveredAfterMove(v, p) true,
  /// with v still at `from`): each point of v's star whose cover left the
  /// bound goes to the star's nearest face, and the margins follow. scratch:
  /// that of the coveredAfterMove(v, p) that passed the move, or null.
  void commitMove(int v, const Vec3& from, const Vec3& p, const CoverScratch* scratch = nullptr) {
    commitMove(v, from, p, ringFaces(v), scratch);
  }

  /// The same for a star given by its faces (see coveredAfterMove).
  void commitMove(int v, const Vec3& from, const Vec3& p, const std::vector<int>& star) {
    commitMove(v, from, p, FaceSpan{star.data(), star.data() + star.size()}, nullptr);
  }

  /// True when the faces f1 and f2, made into t1 and t2 by a flip, still
  /// cover every point they cover now (at the current positions).
  bool coveredAfterFlip(int f1, int f2, const std::array<int, 3>& t1, const std::array<int, 3>& t2) const {
    for (int f : {f1, f2})
      for (int q = cover_[f].head; q >= 0; q = point_[q].next)
        if (!(distance2(q, t1) <= limit2_) && !(distance2(q, t2) <= limit2_)) return false;
    return true;
  }

  /// After the flip of faces f1 and f2 (their corners already changed):
  /// every point either covered goes to the nearer of the two.
  void commitFlip(int f1, int f2) {
    int chain = -1;  // both lists, detached
    for (int f : {f1, f2}) {
      for (int q = cover_[f].head; q >= 0;) {
        const int after = point_[q].next;
        point_[q].next = chain;
        chain = q;
        q = after;
      }
      cover_[f].head = -1;
      cover_[f].minKey = kCoverNoPoints;
    }
    const std::array<int, 3>& t1 = faces_->tri[f1];
    const std::array<int, 3>& t2 = faces_->tri[f2];
    while (chain >= 0) {
      const int q = chain;
      chain = point_[q].next;
      const double d1 = distance2(q, t1), d2 = distance2(q, t2);
      const int f = d1 <= d2 ? f1 : f2;
      link(q, f, keyOf(std::min(d1, d2), cover_[f].consumed));
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

  /// An input point.
  struct Point {
    Vec3 x;
    /// A lower bound of how far inside the limit the point lies (the limit
    /// minus its distance to its cover) plus its cover's consumed at the
    /// time it was measured: its margin now is at least key minus the
    /// cover's consumed now, and a move of a corner by less leaves it
    /// covered, with no distance query.
    float key = 0;
    int next = -1;  ///< the next point of its cover's list (-1: none)
  };

  /// A face's share of the cover.
  struct FaceCover {
    /// The length of the moves of its corners so far (an upper bound): a
    /// point of the triangle moves by no more than the corner that moves,
    /// so a point's distance to it grows by no more than that.
    double consumed = 0;
    /// The smallest key of its points (or less): a move of a corner by
    /// less than minKey - consumed leaves all of them covered.
    double minKey = kCoverNoPoints;
    int head = -1;  ///< its first point (-1: none)
  };

  FaceSpan ringFaces(int v) const {
    const RingTopology& T = *topo_;
    const int* base = T.ringFace.data();
    return FaceSpan{base + T.ringBegin[v], base + T.ringBegin[v + 1]};
  }

  bool coveredAfterMove(int v, const Vec3& p, FaceSpan star, CoverScratch* scratch) const {
    const double step = stepOf(v, p);
    if (scratch) {
      scratch->vertex = -1;
      scratch->entry.clear();
    }
    for (int f : star) {
      if (f < 0) continue;
      const FaceCover& fc = cover_[f];
      if (step <= fc.minKey - fc.consumed) continue;  // no point of f moves out of reach
      for (int q = fc.head; q >= 0; q = point_[q].next) {
        if (step <= point_[q].key - fc.consumed) continue;  // nor does q
        const double d2 = distance2(q, f, v, p);
        std::pair<int, double> to(-1, 0.0);
        if (!(d2 <= limit2_)) {
          to = nearestInStar(q, v, p, star);
          if (to.second > limit2_) return false;
        }
        if (scratch && scratch->entry.size() < scratch->entry.capacity())
          scratch->entry.push_back({q, to.first, d2, to.second});
      }
    }
    if (scratch) {
      scratch->vertex = v;
      scratch->at = p;
    }
    return true;
  }

  void commitMove(int v, const Vec3& from, const Vec3& p, FaceSpan star, const CoverScratch* scratch) {
    const double step = (p - from).Norm() * (1 + 1e-12);
    // The measures of the check that passed this move, in the order it took
    // them (the same points in the same order as below).
    const bool measured = scratch && scratch->vertex == v && scratch->at == p;
    std::size_t e = 0;
    int leaving = -1;  // the points that change cover, linked once every face is done
    for (int f : star) {
      if (f < 0) continue;
      FaceCover& fc = cover_[f];
      const double before = fc.consumed;
      // Every face of the star moves by step (rounded up, so that the sum
      // never falls short of the true path).
      fc.consumed = (before + step) * (1 + 1e-15);
      if (step <= fc.minKey - before) continue;  // every point of f stays within the bound of it
      double smallest = kCoverNoPoints;  // the smallest key of a point kept by f
      int prev = -1;
      for (int q = fc.head; q >= 0;) {
        Point& pt = point_[q];
        const int after = pt.next;
        if (step <= pt.key - before) {  // q stays within the bound of f
          smallest = std::min(smallest, double(pt.key));
          prev = q;
          q = after;
          continue;
        }
        double d2;
        std::pair<int, double> to(f, 0.0);
        if (measured && e < scratch->entry.size() && scratch->entry[e].point == q) {
          const CoverScratch::Entry& m = scratch->entry[e++];
          d2 = m.d2;
          if (m.to >= 0) to = {m.to, m.d2to};
        } else {
          d2 = distance2(q, f, v, p);
          if (!(d2 <= limit2_)) to = nearestInStar(q, v, p, star);
        }
        if (d2 <= limit2_ || to.first == f || to.first < 0 || !(to.second <= limit2_)) {
          pt.key = keyOf(d2, fc.consumed);
          smallest = std::min(smallest, double(pt.key));
          prev = q;
        } else {
          (prev < 0 ? fc.head : point_[prev].next) = after;  // unlink
          face_[q] = to.first;
          pt.key = keyOf(to.second, 0.0);  // the margin alone until linked
          pt.next = leaving;
          leaving = q;
        }
        q = after;
      }
      fc.minKey = smallest;
    }
    while (leaving >= 0) {
      const int q = leaving, f = face_[q];
      leaving = point_[q].next;
      link(q, f, keyBelow(double(point_[q].key) + cover_[f].consumed));
    }
  }

  /// How far a point at squared distance d2 from a face can move (or the
  /// face move under it) and stay within the limit: a lower bound, by 1e-9
  /// of the limit, so that the shortcut it gives never passes a point the
  /// exact test would refuse by rounding.
  double slackOf(double d2) const { return limit_ * (1 - 1e-9) - std::sqrt(d2); }

  /// A float at or below x (minus infinity for NaN).
  static float keyBelow(double x) {
    if (!(x == x)) return -std::numeric_limits<float>::infinity();
    float k = static_cast<float>(x);
    if (double(k) > x) k = std::nextafter(k, -std::numeric_limits<float>::infinity());
    return k;
  }

  /// The key of a point with the given margin on a face whose corners have
  /// moved by consumed so far (see Point::key).
  static float keyOfMargin(double margin, double consumed) { return keyBelow(margin + consumed); }
  float keyOf(double d2, double consumed) const { return keyOfMargin(slackOf(d2), consumed); }

  /// The length of v's move to p, rounded up.
  double stepOf(int v, const Vec3& p) const { return (p - (*pos_)[v]).Norm() * (1 + 1e-12); }

  /// Puts point q first in face f's list, with the given key.
  void link(int q, int f, float key) {
    face_[q] = f;
    point_[q].key = key;
    point_[q].next = cover_[f].head;
    cover_[f].head = q;
    cover_[f].minKey = std::min(cover_[f].minKey, double(key));
  }

  /// Squared distance from point q to triangle t at the current positions.
  double distance2(int q, const std::array<int, 3>& t) const {
    const std::vector<Vec3>& P = *pos_;
    return pointTriangleDistance2(point_[q].x, P[t[0]], P[t[1]], P[t[2]]);
  }

  /// Squared distance from point q to face f, with vertex v at p.
  double distance2(int q, int f, int v, const Vec3& p) const {
    const std::array<int, 3>& t = faces_->tri[f];
    const std::vector<Vec3>& P = *pos_;
    const auto at = [&](int j) -> const Vec3& { return t[j] == v ? p : P[t[j]]; };
    return pointTriangleDistance2(point_[q].x, at(0), at(1), at(2));
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
  double limit_ = 0, limit2_ = 0;
  std::vector<Point> point_;     ///< the input points, each face's together at first
  std::vector<int> face_;        ///< per point, its cover
  std::vector<FaceCover> cover_;  ///< per face
};

}  // namespace sodt
