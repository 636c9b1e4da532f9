// SPDX-License-Identifier: GPL-3.0-or-later
// Local repair after the sweeps (opt-in, SodtParams::repair): where a
// triangle's smallest angle is still below a target, collapse the short edge
// of a needle, flip or split the long edge of a cap or of a sliver, or insert
// a point inside it (its circumcentre or an off-centre, on the input; the
// feature or border edge it would lie beyond or encroach on is split
// instead), and relax the changed neighbourhood with S-ODT under the guards,
// until no triangle is below the target or nothing more can be done; then,
// from the best state, polish with only the changes that raise the smallest
// angle around them. Feature edges (sharper than the feature angle, along a
// crease, or on the border) are never flipped, and collapsed only along
// their line (a vertex between two of them into one of its neighbours
// there, within the bound), corners never move, every change keeps the
// surface near the input both ways at sample points (input near the change
// -> output within kCoverLimitFactor bounds; output -> input within the
// bound, or, in a last tide where that left faces below the target, within
// kCoverLimitFactor and kRepairQuarterFactor bounds), and every face it
// makes or moves
// within the face-turn bound of the input face under it. The vertices it
// adds get their attributes (texture coordinates, colour, quality)
// interpolated along the edge they split or in the face they were inserted
// in.
#pragma once

#include "../maths/classify.h"
#include "../maths/corners.h"
#include "flips.h"
#include "../maths/geometry.h"
#include "../guards/cover.h"
#include "../guards/guarded_move.h"
#include "../guards/input_grid.h"
#include "../maths/local_solve.h"
#include "../params.h"
#include "../sweeps/run_setup.h"
#include "../maths/topology.h"
#include "../mesh/working_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace sodt {

/// The repair's local work around a vertex with more faces than this is
/// not worth its cost: it does not flip around it, relax it, nor relax the
/// whole star around it (a vertex of valence n in every round's region
/// would cost O(n) per round, and such a vertex is a fan's apex whose
/// needles no local change can lift).
constexpr std::size_t kRepairMaxStar = 64;
/// Passes of S-ODT relaxation over the neighbourhood of a round's changes.
/// Most of the repair's time, but not to be cut: with 2 the corpus median
/// fell from 13.2 to 10.8 degrees and the rounds that followed added more
/// vertices for no less time.
constexpr int kRepairRelaxSweeps = 4;

/// The input triangles near a face the repair replaces are found in balls
/// along it (or in one ball around all the faces replaced, where that is
/// smaller), each opening at most this many nodes of the input's tree
/// (about four triangles each); beyond, the change is refused. A sliver's
/// ball holds much of a small part: on a 788-vertex CAD part, with one
/// ball per face, 256 nodes refused every change, 1024 none that 100000
/// allowed.
constexpr long kRepairInputNodes = 1024;
/// The cover check measures each of the input's sample points near a
/// change once when there are at most this many (sorting out the repeated
/// ones costs more than it saves beyond).
constexpr std::size_t kRepairSortedPoints = 512;
/// A change at a vertex with more faces than this is refused before the
/// input is looked up: near such an apex every ball holds all its needles,
/// so each refusal would open kRepairInputNodes nodes (a double fan of
/// 20000 needles took 6 s with --flips --repair before the input cover,
/// over 60 s with it and no such limit). At 256, the caps of a CAD
/// cylinder fanned from a centre of valence 360 were never worked on.
constexpr std::size_t kRepairMaxCoverStar = 1024;
/// ... in at most this many balls along the face's longest edge.
constexpr double kRepairInputBalls = 16;

/// The faces a change makes must lie within the bound of the input at
/// their centroid, edge midpoints and the points halfway from the centroid
/// to each corner. The sweeps hold faces to the bound only at their
/// centroids and spoke midpoints: measured at these points, their faces on
/// a curved CAD part reach 1.1-1.18 bounds (gmsh_t13), so that no face
/// there can be replaced. Where the rounds leave faces below the target,
/// a last tide from their best state (the loose tide) holds the new faces
/// to kCoverLimitFactor bounds at those points (the slack the cover gives
/// the input's points the other way) and to this many at the quarter
/// points of their edges. Without the quarter points, the Hausdorff
/// distance of gmsh_lever rose from 0.146% to 0.186% of its diagonal; with
/// them held to 1.25 bounds too, most of the gain was lost (gmsh_t13 3.1
/// degrees instead of 15.9). Used from the start instead of in a last
/// tide, the looser check took the median smallest angle of the corpus
/// just as high but sent hinge from 25.1 to 18.7 degrees and two small
/// parts from 25 to 9-12 (the rounds take other paths). As a last tide,
/// measured on the corpus (--flips --repair): a median smallest angle of
/// 8.7 -> 12.2 degrees, 17 -> 19 meshes at 20 or more, Hausdorff above
/// 0.15% on 6 -> 4 meshes, for 8% more time.
constexpr double kRepairQuarterFactor = 1.5;

/// Where more faces are below the target than the budget has vertices, the
/// repair works on the worst triangles first: a round tries only the faces
/// below its tide, the smallest angle of the mesh times kRepairTideFactor
/// or plus kRepairTideStepDeg, whichever is larger (at most the target), so
/// that the budget goes to the worst triangles before any other. When a
/// round changes nothing, or kRepairTideStall rounds in a row do not raise
/// the smallest angle (its triangle is pinned), the next tide starts
/// kRepairTideRiseDeg above the last, until it reaches the target. Measured
/// with --flips --repair and the default budget: hinge ends at 10.1
/// degrees (3.3 trying every face below the target each round; a step of 2
/// gave 9.9, 4 gave 5.1). Under a tide where the budget suffices,
/// spot_badquality ended at 21.5 degrees instead of 25.2, so the tide is
/// kept for the meshes that need it.
constexpr double kRepairTideFactor = 1.2;
constexpr double kRepairTideStepDeg = 1.0;
constexpr double kRepairTideRiseDeg = 5.0;
constexpr int kRepairTideStall = 2;
/// The rounds on every face below the target, before any tide.
constexpr int kRepairPlainRounds = 30;
/// Plain rounds end when kRepairPlainPatience rounds in a row found no
/// better state than the best one; the tide then starts from that state
/// with what is left of the budget. On scans whose spikes the bound holds,
/// every round's splits leave a new face below the best smallest angle,
/// and 30 plain rounds returned the swept mesh (cgal_bones 4.4 degrees;
/// 8.6 with the tide after them). Measured on the corpus, 3 rounds cut off
/// late gains (occt_sh1 21.0 -> 18.9 degrees), 6 kept them.
constexpr int kRepairPlainPatience = 6;
/// Rounds under the tide end too when this many in a row found no better
/// state: where the worst triangle is pinned and every round leaves more
/// below the target (a fan's apex of valence 20000 with --flips --repair:
/// twelve rounds added 20000 vertices, each state worse than the swept
/// mesh, which was returned), the rest is work thrown away (that fan took
/// 4.7 s instead of 13). Measured on the corpus, 4 rounds cut off late
/// gains (occt_shape 20.4 -> 6.4 degrees); 6 changed two meshes by 1-3
/// degrees and took the median repair time from 16 to 9 times the
/// sweeps'.
constexpr int kRepairTidePatience = 6;

/// A target above this many degrees is reached in two stages (see
/// LocalRepair::run): first to this angle, then to the target. Measured
/// with the default target of 30 degrees, --flips --repair: hinge ends at
/// 30.1 degrees in two stages, at 11.5 in one (the rounds spend the budget
/// on faces between 25 and 30 degrees before the worst ones are fixed);
/// on the corpus, against one stage to 25, 26 meshes rose and none fell
/// (13 instead of 3 at 30 degrees or more), for 10-20% more repair time.
constexpr double kRepairFirstStageDeg = 25;

/// After the rounds, from their best state, the repair polishes: at most
/// this many more rounds on every face below the target, in which a
/// change is kept only when the smallest angle of the faces it changed
/// rose (or stayed with fewer below the target), so that the mesh's
/// cannot fall; they end when a round finds no better state. Measured on
/// the corpus (--flips --repair): needles 12471 -> 9803, caps 2980 ->
/// 2508, 5 meshes up by 0.5-1.4 degrees and none down, median vertex
/// growth 9.4% -> 13.1%, 10% more time; 10 rounds instead of 4 changed
/// no smallest angle and removed 28 more needles.
constexpr int kRepairPolishRounds = 4;

/// A crease vertex may be collapsed along its crease where the crease turns
/// there by at most this (and the bound holds): a tessellated curve, not a
/// corner of the feature line.
constexpr double kRepairCreaseCollapseTurnDeg = 30;

/// Two vertices at most this times the distance bound apart may be merged
/// whatever their roles (a weld, see LocalRepair::tryCollapse): a CAD
/// export often has two copies of a point on a feature line a hair apart
/// (gmsh_lever: two crease vertices 0.0025 apart, 4% of its bound, with a
/// 0.03-degree sliver between them that no split, flip or insertion can
/// open). Measured on the corpus (--flips --repair): at 0.05, five meshes
/// rose by 0.4-8 degrees and one fell by 0.6; at 0.25, welds of close
/// vertices that were no copies lowered five (occt_sh2 13.5 -> 8.1).
constexpr double kRepairWeldFactor = 0.05;

/// What the repair may do.
struct RepairSettings {
  double targetRad = 25 * kPi / 180;   ///< smallest angle to reach
  double featureRad = 30 * kPi / 180;  ///< edges whose faces turn more are features
  double flipMaxRad = 20 * kPi / 180;  ///< flips only across flatter edges
  double bound = 0;                    ///< distance bound, both ways (0: none)
  /// Squared cosine of the largest turn of a face the repair makes or moves
  /// from the input face under it (faceTurnCos2; 0: 90 degrees, the sign
  /// test alone).
  double maxTurnCos2 = 0;
  int maxRounds = 100;  ///< of the rounds under a tide
  long long maxAdded = 0;  ///< vertices added, at most (removing one costs nothing)
  bool polish = true;  ///< polishing rounds after the best state (kRepairPolishRounds)
};

/// Where the repair put a vertex it added, from up to three working
/// vertices (added ones among them, added before it): (1 - t - s) a + t b
/// + s c, then projected on the input. An edge split has c = -1 and s = 0
/// (a + t (b - a)); a point inserted inside face (a, b, c) has its
/// barycentric coordinates there.
struct EdgePoint {
  int a, b;
  double t;
  int c = -1;
  double s = 0;
  /// The weight of a, b and c.
  std::array<double, 3> weights() const { return {{1 - t - s, t, s}}; }
};

/// Counts of one repair.
struct RepairResult {
  int splits = 0, collapses = 0, flips = 0, inserts = 0;
  int added = 0, removed = 0;
  long long relaxMoves = 0;
  std::vector<RemainingTriangle> remaining;
};

/// The repair on the working arrays: pos and deleted grow by the added
/// vertices, faces by the added faces; removed vertices are flagged
/// deleted and removed faces not live. Vertices with movable[v] unset
/// never move nor go, but for border vertices (setUp's border), which may
/// go along the border; newCrease receives, per added vertex, whether it
/// lies on a feature edge.
class LocalRepair {
 public:
  /// Free moves in its tangent plane; Crease along its feature line, and
  /// may go into a neighbour there; Border never moves, and may go into a
  /// neighbour along the border; Fixed neither moves nor goes.
  enum class Role : unsigned char { Free, Crease, Border, Fixed };

  LocalRepair(std::vector<Vec3>& pos, FaceList& faces, std::vector<char>& deleted, const InputGrid* input,
              const RepairSettings& s)
      : pos_(pos), faces_(faces), deleted_(deleted), input_(input), s_(s) {}

  /// Marks the feature edges and the roles. creaseDir (may be null) adds
  /// the edges that follow a classified crease; border (may be null) the
  /// vertices not movable that may still go along the border, where they
  /// have exactly two feature edges (its two border edges); corners (may
  /// be null) the vertices not movable that may still be welded onto a
  /// neighbour (kRepairWeldFactor): the interior corners the run may change.
  void setUp(const std::vector<char>& movable, const std::vector<VertexClass>* cls,
             const std::vector<Vec3>* creaseDir, const std::vector<char>* border = nullptr,
             const std::vector<char>* corners = nullptr);

  RepairResult run();

  const std::vector<char>& newCrease() const { return newCrease_; }
  /// Per added vertex, in order, the edge it split or the face it was inserted in.
  const std::vector<EdgePoint>& added() const { return added_; }

 private:
  enum Verdict { Done = 0, NoGain, Feature, Topology, OverBound };

  static std::uint64_t key(int a, int b) {
    if (a > b) std::swap(a, b);
    return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
  }
  bool isFeature(int a, int b) const { return feature_.count(key(a, b)) > 0; }
  /// Whether v may be welded: an input vertex the run may change (movable,
  /// or an interior corner), or one the repair added off the border.
  bool mayWeld(int v) const {
    if (deleted_[v]) return false;
    return std::size_t(v) < welds_.size() ? welds_[v] != 0 : role_[v] != Role::Border;
  }
  /// Whether a may be welded onto b: both may be (mayWeld), b off the
  /// border, within kRepairWeldFactor of the bound.
  bool weldable(int a, int b) const {
    const double reach = kRepairWeldFactor * s_.bound;
    return reach > 0 && mayWeld(a) && mayWeld(b) && role_[b] != Role::Border &&
           (pos_[a] - pos_[b]).SquaredNorm() <= reach * reach;
  }
  /// After a was welded onto b: a's feature edges to lines end at b, and
  /// b's role follows from its feature edges.
  void moveFeatures(int a, int b, const std::vector<int>& lines);
  int third(int f, int a, int b) const {
    for (int v : faces_.tri[f])
      if (v != a && v != b) return v;
    return -1;
  }
  /// Live faces with both a and b.
  int edgeFaces(int a, int b, int out[2]) const;
  /// f1 holds a -> b, f2 holds b -> a; false unless the edge has exactly those two.
  bool interiorEdge(int a, int b, int& f1, int& f2) const;
  bool hasEdge(int a, int b) const {
    int dummy[2];
    return edgeFaces(a, b, dummy) > 0;
  }
  /// Whether v's faces leave its star open (more neighbours than faces):
  /// v lies on a border.
  bool openStar(int v) const {
    std::vector<int> around;
    for (int f : vf_[v])
      for (int u : faces_.tri[f])
        if (u != v) around.push_back(u);
    std::sort(around.begin(), around.end());
    return static_cast<std::size_t>(std::unique(around.begin(), around.end()) - around.begin()) > vf_[v].size();
  }
  /// Whether v would keep too few faces after losing one: fewer than three
  /// inside, none on a border (its star is looked at only when small).
  bool tooFewFacesToLoseOne(int v) const { return vf_[v].size() <= 1 || (vf_[v].size() <= 3 && !openStar(v)); }
  double faceMinAngle(int f) const {
    const auto& t = faces_.tri[f];
    return triangleMinAngle(pos_[t[0]], pos_[t[1]], pos_[t[2]]);
  }
  /// The sample points of the triangles lie near the input: centroids,
  /// edge midpoints and the points halfway from the centroid to each
  /// corner within the bound; in the loose tide (loose_), within
  /// kCoverLimitFactor bounds, and the edges' quarter points within
  /// kRepairQuarterFactor bounds.
  bool nearInput(const std::vector<std::array<Vec3, 3>>& tris) const;
  /// nearInput of the star's faces with its centre at y; rim (-1 at a
  /// relax's first call) keeps whether the points of the rim's edges,
  /// which do not move with the centre, are near: they are looked up once
  /// per relax, and each point of a spoke once, not once per face.
  bool starNearInput(const Vec3& y, const Star& st, int& rim) const;
  /// q lies within the bound of one of tris: the input point q is not cut off.
  bool covered(const Vec3& q, const std::vector<std::array<Vec3, 3>>& tris) const;
  /// Faces old becoming made keeps the input near them covered, as the
  /// sweeps' cover does: every sample point of the input triangles near old
  /// (corners, edge midpoints and quarter points, centroid) that lies
  /// within kCoverLimitFactor bounds of old or of the faces around them
  /// stays that near made or those faces.
  bool keepsInputCovered(const std::vector<int>& old, const std::vector<std::array<Vec3, 3>>& made) const;
  /// What keepsInputCovered measures of old alone, for trying several
  /// made in place of the same faces (relax's steps): the sample points
  /// of the input triangles near old that lie within reach of old, each
  /// once, and the faces around old; unknown (gaveUp) when the input near
  /// them is too large to search.
  struct CoverProbe {
    bool off = false, gaveUp = false;
    double reach2 = 0;
    std::vector<Vec3> points;
    std::vector<std::array<Vec3, 3>> around;
    /// Per point: 0 not yet measured, 1 within reach of around, 2 not.
    mutable std::vector<char> nearAround;
  };
  CoverProbe coverProbe(const std::vector<int>& old) const;
  std::vector<std::array<Vec3, 3>> facesAround(const std::vector<int>& old) const;
  bool coverHolds(const CoverProbe& probe, const std::vector<std::array<Vec3, 3>>& made) const;
  /// A corner of the faces has more than kRepairMaxCoverStar faces: a
  /// change of them is refused before anything is measured.
  bool atHugeStar(const std::vector<int>& faces) const {
    for (int f : faces)
      for (int v : faces_.tri[f])
        if (vf_[v].size() > kRepairMaxCoverStar) return true;
    return false;
  }
  /// Each of tris has area and keeps within the face-turn bound of the
  /// input face under its centroid (InputGrid::under).
  bool keepsTurn(const std::vector<std::array<Vec3, 3>>& tris) const;
  /// Adds f to v's faces. A star larger than kRepairMaxStar keeps where
  /// each face is (bigAt_), so that removing one costs O(1), not O(n).
  void addToVf(int v, int f) {
    auto& l = vf_[v];
    l.push_back(f);
    if (l.size() == kRepairMaxStar + 1)
      for (std::size_t k = 0; k < l.size(); ++k) bigAt_[slot(v, l[k])] = static_cast<int>(k);
    else if (l.size() > kRepairMaxStar + 1)
      bigAt_[slot(v, f)] = static_cast<int>(l.size() - 1);
  }
  /// Removes f from v's faces: keeping their order in a small star, moving
  /// the last one into its place in a large one.
  void removeFromVf(int v, int f) {
    auto& l = vf_[v];
    if (l.size() <= kRepairMaxStar) {
      l.erase(std::remove(l.begin(), l.end(), f), l.end());
      return;
    }
    const auto it = bigAt_.find(slot(v, f));
    if (it == bigAt_.end()) return;
    const int k = it->second;
    bigAt_.erase(it);
    if (k + 1 != static_cast<int>(l.size())) {
      l[k] = l.back();
      bigAt_[slot(v, l[k])] = k;
    }
    l.pop_back();
    if (l.size() == kRepairMaxStar)
      for (int g : l) bigAt_.erase(slot(v, g));
  }
  /// Empties v's faces.
  void clearVf(int v) {
    if (vf_[v].size() > kRepairMaxStar)
      for (int g : vf_[v]) bigAt_.erase(slot(v, g));
    vf_[v].clear();
  }
  static std::uint64_t slot(int v, int f) { return (std::uint64_t(std::uint32_t(v)) << 32) | std::uint32_t(f); }
  /// bigAt_ for the large stars of vf_ as it is.
  void indexLargeStars() {
    bigAt_.clear();
    for (std::size_t v = 0; v < vf_.size(); ++v)
      if (vf_[v].size() > kRepairMaxStar)
        for (std::size_t k = 0; k < vf_[v].size(); ++k) bigAt_[slot(int(v), vf_[v][k])] = static_cast<int>(k);
  }

  /// While an insertion is tried: the corners and stars before each
  /// change its flips made, to undo them all when it does not pay.
  struct Journal {
    std::vector<std::pair<int, std::array<int, 3>>> faces;
    std::vector<std::pair<int, std::vector<int>>> stars;
  };
  void keep(int f, std::initializer_list<int> vertices) {
    if (!journal_) return;
    journal_->faces.push_back({f, faces_.tri[f]});
    for (int v : vertices) journal_->stars.push_back({v, vf_[v]});
  }
  /// Sets v's faces to l (large stars indexed in bigAt_).
  void setVf(int v, const std::vector<int>& l) {
    clearVf(v);
    vf_[v] = l;
    if (l.size() > kRepairMaxStar)
      for (std::size_t k = 0; k < l.size(); ++k) bigAt_[slot(v, l[k])] = static_cast<int>(k);
  }
  /// Undoes what j recorded, latest first.
  void undo(const Journal& j) {
    for (auto it = j.faces.rbegin(); it != j.faces.rend(); ++it) faces_.tri[it->first] = it->second;
    for (auto it = j.stars.rbegin(); it != j.stars.rend(); ++it) setVf(it->first, it->second);
  }
  Verdict tryFlip(int a, int b);
  Verdict tryFlipUnderCap(int a, int b);
  /// Edge a-b of faces f1 (a, b, c) and f2 (b, a, d) becomes c-d.
  void applyFlip(int f1, int f2, int a, int b, int c, int d);
  Verdict tryCollapse(int a, int b);
  Verdict collapseAlongCrease(int a, int b, int& q) const;
  Verdict trySplit(int a, int b, double at = 0.5);
  Verdict trySplitIfBetter(int a, int b, double at = 0.5);
  /// trySplit, or trySplitIfBetter while polishing.
  Verdict split(int a, int b, double at = 0.5) { return polish_ ? trySplitIfBetter(a, b, at) : trySplit(a, b, at); }
  bool keepIfBetter(Journal& j, std::size_t nf0, std::size_t nt0, const RepairResult& counts);
  Verdict trySplitBorder(int a, int b);
  /// Where a walk from a face toward a point in its plane ended.
  struct Located {
    int face = -1;                 ///< the face holding the point (-1: none)
    double bary[3] = {0, 0, 0};    ///< its barycentric coordinates there
    int blockA = -1, blockB = -1;  ///< a feature or border edge the point lies beyond or encroaches on
  };
  Located locate(int f, const Vec3& target) const;
  Verdict tryInsert(int f);
  Verdict insertInFace(int g, const double bary[3]);
  bool foldsNeighbour(int g, const std::vector<std::array<Vec3, 3>>& made) const;
  bool fixFace(int f, RepairReason& why);
  void flipAround(const std::vector<int>& vertices);
  bool relax(int v);
  bool orderedRing(int v, std::vector<int>& ring) const;
  /// Why an attempt on a face failed, and the face as it was then: the
  /// reason holds while the face is unchanged.
  struct Left {
    RepairReason why = RepairReason::Rounds;
    std::array<int, 3> tri{{-1, -1, -1}};
  };
  /// The smallest angle of the live faces outside the protected corners
  /// (protectedCorners: where features meet at less than the target, the
  /// measure the report gives), and how many faces are below the target;
  /// all (when given) receives the smallest angle of every live face.
  void score(double& minAngle, std::size_t& below, double* all = nullptr) const;
  /// The smallest angle outside the protected corners as the report
  /// measures it: every edge whose faces turn more than the feature angle
  /// is a feature, whether or not the repair started with it as one.
  double reportedMinAngle() const;
  struct Snapshot;
  void save(Snapshot& s) const;
  void restore(const Snapshot& s);
  bool round(std::vector<Left>& why, bool& budgetOut);
  /// How rounds() ended.
  enum class Stop { Done, Patience, Budget, Rounds };
  /// Whether state x ranks above y: a larger smallest angle outside the
  /// protected corners, up to the target (beyond, all states tie), then
  /// fewer faces below the target.
  bool ranksAbove(const Snapshot& x, const Snapshot& y) const;
  Stop rounds(bool tide, int maxRounds, int patience, Snapshot& best, std::vector<Left>& why);
  /// Rounds from the current state, under a tide or plain (handing over to
  /// the tide after kRepairPlainPatience rounds without a better state);
  /// the best state is left in place and in best.
  Stop attempt(bool tide, Snapshot& best);
  /// What a stage leaves for the report: each face's reason, and whether
  /// the budget ended it.
  struct StageEnd {
    std::vector<Left> why;
    bool budgetOut = false;
  };
  /// The repair towards s_.targetRad from the current state (see run()).
  StageEnd stage();
  /// Lists in r_.remaining the faces below the target and why (end).
  void listRemaining(const StageEnd& end);

  std::vector<Vec3>& pos_;
  FaceList& faces_;
  std::vector<char>& deleted_;
  const InputGrid* input_;
  RepairSettings s_;
  std::vector<Role> role_;
  std::vector<char> welds_;  ///< per vertex of the input: whether it may be welded (mayWeld)
  std::vector<std::vector<int>> vf_;
  std::unordered_map<std::uint64_t, int> bigAt_;  ///< slot(v, f) -> position of f in vf_[v], large stars only
  std::unordered_set<std::uint64_t> feature_;
  std::vector<char> newCrease_;
  std::vector<EdgePoint> added_;
  std::vector<int> touched_;
  RepairResult r_;
  Journal* journal_ = nullptr;  ///< set while an insertion is tried
  bool polish_ = false;         ///< only changes that raise the smallest angle around them
  bool useTide_ = false;        ///< the rounds work below a tide (else below the target)
  double tideFloor_ = 0;        ///< the next round's tide is at least this (radians)
  double tide_ = 0;             ///< the last round's tide
  double floorAll_ = 0;         ///< the smallest angle of every face at the start
  mutable std::vector<unsigned> seenAt_;  ///< per input triangle, the last coverProbe that took it
  mutable unsigned probeStamp_ = 0;
  bool loose_ = false;  ///< the loose tide's check of the new faces (kRepairQuarterFactor)
};

inline int LocalRepair::edgeFaces(int a, int b, int out[2]) const {
  // Through the smaller star: a vertex of valence n costs O(n) only when
  // both ends are that large.
  if (vf_[b].size() < vf_[a].size()) std::swap(a, b);
  int n = 0;
  for (int f : vf_[a]) {
    const auto& t = faces_.tri[f];
    if (t[0] == b || t[1] == b || t[2] == b) {
      if (n < 2) out[n] = f;
      ++n;
    }
  }
  return n;
}

inline bool LocalRepair::interiorEdge(int a, int b, int& f1, int& f2) const {
  int fs[2];
  if (edgeFaces(a, b, fs) != 2 || !faces_.flippable[fs[0]] || !faces_.flippable[fs[1]]) return false;
  const auto follows = [this](int f, int x, int y) {
    const auto& t = faces_.tri[f];
    for (int j = 0; j < 3; ++j)
      if (t[j] == x && t[(j + 1) % 3] == y) return true;
    return false;
  };
  if (follows(fs[0], a, b) && follows(fs[1], b, a)) {
    f1 = fs[0], f2 = fs[1];
  } else if (follows(fs[1], a, b) && follows(fs[0], b, a)) {
    f1 = fs[1], f2 = fs[0];
  } else {
    return false;  // inconsistent winding
  }
  return true;
}

inline void LocalRepair::setUp(const std::vector<char>& movable, const std::vector<VertexClass>* cls,
                               const std::vector<Vec3>* creaseDir, const std::vector<char>* border,
                               const std::vector<char>* corners) {
  const int nv = static_cast<int>(pos_.size());
  welds_.assign(nv, 0);
  for (int v = 0; v < nv; ++v) welds_[v] = !deleted_[v] && (movable[v] || (corners && (*corners)[v]));
  vf_.assign(nv, {});
  bigAt_.clear();
  for (std::size_t f = 0; f < faces_.tri.size(); ++f)
    if (faces_.live[f])
      for (int v : faces_.tri[f]) addToVf(v, static_cast<int>(f));
  role_.assign(nv, Role::Free);
  for (int v = 0; v < nv; ++v)
    if (deleted_[v]) role_[v] = Role::Fixed;
    else if (!movable[v]) role_[v] = border && (*border)[v] ? Role::Border : Role::Fixed;
  const double cosFeature = std::cos(s_.featureRad);
  // Without a classification (basic), an edge of a sliver is no feature: a
  // sliver's normal is nearly arbitrary, so the angle across its edges says
  // nothing, and taken for features they pinned exactly the faces to mend.
  // Measured on the corpus's 21 scans, organic models and isosurfaces: 3
  // up by 1-3.5 degrees, none down. With a classification, whose creases
  // are features anyway, the same rule swung the CAD exports both ways
  // (hinge 12.0 -> 5.0 degrees, cgal_blade 0.8 -> 8.7).
  const double sliverRad = kSliverNormalDeg * kPi / 180;
  const auto featureClass = [&](int v) {
    return cls && ((*cls)[v] == VertexClass::Crease || (*cls)[v] == VertexClass::Corner);
  };
  const auto around = [this](int v, const auto& visit) {
    for (int f : vf_[v])
      for (int u : faces_.tri[f])
        if (u != v) visit(u);
  };
  // Follows the crease of every crease end (a corner-corner edge counts;
  // see sodt::alongCrease in flips.h).
  const auto onCrease = [&](int a, int b) {
    if (!featureClass(a) || !featureClass(b) || !creaseDir) return false;
    if (!((pos_[b] - pos_[a]).SquaredNorm() > 0)) return false;
    for (int v : {a, b})
      if ((*cls)[v] == VertexClass::Crease && !alongCrease(pos_, v, v == a ? b : a, (*creaseDir)[v], around))
        return false;
    return true;
  };
  for (int a = 0; a < nv; ++a) {
    for (int f : vf_[a]) {
      for (int b : faces_.tri[f]) {
        if (b <= a) continue;
        int f1, f2;
        bool feat = !interiorEdge(a, b, f1, f2);  // border, non-manifold
        if (!feat) {
          const auto &t1 = faces_.tri[f1], &t2 = faces_.tri[f2];
          const Vec3 n1 = doubleAreaVector(pos_[t1[0]], pos_[t1[1]], pos_[t1[2]]);
          const Vec3 n2 = doubleAreaVector(pos_[t2[0]], pos_[t2[1]], pos_[t2[2]]);
          const double l = n1.Norm() * n2.Norm();
          if (cls)
            feat = !(l > 0) || n1 * n2 < cosFeature * l || onCrease(a, b);
          else  // no sliver edge (see sliverRad)
            feat = std::min(faceMinAngle(f1), faceMinAngle(f2)) >= sliverRad && n1 * n2 < cosFeature * l;
        }
        if (feat) feature_.insert(key(a, b));
      }
    }
  }
  std::vector<int> count(nv, 0);
  for (std::uint64_t k : feature_) ++count[int(k >> 32)], ++count[int(k & 0xFFFFFFFF)];
  for (int v = 0; v < nv; ++v)
    if (role_[v] == Role::Free && count[v] > 0)
      role_[v] = count[v] == 2 ? Role::Crease : Role::Fixed;
    else if (role_[v] == Role::Border && count[v] != 2)
      role_[v] = Role::Fixed;
}

inline bool LocalRepair::nearInput(const std::vector<std::array<Vec3, 3>>& tris) const {
  if (!input_ || !(s_.bound > 0)) return true;
  const double inner = (loose_ ? kCoverLimitFactor : 1.0) * s_.bound, quarter = kRepairQuarterFactor * s_.bound;
  for (const auto& t : tris) {
    const Vec3 pts[7] = {(t[0] + t[1] + t[2]) / 3.0,     (t[0] + t[1]) * 0.5,          (t[1] + t[2]) * 0.5,
                         (t[2] + t[0]) * 0.5,           (t[0] * 4 + t[1] + t[2]) / 6, (t[0] + t[1] * 4 + t[2]) / 6,
                         (t[0] + t[1] + t[2] * 4) / 6};
    for (const Vec3& q : pts)
      if (!input_->within(q, inner)) return false;
    for (int j = 0; j < 3 && loose_; ++j) {
      const Vec3 &a = t[j], &b = t[(j + 1) % 3];
      if (!input_->within((a * 3 + b) * 0.25, quarter) || !input_->within((a + b * 3) * 0.25, quarter)) return false;
    }
  }
  return true;
}

inline bool LocalRepair::starNearInput(const Vec3& y, const Star& st, int& rim) const {
  if (!input_ || !(s_.bound > 0)) return true;
  const double inner = (loose_ ? kCoverLimitFactor : 1.0) * s_.bound, quarter = kRepairQuarterFactor * s_.bound;
  const std::size_t n = st.size();
  if (rim < 0) {
    rim = 1;
    for (std::size_t k = 0; k < n && rim; ++k) {
      const Vec3 &a = st.at(k), &b = st.at(k + 1);
      rim = input_->within((a + b) * 0.5, inner) &&
            (!loose_ || (input_->within((a * 3 + b) * 0.25, quarter) && input_->within((a + b * 3) * 0.25, quarter)));
    }
  }
  if (!rim) return false;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 &a = st.at(k), &b = st.at(k + 1);
    const Vec3 pts[5] = {(y + a + b) / 3.0, (y + a) * 0.5, (y * 4 + a + b) / 6, (y + a * 4 + b) / 6, (y + a + b * 4) / 6};
    for (const Vec3& q : pts)
      if (!input_->within(q, inner)) return false;
    if (loose_ && (!input_->within((y * 3 + a) * 0.25, quarter) || !input_->within((y + a * 3) * 0.25, quarter)))
      return false;
  }
  return true;
}

inline bool LocalRepair::covered(const Vec3& q, const std::vector<std::array<Vec3, 3>>& tris) const {
  if (!(s_.bound > 0)) return true;
  for (const auto& t : tris)
    if (pointTriangleDistance2(q, t[0], t[1], t[2]) <= s_.bound * s_.bound) return true;
  return false;
}

/// The squared distance from q to the nearest of tris, or the first one
/// found at most stop2.
inline double nearestSquaredDistance(const Vec3& q, const std::vector<std::array<Vec3, 3>>& tris, double stop2) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : tris) {
    best = std::min(best, pointTriangleDistance2(q, t[0], t[1], t[2]));
    if (best <= stop2) break;
  }
  return best;
}

/// The faces that share a corner with old (at a corner with a large star,
/// only those across old's edges there), old excepted, as triangles.
inline std::vector<std::array<Vec3, 3>> LocalRepair::facesAround(const std::vector<int>& old) const {
  std::vector<int> aroundFaces;
  for (int f : old) {
    const auto& t = faces_.tri[f];
    for (int j = 0; j < 3; ++j) {
      const int v = t[j];
      if (vf_[v].size() <= kRepairMaxStar) {
        aroundFaces.insert(aroundFaces.end(), vf_[v].begin(), vf_[v].end());
        continue;
      }
      // A larger star (a fan's apex) is not gathered whole, which would
      // cost O(n) per change: only the faces across the old face's two
      // edges at v, found in the other end's star when that is small.
      for (int k : {t[(j + 1) % 3], t[(j + 2) % 3]})
        if (vf_[k].size() <= kRepairMaxStar)
          for (int g : vf_[k])
            for (int u : faces_.tri[g])
              if (u == v) aroundFaces.push_back(g);
    }
  }
  std::sort(aroundFaces.begin(), aroundFaces.end());
  aroundFaces.erase(std::unique(aroundFaces.begin(), aroundFaces.end()), aroundFaces.end());
  std::vector<std::array<Vec3, 3>> around;
  for (int g : aroundFaces)
    if (std::find(old.begin(), old.end(), g) == old.end()) {
      const auto& t = faces_.tri[g];
      around.push_back({pos_[t[0]], pos_[t[1]], pos_[t[2]]});
    }
  return around;
}

inline LocalRepair::CoverProbe LocalRepair::coverProbe(const std::vector<int>& old) const {
  CoverProbe probe;
  if (!input_ || !(s_.bound > 0)) {
    probe.off = true;
    return probe;
  }
  const double reach = kCoverLimitFactor * s_.bound, reach2 = reach * reach;
  probe.reach2 = reach2;
  std::vector<std::array<Vec3, 3>> before;
  for (int f : old) {
    const auto& t = faces_.tri[f];
    before.push_back({pos_[t[0]], pos_[t[1]], pos_[t[2]]});
  }
  probe.around = facesAround(old);
  // The box of the old faces, grown by reach: no point outside it is
  // within reach of them.
  Vec3 lo = before[0][0], hi = before[0][0];
  for (const auto& t : before)
    for (const Vec3& x : t)
      for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], x[i]), hi[i] = std::max(hi[i], x[i]);
  for (int i = 0; i < 3; ++i) lo[i] -= reach, hi[i] += reach;
  const auto inBox = [&lo, &hi](const Vec3& x) {
    return x[0] >= lo[0] && x[0] <= hi[0] && x[1] >= lo[1] && x[1] <= hi[1] && x[2] >= lo[2] && x[2] <= hi[2];
  };
  const auto meetsBox = [&](int k) {
    const auto& t = input_->triangle(k);
    for (int i = 0; i < 3; ++i)
      if (std::max({t[0][i], t[1][i], t[2][i]}) < lo[i] || std::min({t[0][i], t[1][i], t[2][i]}) > hi[i]) return false;
    return true;
  };
  // Each input triangle is taken once, at the first ball whose search
  // meets its box; triangles beyond reach add only points that the test
  // against before drops.
  if (seenAt_.size() != std::size_t(input_->size())) seenAt_.assign(std::size_t(input_->size()), 0);
  if (++probeStamp_ == 0) {
    std::fill(seenAt_.begin(), seenAt_.end(), 0);
    probeStamp_ = 1;
  }
  const unsigned stamp = probeStamp_;
  std::vector<int> near;
  const auto take = [&](int k) {
    if (seenAt_[std::size_t(k)] == stamp) return;
    seenAt_[std::size_t(k)] = stamp;
    if (meetsBox(k)) near.push_back(k);
  };
  // Balls along each old face's longest edge: every point of the face
  // lies within its height over that edge of it, so a sliver needs a row
  // of small balls, not one as long as itself. Where one ball around all
  // of old is no larger than the row in all (a star of well-shaped faces),
  // that ball is searched instead.
  std::vector<std::pair<Vec3, double>> row;
  double rowArea = 0;
  for (const auto& t : before) {
    int e = 0;
    for (int j = 1; j < 3; ++j)
      if ((t[(j + 1) % 3] - t[j]).SquaredNorm() > (t[(e + 1) % 3] - t[e]).SquaredNorm()) e = j;
    const Vec3 &a = t[e], &b = t[(e + 1) % 3], &c = t[(e + 2) % 3];
    const double len = (b - a).Norm();
    const double height = len > 0 ? ((b - a) ^ (c - a)).Norm() / len : (c - a).Norm();
    const double spacing = std::max(height + reach, len / kRepairInputBalls);
    const int balls = std::max(1, static_cast<int>(std::ceil(len / spacing)));
    for (int i = 0; i < balls; ++i) {
      const double r = len / (2.0 * balls) + height + reach;
      row.push_back({a + (b - a) * ((i + 0.5) / balls), r});
      rowArea += r * r;
    }
  }
  const Vec3 mid = (lo + hi) * 0.5, half = (hi - lo) * 0.5 - Vec3(reach, reach, reach);
  const double whole = half.Norm() + reach;
  if (!(whole * whole <= rowArea && input_->forEachCandidate(mid, whole, take, kRepairInputNodes)))
    for (const auto& ball : row)
      if (!input_->forEachCandidate(ball.first, ball.second, take, kRepairInputNodes)) {
        probe.gaveUp = true;
        return probe;
      }
  std::vector<Vec3>& pts = probe.points;
  for (int k : near) {
    const auto& t = input_->triangle(k);
    const Vec3 all[13] = {t[0], t[1], t[2], (t[0] + t[1]) * 0.5, (t[1] + t[2]) * 0.5, (t[2] + t[0]) * 0.5,
                          (t[0] * 3 + t[1]) * 0.25, (t[0] + t[1] * 3) * 0.25, (t[1] * 3 + t[2]) * 0.25,
                          (t[1] + t[2] * 3) * 0.25, (t[2] * 3 + t[0]) * 0.25, (t[2] + t[0] * 3) * 0.25,
                          (t[0] + t[1] + t[2]) / 3.0};
    for (const Vec3& q : all)
      if (inBox(q)) pts.push_back(q);
  }
  // Triangles sharing a corner or an edge give the same points, bit for
  // bit: each is measured once, unless they are too many to sort for less
  // than that costs (a fan's needles).
  if (pts.size() <= kRepairSortedPoints) {
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  }
  // Only a point the old faces held within reach can be uncovered (one
  // the faces around held stays held).
  pts.erase(std::remove_if(pts.begin(), pts.end(),
                           [&](const Vec3& q) { return nearestSquaredDistance(q, before, reach2) > reach2; }),
            pts.end());
  probe.nearAround.assign(pts.size(), 0);
  return probe;
}

/// Every point of the probe stays within reach of made or of the faces
/// around; the distance to those faces is measured once per point and
/// kept, and only for points made leaves.
inline bool LocalRepair::keepsInputCovered(const std::vector<int>& old,
                                           const std::vector<std::array<Vec3, 3>>& made) const {
  return coverHolds(coverProbe(old), made);
}

inline bool LocalRepair::coverHolds(const CoverProbe& probe, const std::vector<std::array<Vec3, 3>>& made) const {
  if (probe.off) return true;
  if (probe.gaveUp) return false;
  const double reach2 = probe.reach2;
  for (std::size_t i = 0; i < probe.points.size(); ++i) {
    const Vec3& q = probe.points[i];
    if (nearestSquaredDistance(q, made, reach2) <= reach2) continue;
    char& held = probe.nearAround[i];
    if (held == 0) held = nearestSquaredDistance(q, probe.around, reach2) <= reach2 ? 1 : 2;
    if (held == 2) return false;
  }
  return true;
}

inline bool LocalRepair::keepsTurn(const std::vector<std::array<Vec3, 3>>& tris) const {
  if (!input_) return true;
  // The faces already lie within the bound of the input (nearInput).
  const double reach = s_.bound > 0 ? s_.bound : std::numeric_limits<double>::infinity();
  for (const auto& t : tris) {
    const Vec3 a = doubleAreaVector(t[0], t[1], t[2]);
    if (!(a.SquaredNorm() > 0)) return false;
    const InputGrid::Under u = input_->under((t[0] + t[1] + t[2]) / 3.0, a, reach);
    if (!u.found || turnsBeyond(a, u.normal, s_.maxTurnCos2)) return false;
  }
  return true;
}

/// Edge a-b of faces (a, b, c) and (b, a, d) becomes c-d, faces (a, d, c)
/// and (d, b, c), under flipPass's rules, the feature edges of this repair,
/// the two-sided bound (the old edge's midpoint stays covered) and the
/// face-turn bound.
inline LocalRepair::Verdict LocalRepair::tryFlip(int a, int b) {
  if (isFeature(a, b)) return Feature;
  int f1, f2;
  if (!interiorEdge(a, b, f1, f2)) return Topology;
  const int c = third(f1, a, b), d = third(f2, a, b);
  if (c < 0 || d < 0 || c == d || hasEdge(c, d)) return Topology;
  const Vec3 &pa = pos_[a], &pb = pos_[b], &pc = pos_[c], &pd = pos_[d];
  const Vec3 n1 = doubleAreaVector(pa, pb, pc), n2 = doubleAreaVector(pb, pa, pd);
  const double l1 = n1.Norm(), l2 = n2.Norm();
  if (!(l1 > 0) || !(l2 > 0) || !(n1 * n2 > std::cos(s_.flipMaxRad) * l1 * l2)) return Feature;
  const Vec3 m1 = doubleAreaVector(pa, pd, pc), m2 = doubleAreaVector(pd, pb, pc);
  const Vec3 pair = n1 / l1 + n2 / l2;
  if (!(m1 * pair > 0) || !(m2 * pair > 0)) return NoGain;
  const double before = std::min(triangleMinAngle(pa, pb, pc), triangleMinAngle(pb, pa, pd));
  const double after = std::min(triangleMinAngle(pa, pd, pc), triangleMinAngle(pd, pb, pc));
  if (!(after > before + 1e-9)) return NoGain;
  const std::vector<std::array<Vec3, 3>> made = {{pa, pd, pc}, {pd, pb, pc}};
  if (atHugeStar({f1, f2}) || !nearInput(made) || !covered((pa + pb) * 0.5, made) || !keepsTurn(made) ||
      !keepsInputCovered({f1, f2}, made))
    return OverBound;
  applyFlip(f1, f2, a, b, c, d);
  return Done;
}

inline void LocalRepair::applyFlip(int f1, int f2, int a, int b, int c, int d) {
  keep(f1, {a, b, c, d});
  keep(f2, {});
  faces_.tri[f1] = {a, d, c};
  faces_.tri[f2] = {d, b, c};
  removeFromVf(a, f2);
  removeFromVf(b, f1);
  addToVf(c, f2);
  addToVf(d, f1);
  ++r_.flips;
  touched_.insert(touched_.end(), {a, b, c, d});
}

/// A cap (a, b, c) whose long edge a-b no flip may take (a feature edge,
/// or one the faces across it meet at more than the flip limit), with its
/// apex c next to it: the filler a CAD export leaves between a polyline
/// a-c-b of one face and the straight edge a-b of the face (b, a, d) across
/// it. Edge a-b becomes c-d, faces (a, d, c) and (d, b, c): the line runs
/// a-c-b and the cap is gone, without a new vertex. The new faces must keep
/// within the flip limit of (b, a, d) (the cap's own normal says nothing),
/// within both bounds and the face-turn bound, fold onto no neighbour, and
/// their smallest angle must exceed the pair's. a-c and c-b are features
/// when a-b was one or their faces now meet at more than the feature angle.
inline LocalRepair::Verdict LocalRepair::tryFlipUnderCap(int a, int b) {
  int f1, f2;
  if (!interiorEdge(a, b, f1, f2)) return Topology;
  const int c = third(f1, a, b), d = third(f2, a, b);
  if (c < 0 || d < 0 || c == d || hasEdge(c, d) || role_[c] == Role::Fixed || role_[c] == Role::Border)
    return Topology;
  const Vec3 &pa = pos_[a], &pb = pos_[b], &pc = pos_[c], &pd = pos_[d];
  const Vec3 n2 = doubleAreaVector(pb, pa, pd);
  const Vec3 m1 = doubleAreaVector(pa, pd, pc), m2 = doubleAreaVector(pd, pb, pc);
  for (const Vec3& m : {m1, m2})
    if (!(m * n2 > std::cos(s_.flipMaxRad) * m.Norm() * n2.Norm())) return NoGain;
  const double before = std::min(triangleMinAngle(pa, pb, pc), triangleMinAngle(pb, pa, pd));
  const double after = std::min(triangleMinAngle(pa, pd, pc), triangleMinAngle(pd, pb, pc));
  if (!(after > before + 1e-9)) return NoGain;
  const std::vector<std::array<Vec3, 3>> made = {{pa, pd, pc}, {pd, pb, pc}};
  if (atHugeStar({f1, f2}) || foldsNeighbour(f1, made) || foldsNeighbour(f2, made) || !nearInput(made) ||
      !covered((pa + pb) * 0.5, made) || !keepsTurn(made) || !keepsInputCovered({f1, f2}, made))
    return OverBound;
  applyFlip(f1, f2, a, b, c, d);
  const bool wasFeature = feature_.erase(key(a, b)) > 0;
  const double cosFeature = std::cos(s_.featureRad);
  int lines = 0;
  for (int u : {a, b}) {
    int h1, h2;
    bool feat = wasFeature || isFeature(u, c) || !interiorEdge(u, c, h1, h2);
    if (!feat) {
      const auto &t1 = faces_.tri[h1], &t2 = faces_.tri[h2];
      const Vec3 q1 = doubleAreaVector(pos_[t1[0]], pos_[t1[1]], pos_[t1[2]]);
      const Vec3 q2 = doubleAreaVector(pos_[t2[0]], pos_[t2[1]], pos_[t2[2]]);
      feat = !(q1 * q2 >= cosFeature * q1.Norm() * q2.Norm());
    }
    if (feat) feature_.insert(key(u, c)), ++lines;
  }
  if (role_[c] == Role::Free && lines > 0) role_[c] = lines == 2 ? Role::Crease : Role::Fixed;
  return Done;
}

/// Whether crease vertex a may go into b along its crease: a-b is one of
/// its two feature edges, the crease turns at a by at most
/// kRepairCreaseCollapseTurnDeg, and a lies within the bound of the feature
/// edge b-q that replaces b-a-q (q: a's other neighbour on the crease). A
/// CAD export's finely cut circle or fillet edge then coarsens as far as
/// the bound lets it, where splitting alone could only add to the needles
/// along it.
inline LocalRepair::Verdict LocalRepair::collapseAlongCrease(int a, int b, int& q) const {
  if (!isFeature(a, b)) return Feature;
  q = -1;
  for (int f : vf_[a])
    for (int u : faces_.tri[f])
      if (u != a && u != b && isFeature(a, u)) q = u;
  if (q < 0) return Feature;
  if (angleBetween(pos_[a] - pos_[b], pos_[q] - pos_[a]) > kRepairCreaseCollapseTurnDeg * kPi / 180) return Feature;
  const Vec3 e = pos_[q] - pos_[b];
  const double l2 = e.SquaredNorm();
  const double t = l2 > 0 ? std::min(1.0, std::max(0.0, ((pos_[a] - pos_[b]) * e) / l2)) : 0.0;
  if (s_.bound > 0 && (pos_[a] - (pos_[b] + e * t)).SquaredNorm() > s_.bound * s_.bound) return OverBound;
  return Done;
}

inline void LocalRepair::moveFeatures(int a, int b, const std::vector<int>& lines) {
  for (int u : lines) {
    feature_.erase(key(a, u));
    if (u != b) feature_.insert(key(b, u));
  }
  std::vector<int> ends;
  for (int f : vf_[b])
    for (int u : faces_.tri[f])
      if (u != b && isFeature(b, u) && std::find(ends.begin(), ends.end(), u) == ends.end()) ends.push_back(u);
  if (ends.empty() || role_[b] == Role::Fixed) return;
  // A crease through b that keeps two feature edges stays one; anything
  // else (a line ending or branching at b) is a corner.
  role_[b] = role_[b] == Role::Crease && ends.size() == 2 ? Role::Crease : Role::Fixed;
}

/// Removes a by moving it onto b (a half-edge collapse), when a is free,
/// a-b is an interior edge whose ends share no neighbour but the two
/// opposite vertices (the link condition: the mesh stays manifold), no
/// face folds or turns by more than 45 degrees, the smallest angle around
/// grows, and the new faces stay near the input while covering a, and
/// within the face-turn bound of the input under them. A crease vertex
/// goes only along its crease (collapseAlongCrease): the line it lay on
/// stays a chain of feature edges. A border vertex goes the same way along
/// the border, over a-b, the border edge of a single face: a CAD export's
/// unwelded or finely cut border often has two vertices a hair apart, and
/// only their collapse removes the needle between them. Off the border,
/// such a pair is welded whatever the roles (weldable, moveFeatures).
inline LocalRepair::Verdict LocalRepair::tryCollapse(int a, int b) {
  int q = -1;  // a crease or border vertex's other neighbour on its line
  const bool border = role_[a] == Role::Border;
  bool weld = false;  // a goes whatever its role: its feature edges move to b
  if (role_[a] == Role::Crease || border) {
    const Verdict v = collapseAlongCrease(a, b, q);
    if (v != Done) {
      if (border || !weldable(a, b)) return v;
      weld = true;
      q = -1;
    }
  } else if (role_[a] != Role::Free) {
    if (!weldable(a, b)) return Feature;
    weld = true;
  }
  int f1, f2 = -1;
  if (border) {
    int fs[2];
    if (edgeFaces(a, b, fs) != 1 || vf_[a].size() < 2) return Topology;
    f1 = fs[0];
  } else if (!interiorEdge(a, b, f1, f2)) {
    return Topology;
  }
  const int c = third(f1, a, b), d = border ? -1 : third(f2, a, b);
  if (tooFewFacesToLoseOne(c) ||
      (!border && (tooFewFacesToLoseOne(d) || vf_[a].size() + vf_[b].size() < 4 + 3)))
    return Topology;
  std::unordered_set<int> around;
  for (int f : vf_[b])
    for (int v : faces_.tri[f]) around.insert(v);
  for (int f : vf_[a])
    for (int v : faces_.tri[f])
      if (v != a && v != b && v != c && v != d && around.count(v)) return Topology;
  double before = kPi, after = kPi;
  std::vector<std::array<Vec3, 3>> made;
  const double cosTurn = std::cos(45 * kPi / 180);
  for (int f : vf_[a]) {
    before = std::min(before, faceMinAngle(f));
    if (f == f1 || f == f2) continue;
    std::array<Vec3, 3> t, u;
    for (int j = 0; j < 3; ++j) {
      const int v = faces_.tri[f][j];
      t[j] = pos_[v];
      u[j] = v == a ? pos_[b] : pos_[v];
    }
    const Vec3 n0 = doubleAreaVector(t[0], t[1], t[2]), n1 = doubleAreaVector(u[0], u[1], u[2]);
    const double longest = std::max({(u[1] - u[0]).SquaredNorm(), (u[2] - u[1]).SquaredNorm(),
                                     (u[0] - u[2]).SquaredNorm()});
    if (!(n1.Norm() > kCollapse * longest) || !(n0 * n1 > cosTurn * n0.Norm() * n1.Norm())) return NoGain;
    after = std::min(after, triangleMinAngle(u[0], u[1], u[2]));
    made.push_back(u);
  }
  if (!(after > before)) return NoGain;
  if (atHugeStar(vf_[a]) || !nearInput(made) || !covered(pos_[a], made) || !keepsTurn(made) ||
      !keepsInputCovered(vf_[a], made))
    return OverBound;
  std::vector<int> lines;  // a's other ends of feature edges, for a weld
  if (weld)
    for (int f : vf_[a])
      for (int u : faces_.tri[f])
        if (u != a && isFeature(a, u) && std::find(lines.begin(), lines.end(), u) == lines.end()) lines.push_back(u);
  for (int f : vf_[a]) {
    if (f == f1 || f == f2) continue;
    for (int& v : faces_.tri[f])
      if (v == a) v = b;
    addToVf(b, f);
  }
  for (int f : {f1, f2}) {
    if (f < 0) continue;
    faces_.live[f] = 0;
    for (int v : faces_.tri[f])
      if (v != a) removeFromVf(v, f);
  }
  clearVf(a);
  deleted_[a] = 1;
  role_[a] = Role::Fixed;
  if (q >= 0) {
    feature_.erase(key(a, b));
    feature_.erase(key(a, q));
    feature_.insert(key(b, q));
  }
  if (weld) moveFeatures(a, b, lines);
  ++r_.collapses;
  ++r_.removed;
  touched_.insert(touched_.end(), {b, c});
  if (d >= 0) touched_.push_back(d);
  return Done;
}

/// Splits interior edge a-b of faces (a, b, c) and (b, a, d) at a new
/// vertex m (the last vertex), at a + at (b - a): on the edge for a
/// feature edge (it stays a chain of feature edges), else at the input
/// point closest to it; the four faces must keep within both bounds.
inline LocalRepair::Verdict LocalRepair::trySplit(int a, int b, double at) {
  int f1, f2;
  if (!interiorEdge(a, b, f1, f2)) return Topology;
  const int c = third(f1, a, b), d = third(f2, a, b);
  // Refused before the input is searched for the new vertex's place: at a
  // fan's apex every needle would search the whole fan's nodes.
  if (atHugeStar({f1, f2})) return OverBound;
  const bool feat = isFeature(a, b);
  const Vec3 mid = pos_[a] + (pos_[b] - pos_[a]) * at;
  Vec3 p = mid;
  if (!feat && input_ && !input_->closest(mid, 0.5 * (pos_[b] - pos_[a]).Norm(), p)) p = mid;
  const std::vector<std::array<Vec3, 3>> made = {
      {pos_[a], p, pos_[c]}, {p, pos_[b], pos_[c]}, {pos_[b], p, pos_[d]}, {p, pos_[a], pos_[d]}};
  const Vec3 o1 = doubleAreaVector(pos_[a], pos_[b], pos_[c]), o2 = doubleAreaVector(pos_[b], pos_[a], pos_[d]);
  for (std::size_t k = 0; k < made.size(); ++k) {
    const auto& t = made[k];
    const Vec3 n = doubleAreaVector(t[0], t[1], t[2]);
    const double longest =
        std::max({(t[1] - t[0]).SquaredNorm(), (t[2] - t[1]).SquaredNorm(), (t[0] - t[2]).SquaredNorm()});
    if (!(n.Norm() > kCollapse * longest) || !(n * (k < 2 ? o1 : o2) > 0)) return NoGain;
  }
  if (!nearInput(made) || !keepsTurn(made) || !keepsInputCovered({f1, f2}, made)) return OverBound;
  keep(f1, {a, b, c, d});
  keep(f2, {});
  const int m = static_cast<int>(pos_.size());
  pos_.push_back(p);
  deleted_.push_back(0);
  role_.push_back(feat ? Role::Crease : Role::Free);
  newCrease_.push_back(feat ? 1 : 0);
  added_.push_back({a, b, at});
  vf_.emplace_back();
  const int f3 = static_cast<int>(faces_.tri.size()), f4 = f3 + 1;
  faces_.tri[f1] = {a, m, c};
  faces_.tri[f2] = {b, m, d};
  faces_.tri.push_back({m, b, c});
  faces_.tri.push_back({m, a, d});
  for (int k = 0; k < 2; ++k) {
    faces_.live.push_back(1);
    faces_.flippable.push_back(1);
  }
  removeFromVf(b, f1);
  removeFromVf(a, f2);
  vf_[m] = {f1, f2, f3, f4};
  addToVf(b, f3);
  addToVf(c, f3);
  addToVf(a, f4);
  addToVf(d, f4);
  if (feat) {
    feature_.erase(key(a, b));
    feature_.insert(key(a, m));
    feature_.insert(key(m, b));
  }
  ++r_.splits;
  ++r_.added;
  touched_.insert(touched_.end(), {a, b, c, d, m});
  return Done;
}

/// trySplit with the flips around the new vertex, kept only when the
/// smallest angle of the faces they changed rose (or stayed, with fewer
/// below the target); else all of it is undone.
inline LocalRepair::Verdict LocalRepair::trySplitIfBetter(int a, int b, double at) {
  const bool feat = isFeature(a, b);
  Journal j;
  const RepairResult counts = r_;
  const std::size_t nf0 = faces_.tri.size(), nt0 = touched_.size();
  journal_ = &j;
  const Verdict v = trySplit(a, b, at);
  if (v != Done) {
    journal_ = nullptr;
    return v;
  }
  const int m = static_cast<int>(pos_.size()) - 1;
  std::vector<int> around = {a, b, m};
  for (int f : vf_[m])
    for (int u : faces_.tri[f]) around.push_back(u);
  flipAround(around);
  journal_ = nullptr;
  if (keepIfBetter(j, nf0, nt0, counts)) return Done;
  if (feat) {
    feature_.erase(key(a, m));
    feature_.erase(key(m, b));
    feature_.insert(key(a, b));
  }
  return NoGain;
}

/// After a change journaled in j that added one vertex (the last) and the
/// faces from nf0 on: true when the smallest angle of the faces it changed
/// rose, or stayed with fewer below the target; else the change is undone
/// (touched_ back to nt0 entries, the counts to counts) and false.
inline bool LocalRepair::keepIfBetter(Journal& j, std::size_t nf0, std::size_t nt0, const RepairResult& counts) {
  double before = kPi, after = kPi;
  int belowBefore = 0, belowAfter = 0;
  const auto count = [&](double a, double& worst, int& below) {
    worst = std::min(worst, a);
    below += a < s_.targetRad;
  };
  std::unordered_set<int> seen;
  for (std::size_t k = nf0; k < faces_.tri.size(); ++k) count(faceMinAngle(int(k)), after, belowAfter);
  for (const auto& old : j.faces) {
    if (!seen.insert(old.first).second || std::size_t(old.first) >= nf0) continue;
    count(faceMinAngle(old.first), after, belowAfter);
    const auto& c = old.second;
    count(triangleMinAngle(pos_[c[0]], pos_[c[1]], pos_[c[2]]), before, belowBefore);
  }
  if (after > before + 1e-9 || (after > before - 1e-9 && belowAfter < belowBefore)) return true;
  const int m = static_cast<int>(pos_.size()) - 1;
  undo(j);
  clearVf(m);
  vf_.pop_back();
  pos_.pop_back(), deleted_.pop_back(), role_.pop_back(), newCrease_.pop_back(), added_.pop_back();
  faces_.tri.resize(nf0), faces_.live.resize(nf0), faces_.flippable.resize(nf0);
  touched_.resize(nt0);
  r_ = counts;
  return false;
}

/// Splits border edge a-b (one face) at its midpoint, a new vertex that
/// never moves (it may go along the border, as a border vertex): the border
/// stays where it is, as a chain of border edges.
/// For an insertion that lies beyond the border or encroaches on it.
inline LocalRepair::Verdict LocalRepair::trySplitBorder(int a, int b) {
  int fs[2];
  if (edgeFaces(a, b, fs) != 1) return Topology;
  const int f1 = fs[0];
  const std::array<int, 3> t = faces_.tri[f1];
  int j = 0;
  while (j < 3 && (t[j] == a || t[j] == b)) ++j;
  if (j == 3) return Topology;
  const int c = t[j], x = t[(j + 1) % 3], y = t[(j + 2) % 3];  // face (x, y, c)
  const Vec3 p = (pos_[x] + pos_[y]) * 0.5;
  const std::vector<std::array<Vec3, 3>> made = {{pos_[x], p, pos_[c]}, {p, pos_[y], pos_[c]}};
  const Vec3 o = doubleAreaVector(pos_[x], pos_[y], pos_[c]);
  for (const auto& m : made) {
    const Vec3 n = doubleAreaVector(m[0], m[1], m[2]);
    const double l2 = std::max({(m[1] - m[0]).SquaredNorm(), (m[2] - m[1]).SquaredNorm(), (m[0] - m[2]).SquaredNorm()});
    if (!(n.Norm() > kCollapse * l2) || !(n * o > 0)) return NoGain;
  }
  if (atHugeStar({f1}) || !nearInput(made) || !keepsTurn(made) || !keepsInputCovered({f1}, made)) return OverBound;
  if (polish_) {
    // Kept only when it pays, as trySplitIfBetter.
    Journal j;
    const RepairResult counts = r_;
    const std::size_t nf0 = faces_.tri.size(), nt0 = touched_.size();
    polish_ = false;
    journal_ = &j;
    keep(f1, {x, y, c});
    const Verdict v = trySplitBorder(a, b);
    const int m = static_cast<int>(pos_.size()) - 1;
    if (v == Done) flipAround({x, y, c, m});
    journal_ = nullptr;
    polish_ = true;
    if (v != Done) return v;
    if (keepIfBetter(j, nf0, nt0, counts)) return Done;
    feature_.erase(key(x, m));
    feature_.erase(key(m, y));
    feature_.insert(key(x, y));
    return NoGain;
  }
  const int m = static_cast<int>(pos_.size());
  pos_.push_back(p);
  deleted_.push_back(0);
  // It may go along the border again where one of its neighbours there may.
  role_.push_back(role_[x] == Role::Border || role_[y] == Role::Border ? Role::Border : Role::Fixed);
  newCrease_.push_back(1);
  added_.push_back({x, y, 0.5});
  vf_.emplace_back();
  const int f2 = static_cast<int>(faces_.tri.size());
  faces_.tri[f1] = {x, m, c};
  faces_.tri.push_back({m, y, c});
  faces_.live.push_back(1);
  faces_.flippable.push_back(faces_.flippable[f1]);
  removeFromVf(y, f1);
  vf_[m] = {f1, f2};
  addToVf(y, f2);
  addToVf(c, f2);
  feature_.erase(key(x, y));
  feature_.insert(key(x, m));
  feature_.insert(key(m, y));
  ++r_.splits;
  ++r_.added;
  touched_.insert(touched_.end(), {x, y, c, m});
  return Done;
}

/// Walks from face f toward target (a point of f's plane) over at most
/// kInsertWalk faces, each unfolded into f's plane across the edge it
/// shares with the last: only across interior edges that are no feature
/// and whose faces turn less than the flip limit (the input's flat part
/// around f). The face holding the point is returned with its barycentric
/// coordinates, unless the walk meets a feature or border edge on its way,
/// or the point lies inside the diametral circle of such an edge of a face
/// walked (it encroaches on it): that edge is returned instead, to be split
/// (Ruppert's rule: a feature line is refined, never crossed).
inline LocalRepair::Located LocalRepair::locate(int f, const Vec3& target) const {
  constexpr int kInsertWalk = 8;
  Located out;
  const auto& t0 = faces_.tri[f];
  const Vec3 o = pos_[t0[0]];
  Vec3 n = doubleAreaVector(pos_[t0[0]], pos_[t0[1]], pos_[t0[2]]);
  Vec3 e1 = pos_[t0[1]] - o;
  if (!(n.Norm() > 0) || !(e1.Norm() > 0)) return out;
  n /= n.Norm(), e1 /= e1.Norm();
  const Vec3 e2 = n ^ e1;
  using P2 = std::array<double, 2>;
  const auto flat = [&](const Vec3& x) { return P2{{(x - o) * e1, (x - o) * e2}}; };
  const auto cross = [](const P2& a, const P2& b, const P2& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  };
  const P2 q = flat(target);
  int g = f;
  std::array<P2, 3> c = {{flat(pos_[t0[0]]), flat(pos_[t0[1]]), flat(pos_[t0[2]])}};
  std::vector<std::pair<int, int>> constrained;  // feature or border edges of the faces walked, with positions
  std::vector<std::array<P2, 2>> constrainedAt;
  for (int step = 0; step < kInsertWalk; ++step) {
    const auto& t = faces_.tri[g];
    int fs[2];
    for (int j = 0; j < 3; ++j) {
      const int x = t[(j + 1) % 3], y = t[(j + 2) % 3];
      if (isFeature(x, y) || edgeFaces(x, y, fs) != 2)
        constrained.push_back({x, y}), constrainedAt.push_back({{c[(j + 1) % 3], c[(j + 2) % 3]}});
    }
    const double area = cross(c[0], c[1], c[2]);
    if (!(area > 0)) return out;
    double l[3];
    int worst = 0;
    for (int j = 0; j < 3; ++j) {
      l[j] = cross(q, c[(j + 1) % 3], c[(j + 2) % 3]) / area;
      if (l[j] < l[worst]) worst = j;
    }
    const int x = t[(worst + 1) % 3], y = t[(worst + 2) % 3];
    if (l[worst] >= 0) {
      // Found: unless q encroaches on a constrained edge met on the way.
      for (std::size_t k = 0; k < constrained.size(); ++k) {
        const P2 &a = constrainedAt[k][0], &b = constrainedAt[k][1];
        if ((q[0] - a[0]) * (q[0] - b[0]) + (q[1] - a[1]) * (q[1] - b[1]) < 0) {
          out.blockA = constrained[k].first, out.blockB = constrained[k].second;
          return out;
        }
      }
      out.face = g;
      for (int j = 0; j < 3; ++j) out.bary[j] = l[j];
      return out;
    }
    int h1, h2;
    if (isFeature(x, y) || !interiorEdge(x, y, h1, h2)) {
      out.blockA = x, out.blockB = y;
      return out;
    }
    const int h = h1 == g ? h2 : h1;
    const int d = third(h, x, y);
    const Vec3 ng = doubleAreaVector(pos_[t[0]], pos_[t[1]], pos_[t[2]]);
    const Vec3 nh = doubleAreaVector(pos_[faces_.tri[h][0]], pos_[faces_.tri[h][1]], pos_[faces_.tri[h][2]]);
    if (d < 0 || !(ng * nh > std::cos(s_.flipMaxRad) * ng.Norm() * nh.Norm())) return out;
    // d unfolded across x-y: at its foot on the line, on the far side.
    const P2 cx = c[(worst + 1) % 3], cy = c[(worst + 2) % 3];
    const Vec3 xy = pos_[y] - pos_[x];
    const double along = ((pos_[d] - pos_[x]) * xy) / xy.SquaredNorm();
    const double height = (pos_[d] - (pos_[x] + xy * along)).Norm();
    const P2 dir = {{cy[0] - cx[0], cy[1] - cx[1]}};
    const double dl = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1]);
    // (x, y, d) runs y -> x in h, so d lies right of x -> y.
    const P2 cd = {{cx[0] + dir[0] * along + dir[1] / dl * height, cx[1] + dir[1] * along - dir[0] / dl * height}};
    const auto& th = faces_.tri[h];
    for (int j = 0; j < 3; ++j) c[j] = th[j] == x ? cx : th[j] == y ? cy : cd;
    g = h;
  }
  return out;
}

/// Inserts a vertex inside face f below the target (a 1->3 split of the
/// face that holds it), for the slivers no edge split fixes: at f's
/// circumcentre, or at an off-centre (Üngör) on the bisector of f's
/// shortest edge when the circumcentre lies farther from that edge than
/// the apex of a triangle of the target angle over it, which makes fewer
/// new vertices. The point is located by locate(); when it lies beyond or
/// encroaches on a feature or border edge, that edge is split at its
/// midpoint instead.
inline LocalRepair::Verdict LocalRepair::tryInsert(int f) {
  const auto& t = faces_.tri[f];
  const Vec3 p0 = pos_[t[0]], p1 = pos_[t[1]], p2 = pos_[t[2]];
  const Vec3 a = p1 - p0, b = p2 - p0, n = a ^ b;
  const double n2 = n.SquaredNorm();
  if (!(n2 > 0)) return NoGain;
  const Vec3 centre = p0 + ((n ^ a) * b.SquaredNorm() + (b ^ n) * a.SquaredNorm()) / (2 * n2);
  int s = 0;  // shortest edge, opposite t[s]
  double len[3];
  for (int j = 0; j < 3; ++j) len[j] = (pos_[t[(j + 2) % 3]] - pos_[t[(j + 1) % 3]]).Norm();
  for (int j = 1; j < 3; ++j)
    if (len[j] < len[s]) s = j;
  const Vec3 mid = (pos_[t[(s + 1) % 3]] + pos_[t[(s + 2) % 3]]) * 0.5;
  const double reach = 0.5 * len[s] / std::tan(0.5 * std::min(kPi / 3, 1.1 * s_.targetRad));
  Vec3 target = centre;
  const double dc = (centre - mid).Norm();
  if (dc > reach) target = mid + (centre - mid) * (reach / dc);
  if (!isFinite(target)) return NoGain;
  const Located at = locate(f, target);
  if (at.blockA >= 0) {
    int fs[2];
    return edgeFaces(at.blockA, at.blockB, fs) == 1 ? trySplitBorder(at.blockA, at.blockB)
                                                    : split(at.blockA, at.blockB);
  }
  if (at.face < 0) return NoGain;
  return insertInFace(at.face, at.bary);
}

/// A face of made (replacing g) meets a face across one of g's edges at
/// more than 150 degrees (folded onto it) where g did not.
inline bool LocalRepair::foldsNeighbour(int g, const std::vector<std::array<Vec3, 3>>& made) const {
  const double cosFold = std::cos(150 * kPi / 180);
  const auto& t = faces_.tri[g];
  const Vec3 ng = doubleAreaVector(pos_[t[0]], pos_[t[1]], pos_[t[2]]);
  for (const auto& m : made) {
    const Vec3 nm = doubleAreaVector(m[0], m[1], m[2]);
    for (int j = 0; j < 3; ++j) {
      int fs[2];
      const int x = t[j], y = t[(j + 1) % 3];
      if (!(pos_[x] == m[0] || pos_[x] == m[1] || pos_[x] == m[2]) ||
          !(pos_[y] == m[0] || pos_[y] == m[1] || pos_[y] == m[2]))
        continue;
      const int k = edgeFaces(x, y, fs);
      for (int i = 0; i < std::min(k, 2); ++i) {
        if (fs[i] == g) continue;
        const auto& u = faces_.tri[fs[i]];
        const Vec3 nh = doubleAreaVector(pos_[u[0]], pos_[u[1]], pos_[u[2]]);
        const double l = nm.Norm() * nh.Norm(), l0 = ng.Norm() * nh.Norm();
        if (nm * nh < cosFold * l && !(ng * nh < cosFold * l0)) return true;
      }
    }
  }
  return false;
}

/// Splits face g (a, b, c) into (a, b, m), (b, c, m), (c, a, m) at a new
/// vertex m (the last vertex) at barycentric coordinates bary in g,
/// projected on the input; a point next to an edge splits that edge
/// instead (three faces, one of them a sliver, would not help). The new
/// faces must keep g's side, stay within both bounds and the face-turn
/// bound, and fold onto no neighbour; then the edges around are flipped.
inline LocalRepair::Verdict LocalRepair::insertInFace(int g, const double bary[3]) {
  constexpr double kNearEdge = 0.05;
  const std::array<int, 3> t = faces_.tri[g];
  double l[3], sum = 0;
  for (int j = 0; j < 3; ++j) sum += (l[j] = std::max(0.0, bary[j]));
  if (!(sum > 0)) return NoGain;
  int low = 0;
  for (int j = 0; j < 3; ++j) {
    l[j] /= sum;
    if (l[j] < l[low]) low = j;
  }
  if (l[low] < kNearEdge) {
    const int x = t[(low + 1) % 3], y = t[(low + 2) % 3];
    if (isFeature(x, y)) return Feature;
    const double w = l[(low + 1) % 3] + l[(low + 2) % 3];
    return split(x, y, std::min(0.9, std::max(0.1, l[(low + 2) % 3] / w)));
  }
  if (atHugeStar({g})) return OverBound;  // before the input is searched, as in trySplit
  const Vec3 &pa = pos_[t[0]], &pb = pos_[t[1]], &pc = pos_[t[2]];
  const Vec3 q = pa * l[0] + pb * l[1] + pc * l[2];
  const double longest = std::max({(pb - pa).Norm(), (pc - pb).Norm(), (pa - pc).Norm()});
  Vec3 p = q;
  if (input_ && !input_->closest(q, 0.5 * longest, p)) p = q;
  const std::vector<std::array<Vec3, 3>> made = {{pa, pb, p}, {pb, pc, p}, {pc, pa, p}};
  const Vec3 o = doubleAreaVector(pa, pb, pc);
  for (const auto& m : made) {
    const Vec3 nm = doubleAreaVector(m[0], m[1], m[2]);
    const double l2 = std::max({(m[1] - m[0]).SquaredNorm(), (m[2] - m[1]).SquaredNorm(), (m[0] - m[2]).SquaredNorm()});
    if (!(nm.Norm() > kCollapse * l2) || !(nm * o > 0)) return NoGain;
  }
  if (foldsNeighbour(g, made) || !nearInput(made) || !keepsTurn(made) || !keepsInputCovered({g}, made))
    return OverBound;
  // Applied with its flips, then undone unless the smallest angle of the
  // faces they changed rose: with flips bounded by the feature edges and
  // the bound, the triangulation around the point need not become
  // Delaunay, and a point that leaves a worse sliver is no progress.
  Journal j;
  const RepairResult counts = r_;
  const std::size_t nf0 = faces_.tri.size(), nt0 = touched_.size();
  const int m = static_cast<int>(pos_.size());
  pos_.push_back(p);
  deleted_.push_back(0);
  role_.push_back(Role::Free);
  newCrease_.push_back(0);
  EdgePoint e{t[0], t[1], l[1]};
  e.c = t[2], e.s = l[2];
  added_.push_back(e);
  vf_.emplace_back();
  journal_ = &j;
  keep(g, {t[0], t[1], t[2]});
  const int g2 = static_cast<int>(nf0), g3 = g2 + 1;
  faces_.tri[g] = {t[0], t[1], m};
  faces_.tri.push_back({t[1], t[2], m});
  faces_.tri.push_back({t[2], t[0], m});
  for (int k = 0; k < 2; ++k) {
    faces_.live.push_back(1);
    faces_.flippable.push_back(1);
  }
  removeFromVf(t[2], g);
  vf_[m] = {g, g2, g3};
  addToVf(t[1], g2);
  addToVf(t[2], g2);
  addToVf(t[2], g3);
  addToVf(t[0], g3);
  touched_.insert(touched_.end(), {t[0], t[1], t[2], m});
  flipAround({t[0], t[1], t[2], m});
  journal_ = nullptr;
  // Kept when the worst of them got better, or stayed and fewer are below
  // the target (a row of equal slivers loses one at a time).
  if (!keepIfBetter(j, nf0, nt0, counts)) return NoGain;
  ++r_.inserts;
  ++r_.added;
  return Done;
}

/// One attempt on face f: a cap (largest angle over 100 degrees) gets its
/// long edge flipped or split, else a point inside (tryInsert); a needle
/// its short edge collapsed, else a long edge flipped, else a point
/// inside, else its long edge split. why gets the strongest reason of
/// failure.
inline bool LocalRepair::fixFace(int f, RepairReason& why) {
  const auto t = faces_.tri[f];
  double len[3];
  for (int j = 0; j < 3; ++j) len[j] = (pos_[t[(j + 2) % 3]] - pos_[t[(j + 1) % 3]]).SquaredNorm();  // opposite t[j]
  int e[3] = {0, 1, 2};
  std::sort(e, e + 3, [&](int x, int y) { return len[x] < len[y]; });
  const auto ends = [&](int j, int& x, int& y) { x = t[(j + 1) % 3], y = t[(j + 2) % 3]; };
  const Vec3 u = pos_[t[(e[2] + 1) % 3]] - pos_[t[e[2]]], w = pos_[t[(e[2] + 2) % 3]] - pos_[t[e[2]]];
  const bool cap = angleBetween(u, w) > 100 * kPi / 180;
  int worst = NoGain;
  const auto note = [&](Verdict v) {
    if (v == OverBound || (v == Topology && worst != OverBound)) worst = v;
    return v == Done;
  };
  int x, y;
  if (!cap) {
    ends(e[0], x, y);
    if (note(tryCollapse(x, y)) || note(tryCollapse(y, x))) return true;
  }
  for (int k = 2; k >= 1; --k) {
    ends(e[k], x, y);
    if (note(tryFlip(x, y))) return true;
  }
  // A cap whose long edge no flip may take: the filler under a polyline
  // (measured on hinge: its last caps, 170 degrees at an apex 0.05 from a
  // feature edge, held its smallest angle at 5 degrees).
  if (cap) {
    ends(e[2], x, y);  // f runs x -> y
    if (note(tryFlipUnderCap(x, y))) return true;
  }
  // A sliver that no flip fixes gets a point inside (tryInsert) before
  // its long edge is split: measured on slivers spanning flat strips
  // between borders, the insertion first reached 25-32 degrees where the
  // split first stayed at 13-20.
  if (!cap && note(tryInsert(f))) return true;
  ends(e[2], x, y);
  if (!cap) {
    if (note(split(x, y))) return true;
  } else {
    // A cap's apex lies near its long edge: split the edge at the apex's
    // foot and merge the apex into the new vertex when it may go.
    const int apex = t[e[2]];
    const Vec3 d = pos_[y] - pos_[x];
    const double along = std::min(0.8, std::max(0.2, ((pos_[apex] - pos_[x]) * d) / d.SquaredNorm()));
    if (!polish_ && note(trySplit(x, y, along))) {
      tryCollapse(apex, static_cast<int>(pos_.size()) - 1);
      return true;
    }
  }
  // The long edge could not go without leaving the bound: split the
  // middle one, which opens the small angle's other side instead.
  if (worst == OverBound) {
    ends(e[1], x, y);
    if (note(split(x, y))) return true;
  }
  // A cap that no flip nor split fixes: a point inside, last (before the
  // split, it took spot_badquality from 0.132% to 0.155% of its diagonal
  // from the input at the default target, for the same smallest angle).
  if (cap && note(tryInsert(f))) return true;
  // A cap on a feature or border edge, which no flip may take, that
  // nothing above could open loses its short edge, last (measured on the
  // corpus: 6 meshes up, none down; bunny_closed 21.3 -> 25.0 degrees
  // outside its corners. On caps over any edge: 17 up, one down, but
  // hinge fell from 18.9 to 12.9 degrees at a budget of 200%).
  if (cap) {
    ends(e[2], x, y);
    if (isFeature(x, y)) {
      ends(e[0], x, y);
      if (note(tryCollapse(x, y)) || note(tryCollapse(y, x))) return true;
    }
  }
  why = worst == OverBound ? RepairReason::Bound : worst == Topology ? RepairReason::NonManifold
                                                                     : RepairReason::Pinned;
  return false;
}

/// Flips the edges around the given vertices while a flip raises the
/// smaller angle of its pair, a few passes at most.
inline void LocalRepair::flipAround(const std::vector<int>& vertices) {
  std::vector<int> seeds = vertices;
  for (int pass = 0; pass < 5 && !seeds.empty(); ++pass) {
    const std::size_t from = touched_.size();
    for (int a : seeds) {
      if (deleted_[a] || vf_[a].size() > kRepairMaxStar) continue;
      std::vector<int> nbr;
      for (int f : vf_[a])
        for (int b : faces_.tri[f])
          if (b != a) nbr.push_back(b);
      std::sort(nbr.begin(), nbr.end());
      nbr.erase(std::unique(nbr.begin(), nbr.end()), nbr.end());
      for (int b : nbr)
        if (!deleted_[a] && !deleted_[b]) tryFlip(a, b);
    }
    seeds.assign(touched_.begin() + from, touched_.end());
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  }
}

/// The ring of interior vertex v in the orientation of its faces; false
/// when its faces do not form one closed fan.
inline bool LocalRepair::orderedRing(int v, std::vector<int>& ring) const {
  const std::vector<int>& fs = vf_[v];
  ring.clear();
  if (fs.size() < 3) return false;
  std::vector<std::pair<int, int>> next;  // x -> y for face (v, x, y), sorted by x
  for (int f : fs) {
    const auto& t = faces_.tri[f];
    for (int j = 0; j < 3; ++j)
      if (t[j] == v) next.push_back({t[(j + 1) % 3], t[(j + 2) % 3]});
  }
  std::sort(next.begin(), next.end());
  for (std::size_t k = 0; k + 1 < next.size(); ++k)
    if (next[k].first == next[k + 1].first) return false;  // x starts two faces: not one fan
  // From the face first in vf_, as the ring has always started.
  const auto& t0 = faces_.tri[fs[0]];
  int cur = t0[0] == v ? t0[1] : t0[1] == v ? t0[2] : t0[0];
  for (std::size_t k = 0; k < next.size(); ++k) {
    ring.push_back(cur);
    const auto it = std::lower_bound(next.begin(), next.end(), std::make_pair(cur, std::numeric_limits<int>::min()));
    if (it == next.end() || it->first != cur) return false;
    cur = it->second;
  }
  return cur == ring[0];
}

/// One S-ODT move of v under the guards: a free vertex in its tangent
/// plane (Eq. 5's closed form), a crease vertex along the line of its two
/// feature neighbours; the step halves up to three times, then the
/// tangential Laplacian step is tried. A step is taken when no face folds
/// nor gets a smaller smallest angle than the star had, the star stays
/// near the input, covers v's old position and keeps within the face-turn
/// bound of the input under it.
inline bool LocalRepair::relax(int v) {
  if (deleted_[v] || role_[v] == Role::Fixed || role_[v] == Role::Border || vf_[v].size() > kRepairMaxStar)
    return false;
  std::vector<int> ring;
  if (!orderedRing(v, ring)) return false;
  Star st;
  st.center = pos_[v];
  for (int u : ring) st.ring.push_back(pos_[u]);
  const Vec3 n = starNormal(st);
  if (n.SquaredNorm() == 0) return false;
  Vec3 target, fallback;
  const Vec3 centroid = ringCentroid(st);
  if (role_[v] == Role::Free) {
    const LocalMove mv = solveStar(st, n);
    target = mv.ok ? mv.target : st.center;
    fallback = tangentialLaplacianTarget(st, n);
  } else {
    int ends[2], k = 0;
    for (int u : ring)
      if (k < 2 && isFeature(v, u)) ends[k++] = u;
    if (k != 2) return false;
    Vec3 e = pos_[ends[1]] - pos_[ends[0]];
    if (!(e.Norm() > 0)) return false;
    e /= e.Norm();
    Vec3 p;
    target = minimizeOnLine(sodtQuadratic(st, n), Vec3(0, 0, 0), e, p) ? st.center + p : st.center;
    fallback = st.center + e * ((centroid - st.center) * e);
  }
  std::vector<Vec3> cur;
  std::vector<double> edge2;
  const double limit = prepareGuard(st, n, true, cur, edge2);
  const Vec3 steps[5] = {target, st.center + (target - st.center) * 0.5, st.center + (target - st.center) * 0.25,
                         st.center + (target - st.center) * 0.125, fallback};
  std::unique_ptr<CoverProbe> probe;  // measured once, at the first step that needs it
  int rim = -1;                        // starNearInput's
  for (const Vec3& y : steps) {
    if (!isFinite(y) || (y - st.center).SquaredNorm() == 0) continue;
    if (!moveAllowed(st, y, cur, edge2, true, limit)) continue;
    std::vector<std::array<Vec3, 3>> made;
    for (std::size_t k = 0; k < st.size(); ++k) made.push_back({y, st.at(k), st.at(k + 1)});
    if (input_ && s_.bound > 0 && !input_->within(y, s_.bound)) continue;
    if (atHugeStar(vf_[v]) || !starNearInput(y, st, rim) || !covered(st.center, made) || !keepsTurn(made)) continue;
    if (!probe) probe.reset(new CoverProbe(coverProbe(vf_[v])));
    if (!coverHolds(*probe, made)) continue;
    pos_[v] = y;
    ++r_.relaxMoves;
    return true;
  }
  return false;
}

/// The state a round leaves, for returning the best one.
struct LocalRepair::Snapshot {
  std::vector<Vec3> pos;
  FaceList faces;
  std::vector<char> deleted, newCrease;
  std::vector<EdgePoint> added;
  std::vector<Role> role;
  std::vector<std::vector<int>> vf;
  std::unordered_set<std::uint64_t> feature;
  RepairResult counts;
  double minAngle = 0;
  std::size_t below = 0;
  std::vector<Left> why;
};

inline void LocalRepair::score(double& minAngle, std::size_t& below, double* all) const {
  std::vector<std::array<int, 3>> tri;
  tri.reserve(faces_.tri.size());
  below = 0;
  double smallest = kPi;
  for (std::size_t f = 0; f < faces_.tri.size(); ++f) {
    if (!faces_.live[f]) continue;
    tri.push_back(faces_.tri[f]);
    const double a = faceMinAngle(int(f));
    smallest = std::min(smallest, a);
    below += a < s_.targetRad;
  }
  if (all) *all = smallest;
  const auto onFeature = [this](int a, int b) { return isFeature(a, b); };
  minAngle = protectedCorners(tri, pos_, s_.featureRad, s_.targetRad, onFeature).minAngleElsewhere;
}

inline bool LocalRepair::ranksAbove(const Snapshot& x, const Snapshot& y) const {
  const double a = std::min(x.minAngle, s_.targetRad), b = std::min(y.minAngle, s_.targetRad);
  return a > b || (a == b && x.below < y.below);
}

inline double LocalRepair::reportedMinAngle() const {
  std::vector<std::array<int, 3>> tri;
  for (std::size_t f = 0; f < faces_.tri.size(); ++f)
    if (faces_.live[f]) tri.push_back(faces_.tri[f]);
  return protectedCorners(tri, pos_, s_.featureRad, s_.targetRad).minAngleElsewhere;
}

inline void LocalRepair::save(Snapshot& s) const {
  s.pos = pos_, s.faces = faces_, s.deleted = deleted_, s.newCrease = newCrease_, s.added = added_;
  s.role = role_, s.vf = vf_, s.feature = feature_, s.counts = r_;
}

inline void LocalRepair::restore(const Snapshot& s) {
  pos_ = s.pos, faces_ = s.faces, deleted_ = s.deleted, newCrease_ = s.newCrease, added_ = s.added;
  role_ = s.role, vf_ = s.vf, feature_ = s.feature, r_ = s.counts;
  indexLargeStars();
}

/// One round: an attempt on every face below the tide (see
/// kRepairTideFactor), worst first, then flips and S-ODT relaxation around
/// what changed. False when nothing changed; budgetOut is set when the
/// budget stopped the round.
inline bool LocalRepair::round(std::vector<Left>& why, bool& budgetOut) {
  std::vector<std::pair<double, int>> bad;
  // A face whose smallest angle lies at a protected corner cannot beat
  // it while the features stay: it is left as it is (pinned), and the
  // tide starts from the worst other face.
  std::vector<std::array<int, 3>> tri;
  std::vector<int> at;
  for (std::size_t f = 0; f < faces_.tri.size(); ++f)
    if (faces_.live[f]) tri.push_back(faces_.tri[f]), at.push_back(int(f));
  const auto onFeature = [this](int a, int b) { return isFeature(a, b); };
  const CornerView view = protectedCorners(tri, pos_, s_.featureRad, s_.targetRad, onFeature);
  const std::vector<char>& corner = view.atCorner;
  const double worst = view.minAngleElsewhere;
  const double step = std::max(worst * kRepairTideFactor, worst + kRepairTideStepDeg * kPi / 180);
  tide_ = useTide_ ? std::min(s_.targetRad, std::max(tideFloor_, step)) : s_.targetRad;
  why.resize(faces_.tri.size());
  for (std::size_t i = 0; i < at.size(); ++i) {
    const int f = at[i];
    if (corner[i])
      why[std::size_t(f)] = {RepairReason::Pinned, faces_.tri[std::size_t(f)]};
    else if (faceMinAngle(f) < tide_)
      bad.push_back({faceMinAngle(f), f});
  }
  std::sort(bad.begin(), bad.end());
  touched_.clear();
  bool progress = false;
  for (const auto& b : bad) {
    const int f = b.second;
    if (!faces_.live[f] || faceMinAngle(f) >= s_.targetRad) continue;
    if (r_.added >= s_.maxAdded) {
      budgetOut = true;
      break;
    }
    RepairReason w = RepairReason::Pinned;
    if (fixFace(f, w))
      progress = true;
    else if (std::size_t(f) < why.size())
      why[f] = {w, faces_.tri[f]};
  }
  why.resize(faces_.tri.size());
  std::vector<int> region = touched_;
  std::sort(region.begin(), region.end());
  region.erase(std::unique(region.begin(), region.end()), region.end());
  flipAround(region);
  std::vector<int> relaxSet;
  for (int v : region) {
    if (vf_[v].size() > kRepairMaxStar) continue;
    for (int f : vf_[v])
      for (int u : faces_.tri[f]) relaxSet.push_back(u);
  }
  std::sort(relaxSet.begin(), relaxSet.end());
  relaxSet.erase(std::unique(relaxSet.begin(), relaxSet.end()), relaxSet.end());
  for (int sweep = 0; sweep < kRepairRelaxSweeps; ++sweep)
    for (int v : relaxSet) relax(v);
  flipAround(relaxSet);
  return progress;
}

/// Rounds until no face is below the target, a round whose tide is the
/// target changes nothing, patience rounds in a row (0: no limit) find no
/// better state, or the rounds or the budget run out (a round that changes
/// nothing or stalls below a lower tide raises the next one's); best
/// receives the best state seen (the largest smallest angle outside the
/// protected corners, then the fewest faces below the target) and why the
/// reasons of its faces.
/// Returns which of these ended them: Patience, Budget, Rounds (the
/// limit), else Done.
inline LocalRepair::Stop LocalRepair::rounds(bool tide, int maxRounds, int patience, Snapshot& best,
                                             std::vector<Left>& why) {
  why.assign(faces_.tri.size(), Left());
  useTide_ = tide;
  tideFloor_ = 0;
  bool budgetOut = false;
  score(best.minAngle, best.below);
  save(best);
  best.why = why;
  double last = best.minAngle;
  int stall = 0, sinceBest = 0;
  for (int k = 0; k < maxRounds && best.below > 0; ++k) {
    const bool progress = round(why, budgetOut);
    double a, all;
    std::size_t n;
    score(a, n, &all);
    ++sinceBest;
    // A state whose smallest angle anywhere (a protected corner cut into
    // thinner faces included) fell below the start's is never kept.
    if (all >= floorAll_ && (a > best.minAngle || (a == best.minAngle && n < best.below))) {
      save(best);
      best.minAngle = a, best.below = n;
      best.why = why;
      sinceBest = 0;
    }
    if (budgetOut) break;
    if (patience > 0 && sinceBest >= patience) return Stop::Patience;
    if (!progress && tide_ >= s_.targetRad) break;
    stall = a > last ? 0 : stall + 1;
    last = a;
    if (!progress || stall >= kRepairTideStall) {
      tideFloor_ = tide_ + kRepairTideRiseDeg * kPi / 180;
      stall = 0;
    }
    if (k + 1 == maxRounds) return Stop::Rounds;
  }
  return budgetOut ? Stop::Budget : Stop::Done;
}

inline LocalRepair::Stop LocalRepair::attempt(bool tide, Snapshot& best) {
  std::vector<Left> why;
  Stop stop = rounds(tide, tide ? s_.maxRounds : kRepairPlainRounds, tide ? kRepairTidePatience : kRepairPlainPatience,
                     best, why);
  restore(best);
  if (!tide && stop == Stop::Patience) {
    // The plain rounds churn (they split faster than they fix): the tide,
    // from the best state, spends what is left on the worst faces first.
    Snapshot tided;
    stop = rounds(true, s_.maxRounds, kRepairTidePatience, tided, why);
    restore(tided);
    best = std::move(tided);
  }
  return stop;
}

/// Rounds on every face below the target (kRepairPlainRounds at most), or,
/// when more faces are below the target than the budget has vertices (it
/// will run out before every face had its turn), rounds under a rising
/// tide (see kRepairTideFactor) that spend it on the worst first. When
/// plain rounds leave a face below the target outside the protected
/// corners, the tide runs too from the same start and the better is kept
/// (ranksAbove): plain rounds spend about one vertex per two such faces per
/// round (measured on hinge with a budget of 200%: 5.0 degrees, the budget
/// gone in the second round; 17.9 under the tide), yet on other parts they
/// do better (cgal_handle 7.9 degrees, 5.1 under the tide). Before, the
/// tide ran only where the faces were more than half the budget, and a
/// larger budget could end lower (gmsh_t13: 5.3 degrees with 100%, 3.5
/// with 300%); measured on the corpus at 300%, the tide's second try
/// lifted 10 meshes and lowered none, for 20% more time. The best round
/// (the largest smallest angle outside the protected corners, then the
/// fewest faces below the target) is kept, the swept mesh included, and polished
/// (kRepairPolishRounds), so the repair never leaves a worse mesh by the
/// measure its report gives; no state is kept whose smallest angle
/// anywhere is below the start's. Ranked by every face, a corner no change
/// can open ties every state and leaves the choice to the count below the
/// target (measured on the corpus: a median smallest angle outside the
/// corners of 6.2 degrees, against 7.4 with the corners left out of both
/// the ranking and the work).
inline LocalRepair::StageEnd LocalRepair::stage() {
  loose_ = false;
  double worst;
  std::size_t below;
  score(worst, below, &floorAll_);
  const long long n = static_cast<long long>(below);
  Snapshot start, best;
  save(start);
  const double reportedAtStart = reportedMinAngle();
  Stop stop;
  if (n <= s_.maxAdded) {
    // Plain rounds may fix every face within the budget; where they do
    // not (they churn, or spend the budget before every face had its
    // turn), the tide runs from the same start too and the better is kept.
    Snapshot plain;
    const Stop plainStop = attempt(false, plain);
    if (plain.minAngle >= s_.targetRad) {
      best = std::move(plain);
      stop = plainStop;
    } else {
      restore(start);
      stop = attempt(true, best);
      if (ranksAbove(plain, best)) {
        restore(plain);
        best = std::move(plain);
        stop = plainStop;
      }
    }
  } else {
    stop = attempt(true, best);
  }
  if (best.minAngle < s_.targetRad && input_ && s_.bound > 0) {
    // The loose tide (kRepairQuarterFactor), from the best state with what
    // is left of the budget; kept when it ranks above and the report's
    // measure did not fall, and then stays on for the polish.
    const double reported = reportedMinAngle();
    loose_ = true;
    Snapshot loose;
    const Stop looseStop = attempt(true, loose);
    if (ranksAbove(loose, best) && reportedMinAngle() >= reported) {
      best = std::move(loose);
      stop = looseStop;
    } else {
      restore(best);
      loose_ = false;
    }
  }
  bool budgetOut = stop == Stop::Budget;
  std::vector<Left> why = best.why;
  why.resize(faces_.tri.size());
  if (s_.polish) {
    // Rounds of changes that each raise the smallest angle of the faces
    // they change (or keep it with fewer below the target), so that the
    // mesh's cannot fall: what the rounds left is worked on without
    // churn. They end when a round finds nothing better.
    polish_ = true;
    useTide_ = false;
    double a0;
    std::size_t n0;
    score(a0, n0);
    for (int k = 0; k < kRepairPolishRounds && n0 > 0 && !budgetOut; ++k) {
      const bool progress = round(why, budgetOut);
      double a;
      std::size_t n;
      score(a, n);
      if (!progress || !(a > a0 || (a == a0 && n < n0))) break;
      a0 = a, n0 = n;
    }
    polish_ = false;
  }
  // The states are ranked outside the corners between the features the
  // repair started from, which may differ from the report's, taken from
  // the angles across the final edges: a mesh lower than the start by the
  // report's measure is not returned (measured on jittered spheres: 12.1
  // degrees after the sweeps, 6.4 after the repair, whose ranking saw a
  // corner of the start's as a face to lift).
  if (reportedMinAngle() < reportedAtStart) {
    restore(start);
    why.assign(faces_.tri.size(), Left());
  }
  return {std::move(why), budgetOut};
}

inline void LocalRepair::listRemaining(const StageEnd& end) {
  r_.remaining.clear();
  for (std::size_t f = 0; f < faces_.tri.size(); ++f) {
    if (!faces_.live[f]) continue;
    const double a = faceMinAngle(int(f));
    if (a < s_.targetRad) {
      const auto& t = faces_.tri[f];
      // A face changed since its last attempt (or never tried) was left by
      // the end of the rounds, or of the budget.
      const bool tried = f < end.why.size() && end.why[f].tri == t;
      const RepairReason reason = tried ? end.why[f].why : end.budgetOut ? RepairReason::Budget : RepairReason::Rounds;
      const Vec3 c = (pos_[t[0]] + pos_[t[1]] + pos_[t[2]]) / 3.0;
      r_.remaining.push_back({{c[0], c[1], c[2]}, a * 180 / kPi, reason});
    }
  }
}

/// A target above kRepairFirstStageDeg is worked towards in two stages:
/// the whole repair (stage()) to kRepairFirstStageDeg, then again from its
/// result to the target, with what is left of the budget. The second stage
/// is kept only when it raised the smallest angle outside the protected
/// corners (as the report measures it, at the target): fewer faces below
/// the target at the same smallest angle are not worth the distance it
/// spends (spot_badquality: 25.2 degrees either way, its Hausdorff
/// distance 0.132% of the diagonal after the first stage, 0.152% after the
/// second). Where the first stage had faces below its angle and raised
/// none, the second does not run (a fan around a vertex of valence 20000,
/// --flips --repair: 14.2 s with it, 7.8 s without, the same result).
inline RepairResult LocalRepair::run() {
  const double target = s_.targetRad, first = kRepairFirstStageDeg * kPi / 180;
  if (!(target > first)) {
    listRemaining(stage());
    return r_;
  }
  s_.targetRad = first;
  const double start = reportedMinAngle();
  StageEnd end = stage();
  const bool rose = reportedMinAngle() > start;
  s_.targetRad = target;
  if (start < first && !rose) {
    // The first stage had faces below its target and raised none of them
    // (their triangles are pinned or held by the bound): the second would
    // repeat its rounds in vain.
    listRemaining(end);
    return r_;
  }
  const double reached = reportedMinAngle();
  Snapshot staged;
  save(staged);
  StageEnd second = stage();
  if (reportedMinAngle() > reached)
    end = std::move(second);
  else
    restore(staged);
  listRemaining(end);
  return r_;
}

/// The input the repair keeps to: its faces in a tree (taken before the
/// first sweep), each with its own normal, the distance bound both ways (0
/// for none: a run without the deviation guard, or Denoise, which leaves
/// its input) and the face-turn bound (runTurnCos2).
struct RepairInput {
  std::unique_ptr<InputGrid> grid;
  double bound = 0;
  double maxTurnCos2 = 0;

  void prepare(const SodtParams& p, const std::vector<Vec3>& pos, const FaceList& faces, const RingTopology& topo) {
    if (!p.repair) return;
    maxTurnCos2 = runTurnCos2(p);
    grid.reset(new InputGrid(pos, faces));
    if (DeviationInput::applies(p)) bound = p.maxDeviationRel * surfaceDiagonal(pos, topo);
  }
};

/// The largest turn, in degrees, of the live faces of a repaired mesh
/// (SodtStats::maxFaceTurnDeg): a face the repair left as it was (the
/// same corners at the same positions as in before / posBefore) from its
/// input orientation refNormal (as largestFaceTurnDeg), a face it made or
/// moved from the input face under its centroid (InputGrid::under), the
/// reference its guard kept it to. Faces without area, or without a
/// reference, are left out.
inline double repairedFaceTurnDeg(const FaceList& faces, const std::vector<Vec3>& pos, const FaceList& before,
                                  const std::vector<Vec3>& posBefore, const std::vector<Vec3>& refNormal,
                                  const InputGrid& input) {
  double worst = 0;
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    const std::array<int, 3>& t = faces.tri[f];
    const Vec3 area = doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]);
    if (area.SquaredNorm() == 0) continue;
    bool same = f < before.tri.size() && before.live[f] && before.tri[f] == t;
    for (int j = 0; j < 3 && same; ++j)
      same = static_cast<std::size_t>(t[j]) < posBefore.size() && posBefore[t[j]] == pos[t[j]];
    if (same) {
      if (refNormal[f].SquaredNorm() > 0) worst = std::max(worst, angleBetween(area, refNormal[f]));
      continue;
    }
    const InputGrid::Under u = input.under((pos[t[0]] + pos[t[1]] + pos[t[2]]) / 3.0, area,
                                           std::numeric_limits<double>::infinity(), std::numeric_limits<long>::max());
    if (u.found) worst = std::max(worst, angleBetween(area, u.normal));
  }
  return worst * kRadToDeg;
}

/// Gives the vertices a repair added to m (working indices nv0 on, m's
/// order[i]) the per-vertex attributes m has, interpolated from the
/// vertices each was made from (added, in order: a source added before is
/// set first; EdgePoint::weights): texture coordinates (the texture index
/// of the heaviest source), colour and quality. Normals are not set:
/// writeBack computes them.
template <class MeshType>
void interpolateAddedVertices(MeshType& m, const std::vector<int>& order, std::size_t nv0,
                              const std::vector<EdgePoint>& added) {
  using VertexType = typename MeshType::VertexType;
  const bool tex = vcg::tri::HasPerVertexTexCoord(m), color = vcg::tri::HasPerVertexColor(m),
             quality = vcg::tri::HasPerVertexQuality(m);
  if (!tex && !color && !quality) return;
  for (std::size_t k = 0; k < added.size(); ++k) {
    const EdgePoint& e = added[k];
    VertexType& v = m.vert[order[nv0 + k]];
    const std::array<double, 3> w = e.weights();
    const int n = e.c >= 0 ? 3 : 2;
    const VertexType* src[3] = {&m.vert[order[e.a]], &m.vert[order[e.b]], e.c >= 0 ? &m.vert[order[e.c]] : nullptr};
    const auto mix = [&](const auto& get) {
      double x = 0;
      for (int i = 0; i < n; ++i) x += w[i] * get(*src[i]);
      return x;
    };
    if (tex) {
      using TexScalar = typename VertexType::TexCoordType::ScalarType;
      v.T().U() = static_cast<TexScalar>(mix([](const VertexType& s) { return double(s.cT().U()); }));
      v.T().V() = static_cast<TexScalar>(mix([](const VertexType& s) { return double(s.cT().V()); }));
      int heaviest = 0;
      for (int i = 1; i < n; ++i)
        if (w[i] > w[heaviest]) heaviest = i;
      // An edge's midpoint takes a's index, as it always has.
      v.T().N() = src[heaviest]->cT().N();
    }
    if (color)
      for (int c = 0; c < 4; ++c) {
        const double x = std::round(mix([c](const VertexType& s) { return double(s.cC()[c]); }));
        v.C()[c] = static_cast<typename VertexType::ColorType::ScalarType>(std::min(255.0, std::max(0.0, x)));
      }
    if (quality)
      v.Q() = static_cast<typename VertexType::QualityType>(mix([](const VertexType& s) { return double(s.cQ()); }));
  }
}

/// Refuses a repair or flips on a mesh with per-wedge texture coordinates,
/// normals or colours: they belong to the corners of faces, which splits,
/// collapses and flips rewire, and they cannot be interpolated per vertex.
/// \throw InvalidInput before anything is touched.
template <class MeshType>
void checkConnectivityMayChange(const MeshType& m, const SodtParams& p) {
  if (!p.repair && !p.flips) return;
  if (vcg::tri::HasPerWedgeTexCoord(m) || vcg::tri::HasPerWedgeNormal(m) || vcg::tri::HasPerWedgeColor(m))
    throw InvalidInput(std::string(p.repair ? "the local repair" : "edge flips") +
                       " would scramble the per-wedge texture coordinates, normals or colours of this mesh "
                       "(they cannot be interpolated per vertex); the mesh was not changed. Turn " +
                       (p.repair && p.flips ? "the repair and flips" : p.repair ? "the repair" : "flips") +
                       " off, or remove the per-wedge attributes first");
}

/// Runs the repair (SodtParams::repair) on the swept working mesh and
/// resizes m for what it added and removed, with the added vertices'
/// attributes interpolated (interpolateAddedVertices); cls grows by the
/// added vertices (smooth, or crease on a feature edge) and moved receives
/// them. faceNormal: the swept faces' input orientations, from which
/// stats.maxFaceTurnDeg is measured again on the repaired mesh.
template <class MeshType>
void repairWorkingMesh(MeshType& m, const SodtParams& p, WorkingMesh& w, const RepairInput& input,
                       const std::vector<Vec3>& faceNormal, Classification& cls, std::vector<int>& moved,
                       SodtStats& stats) {
  const std::size_t nv0 = w.pos.size();
  const std::vector<char> liveBefore = w.faces.live;
  const FaceList facesBefore = w.faces;
  const std::vector<Vec3> posBefore = w.pos;
  std::vector<char> movable(nv0, 0);
  for (int v : moved) movable[v] = 1;
  RepairSettings s;
  s.targetRad = p.repairAngleDeg * kPi / 180;
  s.featureRad = p.featureAngleDeg * kPi / 180;
  s.flipMaxRad = std::max(p.flipMaxDihedralDeg, 1.0) * kPi / 180;
  s.bound = input.bound;
  s.maxTurnCos2 = input.maxTurnCos2;
  s.maxAdded = std::llround(static_cast<double>(nv0) * p.repairBudgetPct / 100.0);
  LocalRepair repair(w.pos, w.faces, w.deleted, input.grid.get(), s);
  const bool classified = p.algorithm == Algorithm::Feature || p.algorithm == Algorithm::Denoise;
  // Border vertices the run may change (selected ones with selectedOnly)
  // may go along the border.
  std::vector<char> border(nv0, 0);
  for (std::size_t v = 0; v < nv0; ++v)
    border[v] = w.topo.kind[v] == VertexKind::Boundary && (!p.selectedOnly || w.selected[v]);
  // Interior corners the run may change may be welded (kRepairWeldFactor).
  std::vector<char> corners(nv0, 0);
  if (classified)
    for (std::size_t v = 0; v < nv0; ++v)
      corners[v] = w.topo.kind[v] == VertexKind::Interior && cls.cls[v] == VertexClass::Corner &&
                   (!p.selectedOnly || w.selected[v]);
  repair.setUp(movable, classified ? &cls.cls : nullptr, classified ? &cls.creaseDir : nullptr, &border, &corners);
  const RepairResult r = repair.run();
  stats.repairSplits = r.splits;
  stats.repairCollapses = r.collapses;
  stats.repairFlips = r.flips;
  stats.repairInserts = r.inserts;
  stats.verticesAdded = r.added;
  stats.verticesRemoved = r.removed;
  stats.repairMoves = r.relaxMoves;
  stats.belowTarget = r.remaining;
  for (char c : repair.newCrease()) {
    cls.cls.push_back(c ? VertexClass::Crease : VertexClass::Smooth);
    if (!cls.creaseDir.empty()) cls.creaseDir.push_back(Vec3(0, 0, 0));
  }
  for (std::size_t i = nv0; i < w.pos.size(); ++i) moved.push_back(static_cast<int>(i));
  stats.maxFaceTurnDeg = repairedFaceTurnDeg(w.faces, w.pos, facesBefore, posBefore, faceNormal, *input.grid);
  resizeForRepair(m, w, nv0, liveBefore, p.selectedOnly);
  interpolateAddedVertices(m, w.order, nv0, repair.added());
  w.topo = buildRingTopology(w.faces, w.deleted);
}

}  // namespace sodt
