// SPDX-License-Identifier: GPL-3.0-or-later
// One S-ODT run as a list of stages. RunState holds what the stages share
// (the working mesh, the classes, the guards' inputs, the sweeper); each
// optional feature is a Stage with the hooks it needs, called in list order:
//   beforeClasses  on the input, before the classification (Filtered's filter)
//   prepare        after the set-up, before the first sweep
//   afterSweep     after each sweep (flips, keep-best); true stops the sweeps
//   afterSweeps    restores the returned state (keep-best, Filtered's restore)
//   finish         changes the returned mesh (repair) and counts
//   last           after every stage's finish: checks of the returned mesh
// A new feature adds a stage to makeStages(), not lines to SodtSmoother::Apply.
#pragma once

#include "denoise/filter_select.h"
#include "denoise/surface_restore.h"
#include "guards/cover.h"
#include "guards/facing.h"
#include "guards/guarded_move.h"
#include "guards/sweep_quality.h"
#include "mesh/working_mesh.h"
#include "params.h"
#include "remesh/flips.h"
#include "remesh/repair.h"
#include "sweeps/boundary.h"
#include "sweeps/run_setup.h"
#include "sweeps/sweeper.h"

#include <wrap/callback.h>

#include <memory>
#include <vector>

namespace sodt {

/// The state of one run, shared by its stages. Built once by
/// SodtSmoother::Apply; not copyable (the guards hold references into it).
template <class MeshType>
struct RunState {
  using Scalar = typename MeshType::ScalarType;

  RunState(MeshType& mesh, const SodtParams& params, vcg::CallBackPos* callback, SweepTuning t, SodtStats& s)
      : m(mesh), given(params), p(params), cb(callback), tuning(t), stats(s) {}
  RunState(const RunState&) = delete;
  RunState& operator=(const RunState&) = delete;

  MeshType& m;
  const SodtParams& given;  ///< the caller's parameters
  SodtParams p;             ///< the sweeps' (Filtered's stage changes them)
  vcg::CallBackPos* cb;
  SweepTuning tuning;
  SodtStats& stats;

  WorkingMesh w;
  int threads = 1;
  double meanEdge = 0;  ///< the length scale of Feature and Denoise
  Classification cls;
  std::vector<int> active;  ///< the vertices the sweeps move
  /// The input orientation of every face (flips merge the flipped pair's):
  /// the guards and keep-best test faces against it, and the returned
  /// state's largest face turn is measured from it.
  std::vector<Vec3> faceNormal;
  std::vector<Vec3> noNormals;
  const std::vector<Vec3>* guardNormal = &noNormals;
  double turnCos2 = 0;
  std::vector<FittedFrame> fit;  ///< Denoise: the fitted planes and lines
  DeviationInput input;
  std::unique_ptr<VisitContext> ctx;  ///< made by setUpRun
  BoundarySlide slide;  ///< the border vertices that slide (empty without slideBoundary)
  std::unique_ptr<Sweeper<Scalar>> sweeper;

  Classification outCls;   ///< the classes of the returned mesh
  std::vector<int> moved;  ///< the vertices the sweeps (and the repair) may have moved
  std::vector<int> written;  ///< others that may have moved (slid, filtered)
};

/// A feature of the run; see the hooks' order at the top of this file.
template <class MeshType>
struct Stage {
  virtual ~Stage() = default;
  virtual void beforeClasses(RunState<MeshType>&) {}
  virtual void prepare(RunState<MeshType>&) {}
  virtual bool afterSweep(RunState<MeshType>&) { return false; }
  virtual void afterSweeps(RunState<MeshType>&) {}
  virtual void finish(RunState<MeshType>&) {}
  virtual void last(RunState<MeshType>&) {}
};

/// The set-up every run has, between beforeClasses and prepare: length
/// scale, classes and their counts, the moving vertices, the input face
/// orientations, Denoise's fits, the deviation bound's input and the box
/// no move may leave.
template <class MeshType>
void setUpRun(RunState<MeshType>& r) {
  const SodtParams& p = r.p;
  const bool usesMeanEdge = p.algorithm == Algorithm::Feature || p.algorithm == Algorithm::Denoise;
  r.meanEdge = usesMeanEdge ? meanEdgeLength(r.m) : 0.0;
  r.threads = resolveThreads(p.threads);
  r.stats.threads = r.threads;
  std::vector<Vec3> projected;  // Denoise: the input on its fitted planes
  r.cls = classifyForAlgorithm(p, r.w.topo, r.w.pos, r.meanEdge, r.threads, projected);
  r.stats.smoothVertices = r.cls.smooth();
  r.stats.creaseVertices = r.cls.crease();
  r.stats.cornerVertices = r.cls.corner();
  r.active = activeVertices(p, r.w.topo, r.cls, r.w.selected, r.stats);
  r.turnCos2 = runTurnCos2(p);
  r.faceNormal = faceNormals(r.w.faces, r.w.pos, r.turnCos2 > 0 ? p.maxFaceTurnDeg : 90.0);
  if (p.guard != Guard::None || p.keepBest) r.guardNormal = &r.faceNormal;
  if (p.algorithm == Algorithm::Denoise)
    r.fit = fitDenoiseFrames(r.w.topo, r.w.pos, std::move(projected), r.cls, r.active, r.threads);
  r.input.prepare(p, r.w.pos, r.w.topo, r.w.faces);
  r.ctx.reset(new VisitContext{MoveInputs{r.p, r.cls, r.fit, r.meanEdge}, r.input.get(),
                               r.tuning.simd && lanes::available(), Vec3(0, 0, 0), Vec3(0, 0, 0)});
  reachBox(p, r.w.pos, r.w.topo, r.meanEdge, r.ctx->boxLo, r.ctx->boxHi);
}

/// Filtered (Algorithm::Filtered): denoises first (filter_select.h); the
/// sweeps then run Algorithm 2 with the denoised surface as their input
/// (its classes, face orientations and deviation bound), and its smooth
/// vertices are set back on the denoised surface's quadrics after them,
/// within the bound. The filter may move vertices the sweeps hold still
/// (corners): they are written back too.
template <class MeshType>
struct FilterStage : Stage<MeshType> {
  void beforeClasses(RunState<MeshType>& r) override {
    r.stats.filter = denoiseFirst(r.w, r.given, resolveThreads(r.given.threads), r.cb, filtered_);
    r.p = sweepParams(r.given, r.stats.filter.kind);
    r.p.maxDeviationRel = sweepBound(r.given.maxDeviationRel, r.stats.filter, r.m, r.w);
    r.stats.filteredSweepBoundRel = r.p.maxDeviationRel;
  }
  void prepare(RunState<MeshType>& r) override {
    for (int i : r.active)
      if (r.cls.cls[i] == VertexClass::Smooth) onQuadrics_.push_back(i);
    quadrics_.fit(r.w.topo, r.w.pos, onQuadrics_, std::cos(r.p.featureAngleDeg * kPi / 360.0), r.threads);
  }
  void afterSweeps(RunState<MeshType>& r) override {
    if (onQuadrics_.empty()) return;
    r.stats.restoredVertices = restoreOnQuadrics(quadrics_, r.w.topo, r.faceNormal, r.p.guard == Guard::Quality,
                                                 r.input.get(), r.meanEdge, onQuadrics_, r.w.pos);
  }
  void finish(RunState<MeshType>& r) override {
    r.written.insert(r.written.end(), filtered_.begin(), filtered_.end());
  }

  /// The parameters of the sweeps: Algorithm 2's, with the deviation
  /// bound against the denoised surface (against the input when no filter
  /// ran), so that the result is never farther from the input than the
  /// filter moved it plus the bound, and with their own face turn bound
  /// (filteredFaceTurnDeg; SodtParams::maxFaceTurnDeg is not used).
  static SodtParams sweepParams(const SodtParams& params, FilterKind filter) {
    SodtParams p = params;
    p.algorithm = Algorithm::Feature;
    p.maxFaceTurnDeg = filteredFaceTurnDeg(filter);
    return p;
  }

  /// The sweeps' deviation bound against the denoised surface, relative to
  /// the diagonal: the given bound, and after a filter at least
  /// kFilteredNoiseShare of the noise's standard deviation, since the
  /// filter leaves the surface known no better than that and a tighter
  /// bound holds the residual bumps' slivers in place (0: no bound).
  static double sweepBound(double given, const FilterChoice& c, const MeshType& m, const WorkingMesh& w) {
    if (!(given > 0) || c.kind == FilterKind::None || !(c.noiseEdges > 0) || !std::isfinite(c.noiseEdges))
      return given;
    const double diagonal = surfaceDiagonal(w.pos, w.topo);
    if (!(diagonal > 0)) return given;
    return std::max(given, kFilteredNoiseShare * c.noiseEdges * meanEdgeLength(m) / diagonal);
  }

 private:
  /// The filter on the working mesh: interior vertices move (only selected
  /// ones with selectedOnly); border and non-manifold vertices stay, as in
  /// the sweeps. moved gets the vertices that may have moved (none when no
  /// filter was chosen).
  static FilterChoice denoiseFirst(WorkingMesh& w, const SodtParams& p, int threads, vcg::CallBackPos* cb,
                                   std::vector<int>& moved) {
    std::vector<char> movable(w.pos.size(), 0);
    for (std::size_t i = 0; i < w.pos.size(); ++i)
      movable[i] = w.topo.kind[i] == VertexKind::Interior && (!p.selectedOnly || w.selected[i]);
    const FilterChoice c = filteredDenoise(w.faces, movable, p.featureAngleDeg, p.noiseLevelEdges, threads, w.pos, cb);
    moved.clear();
    if (c.kind != FilterKind::None)
      for (std::size_t i = 0; i < movable.size(); ++i)
        if (movable[i]) moved.push_back(static_cast<int>(i));
    return c;
  }

  std::vector<int> filtered_;    // the vertices the filter may have moved
  std::vector<int> onQuadrics_;  // the smooth moving vertices
  SurfaceQuadrics quadrics_;     // the denoised surface's, at them
};

/// slideBoundary: border vertices slide along the border (boundary.h).
/// The slide state lives in RunState (the sweeper and the flips use it).
template <class MeshType>
struct SlideStage : Stage<MeshType> {
  void prepare(RunState<MeshType>& r) override {
    r.slide.prepare(r.p, r.w.faces, r.w.topo, r.w.pos, r.w.selected);
    start_ = r.slide.positions(r.w.pos);
  }
  void finish(RunState<MeshType>& r) override {
    r.stats.movedBoundary = r.slide.movedFrom(start_, r.w.pos);
    r.written.insert(r.written.end(), r.slide.vertex.begin(), r.slide.vertex.end());
  }

 private:
  std::vector<Vec3> start_;
};

/// The deviation bound's other direction: the input near the output stays
/// covered by it (cover.h). With the bound only.
template <class MeshType>
struct CoverStage : Stage<MeshType> {
  void prepare(RunState<MeshType>& r) override {
    if (!r.input.get()) return;
    cover_.prepare(r.w.faces, r.w.topo, r.w.pos, kCoverLimitFactor * r.input.get()->limit);
    r.ctx->cover = &cover_;
  }

 private:
  InputCover cover_;
};

/// flips: edge flips after each sweep (flips.h), under the run's bound, its
/// cover and its face turn bound.
template <class MeshType>
struct FlipStage : Stage<MeshType> {
  /// Flip passes after a sweep, at most (each pass flips an edge only when
  /// the pair's smaller angle grows, so passes end anyway).
  static constexpr int kMaxFlipPasses = 10;

  void prepare(RunState<MeshType>& r) override {
    rules_.maxDihedralRad = r.p.flipMaxDihedralDeg * kPi / 180.0;
    if (r.p.algorithm != Algorithm::Basic) {
      rules_.cls = &r.cls.cls;
      rules_.creaseDir = &r.cls.creaseDir;
    }
    rules_.input = r.input.get();
    rules_.cover = r.ctx->cover;
    rules_.keepTurn = r.turnCos2 > 0;
    rules_.maxTurnCos2 = r.turnCos2;
  }

  /// Flips edges (see flipPass) and tells the sweeper (and the sliding
  /// border vertices' fans) what changed. After the first pass, only edges
  /// around the flips of the pass before can flip.
  bool afterSweep(RunState<MeshType>& r) override {
    WorkingMesh& w = r.w;
    int flipped = 0;
    std::vector<int> flippedVertices;  // a, b, c, d of each flip
    std::vector<char> seed;
    for (int pass = 0; pass < kMaxFlipPasses; ++pass) {
      const std::size_t from = flippedVertices.size();
      const int n = flipPass(w.faces, w.pos, rules_, &r.faceNormal, &flippedVertices, pass > 0 ? &seed : nullptr);
      flipped += n;
      if (n == 0) break;
      seed.assign(w.pos.size(), 0);
      for (std::size_t k = from; k < flippedVertices.size(); ++k) seed[flippedVertices[k]] = 1;
    }
    if (flipped == 0) return false;
    r.stats.flips += flipped;
    const RingTopology before = std::move(w.topo);
    w.topo = buildRingTopology(w.faces, w.deleted);
    r.slide.rebuildFans(w.faces, static_cast<int>(w.pos.size()));
    r.sweeper->connectivityChanged(before, flippedVertices);
    return false;
  }

 private:
  FlipRules rules_;
};

/// keepBest and toleranceDeg (sweep_quality.h): measures each sweep's
/// state, stops when the tolerance is met, returns the best state.
template <class MeshType>
struct BestStateStage : Stage<MeshType> {
  void prepare(RunState<MeshType>& r) override {
    best_ = std::make_unique<BestState>(r.p.keepBest, r.p.toleranceDeg, r.p.flips, r.w.faces, r.w.pos,
                                        *r.guardNormal, r.threads, r.tuning.simd);
  }
  bool afterSweep(RunState<MeshType>& r) override {
    return best_->afterSweep(r.stats.iterations, r.w.faces, r.w.pos, *r.guardNormal);
  }
  void afterSweeps(RunState<MeshType>& r) override {
    r.stats.returnedSweep = best_->restore(r.stats.iterations, r.w.pos, r.w.faces, r.faceNormal);
    if (r.stats.returnedSweep != r.stats.iterations && r.p.flips) r.w.topo = buildRingTopology(r.w.faces, r.w.deleted);
  }

 private:
  std::unique_ptr<BestState> best_;
};

/// repair: local remeshing of the worst triangles after the sweeps
/// (repair.h), against the input taken before the first sweep.
template <class MeshType>
struct RepairStage : Stage<MeshType> {
  void prepare(RunState<MeshType>& r) override { input_.prepare(r.p, r.w.pos, r.w.faces, r.w.topo); }
  void finish(RunState<MeshType>& r) override {
    repairWorkingMesh(r.m, r.p, r.w, input_, r.faceNormal, r.outCls, r.moved, r.stats);
  }

 private:
  RepairInput input_;
};

/// The stages of a run with parameters p (the caller's), in hook order.
/// With a guard: no returned face faces away from the input under it
/// (facing.h), the surface the sweeps keep to (Filtered's denoised one
/// when its filter ran), under the sweeps' face-turn and deviation bounds.
/// Takes that surface before the first sweep, mends after every stage has
/// finished (and, with a repair, before it: it is the first stage).
template <class MeshType>
struct UnfoldStage : Stage<MeshType> {
  static bool applies(const SodtParams& p) { return p.guard != Guard::None && p.algorithm != Algorithm::Denoise; }
  void prepare(RunState<MeshType>& r) override {
    input_ = std::make_unique<FacingInput>(r.w.pos, r.w.faces);
    pos_ = r.w.pos;
    if (DeviationInput::applies(r.p)) bound_ = r.p.maxDeviationRel * surfaceDiagonal(r.w.pos, r.w.topo);
  }
  /// With a repair, mends before it too: the repair then starts from
  /// faces that face along the input, and the counts say what was found
  /// first.
  void finish(RunState<MeshType>& r) override {
    if (!r.p.repair) return;
    const UnfoldResult u = mend(r);
    r.stats.facingAwayFound = u.found;
    r.stats.unfoldMoves = u.moves;
    r.stats.unfoldFlips = u.flips;
    mendedBefore_ = true;
  }
  void last(RunState<MeshType>& r) override {
    const UnfoldResult u = mend(r);
    if (!mendedBefore_) r.stats.facingAwayFound = u.found;
    r.stats.unfoldMoves += u.moves;
    r.stats.unfoldFlips += u.flips;
    r.stats.facingAwayLeft = u.left;
  }

 private:
  /// unfoldFacingAway on the mesh as it is: flips when the run may change
  /// the connectivity, moves to the middle for the smooth interior
  /// vertices the run moves.
  UnfoldResult mend(RunState<MeshType>& r) {
    std::vector<int> moved;
    UnfoldFreedom may;
    may.flip = r.p.flips || r.p.repair;
    std::vector<char> centre(r.w.pos.size(), 0);
    for (int v : r.moved) {
      const std::size_t i = static_cast<std::size_t>(v);
      centre[i] = !r.w.deleted[i] && r.w.topo.kind[i] == VertexKind::Interior && i < r.outCls.cls.size() &&
                  r.outCls.cls[i] == VertexClass::Smooth;
    }
    may.centre = &centre;
    may.refNormal = &r.faceNormal;
    const UnfoldResult u = unfoldFacingAway(r.w.pos, r.w.faces, may, r.w.deleted, pos_, *input_, r.turnCos2,
                                            bound_, r.threads, &moved);
    if (u.flips > 0) r.w.topo = buildRingTopology(r.w.faces, r.w.deleted);
    r.written.insert(r.written.end(), moved.begin(), moved.end());
    return u;
  }

  bool mendedBefore_ = false;  ///< finish() mended before the repair
  std::unique_ptr<FacingInput> input_;
  std::vector<Vec3> pos_;  ///< the input positions
  double bound_ = 0;       ///< the deviation bound (0: none)
};

template <class MeshType>
std::vector<std::unique_ptr<Stage<MeshType>>> makeStages(const SodtParams& p) {
  std::vector<std::unique_ptr<Stage<MeshType>>> s;
  if (UnfoldStage<MeshType>::applies(p)) s.push_back(std::make_unique<UnfoldStage<MeshType>>());
  if (p.slideBoundary) s.push_back(std::make_unique<SlideStage<MeshType>>());
  s.push_back(std::make_unique<CoverStage<MeshType>>());
  if (p.flips) s.push_back(std::make_unique<FlipStage<MeshType>>());
  s.push_back(std::make_unique<BestStateStage<MeshType>>());
  if (p.algorithm == Algorithm::Filtered) s.push_back(std::make_unique<FilterStage<MeshType>>());
  if (p.repair) s.push_back(std::make_unique<RepairStage<MeshType>>());
  return s;
}

}  // namespace sodt
