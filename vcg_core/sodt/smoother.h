// SPDX-License-Identifier: GPL-3.0-or-later
// Gauss-Seidel S-ODT sweeps over a vcg triangle mesh (paper Algorithms 1-3),
// with the fold / quality safeguards applied to every move before it is committed.
#pragma once

#include "classify.h"
#include "deviation.h"
#include "fitting.h"
#include "flips.h"
#include "lanes.h"
#include "normals.h"
#include "local_solve.h"
#include "odt.h"
#include "params.h"
#include "sweep_quality.h"
#include "topology.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/topology.h>
#include <vcg/complex/complex.h>
#include <wrap/callback.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sodt {

/// Smooths a vcg triangle mesh in place with S-ODT.
template <class MeshType>
struct SodtSmoother {
  using ScalarType = typename MeshType::ScalarType;
  using CoordType = typename MeshType::CoordType;

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
  /// isolated and deleted vertices never move; with p.selectedOnly only
  /// selected vertices move. Updates the bounding box, and the unit face and
  /// vertex normals when present (see writeNormals).
  ///
  /// \param m  mesh to smooth; needs per-vertex flags (deleted, selected).
  /// \param p  validated by this call.
  /// \param cb optional progress callback (0..100), called once per sweep;
  ///           returning false stops after the current sweep.
  /// \param classes when not null, receives the classification used (all
  ///        interior vertices Smooth for Basic).
  /// \throw InvalidInput for bad parameters, a non-finite coordinate or a
  ///        mesh outside the sizes of checkMeshSize(); the mesh is untouched then.
  static SodtStats Apply(MeshType& m, const SodtParams& p, vcg::CallBackPos* cb = nullptr,
                         Classification* classes = nullptr) {
    p.validate();
    SodtStats stats;
    const int nv = static_cast<int>(m.vert.size());
    int nonFinite = 0, firstNonFinite = -1;
    for (int i = 0; i < nv; ++i)
      if (!m.vert[i].IsD() && !isFinite(toVec3(m.vert[i].cP())) && nonFinite++ == 0) firstNonFinite = i;
    if (nonFinite > 0)
      throw InvalidInput(std::to_string(nonFinite) + (nonFinite > 1 ? " vertices have" : " vertex has") +
                         " a non-finite coordinate (NaN or infinite; first: vertex " +
                         std::to_string(firstNonFinite) + "); the mesh was not changed");

    // The working order of the vertices is breadth-first over the faces, so
    // that a vertex's neighbours lie near it in memory (meshes refined by
    // subdivision or merged from parts store them far apart). Everything
    // below indexes vertices in this order; the mesh is written back through
    // `order` at the end.
    FaceList faces = makeFaceList(m, p.selectedOnly);
    std::vector<char> deleted(nv, 0);
    for (int i = 0; i < nv; ++i) deleted[i] = m.vert[i].IsD();
    const std::vector<int> order = breadthFirstOrder(faces, deleted);  // working index -> index in m.vert
    std::vector<int> slot(nv);                                         // index in m.vert -> working index
    for (int i = 0; i < nv; ++i) slot[order[i]] = i;
    std::vector<Vec3> pos(nv, Vec3(0, 0, 0));
    std::vector<char> selected(nv, 0);
    for (int i = 0; i < nv; ++i) {
      const auto& v = m.vert[order[i]];
      deleted[i] = v.IsD();
      selected[i] = v.IsS();
      if (!deleted[i]) pos[i] = toVec3(v.cP());
    }
    for (std::size_t f = 0; f < faces.tri.size(); ++f)
      if (faces.live[f])
        for (int& v : faces.tri[f]) v = slot[v];
    std::vector<int>().swap(slot);
    const std::vector<int> faceOrder = sortFacesByVertex(faces, nv);  // working face -> index in m.face
    RingTopology topo = buildRingTopology(faces, deleted);  // rebuilt after edge flips
    // Inconsistent winding would leave the vertices where it changes fixed:
    // each component gets the winding of the majority of its faces first
    // (faces are written back then, and the count reported).
    if (std::find(topo.kind.begin(), topo.kind.end(), VertexKind::NonManifold) != topo.kind.end()) {
      stats.reorientedFaces = orientCoherently(faces, nv);
      if (stats.reorientedFaces > 0) topo = buildRingTopology(faces, deleted);
    }
    checkMeshSize(surfaceDiagonal(pos, topo));
    // The length scale of classification, crease moves and denoising steps;
    // Algorithm 1 and the references do not use it.
    const bool usesMeanEdge = p.algorithm == Algorithm::Feature || p.algorithm == Algorithm::Denoise;
    const double meanEdge = usesMeanEdge ? meanEdgeLength(m) : 0.0;

    const int threads = resolveThreads(p.threads);
    stats.threads = threads;
    Classification cls;
    // Denoise: the input projected once on its fitted planes, which both the
    // classification and the first of the fits' projection passes use.
    std::vector<Vec3> projected;
    if (p.algorithm == Algorithm::Basic || p.algorithm == Algorithm::Odt || p.algorithm == Algorithm::Laplacian) {
      cls.cls.assign(nv, VertexClass::Fixed);  // no crease directions: there are no creases
      for (int i = 0; i < nv; ++i) {
        if (topo.kind[i] == VertexKind::Deleted) continue;
        cls.cls[i] = topo.kind[i] == VertexKind::Interior ? VertexClass::Smooth : VertexClass::Fixed;
        ++cls.count[static_cast<int>(cls.cls[i])];
      }
    } else if (p.algorithm == Algorithm::Feature) {
      cls = classifyRings(topo, pos, meanEdge, p.epsilon, p.eta, threads);
    } else {
      // Noise turns single spikes into false corners and creases: classify the
      // input after projecting every vertex on its fitted plane (a vertex on a
      // true crease or corner has too few agreeing neighbours to fit and stays).
      projected = projectOnFittedPlanes(topo, pos, threads);
      cls = classifyRings(topo, projected, meanEdge, p.epsilon, p.eta, threads);
    }
    stats.smoothVertices = cls.smooth();
    stats.creaseVertices = cls.crease();
    stats.cornerVertices = cls.corner();

    std::vector<int> active;
    for (int i = 0; i < nv; ++i) {
      switch (topo.kind[i]) {
        case VertexKind::Interior:
          if (cls.cls[i] != VertexClass::Corner && (!p.selectedOnly || selected[i])) active.push_back(i);
          break;
        case VertexKind::Boundary: ++stats.fixedBoundary; break;
        case VertexKind::NonManifold: ++stats.fixedNonManifold; break;
        default: break;
      }
    }
    stats.activeVertices = static_cast<int>(active.size());

    // Input orientation of every face: guarded moves keep each face within
    // 90 degrees of it, so no face ends up inverted however far it drifts.
    std::vector<Vec3> faceNormal;
    if (p.guard != Guard::None || p.keepBest) {
      faceNormal.assign(faces.tri.size(), Vec3(0, 0, 0));
      for (std::size_t f = 0; f < faces.tri.size(); ++f) {
        if (!faces.live[f]) continue;
        const std::array<int, 3>& t = faces.tri[f];
        const Vec3 a = doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]);
        const double len = a.Norm();
        if (len > 0 && std::isfinite(len)) faceNormal[f] = a / len;
      }
    }

    // Denoise: the fitted plane or crease line of every moving vertex, from the input.
    std::vector<FittedFrame> fit;
    if (p.algorithm == Algorithm::Denoise) {
      fit.resize(nv);
      // Planes are fitted to the input after two projection passes: a plane
      // fitted to raw noisy neighbours keeps about half the noise, one fitted
      // to pre-smoothed neighbours much less. Crease lines use the input, whose
      // crease vertices the projections leave (nearly) in place anyway.
      static_assert(kDenoisePrePasses >= 1, "the first pass is the classification's");
      std::vector<Vec3> src = std::move(projected);
      for (int k = 1; k < kDenoisePrePasses; ++k) src = projectOnFittedPlanes(topo, src, threads);
      const std::vector<Vec3> nrm = vertexNormals(topo, src, threads);
      const long na = static_cast<long>(active.size());
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
#endif
      for (long a = 0; a < na; ++a) {
        const int i = active[a];
        if (cls.cls[i] == VertexClass::Smooth)
          fit[i] = fitPlane(i, topo, src, nrm);
        else if (cls.cls[i] == VertexClass::Crease)
          fit[i] = fitCreaseLine(i, cls.creaseDir[i], topo, pos, cls.cls);
      }
    }

    // The deviation guard reads the input mesh. Flips change the working
    // connectivity, so only then does the input need copies of its own.
    const bool deviationGuard =
        p.guard != Guard::None && p.algorithm != Algorithm::Denoise && p.maxDeviationRel > 0;
    std::vector<Vec3> pos0;
    RingTopology topo0;
    FaceList faces0;
    InputSurface input;
    if (deviationGuard) {
      pos0 = pos;
      if (p.flips) {
        topo0 = topo;
        faces0 = faces;
      }
      input.faces = p.flips ? &faces0 : &faces;
      input.topo = p.flips ? &topo0 : &topo;
      input.pos = &pos0;
      input.prepare(p.maxDeviationRel * surfaceDiagonal(pos, topo));
    }
    Context ctx{p, cls, fit, meanEdge, deviationGuard ? &input : nullptr, p.simd && lanes::available(),
                Vec3(0, 0, 0), Vec3(0, 0, 0)};
    reachBox(p, pos, topo, meanEdge, ctx.boxLo, ctx.boxHi);
    FlipRules flipRules;
    flipRules.maxDihedralRad = p.flipMaxDihedralDeg * kPi / 180.0;
    if (p.algorithm != Algorithm::Basic) flipRules.cls = &cls.cls;
    if (deviationGuard) flipRules.input = &input;  // flips must keep the bound too

    // Best state seen, for keepBest (the input is state 0), and the last
    // quality, for toleranceDeg.
    const bool measuring = p.keepBest || p.toleranceDeg > 0;
    SweepQualityMeter meter;
    Quality last = measuring ? meter(faces, pos, faceNormal, threads, p.simd) : Quality{};
    Quality best = last;
    std::vector<Vec3> bestPos = p.keepBest ? pos : std::vector<Vec3>();
    FaceList bestFaces = p.keepBest && p.flips ? faces : FaceList();
    int bestSweep = 0;

    // Gauss-Seidel by colours: no two neighbours share a colour, so the
    // vertices of one colour read only positions that stay fixed while that
    // colour is swept, and can move in any order or in parallel with the same
    // result. Guarded sweeps take the colours tile by tile (see kTileVertices). A visit is a function of the positions of the vertex's star
    // (and of data fixed for the run), so a visit that moved nothing need not
    // be repeated until something in its star moves: it is answered from the
    // previous outcome. Both keep the result independent of the thread count.
    const int tile = p.guard != Guard::None ? kTileVertices : 0;
    SweepPlan plan = colourVertices(topo, active, tile);
    std::vector<int> lastVisit(nv, -1), movedAt(nv, -1);
    std::vector<Outcome> lastOutcome(nv, Outcome::Moved);
    // Per vertex, the input face its position was last found near (a hint
    // for the deviation guard; every vertex writes only its own).
    std::vector<int> pointHint(nv, -1);
    // What the deviation guard remembers between visits (see
    // InputSurface::keeps): per vertex the length of the path it has moved
    // so far and the margin of its position; per ring slot the margin of
    // that star triangle and the ring vertex's path length at the time
    // (rounded down).
    const std::size_t ringSlots = deviationGuard ? topo.ringIdx.size() : 0;
    std::vector<double> odo(deviationGuard ? nv : 0, 0.0);
    // The input's points are on the input: the first visits start from
    // their margin, no query needed.
    const float startMargin = deviationGuard && p.reuseDeviationMargins ? input.inputMargin : -1.f;
    std::vector<float> pointMargin(deviationGuard ? nv : 0, startMargin);
    std::vector<float> slotMargin(ringSlots, startMargin), slotOdo(ringSlots, 0.f);
    // Per ring slot, the input face the centroid of that star triangle was
    // last found near; at first, the face the triangle is in the input.
    std::vector<int> slotHint = deviationGuard ? topo.ringFace : std::vector<int>();
    std::vector<Scratch> scratch(threads);
    std::vector<int> flippedVertices;  // a, b, c, d of each flip after a sweep
    int maxValence = 0;
    for (int i : active) maxValence = std::max(maxValence, topo.ringSize(i));
    for (Scratch& s : scratch) s.reserve(maxValence);
    // Algorithm 1, the smooth vertices of Algorithm 2 (whose update is
    // Algorithm 1's) and those of Algorithm 3 with a fitted plane: the 4-lane
    // kernel when the processor has it.
    const bool denoiseLanes = p.algorithm == Algorithm::Denoise;
    const bool useLanes = p.simd &&
                          (p.algorithm == Algorithm::Basic || p.algorithm == Algorithm::Feature || denoiseLanes) &&
                          lanes::available() && nv < std::numeric_limits<int>::max() / 3;
    std::vector<char> laneable;
    lanes::DenoiseInput laneDenoise;
    if (useLanes) {
      laneable.assign(nv, 0);
      for (int i : active)
        laneable[i] = cls.cls[i] == VertexClass::Smooth && (!denoiseLanes || fit[i].ok);
      if (denoiseLanes && !fit.empty()) {
        static_assert(sizeof(FittedFrame) % sizeof(double) == 0, "frames must be read as doubles");
        laneDenoise.point = &fit[0].point[0];
        laneDenoise.dir = &fit[0].dir[0];
        laneDenoise.stride = static_cast<int>(sizeof(FittedFrame) / sizeof(double));
        laneDenoise.lim = p.maxNormalStepRel * meanEdge;
      }
    }
    // The kernel also tests the full step under the fold and angle guard
    // (when the mesh stores float or double coordinates, what
    // representable() rounds to), and an accepted step is committed with no
    // scalar work: without the deviation bound always, with it when the
    // margins of the vertex's last move cover every checked point (see
    // laneKeeps), as they do for most full steps.
    const bool laneGuard = useLanes && p.guard != Guard::None && (!deviationGuard || p.reuseDeviationMargins) &&
                           (std::is_same<ScalarType, float>::value || std::is_same<ScalarType, double>::value);
    // Guarded visits of the kernel's vertices take what prepareGuard
    // computes from the kernel too, which has the star in its lanes already.
    const bool lanePrepare = useLanes && p.guard != Guard::None;
    lanes::GuardInput laneGuardInput;
    if (lanePrepare) {
      laneGuardInput.faceNormal = faceNormal.empty() ? nullptr : &faceNormal[0][0];
      laneGuardInput.quality = p.guard == Guard::Quality;
      laneGuardInput.roundToFloat = std::is_same<ScalarType, float>::value;
    }
    LanePlan lanePlan = useLanes ? planLanes(plan, topo, laneable, laneGuard) : LanePlan();
    const bool prefetchFaces = p.guard != Guard::None && !faceNormal.empty();
    const bool laneMargins = laneGuard && deviationGuard;
    // Without the deviation bound the kernel's full-step test pays only when
    // most lanes pass it (see kLikelyLanes); with it, a lane that passes
    // usually saves a whole scalar visit, so every group is tested.
    const int likelyNeeded = laneMargins ? 0 : kLikelyLanes;
    int phase = 0;  // phases swept so far, over all sweeps
    // A guarded visit costs from one test to a dozen (a rejected one tries
    // every step length twice), and a thread can be held up: the threads
    // take guarded work in small chunks as they get to it. Unguarded visits
    // cost about the same and little, so they are split in equal halves.
    const bool dynamicSchedule = p.guard != Guard::None || p.algorithm == Algorithm::Odt;
    const int minParallel = dynamicSchedule ? kMinParallelGuardedPhase : kMinParallelPhase;

    const auto sweepsStart = std::chrono::steady_clock::now();
    for (int it = 0; it < p.iterations && !active.empty(); ++it) {
      const int sweepBase = phase;
      // Sweeps phase c, numbered phaseNo among all phases of the run, on the
      // calling thread with scratch sc0, or split between the threads when
      // parallel.
      const auto runPhase = [&](std::size_t c, int phaseNo, Scratch& sc0, bool parallel) {
        (void)parallel;
          // A visit whose outcome did not move the vertex need not be repeated
          // while nothing in its star has moved since.
          const auto still = [&](int i) {
            if (lastVisit[i] < 0 || moves(lastOutcome[i])) return false;
            for (int k = topo.ringBegin[i]; k < topo.ringBegin[i + 1]; ++k)
              if (movedAt[topo.ringIdx[k]] >= lastVisit[i]) return false;
            return true;
          };
          const auto skip = [&](int i, Scratch& sc) {
            ++sc.count[static_cast<int>(lastOutcome[i])];
            ++sc.skipped;
          };
          const auto record = [&](int i, Outcome o, Scratch& sc) {
            ++sc.count[static_cast<int>(o)];
            lastVisit[i] = phaseNo;
            lastOutcome[i] = o;
            if (moves(o)) movedAt[i] = phaseNo;
          };
          // The deviation guard's view of vertex i's margins (see Budget).
          const auto prepareBudget = [&](int i, Scratch& sc, Budget& budget) {
            const int b = topo.ringBegin[i], e = topo.ringBegin[i + 1];
            // Path lengths grow by rounding too: a margin of 1e-12 of them.
            const double eps = 1e-12 * (odo[i] + input.limit);
            sc.drift.resize(e - b);  // within the reserved size
            for (int k = b; k < e; ++k) {
              const double o = odo[topo.ringIdx[k]];
              sc.drift[k - b] = o - slotOdo[k] + 1e-12 * o + eps;
            }
            sc.nextSlot.resize(e - b);
            budget.drift = sc.drift.data();
            budget.eps = eps;
            budget.last.point = pointMargin[i];
            budget.last.slot = slotMargin.data() + b;
            budget.next.slot = sc.nextSlot.data();
          };
          // Keeps the margins of vertex i's accepted move from `from`.
          const auto commitMargins = [&](int i, const Vec3& from, const Budget& budget) {
            odo[i] += (pos[i] - from).Norm();
            pointMargin[i] = budget.next.point;
            for (int k = topo.ringBegin[i]; k < topo.ringBegin[i + 1]; ++k) {
              slotMargin[k] = budget.next.slot[k - topo.ringBegin[i]];
              slotOdo[k] = InputSurface::floatBelow(odo[topo.ringIdx[k]]);
            }
          };
          // Visits vertex i, with its proposal when one was computed already;
          // false when the visit was answered from the previous one.
          const auto visitOne = [&](int i, Scratch& sc, const Proposal* given, FullStep full) {
            if (still(i)) {
              skip(i, sc);
              return false;
            }
            Star& star = sc.star;
            const int b = topo.ringBegin[i], e = topo.ringBegin[i + 1];
            star.center = pos[i];
            star.ring.resize(e - b);
            for (int k = b; k < e; ++k) star.ring[k - b] = pos[topo.ringIdx[k]];
            if (!faceNormal.empty()) {
              star.refNormal.resize(e - b);
              for (int k = b; k < e; ++k) star.refNormal[k - b] = faceNormal[topo.ringFace[k]];
            }
            int* hints = deviationGuard ? slotHint.data() + b : nullptr;
            Budget budget;
            if (deviationGuard) prepareBudget(i, sc, budget);
            const Vec3 from = pos[i];
            const Outcome o = visitVertex(ctx, i, star, hints, pointHint[i], sc, budget, pos[i], given, full);
            sc.queried += budget.queried;
            sc.reused += budget.reused;
            record(i, o, sc);
            if (moves(o) && deviationGuard && p.reuseDeviationMargins) commitMargins(i, from, budget);
            return true;
          };
          // withinReach for a vertex the kernel moved, from its ring in pos.
          const auto laneWithinReach = [&](int i, const Vec3& y) {
            for (int k = 0; k < 3; ++k)
              if (!(y[k] >= ctx.boxLo[k] && y[k] <= ctx.boxHi[k])) return false;
            const double s2 = (y - pos[i]).SquaredNorm();
            for (int k = topo.ringBegin[i]; k < topo.ringBegin[i + 1]; ++k)
              if (s2 <= (pos[topo.ringIdx[k]] - pos[i]).SquaredNorm()) return true;
            return false;
          };
          // When the margins of vertex i's last move answer the deviation test
          // of its move to y with no distance query, commits the move as the
          // visit would (InputSurface::keepsByMargins); false, with nothing
          // changed, otherwise: the visit then runs in full.
          const auto laneKeeps = [&](int i, const Vec3& y, Scratch& sc) {
            Budget budget;
            prepareBudget(i, sc, budget);
            const double step = (y - pos[i]).Norm() + budget.eps;
            if (!input.keepsByMargins(i, sc.drift.size(), step, budget.drift, budget.last, budget.next, sc.reused))
              return false;
            const Vec3 from = pos[i];
            pos[i] = y;
            record(i, Outcome::Moved, sc);
            commitMargins(i, from, budget);
            return true;
          };
          if (useLanes) {
            // Four vertices of equal valence per kernel call, then the rest
            // one by one: all of one colour, so the order does not matter.
            const int g0 = lanePlan.groupBegin[c], ng = lanePlan.groupBegin[c + 1] - g0;
            const int* rest = lanePlan.rest.data() + lanePlan.restBegin[c];
            const int nr = lanePlan.restBegin[c + 1] - lanePlan.restBegin[c];
            const auto visitGroup = [&](int g, Scratch& sc) {
#if defined(__GNUC__) || defined(__clang__)
              // (Here, not in a function of its own: GCC takes a function that
              // only prefetches for one without effects and drops its calls.)
              if (g + kPrefetchGroups < g0 + ng) {
                const int ahead = g + kPrefetchGroups;
                const int* table = lanePlan.table.data() + lanePlan.tableBegin[ahead];
                const int entries = lanes::kWidth * (lanePlan.valence[ahead] + 1);
                for (int e = 0; e < entries; ++e) __builtin_prefetch(&pos[0][0] + table[e]);
                // The deviation guard's margins and path lengths.
                if (laneMargins) {
                  for (int e = 0; e < entries; ++e) __builtin_prefetch(&odo[table[e] / 3]);
                  const int* va = lanePlan.vertex.data() + lanes::kWidth * ahead;
                  for (int l = 0; l < lanes::kWidth; ++l) {
                    __builtin_prefetch(&slotMargin[topo.ringBegin[va[l]]]);
                    __builtin_prefetch(&slotOdo[topo.ringBegin[va[l]]]);
                  }
                }
                // The guard reads the input normals of the ring's faces.
                if (prefetchFaces) {
                  const int* va = lanePlan.vertex.data() + lanes::kWidth * ahead;
                  for (int l = 0; l < lanes::kWidth; ++l)
                    for (int k = topo.ringBegin[va[l]]; k < topo.ringBegin[va[l] + 1]; ++k)
                      __builtin_prefetch(&faceNormal[topo.ringFace[k]]);
                }
              }
#endif
              const int* vs = lanePlan.vertex.data() + lanes::kWidth * g;
              lanes::Targets t;
              // The full-step test (see likelyNeeded).
              int likely = 0;
              if (laneGuard)
                for (int l = 0; l < lanes::kWidth; ++l) likely += lastOutcome[vs[l]] == Outcome::Moved;
              lanes::StepVerdict v;
              lanes::targets4(&pos[0][0], lanePlan.table.data() + lanePlan.tableBegin[g], lanePlan.valence[g], t,
                              lanePrepare ? &laneGuardInput : nullptr, likely >= likelyNeeded ? &v : nullptr,
                              lanePrepare ? &sc.prepared : nullptr, denoiseLanes ? &laneDenoise : nullptr);
              if (likely < likelyNeeded) v.allowed = v.refused = 0;
              for (int l = 0; l < lanes::kWidth; ++l) {
                const int i = vs[l];
                const bool ok = (t.ok >> l & 1) != 0;
                if (p.guard != Guard::None) {
                  if ((v.allowed >> l & 1) && laneWithinReach(i, Vec3(v.x[l], v.y[l], v.z[l]))) {
                    // The visit moves the vertex by the full step when nothing
                    // else is to be tested: no deviation bound, or margins that
                    // answer it. It cannot be one still() would answer: that
                    // visit, on the same star with the same margins, did not
                    // move the vertex.
                    const Vec3 y(v.x[l], v.y[l], v.z[l]);
                    if (!deviationGuard) {
                      pos[i] = y;
                      record(i, Outcome::Moved, sc);
                      ++sc.laneVisits;
                      continue;
                    }
                    if (laneKeeps(i, y, sc)) {
                      ++sc.laneVisits;
                      continue;
                    }
                  }
                  FullStep full;
                  full.prepared = &sc.prepared;
                  full.lane = l;
                  full.allowed = (v.allowed >> l & 1) != 0;
                  if (v.refused >> l & 1) {
                    full.refused = true;
                    full.first = v.first[l];
                  }
                  // The guarded visit, with propose()'s result from the kernel.
                  Proposal pr;
                  if (ok) {
                    pr.ok = true;
                    pr.target = Vec3(t.x[l], t.y[l], t.z[l]);
                    pr.normal = Vec3(t.nx[l], t.ny[l], t.nz[l]);
                    if (denoiseLanes)
                      pr.fallback = Vec3(t.fx[l], t.fy[l], t.fz[l]);
                    else
                      pr.tangentialFallback = true;
                  }
                  sc.laneVisits += visitOne(i, sc, &pr, full);
                  continue;
                }
                if (still(i)) {
                  skip(i, sc);  // the kernel's answer is the one recorded last time
                  continue;
                }
                const Outcome o = ok ? commitUnguarded(Vec3(t.x[l], t.y[l], t.z[l]), pos[i]) : Outcome::Failed;
                record(i, o, sc);
                ++sc.laneVisits;
              }
            };
#ifdef _OPENMP
            if (parallel && lanes::kWidth * ng + nr >= minParallel) {
#pragma omp parallel num_threads(threads)
              {
                Scratch& sc = scratch[omp_get_thread_num()];
                if (dynamicSchedule) {
#pragma omp for schedule(dynamic, 16) nowait
                  for (int g = 0; g < ng; ++g) visitGroup(g0 + g, sc);
#pragma omp for schedule(dynamic, 32)
                  for (int j = 0; j < nr; ++j) visitOne(rest[j], sc, nullptr, FullStep());
                } else {
#pragma omp for schedule(static) nowait
                  for (int g = 0; g < ng; ++g) visitGroup(g0 + g, sc);
#pragma omp for schedule(static)
                  for (int j = 0; j < nr; ++j) visitOne(rest[j], sc, nullptr, FullStep());
                }
              }
              return;
            }
#endif
            for (int g = 0; g < ng; ++g) visitGroup(g0 + g, sc0);
            for (int j = 0; j < nr; ++j) visitOne(rest[j], sc0, nullptr, FullStep());
            return;
          }
          const int* vs = plan.order.data() + plan.phaseBegin[c];
          const int n = plan.phaseBegin[c + 1] - plan.phaseBegin[c];
#ifdef _OPENMP
          if (parallel && n >= minParallel) {
            if (dynamicSchedule) {
#pragma omp parallel for num_threads(threads) schedule(dynamic, 32)
              for (int j = 0; j < n; ++j) visitOne(vs[j], scratch[omp_get_thread_num()], nullptr, FullStep());
            } else {
#pragma omp parallel for num_threads(threads) schedule(static)
              for (int j = 0; j < n; ++j) visitOne(vs[j], scratch[omp_get_thread_num()], nullptr, FullStep());
            }
            return;
          }
#endif
          for (int j = 0; j < n; ++j) visitOne(vs[j], sc0, nullptr, FullStep());
      };
      const std::size_t phases = plan.phaseBegin.size() - 1;
#ifdef _OPENMP
      const std::size_t planTiles = plan.tileBegin.empty() ? 0 : plan.tileBegin.size() - 1;
      if (threads > 1 && planTiles >= static_cast<std::size_t>(kMinParallelTiles) * threads) {
        // Tile by tile on each thread, the tiles of a group at once (see
        // SweepPlan): a wait per group, not per phase.
        for (std::size_t g = 0; g + 1 < plan.groupBegin.size(); ++g) {
          const int t0 = plan.groupBegin[g], nt = plan.groupBegin[g + 1] - t0;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
          for (int t = 0; t < nt; ++t) {
            Scratch& sc = scratch[omp_get_thread_num()];
            for (int c = plan.tileBegin[t0 + t]; c < plan.tileBegin[t0 + t + 1]; ++c)
              runPhase(static_cast<std::size_t>(c), sweepBase + c, sc, false);
          }
        }
      } else
#endif
      {
        for (std::size_t c = 0; c < phases; ++c) runPhase(c, sweepBase + static_cast<int>(c), scratch[0], threads > 1);
      }
      phase = sweepBase + static_cast<int>(phases);
      ++stats.iterations;
      if (p.flips) {
        int flipped = 0;
        flippedVertices.clear();
        // After the first pass, only edges around the flips of the pass
        // before can flip (see flipPass): the others are passed over.
        std::vector<char> seed;
        for (int pass = 0; pass < kMaxFlipPasses; ++pass) {
          const std::size_t from = flippedVertices.size();
          const int n = flipPass(faces, pos, flipRules, &faceNormal, &flippedVertices, pass > 0 ? &seed : nullptr);
          flipped += n;
          if (n == 0) break;
          seed.assign(nv, 0);
          for (std::size_t k = from; k < flippedVertices.size(); ++k) seed[flippedVertices[k]] = 1;
        }
        if (flipped > 0) {
          stats.flips += flipped;
          RingTopology before = std::move(topo);
          topo = buildRingTopology(faces, deleted);
          plan = colourVertices(topo, active, tile);
          if (useLanes) lanePlan = planLanes(plan, topo, laneable, laneGuard);
          for (int i : active) maxValence = std::max(maxValence, topo.ringSize(i));
          for (Scratch& s : scratch) s.reserve(maxValence);
          // Only the four vertices of a flip have a new star; every other
          // star has the same faces, and its ring starts at its smallest
          // neighbour as before, so what was remembered of it still holds.
          // (Compared anyway: a star that differs is treated as new.)
          std::vector<char> sameStar(nv, 1);
          for (int v : flippedVertices) sameStar[v] = 0;
          for (int v = 0; v < nv; ++v) {
            const int n = topo.ringSize(v);
            if (sameStar[v] && n == before.ringSize(v) && topo.kind[v] == before.kind[v]) {
              const int from = before.ringBegin[v], to = topo.ringBegin[v];
              sameStar[v] = std::equal(topo.ringIdx.begin() + to, topo.ringIdx.begin() + to + n,
                                       before.ringIdx.begin() + from) &&
                            std::equal(topo.ringFace.begin() + to, topo.ringFace.begin() + to + n,
                                       before.ringFace.begin() + from);
            } else {
              sameStar[v] = 0;
            }
            if (!sameStar[v]) lastVisit[v] = -1;  // visit new stars again
          }
          if (deviationGuard) {
            // The vertex margins depend on the vertex and its input patch
            // alone; the star triangles' margins move to their new slots,
            // and new stars are checked in full.
            std::vector<float> margin(topo.ringIdx.size(), -1.f), slotOdoNew(topo.ringIdx.size(), 0.f);
            std::vector<int> hint(topo.ringIdx.size(), -1);
            for (int v = 0; v < nv; ++v) {
              if (!sameStar[v]) continue;
              const int n = topo.ringSize(v), from = before.ringBegin[v], to = topo.ringBegin[v];
              std::copy(slotMargin.begin() + from, slotMargin.begin() + from + n, margin.begin() + to);
              std::copy(slotOdo.begin() + from, slotOdo.begin() + from + n, slotOdoNew.begin() + to);
              std::copy(slotHint.begin() + from, slotHint.begin() + from + n, hint.begin() + to);
            }
            slotMargin.swap(margin);
            slotOdo.swap(slotOdoNew);
            slotHint.swap(hint);
          }
        }
      }
      bool stop = false;
      if (measuring) {
        const Quality q = meter(faces, pos, faceNormal, threads, p.simd);
        if (p.keepBest && q.better(best)) {
          best = q;
          bestSweep = it + 1;
          bestPos = pos;
          if (p.flips) bestFaces = faces;
        }
        stop = p.toleranceDeg > 0 && q.minDeg - last.minDeg <= p.toleranceDeg &&
               q.p1Deg - last.p1Deg <= p.toleranceDeg;
        last = q;
      }
      const bool goOn = !cb || cb(100 * (it + 1) / p.iterations,
                                  ("S-ODT sweep " + std::to_string(it + 1) + "/" +
                                   std::to_string(p.iterations)).c_str());
      if (stop) {
        stats.stoppedEarly = true;
        break;
      }
      if (!goOn) {
        stats.cancelled = true;
        break;
      }
    }
    stats.sweepSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sweepsStart).count();
    for (const Scratch& sc : scratch) {
      for (int o = 0; o < kOutcomes; ++o) count(stats, static_cast<Outcome>(o), sc.count[o]);
      stats.skipped += sc.skipped;
      stats.deviationQueries += sc.queried;
      stats.deviationReused += sc.reused;
      stats.laneVisits += sc.laneVisits;
    }
    stats.returnedSweep = stats.iterations;
    if (p.keepBest && bestSweep != stats.iterations) {
      pos = bestPos;
      if (p.flips) {
        faces = bestFaces;
        topo = buildRingTopology(faces, deleted);  // for the normals
      }
      stats.returnedSweep = bestSweep;
    }
    // The mesh is written only here, positions and faces together.
    const bool facesChanged = stats.flips > 0 || stats.reorientedFaces > 0;
    if (facesChanged) writeFaces(m, faces, order, faceOrder);
    if (facesChanged) {
      // Flips and reorientation invalidate any adjacency the caller had computed.
      if (vcg::tri::HasFFAdjacency(m)) vcg::tri::UpdateTopology<MeshType>::FaceFace(m);
      if (vcg::tri::HasVFAdjacency(m)) vcg::tri::UpdateTopology<MeshType>::VertexFace(m);
    }

    for (int i : active)
      m.vert[order[i]].P() = CoordType(ScalarType(pos[i][0]), ScalarType(pos[i][1]), ScalarType(pos[i][2]));
    vcg::tri::UpdateBounding<MeshType>::Box(m);
    writeNormals(m, faces, topo, pos, order, faceOrder, threads);
    if (classes) {
      // Back to the mesh's vertex order.
      *classes = cls;
      for (int i = 0; i < nv; ++i) classes->cls[order[i]] = cls.cls[i];
      if (!cls.creaseDir.empty())
        for (int i = 0; i < nv; ++i) classes->creaseDir[order[i]] = cls.creaseDir[i];
      else
        classes->creaseDir.assign(nv, Vec3(0, 0, 0));
    }
    return stats;
  }

 private:
  /// Projection passes that pre-smooth the input before the denoising planes are fitted.
  static constexpr int kDenoisePrePasses = 2;

  /// Every interior vertex projected on its weighted least-squares plane
  /// (Eq. 12-13) computed from the given positions; others unchanged.
  static std::vector<Vec3> projectOnFittedPlanes(const RingTopology& topo, const std::vector<Vec3>& pos,
                                                 int threads) {
    const std::vector<Vec3> nrm = vertexNormals(topo, pos, threads);
    std::vector<Vec3> out = pos;
    const long nv = static_cast<long>(pos.size());
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
#endif
    for (long i = 0; i < nv; ++i) {
      if (topo.kind[i] != VertexKind::Interior) continue;
      const FittedFrame f = fitPlane(static_cast<int>(i), topo, pos, nrm);
      if (f.ok) out[i] = pos[i] - f.dir * ((pos[i] - f.point) * f.dir);
    }
    return out;
  }

  /// Flip passes after a sweep, at most (each pass flips an edge only when
  /// the pair's smaller angle grows, so passes end anyway).
  static constexpr int kMaxFlipPasses = 10;

  using Quality = SweepQuality;

  /// Writes the vertex references of the face list (working indices, working
  /// face f is m.face[faceOrder[f]]) back into m.
  static void writeFaces(MeshType& m, const FaceList& fl, const std::vector<int>& order,
                         const std::vector<int>& faceOrder) {
    for (std::size_t f = 0; f < fl.tri.size(); ++f)
      if (fl.live[f])
        for (int j = 0; j < 3; ++j) m.face[faceOrder[f]].V(j) = &m.vert[order[fl.tri[f][j]]];
  }

  static Vec3 toVec3(const CoordType& c) { return Vec3(c[0], c[1], c[2]); }

  /// Read-only state shared by all visits of a run.
  struct Context {
    const SodtParams& p;
    const Classification& cls;
    const std::vector<FittedFrame>& fit;  ///< Denoise only
    double meanEdge;
    const InputSurface* input;  ///< deviation guard, or null
    /// tryStep tests step lengths four at once (lanes::allowedAt).
    bool lengthLanes;
    /// The box no guarded move may leave (see reachBox).
    Vec3 boxLo, boxHi;
  };

  /// The box a guarded move must stay in: the input surface's bounding box
  /// grown by the deviation bound (by a mean edge length for Denoise, which
  /// has none), plus 1e-9 of its diagonal for rounding. With the fold test
  /// alone a star whose ring does not surround its centre in the tangent
  /// plane (needles around a high-valence vertex) lets a move fly off
  /// without folding anything; this and the star's reach (withinReach) stop
  /// it, whatever the other options.
  static void reachBox(const SodtParams& p, const std::vector<Vec3>& pos, const RingTopology& topo, double meanEdge,
                       Vec3& lo, Vec3& hi) {
    bool any = false;
    for (std::size_t i = 0; i < pos.size(); ++i) {
      if (topo.kind[i] == VertexKind::Deleted || topo.kind[i] == VertexKind::Isolated) continue;
      for (int k = 0; k < 3; ++k) {
        lo[k] = any ? std::min(lo[k], pos[i][k]) : pos[i][k];
        hi[k] = any ? std::max(hi[k], pos[i][k]) : pos[i][k];
      }
      any = true;
    }
    const double diag = any ? (hi - lo).Norm() : 0.0;
    double grow = p.algorithm == Algorithm::Denoise ? meanEdge : p.maxDeviationRel * diag;
    grow += 1e-9 * diag;
    for (int k = 0; k < 3; ++k) {
      lo[k] -= grow;
      hi[k] += grow;
    }
  }

  /// A guarded move to y stays in the reach box and no farther from the
  /// centre than the centre's farthest ring vertex (a healthy star's
  /// S-ODT, Laplacian and crease targets all lie well inside that).
  static bool withinReach(const Context& c, const Vec3& centre, const Vec3& y, const Vec3* ring, std::size_t n) {
    for (int k = 0; k < 3; ++k)
      if (!(y[k] >= c.boxLo[k] && y[k] <= c.boxHi[k])) return false;
    const double s2 = (y - centre).SquaredNorm();
    for (std::size_t k = 0; k < n; ++k)
      if (s2 <= (ring[k] - centre).SquaredNorm()) return true;
    return false;
  }

  /// How one vertex visit ended.
  enum class Outcome : unsigned char { Moved, Backtracked, Fallback, Rejected, Unchanged, Failed };

  static constexpr int kOutcomes = 6;

  /// True for the outcomes that changed the vertex's position.
  static bool moves(Outcome o) { return o == Outcome::Moved || o == Outcome::Backtracked || o == Outcome::Fallback; }

  static void count(SodtStats& s, Outcome o, long long n) {
    switch (o) {
      case Outcome::Moved: s.moved += n; break;
      case Outcome::Backtracked: s.backtracked += n; break;
      case Outcome::Fallback: s.fallbackMoves += n; break;
      case Outcome::Rejected: s.rejected += n; break;
      case Outcome::Unchanged: s.unchanged += n; break;
      case Outcome::Failed: s.failedSolves += n; break;
    }
  }

  /// Per-thread working memory of the sweeps and its share of the counters.
  /// The threads' Scratch lie side by side in one array, and both ends are
  /// written on every visit (the star's centre and size, the lane kernel's
  /// results): the padding keeps those of neighbouring threads off a shared
  /// cache line, which cost a tenth of a guarded sweep on two threads.
  struct Scratch {
    char padFront[64];
    Star star;
    std::vector<Vec3> foldRef;  ///< see foldReferences
    std::vector<double> ringEdge2;  ///< see ringEdgeLengths2
    std::array<long long, kOutcomes> count{};
    long long skipped = 0;
    long long queried = 0, reused = 0;  ///< deviation-guard points, see SodtStats
    long long laneVisits = 0;
    std::vector<double> drift;  ///< see Budget
    std::vector<float> nextSlot;
    lanes::Prepared prepared;  ///< of the lane group being visited
    char padBack[64];
    /// Sized up front so that no visit allocates (allocation inside a
    /// parallel region could not report failure).
    void reserve(int valence) {
      star.ring.reserve(valence);
      star.refNormal.reserve(valence);
      foldRef.reserve(valence);
      ringEdge2.reserve(valence);
      drift.reserve(valence);
      nextSlot.reserve(valence);
    }
  };

  /// Without the deviation bound, the kernel tests the full steps of a group
  /// of lanes when at least this many of them moved by their full step at
  /// their last visit.
  static constexpr int kLikelyLanes = 3;

  /// Phases with fewer vertices than this are swept by one thread: starting
  /// the others would cost more than it saves. Guarded visits cost ten times
  /// as much as unguarded ones, so their phases are split from fewer.
  static constexpr int kMinParallelPhase = 512;
  static constexpr int kMinParallelGuardedPhase = 128;
  /// Tiled sweeps go tile by tile on each thread, the tiles of a group at
  /// once, when there are this many tiles per thread; fewer tiles are swept
  /// one after the other, each phase split between the threads.
  static constexpr int kMinParallelTiles = 4;

  /// Guarded sweeps go through the mesh in tiles of this many consecutive
  /// working indices (breadth-first order), colour by colour within each
  /// tile (colourVertices). A guarded visit reads some 300 bytes besides the
  /// positions (margins, path lengths, hints, input normals and faces), so a
  /// tile's data stays in a core's cache while its colours are swept, where
  /// colour by colour over the whole mesh fetched it from memory once per
  /// colour. Fixed, not taken from the processor: the order of the visits,
  /// and so the result, must not depend on the machine.
  static constexpr int kTileVertices = 2048;

  /// The thread count a run uses: p.threads, or all hardware threads for 0;
  /// 1 when the build has no OpenMP.
  static int resolveThreads(int requested) {
#ifdef _OPENMP
    if (requested > 0) return requested;
    return std::max(1u, std::thread::hardware_concurrency());
#else
    (void)requested;
    return 1;
#endif
  }

  /// Rounds a double position to what the mesh can store.
  static Vec3 representable(const Vec3& x) {
    return roundedTo<ScalarType>(x);
  }

  /// One visit's view of the deviation guard's margins (see
  /// InputSurface::keeps).
  struct Budget {
    InputSurface::Margins last;  ///< of the vertex's last accepted move
    const double* drift = nullptr;  ///< per ring vertex: path length since then (upper bound)
    InputSurface::Margins next;  ///< of the accepted move
    double eps = 0;  ///< added to the vertex's step for the rounding of path lengths
    long long queried = 0, reused = 0;  ///< points checked each way
  };

  /// What the lane kernel found of a visit (lanes::StepVerdict,
  /// lanes::Prepared).
  struct FullStep {
    bool refused = false;  ///< moveAllowed refuses the full step
    int first = 0;         ///< then the first triangle that fails
    bool allowed = false;  ///< moveAllowed accepts the full step
    /// When not null, prepareGuard's results are lane `lane` of this.
    const lanes::Prepared* prepared = nullptr;
    int lane = 0;
  };

  /// Tries the step from the centre towards target, shortened by halvings,
  /// under the guard. Returns the number of halvings used, -1 when every
  /// length was vetoed, -2 when the step rounds to no move at all. witness:
  /// see moveAllowed, shared by the calls of one visit. fullRefused
  /// (fullAllowed): the full step is known to fail (pass) moveAllowed.
  ///
  /// The lengths are taken in order and the first that passes is
  /// committed. With c.lengthLanes, the shortened steps go through
  /// moveAllowed's test four at once (lanes::allowedAt, the same answers);
  /// the deviation test then runs on those that passed, in order, as it
  /// would one by one.
  static int tryStep(const Context& c, int i, const Star& star, int* hints, const std::vector<Vec3>& foldRef,
                     const std::vector<double>& ringEdge2, const Vec3& target, double minAngleCos2Before,
                     int& pointHint, Budget& budget, int& witness, Vec3& x, bool fullRefused = false,
                     bool fullAllowed = false) {
    const SodtParams& p = c.p;
    const bool quality = p.guard == Guard::Quality;
    const Vec3 step = target - star.center;
    double f = 1.0;
    int j = 0;
    while (j <= p.maxBacktracks) {
      // The next lengths to test: the first alone (the full step passes
      // most often), then up to four at once.
      Vec3 y[lanes::kWidth];
      int yj[lanes::kWidth];
      // end: the answer (-2 or -1) once a length rounds to no move, after
      // which no shorter one is tried; 0 before.
      int m = 0, end = 0;
      const int want = c.lengthLanes && !(j == 0 && !fullRefused) ? lanes::kWidth : 1;
      for (; j <= p.maxBacktracks && m < want; ++j, f *= 0.5) {
        const Vec3 yy = representable(star.center + step * f);
        if (!isFinite(yy)) continue;
        if (yy == x) {
          end = j == 0 ? -2 : -1;  // shorter steps round to nothing as well
          break;
        }
        if (j == 0 && fullRefused) continue;
        y[m] = yy;
        yj[m++] = j;
      }
      int pass = 0;
      if (m == 1 && yj[0] == 0 && fullAllowed) {
        pass = 1;
      } else if (m == 1) {
        pass = moveAllowed(star, y[0], foldRef, ringEdge2, quality, minAngleCos2Before, &witness) ? 1 : 0;
      } else if (m > 1) {
        pass = lanes::allowedAt(star.ring.data(), static_cast<int>(star.size()), foldRef.data(), ringEdge2.data(),
                                star.refNormal.size() == star.size() ? star.refNormal.data() : nullptr, quality,
                                minAngleCos2Before, y, m, &witness);
      }
      for (int l = 0; l < m; ++l) {
        if (!(pass >> l & 1)) continue;
        if (!withinReach(c, star.center, y[l], star.ring.data(), star.size())) continue;
        if (c.input && !c.input->keeps(i, star, y[l], hints, pointHint, (y[l] - star.center).Norm() + budget.eps,
                                       budget.drift, budget.last, budget.next, budget.queried, budget.reused))
          continue;
        x = y[l];
        return yj[l];
      }
      if (end < 0) return end;
    }
    return -1;
  }

  /// A proposed move: the S-ODT target and the Laplacian fallback target, both
  /// on the same plane or line.
  struct Proposal {
    bool ok = false;
    Vec3 target = Vec3(0, 0, 0), fallback = Vec3(0, 0, 0);
    Vec3 normal = Vec3(0, 0, 0);  ///< tangent-plane normal, for the fold test of degenerate faces
    /// The fallback is the tangential Laplacian target in the plane of
    /// normal, computed only if needed (fallback is unset then).
    bool tangentialFallback = false;
  };

  /// Where the chosen algorithm wants vertex i (star centre) to go.
  static Proposal propose(const Context& c, int i, const Star& star) {
    Proposal pr;
    pr.normal = starNormal(star);
    if (pr.normal.SquaredNorm() == 0 || star.size() < 3) return pr;
    const VertexClass vc = c.cls.cls[i];
    const bool smoothBasic = vc != VertexClass::Crease &&
                             (c.p.algorithm != Algorithm::Denoise || !c.fit[i].ok);
    if (smoothBasic) {
      // The hot path: Algorithms 1-2 on a smooth vertex and the references.
      pr.tangentialFallback = true;
      if (c.p.algorithm == Algorithm::Odt) {
        const LocalMove mv = solveStarOdt(star);
        if (!mv.ok) return pr;
        pr.target = mv.target;
      } else if (c.p.algorithm == Algorithm::Laplacian) {
        Vec3 centroid(0, 0, 0);
        for (const Vec3& q : star.ring) centroid += q;
        pr.target = centroid / double(star.size());  // Eq. 3 with every S'_k = 1: not restricted to the tangent plane
      } else {
        const LocalMove mv = solveStar(star, pr.normal);
        if (!mv.ok) return pr;
        pr.target = mv.target;
      }
      pr.ok = true;
      return pr;
    }
    const Vec3 centroid = ringCentroid(star);

    if (c.p.algorithm == Algorithm::Denoise && c.fit[i].ok) {
      const FittedFrame& f = c.fit[i];
      Vec3 p;
      if (vc == VertexClass::Smooth) {
        pr.ok = denoiseTargets(star, f.point, f.dir, c.p.maxNormalStepRel * c.meanEdge, pr.target, pr.fallback);
        return pr;
      } else {
        const StarQuadratic q = sodtQuadratic(star, pr.normal);
        const Vec3 p0 = f.point - star.center;
        if (!minimizeOnLine(q, p0, f.dir, p)) return pr;
        pr.target = star.center + p;
        pr.fallback = f.point + f.dir * ((centroid - f.point) * f.dir);
        const double lim = c.p.maxNormalStepRel * c.meanEdge;
        for (Vec3* x : {&pr.target, &pr.fallback}) {
          const Vec3 d = *x - star.center;
          const Vec3 across = d - f.dir * (d * f.dir);
          const double h = across.Norm();
          if (h > lim) *x -= across * (1 - lim / h);
        }
      }
      pr.ok = isFinite(pr.target) && isFinite(pr.fallback);
      return pr;
    }

    if (vc == VertexClass::Crease) {
      // Along the crease direction of the current star (it follows curved creases).
      const TensorClass t = classifyStar(star.center, star.ring, c.meanEdge, c.p.epsilon, c.p.eta);
      const Vec3 e = t.creaseDir;
      if (e.SquaredNorm() == 0) return pr;
      const StarQuadratic q = sodtQuadratic(star, pr.normal);
      Vec3 p;
      if (!minimizeOnLine(q, Vec3(0, 0, 0), e, p)) return pr;
      pr.target = star.center + p;
      pr.fallback = star.center + e * ((centroid - star.center) * e);
      pr.ok = isFinite(pr.target);
      return pr;
    }

    return pr;
  }

  /// Commits an unguarded move to target into x. Unguarded updates can
  /// diverge; a position the mesh cannot hold (too large for its scalar
  /// type) is never written.
  static Outcome commitUnguarded(const Vec3& target, Vec3& x) {
    const Vec3 y = representable(target);
    if (!isFinite(y)) return Outcome::Failed;
    if (y == x) return Outcome::Unchanged;
    x = y;
    return Outcome::Moved;
  }

  /// The sweep plan regrouped for lanes::targets4: per phase, groups of
  /// lanes::kWidth vertices of equal valence (3 to lanes::kMaxValence),
  /// each group complete where its last member comes in the phase's order,
  /// then the vertices left over.
  struct LanePlan {
    std::vector<int> vertex;      ///< lanes::kWidth per group
    std::vector<int> valence;     ///< per group
    std::vector<int> table;       ///< the groups' index tables (lanes::packGroup)
    std::vector<std::size_t> tableBegin;  ///< per group, into table
    std::vector<int> groupBegin;  ///< per phase, first group (phases + 1 entries)
    std::vector<int> rest;        ///< visited one by one
    std::vector<int> restBegin;   ///< per phase, into rest (phases + 1 entries)
  };

  /// Groups ahead whose centre and ring positions a lane visit asks the
  /// cache for: on a mesh larger than the cache the kernel waits on its
  /// gathers otherwise (a fifth of an unguarded sweep at 1M vertices).
  static constexpr int kPrefetchGroups = 4;

  /// Only the vertices marked laneable go into groups (those whose update
  /// the kernel computes). withFaces: the tables get the face rows of the
  /// full-step test.
  static LanePlan planLanes(const SweepPlan& plan, const RingTopology& topo, const std::vector<char>& laneable,
                            bool withFaces) {
    LanePlan lp;
    const std::size_t phases = plan.phaseBegin.size() - 1;
    lp.vertex.reserve(plan.order.size());
    lp.table.reserve(plan.order.size() + (withFaces ? 2 : 1) * topo.ringIdx.size());
    lp.rest.reserve(plan.order.size() / 8);
    lp.groupBegin.push_back(0);
    lp.restBegin.push_back(0);
    std::array<std::vector<int>, lanes::kMaxValence + 1> open;  // per valence, a group being filled
    for (std::size_t c = 0; c < phases; ++c) {
      for (int j = plan.phaseBegin[c]; j < plan.phaseBegin[c + 1]; ++j) {
        const int v = plan.order[j], n = topo.ringSize(v);
        if (n < 3 || n > lanes::kMaxValence || !laneable[v]) {
          lp.rest.push_back(v);
          continue;
        }
        open[n].push_back(v);
        if (static_cast<int>(open[n].size()) == lanes::kWidth) {
          int begin[lanes::kWidth];
          for (int l = 0; l < lanes::kWidth; ++l) begin[l] = topo.ringBegin[open[n][l]];
          lp.tableBegin.push_back(lp.table.size());
          lp.table.resize(lp.table.size() + lanes::kWidth * (withFaces ? 2 * n + 1 : n + 1));
          lanes::packGroup(open[n].data(), topo.ringIdx.data(), begin, n, lp.table.data() + lp.tableBegin.back(),
                           withFaces ? topo.ringFace.data() : nullptr);
          lp.vertex.insert(lp.vertex.end(), open[n].begin(), open[n].end());
          lp.valence.push_back(n);
          open[n].clear();
        }
      }
      for (std::vector<int>& g : open) {
        lp.rest.insert(lp.rest.end(), g.begin(), g.end());
        g.clear();
      }
      lp.groupBegin.push_back(static_cast<int>(lp.valence.size()));
      lp.restBegin.push_back(static_cast<int>(lp.rest.size()));
    }
    return lp;
  }

  /// Proposes (unless given: propose()'s result, computed elsewhere),
  /// guards and commits the move of vertex i into x. hints: per star
  /// triangle, an input face for the deviation guard to try first (see
  /// InputSurface::keeps), or null.
  static Outcome visitVertex(const Context& c, int i, const Star& star, int* hints, int& pointHint, Scratch& sc,
                             Budget& budget, Vec3& x, const Proposal* given = nullptr, FullStep full = FullStep()) {
    const Proposal pr = given ? *given : propose(c, i, star);
    if (!pr.ok) return Outcome::Failed;
    const SodtParams& p = c.p;
    if (p.guard == Guard::None) return commitUnguarded(pr.target, x);
    double before;
    if (full.prepared) {
      const lanes::Prepared& pg = *full.prepared;
      const int l = full.lane, n = static_cast<int>(star.size());
      sc.foldRef.resize(n);
      sc.ringEdge2.resize(n);
      for (int k = 0; k < n; ++k) {
        sc.foldRef[k] = Vec3(pg.cx[k][l], pg.cy[k][l], pg.cz[k][l]);
        sc.ringEdge2[k] = pg.ee[k][l];
      }
      before = pg.limit[l];
    } else {
      before = prepareGuard(star, pr.normal, p.guard == Guard::Quality, sc.foldRef, sc.ringEdge2);
    }
    int witness = full.refused ? full.first : 0;
    const int r = tryStep(c, i, star, hints, sc.foldRef, sc.ringEdge2, pr.target, before, pointHint, budget, witness,
                          x, full.refused, full.allowed);
    if (r == 0) return Outcome::Moved;
    if (r > 0) return Outcome::Backtracked;
    if (p.laplacianFallback) {
      const Vec3 fallback = pr.tangentialFallback ? tangentialLaplacianTarget(star, pr.normal) : pr.fallback;
      if (tryStep(c, i, star, hints, sc.foldRef, sc.ringEdge2, fallback, before, pointHint, budget, witness, x) >= 0)
        return Outcome::Fallback;
    }
    return r == -2 ? Outcome::Unchanged : Outcome::Rejected;
  }
};

}  // namespace sodt
