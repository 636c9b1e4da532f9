// SPDX-License-Identifier: GPL-3.0-or-later
// Gauss-Seidel S-ODT sweeps over a vcg triangle mesh (paper Algorithms 1-3),
// with the fold / quality safeguards applied to every move before it is
// committed. The run as a recipe; its steps live in their own headers:
//   working_mesh.h  the mesh as index arrays in a cache-friendly order
//   run_setup.h     classes, moving vertices, input normals, fits, the input surface
//   moves.h         each algorithm's move of one vertex (smoothMove, creaseMove, ...)
//   guarded_move.h  one visit: the move under the guards
//   sweeper.h       the sweeps, colour by colour, lanes and threads
//   flips.h         edge flips between sweeps
//   sweep_quality.h the best state for keepBest and toleranceDeg
//   surface_restore.h Filtered: smooth vertices back on the denoised surface
#pragma once

#include "sweeps/boundary.h"
#include "maths/classify.h"
#include "remesh/flips.h"
#include "guards/guarded_move.h"
#include "denoise/filter_select.h"
#include "params.h"
#include "remesh/repair.h"
#include "sweeps/run_setup.h"
#include "denoise/surface_restore.h"
#include "guards/sweep_quality.h"
#include "sweeps/sweeper.h"
#include "maths/topology.h"
#include "mesh/working_mesh.h"

#include <wrap/callback.h>

#include <chrono>
#include <string>
#include <vector>

namespace sodt {

/// Smooths a vcg triangle mesh in place with S-ODT.
template <class MeshType>
struct SodtSmoother {
  using ScalarType = typename MeshType::ScalarType;

  /// Runs p.iterations Gauss-Seidel sweeps of the chosen algorithm.
  ///
  /// Basic (Algorithm 1, Sec. 2.3): each vertex with a closed, manifold
  /// one-ring moves in its tangent plane (Eq. 4) to the closed-form minimiser
  /// of Eq. 5. Feature (Algorithm 2, Sec. 2.4): vertices are classified once,
  /// on the input, by their normal tensor (Eq. 9-10); corners stay fixed,
  /// creases move along the crease direction e3 to the minimiser of Eq. 5 on
  /// that line, smooth vertices as in Basic. Denoise (Algorithm 3, Sec. 2.5):
  /// as Feature, but each smooth vertex moves on the weighted least-squares
  /// plane of Eq. 12-13 and each crease vertex on a line fitted to the crease
  /// vertices around it; both are fitted once, on the input, so the result
  /// stays on the input's local fits instead of creeping inwards sweep after
  /// sweep, and a vertex moves at most p.maxNormalStepRel mean edge lengths
  /// along its fitted normal per sweep.
  ///
  /// The local solves are done in double; the committed position is the one
  /// representable in ScalarType, and that rounded position is what the guard
  /// checks. With Basic, Guard::None and a double mesh the enclosed volume of
  /// a closed mesh is kept to rounding (Appendix D). Boundary, non-manifold,
  /// isolated and deleted vertices never move (border vertices slide along
  /// the border with p.slideBoundary, see boundary.h); with p.selectedOnly only
  /// selected vertices move. Updates the bounding box, and the unit face and
  /// vertex normals when present (see writeNormals).
  ///
  /// \param m  mesh to smooth; needs per-vertex flags (deleted, selected).
  /// \param p  validated by this call.
  /// \param cb optional progress callback (0..100), called once per sweep;
  ///           returning false stops after the current sweep.
  /// \param classes when not null, receives the classification used (all
  ///        interior vertices Smooth for Basic).
  /// \param tuning switches of speed alone: the result is the same for
  ///        every setting.
  /// \throw InvalidInput for bad parameters, a non-finite coordinate or a
  ///        mesh outside the sizes of checkMeshSize(); the mesh is untouched then.
  static SodtStats Apply(MeshType& m, const SodtParams& params, vcg::CallBackPos* cb = nullptr,
                         Classification* classes = nullptr, SweepTuning tuning = SweepTuning()) {
    params.validate();
    checkFiniteCoordinates(m);
    SodtStats stats;
    WorkingMesh w = loadWorkingMesh(m, params.selectedOnly);
    stats.reorientedFaces = w.reorientedFaces;
    // Filtered: denoise first (filter_select.h); the sweeps then run
    // Algorithm 2 with the denoised surface as their input (its classes and
    // face orientations), without the deviation bound.
    // The filter may move vertices the sweeps then hold still (corners):
    // they are written back too.
    std::vector<int> filtered;
    if (params.algorithm == Algorithm::Filtered)
      stats.filter = denoiseFirst(w, params, resolveThreads(params.threads), cb, filtered);
    const SodtParams p = sweepParams(params, stats.filter.kind);
    // The length scale of classification, crease moves and denoising steps.
    const bool usesMeanEdge = p.algorithm == Algorithm::Feature || p.algorithm == Algorithm::Denoise;
    const double meanEdge = usesMeanEdge ? meanEdgeLength(m) : 0.0;
    const int threads = resolveThreads(p.threads);
    stats.threads = threads;

    std::vector<Vec3> projected;  // Denoise: the input on its fitted planes
    const Classification cls = classifyForAlgorithm(p, w.topo, w.pos, meanEdge, threads, projected);
    stats.smoothVertices = cls.smooth();
    stats.creaseVertices = cls.crease();
    stats.cornerVertices = cls.corner();
    const std::vector<int> active = activeVertices(p, w.topo, cls, w.selected, stats);
    BoundarySlide slide;  // the border vertices that slide (slideBoundary)
    if (p.slideBoundary) slide.prepare(p, w.faces, w.topo, w.pos, w.selected);
    slide.count(stats);
    const std::vector<Vec3> slideStart = slide.positions(w.pos);
    // The input orientation of every face (flips merge the flipped pair's):
    // the guards and keepBest test faces against it, and the returned
    // state's largest face turn is measured from it.
    const double turnCos2 = runTurnCos2(p);
    std::vector<Vec3> faceNormal = faceNormals(w.faces, w.pos, turnCos2 > 0 ? p.maxFaceTurnDeg : 90.0);
    const std::vector<Vec3> none;
    const std::vector<Vec3>& guardNormal = p.guard != Guard::None || p.keepBest ? faceNormal : none;
    const std::vector<FittedFrame> fit =
        p.algorithm == Algorithm::Denoise
            ? fitDenoiseFrames(w.topo, w.pos, std::move(projected), cls, active, threads)
            : std::vector<FittedFrame>();
    DeviationInput input;
    input.prepare(p, w.pos, w.topo, w.faces);
    RepairInput repairInput;
    repairInput.prepare(p, w.pos, w.faces, w.topo);
    VisitContext ctx{MoveInputs{p, cls, fit, meanEdge}, input.get(), tuning.simd && lanes::available(),
                     Vec3(0, 0, 0), Vec3(0, 0, 0)};
    reachBox(p, w.pos, w.topo, meanEdge, ctx.boxLo, ctx.boxHi);
    InputCover cover;  // the bound's other direction: the input near the output
    if (input.get()) {
      cover.prepare(w.faces, w.topo, w.pos, kCoverLimitFactor * input.get()->limit);
      ctx.cover = &cover;
    }
    FlipRules flipRules;
    flipRules.maxDihedralRad = p.flipMaxDihedralDeg * kPi / 180.0;
    if (p.algorithm != Algorithm::Basic) {
      flipRules.cls = &cls.cls;
      flipRules.creaseDir = &cls.creaseDir;
    }
    flipRules.input = input.get();  // flips must keep the bound too
    flipRules.cover = ctx.cover;
    flipRules.keepTurn = turnCos2 > 0;  // and the face turn bound
    flipRules.maxTurnCos2 = turnCos2;
    // Filtered: the denoised surface's quadrics at its smooth vertices, to
    // set them back on it after the sweeps.
    std::vector<int> onQuadrics;
    SurfaceQuadrics quadrics;
    if (params.algorithm == Algorithm::Filtered) {
      for (int i : active)
        if (cls.cls[i] == VertexClass::Smooth) onQuadrics.push_back(i);
      quadrics.fit(w.topo, w.pos, onQuadrics, std::cos(p.featureAngleDeg * kPi / 360.0), threads);
    }
    BestState best(p.keepBest, p.toleranceDeg, p.flips, w.faces, w.pos, guardNormal, threads, tuning.simd);

    Sweeper<ScalarType> sweeper(ctx, w.pos, w.topo, guardNormal, active, threads, tuning, &slide);
    const auto sweepsStart = std::chrono::steady_clock::now();
    for (int it = 0; it < p.iterations && !(active.empty() && slide.empty()); ++it) {
      sweeper.sweep();
      ++stats.iterations;
      if (p.flips) flipEdges(w, flipRules, faceNormal, sweeper, slide, stats);
      const bool stop = best.afterSweep(it + 1, w.faces, w.pos, guardNormal);
      const bool goOn = !cb || cb(100 * (it + 1) / p.iterations, ("S-ODT sweep " + std::to_string(it + 1) + "/" +
                                                                  std::to_string(p.iterations)).c_str());
      stats.stoppedEarly = stop;
      stats.cancelled = !stop && !goOn;
      if (stop || !goOn) break;
    }
    stats.sweepSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sweepsStart).count();
    sweeper.addCounts(stats);
    stats.returnedSweep = best.restore(stats.iterations, w.pos, w.faces, faceNormal);
    if (stats.returnedSweep != stats.iterations && p.flips) w.topo = buildRingTopology(w.faces, w.deleted);
    if (!onQuadrics.empty())
      stats.restoredVertices =
          restoreOnQuadrics(quadrics, w.topo, faceNormal, p.guard == Guard::Quality, meanEdge, onQuadrics, w.pos);
    stats.maxFaceTurnDeg = largestFaceTurnDeg(w.faces, w.pos, faceNormal);

    Classification outCls = cls;
    std::vector<int> moved = active;
    stats.movedBoundary = slide.movedFrom(slideStart, w.pos);
    if (p.repair) repairWorkingMesh(m, p, w, repairInput, outCls, moved, stats);

    // The mesh is written only here, positions and faces together.
    std::vector<int> moving = moved;
    moving.insert(moving.end(), slide.vertex.begin(), slide.vertex.end());
    moving.insert(moving.end(), filtered.begin(), filtered.end());
    writeBack(m, w, moving, stats.flips > 0 || stats.reorientedFaces > 0 || p.repair, threads);
    if (classes) *classes = inMeshOrder(outCls, w.order);
    return stats;
  }

 private:
  /// The parameters of the sweeps: Filtered's sweeps are Algorithm 2's,
  /// without the deviation bound, with their own face turn bound
  /// (filteredFaceTurnDeg; SodtParams::maxFaceTurnDeg is not used). Their moves are tangential to the denoised surface anyway: on
  /// the noise benchmark's meshes the deviation bound (against the denoised
  /// surface) only kept the triangles worse, at the same distance to the
  /// clean surface.
  static SodtParams sweepParams(const SodtParams& params, FilterKind filter) {
    SodtParams p = params;
    if (p.algorithm == Algorithm::Filtered) {
      p.algorithm = Algorithm::Feature;
      p.maxDeviationRel = 0;
      p.maxFaceTurnDeg = filteredFaceTurnDeg(filter);
    }
    return p;
  }

  /// Filtered's first stage (filter_select.h) on the working mesh:
  /// interior vertices move (only selected ones with selectedOnly); border
  /// and non-manifold vertices stay, as in the sweeps. moved gets the
  /// vertices that may have moved (none when no filter was chosen).
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

  /// Flip passes after a sweep, at most (each pass flips an edge only when
  /// the pair's smaller angle grows, so passes end anyway).
  static constexpr int kMaxFlipPasses = 10;

  /// Flips edges after a sweep (see flipPass) and tells the sweeper (and
  /// the sliding border vertices' fans) what changed. After the first pass,
  /// only edges around the flips of the pass before can flip: the others
  /// are passed over.
  static void flipEdges(WorkingMesh& w, const FlipRules& rules, std::vector<Vec3>& faceNormal,
                        Sweeper<ScalarType>& sweeper, BoundarySlide& slide, SodtStats& stats) {
    int flipped = 0;
    std::vector<int> flippedVertices;  // a, b, c, d of each flip
    std::vector<char> seed;
    for (int pass = 0; pass < kMaxFlipPasses; ++pass) {
      const std::size_t from = flippedVertices.size();
      const int n = flipPass(w.faces, w.pos, rules, &faceNormal, &flippedVertices, pass > 0 ? &seed : nullptr);
      flipped += n;
      if (n == 0) break;
      seed.assign(w.pos.size(), 0);
      for (std::size_t k = from; k < flippedVertices.size(); ++k) seed[flippedVertices[k]] = 1;
    }
    if (flipped == 0) return;
    stats.flips += flipped;
    const RingTopology before = std::move(w.topo);
    w.topo = buildRingTopology(w.faces, w.deleted);
    slide.rebuildFans(w.faces, static_cast<int>(w.pos.size()));
    sweeper.connectivityChanged(before, flippedVertices);
  }
};

}  // namespace sodt
