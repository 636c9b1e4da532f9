// SPDX-License-Identifier: GPL-3.0-or-later
// Gauss-Seidel S-ODT sweeps over a vcg triangle mesh (paper Algorithms 1-3),
// with the fold / quality safeguards applied to every move before it is
// committed. Apply is the run as a list of stages (stages.h); the folders
// beside this file hold the rest, from the bottom up:
//   maths/    the paper's equations: local solves, ODT, classes, fits, moves
//   mesh/     the working mesh, its normals, the output attributes
//   guards/   the guarded move, the deviation bound and its cover, keep-best
//   sweeps/   the sweeper, its lanes and colours, the boundary slide, set-up
//   remesh/   edge flips and the local repair
//   denoise/  Filtered's normal filter, its choice, the noise estimate
#pragma once

#include "params.h"
#include "stages.h"

#include <wrap/callback.h>

#include <chrono>
#include <memory>
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
  /// \throw InvalidInput for bad parameters, a non-finite coordinate, a
  ///        mesh outside the sizes of checkMeshSize(), or repair or flips on
  ///        per-wedge attributes (checkConnectivityMayChange); the mesh is
  ///        untouched then.
  static SodtStats Apply(MeshType& m, const SodtParams& params, vcg::CallBackPos* cb = nullptr,
                         Classification* classes = nullptr, SweepTuning tuning = SweepTuning()) {
    params.validate();
    checkFiniteCoordinates(m);
    checkConnectivityMayChange(m, params);
    SodtStats stats;
    RunState<MeshType> r(m, params, cb, tuning, stats);
    r.w = loadWorkingMesh(m, params.selectedOnly, params.repair);
    stats.reorientedFaces = r.w.reorientedFaces;
    stats.collapsedFacesRemoved = static_cast<int>(r.w.droppedFaces.size());
    const auto stages = makeStages<MeshType>(params);
    for (auto& s : stages) s->beforeClasses(r);
    setUpRun(r);
    for (auto& s : stages) s->prepare(r);
    r.slide.count(stats);

    r.sweeper = std::make_unique<Sweeper<ScalarType>>(*r.ctx, r.w.pos, r.w.topo, *r.guardNormal, r.active,
                                                      r.threads, tuning, &r.slide);
    const auto sweepsStart = std::chrono::steady_clock::now();
    for (int it = 0; it < r.p.iterations && !(r.active.empty() && r.slide.empty()); ++it) {
      r.sweeper->sweep();
      ++stats.iterations;
      bool stop = false;
      for (auto& s : stages) stop = s->afterSweep(r) || stop;
      const bool goOn = !cb || cb(100 * (it + 1) / r.p.iterations, ("S-ODT sweep " + std::to_string(it + 1) + "/" +
                                                                    std::to_string(r.p.iterations)).c_str());
      stats.stoppedEarly = stop;
      stats.cancelled = !stop && !goOn;
      if (stop || !goOn) break;
    }
    stats.sweepSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sweepsStart).count();
    r.sweeper->addCounts(stats);
    stats.returnedSweep = stats.iterations;
    for (auto& s : stages) s->afterSweeps(r);
    stats.maxFaceTurnDeg = largestFaceTurnDeg(r.w.faces, r.w.pos, r.faceNormal);

    r.outCls = r.cls;
    r.moved = r.active;
    for (auto& s : stages) s->finish(r);
    for (auto& s : stages) s->last(r);
    // The mesh is written only here, positions and faces together.
    std::vector<int> moving = r.moved;
    moving.insert(moving.end(), r.written.begin(), r.written.end());
    writeBack(m, r.w, moving, stats.flips > 0 || stats.unfoldFlips > 0 || stats.reorientedFaces > 0 || params.repair, r.threads);
    if (classes) *classes = inMeshOrder(r.outCls, r.w.order);
    return stats;
  }
};

}  // namespace sodt
