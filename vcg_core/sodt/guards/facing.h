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
// sliver folded against the surface in the input can open up on its
// folded side. Both read as faces facing away from the input under them, which
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
/// tree, each with its own orientation, and for a face folded against
/// the surface at its corners (foldedFaceSurfaceNormals) that surface's
/// orientation as a second one.
class FacingInput {
 public:
  FacingInput(const std::vector<Vec3>& pos, const FaceList& faces) : grid_(pos, faces) {
    const std::vector<Vec3> all = foldedFaceSurfaceNormals(faces, pos);
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

  /// The facing test. Over a folded face of the input, a face counts as
  /// facing away only when it also faces away from the surface there, and
  /// its turn is the nearer of the two; either side is a valid
  /// orientation there, and moves or a filter may unfold such a fold. maxNodes:
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
  /// The input point nearest q within r (InputGrid::closest).
  bool closest(const Vec3& q, double r, Vec3& out) const { return grid_.closest(q, r, out); }

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
  int flips = 0;  ///< edges flipped
  int left = 0;   ///< faces still facing away after
};

/// What unfoldFacingAway may do besides putting vertices back.
struct UnfoldFreedom {
  /// Flip edges (a run that may change the connectivity: flips, repair).
  bool flip = false;
  /// Per vertex (may be null): it may move to the middle of its
  /// neighbours, on the input (the run's smooth interior vertices, which
  /// the sweeps move freely too).
  const std::vector<char>* centre = nullptr;
  /// Per face (may be null or empty): the orientation the guards keep each
  /// face near; a flip gives both new faces the pair's, merged (as
  /// flipPass does).
  std::vector<Vec3>* refNormal = nullptr;
};

namespace detail {

/// The state of one unfoldFacingAway call (see there).
class Unfolder {
 public:
  Unfolder(std::vector<Vec3>& pos, FaceList& faces, const UnfoldFreedom& may, const std::vector<char>& deleted,
           const std::vector<Vec3>& inputPos, const FacingInput& input, double maxTurnCos2, double bound,
           std::vector<int>* moved)
      : pos_(pos), faces_(faces), may_(may), deleted_(deleted), inputPos_(inputPos), input_(input),
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
    res.flips = flips_;
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

  /// Face f's vertices back one at a time; else together, then with the
  /// vertices of the faces that refused, ring by ring: a patch put back
  /// whole is the input there, which faces nowhere away. Where the way
  /// back is barred (an input that is folded itself, a vertex the repair
  /// added, a smallest angle it would lower): one of its edges flipped
  /// (when the run may flip), else one of its vertices moved to the
  /// middle of its neighbours (those that may move so).
  bool mend(int f) {
    const auto t = faces_.tri[static_cast<std::size_t>(f)];
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
    if (may_.flip)
      for (int j = 0; j < 3; ++j)
        if (tryFlip(f, t[j], t[(j + 1) % 3])) return true;
    if (may_.centre)
      for (int v : t)
        if ((*may_.centre)[static_cast<std::size_t>(v)] && tryCentre(v)) return true;
    return false;
  }

  /// The corners of the star faces as they are now, to test the cover
  /// against after a change (keepsCover).
  std::vector<std::array<Vec3, 3>> starTriangles() const {
    std::vector<std::array<Vec3, 3>> tris;
    for (int f : star_) {
      const auto& t = faces_.tri[static_cast<std::size_t>(f)];
      tris.push_back({pos_[t[0]], pos_[t[1]], pos_[t[2]]});
    }
    return tris;
  }

  /// The other side of the bound, for a change that is not a way back to
  /// the input: the input points nearest the old faces' corners, edge
  /// midpoints and centroids (those within the bound of them) must lie
  /// within the bound of the star's faces now, or of the faces next to
  /// them. A flip across a crease or a
  /// vertex pulled off a tip would leave the input there uncovered. True
  /// without a bound.
  bool keepsCover(const std::vector<std::array<Vec3, 3>>& old) const {
    if (!(bound_ > 0)) return true;
    const double b2 = bound_ * bound_;
    std::vector<int> around;  // the star's faces and those next to them
    for (int f : star_)
      for (int v : faces_.tri[static_cast<std::size_t>(f)])
        for (int g : vf_[static_cast<std::size_t>(v)]) around.push_back(g);
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    for (const auto& o : old) {
      const Vec3 g = (o[0] + o[1] + o[2]) / 3.0;
      const Vec3 pts[7] = {o[0], o[1], o[2], (o[0] + o[1]) * 0.5, (o[1] + o[2]) * 0.5, (o[2] + o[0]) * 0.5, g};
      for (const Vec3& p : pts) {
        Vec3 q;
        if (!input_.closest(p, bound_, q)) continue;
        bool near = false;
        for (std::size_t k = 0; k < around.size() && !near; ++k) {
          const auto& t = faces_.tri[static_cast<std::size_t>(around[k])];
          near = pointTriangleDistance2(q, pos_[t[0]], pos_[t[1]], pos_[t[2]]) <= b2;
        }
        if (!near) return false;
      }
    }
    return true;
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

  /// Flips the edge a-b of face f = (a, b, c) against its other face
  /// g = (b, a, d) into c-d: f becomes (a, d, c), g (d, b, c). The
  /// undoing of a fold the vertices cannot undo: a sliver folded over its
  /// neighbour (both cover the part they overlap once, with opposite
  /// orientations) becomes two faces that cover the rest once, the right
  /// way up; an edge a flip made across a sharp edge goes back. Done only
  /// when a-b is a manifold edge of two flippable faces, c-d no edge yet,
  /// a and b keep three faces or more, and both new faces pass the tests
  /// of a move (accepts): none faces away, turns beyond the bound, has a
  /// smallest angle below the pair's before, or leaves the deviation
  /// bound; and the input the pair covered stays covered
  /// (keepsCover).
  bool tryFlip(int f, int a, int b) {
    const std::size_t fi = static_cast<std::size_t>(f);
    if (!faces_.flippable[fi]) return false;
    const auto& fa = vf_[static_cast<std::size_t>(a)];
    const auto& fb = vf_[static_cast<std::size_t>(b)];
    if (fa.size() < 4 || fb.size() < 4 || fa.size() > kUnfoldMaxStar || fb.size() > kUnfoldMaxStar) return false;
    int g = -1, d = -1, shared = 0;
    for (int h : fa) {
      const auto& u = faces_.tri[static_cast<std::size_t>(h)];
      if (std::find(u.begin(), u.end(), b) == u.end()) continue;
      ++shared;
      if (h == f) continue;
      for (int j = 0; j < 3; ++j)  // g runs b -> a
        if (u[j] == b && u[(j + 1) % 3] == a) { g = h; d = u[(j + 2) % 3]; }
    }
    const int c = thirdVertex(fi, a, b);
    if (shared != 2 || g < 0 || c < 0 || c == d || !faces_.flippable[static_cast<std::size_t>(g)]) return false;
    if (vf_[static_cast<std::size_t>(c)].size() > kUnfoldMaxStar || vf_[static_cast<std::size_t>(d)].size() > kUnfoldMaxStar)
      return false;  // as every mend: no corner of more faces (and c-d is looked up around c)
    for (int h : vf_[static_cast<std::size_t>(c)]) {
      const auto& u = faces_.tri[static_cast<std::size_t>(h)];
      if (std::find(u.begin(), u.end(), d) != u.end()) return false;  // c-d exists
    }
    const std::size_t gi = static_cast<std::size_t>(g);
    const double angle0 = std::min(minAngle(fi), minAngle(gi));  // not the mesh's: a flip is no way back
    const std::array<int, 3> oldF = faces_.tri[fi], oldG = faces_.tri[gi];
    star_.assign({f, g});
    const std::vector<std::array<Vec3, 3>> old = starTriangles();
    faces_.tri[fi] = {a, d, c};
    faces_.tri[gi] = {d, b, c};
    bool ok = true;
    for (std::size_t k = 0; k < 2 && ok; ++k) {
      const Vec3 now = area(static_cast<std::size_t>(star_[k]));
      // A new face has no orientation of its own before: each must have an
      // area, and the tests of a face that faced along the input.
      ok = now.SquaredNorm() > 0 && accepts(k, now, 0.0, angle0);
    }
    ok = ok && keepsCover(old);
    if (!ok) {
      faces_.tri[fi] = oldF;
      faces_.tri[gi] = oldG;
      return false;
    }
    const auto drop = [this](int v, int h) {
      auto& l = vf_[static_cast<std::size_t>(v)];
      l.erase(std::find(l.begin(), l.end(), h));
    };
    drop(a, g);
    drop(b, f);
    vf_[static_cast<std::size_t>(c)].push_back(g);
    vf_[static_cast<std::size_t>(d)].push_back(f);
    away_[fi] = away_[gi] = 0;
    if (may_.refNormal && may_.refNormal->size() == faces_.tri.size()) {
      auto& ref = *may_.refNormal;
      const Vec3 merged = ref[fi] + ref[gi];
      const double len = merged.Norm();
      ref[fi] = ref[gi] = len > 0 ? merged / len : Vec3(0, 0, 0);
    }
    ++flips_;
    return true;
  }
  /// Moves v to the input point nearest the centroid of its neighbours
  /// (within the bound, when there is one), then halfway there, under the
  /// tests of tryBack (but no smallest angle below the star's before) and
  /// keepsCover. A vertex pushed through the surface, its faces
  /// folded over the others around it, comes back inside its ring; the
  /// input position may be no help there (a fold of the input itself, or
  /// a vertex the repair added).
  bool tryCentre(int v) {
    const std::size_t vi = static_cast<std::size_t>(v);
    if (vf_[vi].size() < 3 || !collectStar({v})) return false;
    Vec3 sum(0, 0, 0);
    int n = 0;
    for (int f : vf_[vi])
      for (int u : faces_.tri[static_cast<std::size_t>(f)])
        if (u != v) sum += pos_[static_cast<std::size_t>(u)], ++n;
    Vec3 target;
    const double reach = bound_ > 0 ? bound_ : std::numeric_limits<double>::infinity();
    if (!input_.closest(sum / static_cast<double>(n), reach, target)) return false;
    // No face may end with a smallest angle below the star's before: not
    // the mesh's, which a way back to the input may reach.
    double starAngle = kPi;
    for (int f : star_) starAngle = std::min(starAngle, minAngle(static_cast<std::size_t>(f)));
    std::vector<Vec3> area0(star_.size());
    std::vector<double> turn0(star_.size()), angle0(star_.size(), starAngle);
    for (std::size_t k = 0; k < star_.size(); ++k) {
      const std::size_t f = static_cast<std::size_t>(star_[k]);
      area0[k] = away_[f] ? Vec3(0, 0, 0) : area(f);  // a face facing away may turn over
      turn0[k] = test(f).turnRad;
    }
    const Vec3 before = pos_[vi];
    const std::vector<std::array<Vec3, 3>> old = starTriangles();
    for (double frac : {1.0, 0.5}) {
      pos_[vi] = before + (target - before) * frac;
      bool ok = true;
      for (std::size_t k = 0; k < star_.size() && ok; ++k) ok = accepts(k, area0[k], turn0[k], angle0[k]);
      ok = ok && keepsCover(old);
      if (ok) {
        for (int f : star_) away_[static_cast<std::size_t>(f)] = 0;
        if (moved_) moved_->push_back(v);
        ++moves_;
        return true;
      }
    }
    pos_[vi] = before;
    return false;
  }
  int thirdVertex(std::size_t f, int a, int b) const {
    for (int v : faces_.tri[f])
      if (v != a && v != b) return v;
    return -1;
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
  FaceList& faces_;
  const UnfoldFreedom& may_;
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
  int flips_ = 0;
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
/// no single vertex of a face can mend it, one of its edges may flip
/// (may.flip; Unfolder::tryFlip), or one of its vertices move to the
/// middle of its neighbours (may.centre; Unfolder::tryCentre), under the
/// same tests; else its vertices go back together, then with those of the faces that
/// refused (Unfolder::mend). Faces
/// without area, deleted vertices and faces with a corner of more than
/// kUnfoldMaxStar faces are left alone. moved (may be null) gets every
/// vertex that moved. Detection costs one query of the input per live face
/// (on threads threads); the mending, a few per face found.
inline UnfoldResult unfoldFacingAway(std::vector<Vec3>& pos, FaceList& faces, const UnfoldFreedom& may,
                                     const std::vector<char>& deleted, const std::vector<Vec3>& inputPos,
                                     const FacingInput& input, double maxTurnCos2, double bound, int threads = 1,
                                     std::vector<int>* moved = nullptr) {
  return detail::Unfolder(pos, faces, may, deleted, inputPos, input, maxTurnCos2, bound, moved).run(threads);
}

}  // namespace sodt
