// SPDX-License-Identifier: GPL-3.0-or-later
// Which way the input faces under a face, and the last step of a guarded
// run: no returned face may face away from the input surface under it.
//
// The moves keep every face within the turn bound of its own input face,
// and flips and the repair keep every face they make within it of the
// input under it. Neither sees where a face ends up: near an edge sharper
// than 90 degrees (the trailing edge of a blade, a fin, the lip of a
// hole) or two sheets of the input that touch, a face that slid within
// the bound can end nearer the other side of the edge than its own, and a
// sliver folded against the surface in the input can open up on its own
// side. Both read as faces facing away from the input under them, which
// is what a user measures. The pass below finds them and puts vertices
// back towards where the input had them, as far as that breaks nothing
// else.
#pragma once

#include "../maths/geometry.h"
#include "../maths/topology.h"
#include "input_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace sodt {

/// The input surface as the facing test reads it: its live faces in a
/// tree, each with its own orientation, and for a sliver folded against
/// the surface at its corners (foldedSliverSurfaceNormals) that surface's
/// orientation as a second one.
class FacingInput {
 public:
  FacingInput(const std::vector<Vec3>& pos, const FaceList& faces) : grid_(pos, faces) {
    const std::vector<Vec3> all = foldedSliverSurfaceNormals(faces, pos);
    for (std::size_t f = 0; f < faces.tri.size(); ++f)
      if (faces.live[f]) folded_.push_back(all[f]);
  }

  /// How a face (a, b, c) lies against the input face under its centroid
  /// (the nearest one at any distance; of those equally near up to
  /// rounding, the best aligned: InputGrid::under).
  struct Verdict {
    bool measured = false;  ///< false: the face has no area, or no input face has an orientation
    bool away = false;      ///< its normal is more than 90 degrees from that face's
    double turnRad = 0;     ///< the angle between the two
  };

  /// The facing test. Over a folded sliver of the input, a face counts as
  /// facing away only when it also faces away from the surface there, and
  /// its turn is the nearer of the two; either side is a valid
  /// orientation there, and the sweeps may unfold such a sliver. maxNodes:
  /// as InputGrid::under (not measured when the query gives up). Safe to
  /// call concurrently.
  Verdict test(const Vec3& a, const Vec3& b, const Vec3& c,
               long maxNodes = std::numeric_limits<long>::max()) const {
    Verdict v;
    const Vec3 area = doubleAreaVector(a, b, c);
    if (!(area.SquaredNorm() > 0)) return v;
    const InputGrid::Under u = grid_.under((a + b + c) / 3.0, area, std::numeric_limits<double>::infinity(), maxNodes);
    if (!u.found) return v;
    v.measured = true;
    v.turnRad = angleBetween(area, u.normal);
    v.away = area * u.normal < 0;
    const Vec3& other = folded_[static_cast<std::size_t>(u.face)];
    if (other.SquaredNorm() > 0) {
      v.turnRad = std::min(v.turnRad, angleBetween(area, other));
      v.away = v.away && area * other < 0;
    }
    return v;
  }

  /// True when some input point lies within r of q (InputGrid::within;
  /// not safe to call concurrently).
  bool within(const Vec3& q, double r) const { return grid_.within(q, r); }

 private:
  InputGrid grid_;
  std::vector<Vec3> folded_;  ///< per live input face, in order: the second orientation, or zero
};

/// Rounds of unfoldFacingAway, at most: each round tries every face still
/// facing away; a vertex put back in one round can free another's in the
/// next.
constexpr int kUnfoldRounds = 4;

/// A face no single vertex can mend takes its vertices back together, and
/// then those of the faces that refused, for at most this many rings and
/// this many vertices.
constexpr int kUnfoldGrowth = 4;
constexpr std::size_t kUnfoldMaxRegion = 64;
/// No face with a corner of more faces than this is mended: each try tests
/// every face around the vertices it moves, near such a corner the input
/// is thousands of faces within rounding of each other, and a vertex of
/// valence n tried for each of its faces would cost n^2.
constexpr std::size_t kUnfoldMaxStar = 256;

/// What unfoldFacingAway did.
struct UnfoldResult {
  int found = 0;  ///< faces facing away before
  int moves = 0;  ///< vertices put back (wholly or part of the way)
  int left = 0;   ///< faces still facing away after
};

namespace detail {

/// The state of one unfoldFacingAway call (see there).
class Unfolder {
 public:
  Unfolder(std::vector<Vec3>& pos, const FaceList& faces, const std::vector<char>& deleted,
           const std::vector<Vec3>& inputPos, const FacingInput& input, double maxTurnCos2, double bound,
           std::vector<int>* moved)
      : pos_(pos), faces_(faces), deleted_(deleted), inputPos_(inputPos), input_(input),
        maxTurnCos2_(maxTurnCos2), bound_(bound), moved_(moved), away_(faces.tri.size(), 0) {}

  UnfoldResult run(int threads) {
    UnfoldResult res;
    std::vector<int> bad = detect(threads);
    res.found = static_cast<int>(bad.size());
    if (bad.empty()) return res;
    prepare();
    for (int round = 0; round < kUnfoldRounds && !bad.empty(); ++round) {
      bool any = false;
      for (int f : bad)
        if (away_[static_cast<std::size_t>(f)]) any = mend(f) || any;
      std::vector<int> still;
      for (int f : bad)
        if (away_[static_cast<std::size_t>(f)]) still.push_back(f);
      bad.swap(still);
      if (!any) break;
    }
    res.moves = moves_;
    res.left = static_cast<int>(bad.size());
    return res;
  }

 private:
  /// The live faces facing away, in order.
  std::vector<int> detect(int threads) {
    const long long nf = static_cast<long long>(faces_.tri.size());
    threads = std::max(1, std::min(threads, 1024));
#pragma omp parallel for num_threads(threads) schedule(dynamic, 256) if (threads > 1 && nf >= 8192)
    for (long long f = 0; f < nf; ++f) {
      const std::size_t g = static_cast<std::size_t>(f);
      if (faces_.live[g]) away_[g] = test(g).away;
    }
    std::vector<int> bad;
    for (std::size_t f = 0; f < away_.size(); ++f)
      if (away_[f]) bad.push_back(static_cast<int>(f));
    return bad;
  }

  /// The faces around each vertex, and the mesh's smallest angle.
  void prepare() {
    vf_.assign(pos_.size(), {});
    for (std::size_t f = 0; f < faces_.tri.size(); ++f) {
      if (!faces_.live[f]) continue;
      for (int v : faces_.tri[f]) vf_[static_cast<std::size_t>(v)].push_back(static_cast<int>(f));
      floor_ = std::min(floor_, minAngle(f));
    }
  }

  FacingInput::Verdict test(std::size_t f) const {
    const auto& t = faces_.tri[f];
    return input_.test(pos_[t[0]], pos_[t[1]], pos_[t[2]], InputGrid::kMaxNodes);
  }
  double minAngle(std::size_t f) const {
    const auto& t = faces_.tri[f];
    return triangleMinAngle(pos_[t[0]], pos_[t[1]], pos_[t[2]]);
  }
  Vec3 area(std::size_t f) const {
    const auto& t = faces_.tri[f];
    return doubleAreaVector(pos_[t[0]], pos_[t[1]], pos_[t[2]]);
  }
  /// A vertex with an input position it is not at.
  bool hasInput(int v) const {
    const std::size_t i = static_cast<std::size_t>(v);
    return i < inputPos_.size() && !deleted_[i] && !(pos_[i] == inputPos_[i]);
  }

  /// Face f's vertices one at a time; else together, then with the
  /// vertices of the faces that refused, ring by ring: a patch put back
  /// whole is the input there, which faces nowhere away.
  bool mend(int f) {
    const auto& t = faces_.tri[static_cast<std::size_t>(f)];
    for (int v : t)
      if (hasInput(v) && tryBack({v}, nullptr)) return true;
    std::vector<int> region, failed;
    for (int v : t)
      if (hasInput(v)) region.push_back(v);
    for (int grow = 0; grow <= kUnfoldGrowth && !region.empty(); ++grow) {
      failed.clear();
      if (tryBack(region, grow < kUnfoldGrowth ? &failed : nullptr)) return true;
      const std::size_t n = region.size();
      for (int g : failed)
        for (int v : faces_.tri[static_cast<std::size_t>(g)])
          if (hasInput(v) && std::find(region.begin(), region.end(), v) == region.end()) region.push_back(v);
      if (region.size() == n || region.size() > kUnfoldMaxRegion) break;
    }
    return false;
  }

  /// The faces around vs, sorted; false when one has a corner of more
  /// than kUnfoldMaxStar faces.
  bool collectStar(const std::vector<int>& vs) {
    std::size_t around = 0;
    for (int v : vs) around += vf_[static_cast<std::size_t>(v)].size();
    if (around > 3 * kUnfoldMaxStar) return false;
    star_.clear();
    for (int v : vs)
      for (int f : vf_[static_cast<std::size_t>(v)]) star_.push_back(f);
    std::sort(star_.begin(), star_.end());
    star_.erase(std::unique(star_.begin(), star_.end()), star_.end());
    for (int f : star_)
      for (int v : faces_.tri[static_cast<std::size_t>(f)])
        if (vf_[static_cast<std::size_t>(v)].size() > kUnfoldMaxStar) return false;
    return true;
  }

  /// Whether star face k (area0, turn0, angle0: before the move) is
  /// acceptable now.
  bool accepts(std::size_t k, const Vec3& area0, double turn0, double angle0) const {
    const std::size_t f = static_cast<std::size_t>(star_[k]);
    const Vec3 a = area(f);
    if (!(a.SquaredNorm() > 0)) return !(area0.SquaredNorm() > 0);  // no face loses its area
    if (area0.SquaredNorm() > 0 && !(a * area0 > 0)) return false;  // nor turns over
    if (minAngle(f) < angle0) return false;  // nor takes an angle below the mesh's and its own
    const auto& t = faces_.tri[f];
    if (bound_ > 0 && !nearInput(pos_[t[0]], pos_[t[1]], pos_[t[2]])) return false;  // nor leaves the bound
    // Nor faces away, nor turns beyond the bound unless it already did
    // and turns less now.
    const FacingInput::Verdict v = test(f);
    const double c = std::cos(v.turnRad);
    const bool beyond = maxTurnCos2_ > 0 && (c <= 0 || c * c < maxTurnCos2_);
    return v.measured && !v.away && (!beyond || v.turnRad <= turn0);
  }

  /// A face's corners, edge midpoints, centroid and the points halfway
  /// from it to the corners lie within the bound of the input.
  bool nearInput(const Vec3& a, const Vec3& b, const Vec3& c) const {
    const Vec3 g = (a + b + c) / 3.0;
    const Vec3 pts[10] = {a, b, c, (a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5, g, (g + a) * 0.5, (g + b) * 0.5,
                          (g + c) * 0.5};
    for (const Vec3& q : pts)
      if (!input_.within(q, bound_)) return false;
    return true;
  }

  /// Tries the vertices vs a quarter of the way back, then half of it,
  /// then all of it: the first state accepted stays. failed (may be null)
  /// gets the faces that refused the whole way.
  bool tryBack(const std::vector<int>& vs, std::vector<int>* failed) {
    if (!collectStar(vs)) return false;
    std::vector<Vec3> area0(star_.size()), before;
    std::vector<double> turn0(star_.size()), angle0(star_.size());
    for (std::size_t k = 0; k < star_.size(); ++k) {
      const std::size_t f = static_cast<std::size_t>(star_[k]);
      area0[k] = area(f);
      turn0[k] = test(f).turnRad;
      angle0[k] = std::min(floor_, minAngle(f));
    }
    for (int v : vs) before.push_back(pos_[static_cast<std::size_t>(v)]);
    for (double frac : {0.25, 0.5, 1.0}) {
      for (std::size_t i = 0; i < vs.size(); ++i) {
        const std::size_t v = static_cast<std::size_t>(vs[i]);
        pos_[v] = frac == 1.0 ? inputPos_[v] : before[i] + (inputPos_[v] - before[i]) * frac;
      }
      const bool collect = failed && frac == 1.0;
      bool ok = true;
      for (std::size_t k = 0; k < star_.size() && (ok || collect); ++k) {
        const bool good = accepts(k, area0[k], turn0[k], angle0[k]);
        if (!good && collect) failed->push_back(star_[k]);
        ok = ok && good;
      }
      if (ok) {
        for (int f : star_) away_[static_cast<std::size_t>(f)] = 0;
        if (moved_) moved_->insert(moved_->end(), vs.begin(), vs.end());
        moves_ += static_cast<int>(vs.size());
        return true;
      }
    }
    for (std::size_t i = 0; i < vs.size(); ++i) pos_[static_cast<std::size_t>(vs[i])] = before[i];
    return false;
  }

  std::vector<Vec3>& pos_;
  const FaceList& faces_;
  const std::vector<char>& deleted_;
  const std::vector<Vec3>& inputPos_;
  const FacingInput& input_;
  const double maxTurnCos2_, bound_;
  std::vector<int>* moved_;
  std::vector<char> away_;  ///< per face: faces away now
  std::vector<std::vector<int>> vf_;
  std::vector<int> star_;  ///< the faces tryBack tests
  double floor_ = kPi;     ///< the mesh's smallest angle, which no mending lowers
  int moves_ = 0;
};

}  // namespace detail

/// Puts vertices of the faces that face away from the input under them
/// (FacingInput::test) back towards their input positions inputPos (the
/// first inputPos.size() vertices of pos have one; the others, added by a
/// repair, stay): a quarter, half or all of the way, the first that is
/// accepted. A vertex moves only when afterwards no face around it faces
/// away, loses its area, turns over against its orientation before the
/// move, turns by more than maxTurnCos2 (0: no limit) from the input under
/// it (unless it already did and turns less), takes a smallest angle below
/// both its own and the mesh's, or (with a bound above 0) has a corner,
/// edge midpoint or point around its centroid farther than bound from the
/// input: the move mends where it stands and breaks nothing around. When
/// no single vertex of a face can mend it, its vertices go back together,
/// then with those of the faces that refused (Unfolder::mend). Faces
/// without area, deleted vertices and faces with a corner of more than
/// kUnfoldMaxStar faces are left alone. moved (may be null) gets every
/// vertex that moved. Detection costs one query of the input per live face
/// (on threads threads); the mending, a few per face found.
inline UnfoldResult unfoldFacingAway(std::vector<Vec3>& pos, const FaceList& faces, const std::vector<char>& deleted,
                                     const std::vector<Vec3>& inputPos, const FacingInput& input,
                                     double maxTurnCos2, double bound, int threads = 1,
                                     std::vector<int>* moved = nullptr) {
  return detail::Unfolder(pos, faces, deleted, inputPos, input, maxTurnCos2, bound, moved).run(threads);
}

}  // namespace sodt
