// SPDX-License-Identifier: GPL-3.0-or-later
// The Gauss-Seidel sweeps: every active vertex visited once per sweep, colour
// by colour (no two neighbours at once), by the 4-lane kernel where it
// applies and one by one elsewhere, on one thread or several with the same
// result. What a visit does is guarded_move.h's.
#pragma once

#include "boundary.h"
#include "../guards/deviation.h"
#include "../guards/guarded_move.h"
#include "lane_plan.h"
#include "../maths/lanes.h"
#include "../maths/local_solve.h"
#include "../params.h"
#include "../maths/topology.h"

#include <algorithm>
#include <array>
#include <limits>
#include <type_traits>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sodt {

/// Switches that change how fast a run is, never its result: tests and
/// benchmarks compare both settings; users have no reason to touch them.
struct SweepTuning {
  /// The deviation guard remembers, per vertex and per star triangle, how
  /// far inside the bound its last accepted move left the checked points,
  /// and skips the distance queries of later moves too short to use that
  /// margin up.
  bool reuseDeviationMargins = true;
  /// Algorithm 1 sweeps, Algorithm 2's smooth vertices (whose update is
  /// Algorithm 1's) and Algorithm 3's smooth vertices with a fitted plane
  /// solve four vertices at once in AVX2 lanes when the processor has them
  /// (see lanes.h), and test the full step under the fold and angle guard
  /// there too (without the deviation bound, only for groups whose vertices
  /// mostly moved by their full step at their last visit). A step that
  /// passes is committed with no scalar work when nothing else is to be
  /// tested: no deviation bound, or margins of the vertex's last move that
  /// cover every point the deviation guard checks (reuseDeviationMargins);
  /// every other visit is guarded one vertex at a time as usual. Every
  /// algorithm's guard tests the shortened steps of a visit four lengths at
  /// once. The quality measured after each sweep for keepBest and
  /// toleranceDeg takes four faces at once too.
  bool simd = true;
};

/// Guarded sweeps go through the mesh in tiles of this many consecutive
/// working indices (breadth-first order), colour by colour within each
/// tile (colourVertices). A guarded visit reads some 300 bytes besides the
/// positions (margins, path lengths, hints, input normals and faces), so a
/// tile's data stays in a core's cache while its colours are swept, where
/// colour by colour over the whole mesh fetched it from memory once per
/// colour. Fixed, not taken from the processor: the order of the visits,
/// and so the result, must not depend on the machine.
constexpr int kTileVertices = 2048;

/// Sweeps the active vertices of a mesh held as positions and ring topology
/// (see SodtSmoother::Apply), for a mesh that stores coordinates as Scalar.
///
/// A visit is a function of the positions of the vertex's star (and of data
/// fixed for the run), so a visit that moved nothing need not be repeated
/// until something in its star moves: it is answered from the previous
/// outcome. Vertices of one colour read only positions that stay fixed
/// while that colour is swept, so they can move in any order or in parallel
/// with the same result. Both keep the result independent of the thread
/// count.
template <class Scalar>
class Sweeper {
 public:
  /// pos and topo are the run's, read and written by every sweep; topo may
  /// change between sweeps (see connectivityChanged). faceNormal: the input
  /// orientation of every face, or empty without a guard. slide: the
  /// border vertices that slide (SodtParams::slideBoundary), or null.
  Sweeper(const VisitContext& ctx, std::vector<Vec3>& pos, const RingTopology& topo,
          const std::vector<Vec3>& faceNormal, const std::vector<int>& active, int threads, SweepTuning tuning,
          const BoundarySlide* slide = nullptr)
      : ctx_(ctx), p_(ctx.move.p), tuning_(tuning), pos_(pos), topo_(topo), faceNormal_(faceNormal),
        active_(active), threads_(threads), scratch_(threads), slide_(slide) {
    deviationGuard_ = ctx.input != nullptr;
    tile_ = p_.guard != Guard::None ? kTileVertices : 0;
    plan_ = colourVertices(topo, active, tile_);
    const int nv = static_cast<int>(pos.size());
    lastVisit_.assign(nv, -1);
    movedAt_.assign(nv, -1);
    lastOutcome_.assign(nv, Outcome::Moved);
    pointHint_.assign(nv, -1);
    if (deviationGuard_) initMargins(nv);
    reserveScratch();
    planKernel();
    if (slide_)
      for (std::size_t s = 0; s < slide_->vertex.size(); ++s) slideArc_.push_back(slide_->startArc(s));
  }

  /// One sweep over every active vertex, colour by colour, then over the
  /// sliding border vertices (see sweepBorder).
  void sweep() {
    const int sweepBase = phase_;
    const std::size_t phases = plan_.phaseBegin.size() - 1;
#ifdef _OPENMP
    const std::size_t planTiles = plan_.tileBegin.empty() ? 0 : plan_.tileBegin.size() - 1;
    if (threads_ > 1 && planTiles >= static_cast<std::size_t>(kMinParallelTiles) * threads_) {
      // Tile by tile on each thread, the tiles of a group at once (see
      // SweepPlan): a wait per group, not per phase.
      for (std::size_t g = 0; g + 1 < plan_.groupBegin.size(); ++g) {
        const int t0 = plan_.groupBegin[g], nt = plan_.groupBegin[g + 1] - t0;
#pragma omp parallel for num_threads(threads_) schedule(dynamic, 1)
        for (int t = 0; t < nt; ++t) {
          Scratch& sc = scratch_[omp_get_thread_num()];
          for (int c = plan_.tileBegin[t0 + t]; c < plan_.tileBegin[t0 + t + 1]; ++c)
            runPhase(static_cast<std::size_t>(c), sweepBase + c, sc, false);
        }
      }
    } else
#endif
    {
      for (std::size_t c = 0; c < phases; ++c)
        runPhase(c, sweepBase + static_cast<int>(c), scratch_[0], threads_ > 1);
    }
    phase_ = sweepBase + static_cast<int>(phases);
    if (slide_ && !slide_->empty()) sweepBorder(phase_++);
  }

  /// After edge flips: topo (the run's, rebuilt) replaces before. Only the
  /// flipped vertices (a, b, c, d of each flip) have a new star; every other
  /// star has the same faces, and its ring starts at its smallest neighbour
  /// as before, so what was remembered of it still holds. (Compared anyway:
  /// a star that differs is treated as new and visited again.)
  void connectivityChanged(const RingTopology& before, const std::vector<int>& flippedVertices) {
    const RingTopology& topo = topo_;
    plan_ = colourVertices(topo, active_, tile_);
    if (useLanes_) lanePlan_ = planLanes(plan_, topo, laneable_, laneGuard_);
    reserveScratch();
    const int nv = static_cast<int>(pos_.size());
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
      if (!sameStar[v]) lastVisit_[v] = -1;  // visit new stars again
    }
    if (deviationGuard_) moveSlotMargins(before, sameStar);
  }

  /// Adds the sweeps' counters to s.
  void addCounts(SodtStats& s) const {
    for (const Scratch& sc : scratch_) {
      for (int o = 0; o < kOutcomes; ++o) count(s, static_cast<Outcome>(o), sc.count[o]);
      s.skipped += sc.skipped;
      s.deviationQueries += sc.queried;
      s.deviationReused += sc.reused;
      s.laneVisits += sc.laneVisits;
    }
  }

 private:
  using Move = GuardedMove<Scalar>;

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

  /// Per-thread working memory of the sweeps and its share of the counters.
  /// The threads' Scratch lie side by side in one array, and both ends are
  /// written on every visit (the star's centre and size, the lane kernel's
  /// results): the padding keeps those of neighbouring threads off a shared
  /// cache line, which cost a tenth of a guarded sweep on two threads.
  struct Scratch {
    char padFront[64];
    Star star;
    std::vector<Vec3> foldRef;      ///< see prepareGuard
    std::vector<double> ringEdge2;  ///< see prepareGuard
    std::array<long long, kOutcomes> count{};
    long long skipped = 0;
    long long queried = 0, reused = 0;  ///< deviation-guard points, see SodtStats
    long long laneVisits = 0;
    std::vector<double> drift;  ///< see Budget
    std::vector<float> nextSlot;
    CoverScratch cover;
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
      cover.reserve(16 * static_cast<std::size_t>(valence) + 64);
    }
  };

  /// What the deviation guard remembers between visits (see
  /// InputSurface::keeps): per vertex the length of the path it has moved
  /// so far and the margin of its position; per ring slot the margin of
  /// that star triangle and the ring vertex's path length at the time
  /// (rounded down), and the input face its centroid was last found near
  /// (at first, the face the triangle is in the input).
  void initMargins(int nv) {
    const std::size_t ringSlots = topo_.ringIdx.size();
    odo_.assign(nv, 0.0);
    // The input's points are on the input: the first visits start from
    // their margin, no query needed.
    const float startMargin = tuning_.reuseDeviationMargins ? ctx_.input->inputMargin : -1.f;
    pointMargin_.assign(nv, startMargin);
    slotMargin_.assign(ringSlots, startMargin);
    slotOdo_.assign(ringSlots, 0.f);
    slotHint_ = topo_.ringFace;
  }

  /// After flips: the vertex margins depend on the vertex and its input
  /// patch alone; the star triangles' margins move to their new slots, and
  /// new stars are checked in full.
  void moveSlotMargins(const RingTopology& before, const std::vector<char>& sameStar) {
    const RingTopology& topo = topo_;
    std::vector<float> margin(topo.ringIdx.size(), -1.f), slotOdoNew(topo.ringIdx.size(), 0.f);
    std::vector<int> hint(topo.ringIdx.size(), -1);
    for (std::size_t v = 0; v < sameStar.size(); ++v) {
      if (!sameStar[v]) continue;
      const int n = topo.ringSize(static_cast<int>(v)), from = before.ringBegin[v], to = topo.ringBegin[v];
      std::copy(slotMargin_.begin() + from, slotMargin_.begin() + from + n, margin.begin() + to);
      std::copy(slotOdo_.begin() + from, slotOdo_.begin() + from + n, slotOdoNew.begin() + to);
      std::copy(slotHint_.begin() + from, slotHint_.begin() + from + n, hint.begin() + to);
    }
    slotMargin_.swap(margin);
    slotOdo_.swap(slotOdoNew);
    slotHint_.swap(hint);
  }

  void reserveScratch() {
    for (int i : active_) maxValence_ = std::max(maxValence_, topo_.ringSize(i));
    const double turn = runTurnCos2(p_);
    for (Scratch& s : scratch_) {
      s.reserve(maxValence_);
      s.star.maxTurnCos2 = turn;  // the same for every star of the run
    }
  }

  /// Algorithm 1, the smooth vertices of Algorithm 2 (whose update is
  /// Algorithm 1's) and those of Algorithm 3 with a fitted plane: the
  /// 4-lane kernel when the processor has it.
  void planKernel() {
    const Algorithm a = p_.algorithm;
    const int nv = static_cast<int>(pos_.size());
    denoiseLanes_ = a == Algorithm::Denoise;
    useLanes_ = tuning_.simd && (a == Algorithm::Basic || a == Algorithm::Feature || denoiseLanes_) &&
                lanes::available() && nv < std::numeric_limits<int>::max() / 3;
    if (useLanes_) {
      const std::vector<FittedFrame>& fit = ctx_.move.fit;
      laneable_.assign(nv, 0);
      for (int i : active_)
        laneable_[i] = ctx_.move.cls.cls[i] == VertexClass::Smooth && (!denoiseLanes_ || fit[i].ok);
      if (denoiseLanes_ && !fit.empty()) {
        static_assert(sizeof(FittedFrame) % sizeof(double) == 0, "frames must be read as doubles");
        laneDenoise_.point = &fit[0].point[0];
        laneDenoise_.dir = &fit[0].dir[0];
        laneDenoise_.stride = static_cast<int>(sizeof(FittedFrame) / sizeof(double));
        laneDenoise_.lim = p_.maxNormalStepRel * ctx_.move.meanEdge;
      }
    }
    // The kernel also tests the full step under the fold and angle guard
    // (when the mesh stores float or double coordinates, what
    // representable() rounds to), and an accepted step is committed with no
    // scalar work: without the deviation bound always, with it when the
    // margins of the vertex's last move cover every checked point (see
    // laneKeeps), as they do for most full steps.
    laneGuard_ = useLanes_ && p_.guard != Guard::None && (!deviationGuard_ || tuning_.reuseDeviationMargins) &&
                 (std::is_same<Scalar, float>::value || std::is_same<Scalar, double>::value);
    // Guarded visits of the kernel's vertices take what prepareGuard
    // computes from the kernel too, which has the star in its lanes already.
    lanePrepare_ = useLanes_ && p_.guard != Guard::None;
    if (lanePrepare_) {
      laneGuardInput_.faceNormal = faceNormal_.empty() ? nullptr : &faceNormal_[0][0];
      laneGuardInput_.quality = p_.guard == Guard::Quality;
      laneGuardInput_.maxTurnCos2 = runTurnCos2(p_);
      laneGuardInput_.roundToFloat = std::is_same<Scalar, float>::value;
    }
    if (useLanes_) lanePlan_ = planLanes(plan_, topo_, laneable_, laneGuard_);
    prefetchFaces_ = p_.guard != Guard::None && !faceNormal_.empty();
    laneMargins_ = laneGuard_ && deviationGuard_;
    // Without the deviation bound the kernel's full-step test pays only when
    // most lanes pass it (see kLikelyLanes); with it, a lane that passes
    // usually saves a whole scalar visit, so every group is tested.
    likelyNeeded_ = laneMargins_ ? 0 : kLikelyLanes;
    // A guarded visit costs from one test to a dozen (a rejected one tries
    // every step length twice), and a thread can be held up: the threads
    // take guarded work in small chunks as they get to it. Unguarded visits
    // cost about the same and little, so they are split in equal halves.
    dynamicSchedule_ = p_.guard != Guard::None || a == Algorithm::Odt;
    minParallel_ = dynamicSchedule_ ? kMinParallelGuardedPhase : kMinParallelPhase;
  }

  /// Sweeps phase c, numbered phaseNo among all phases of the run, on the
  /// calling thread with scratch sc0, or split between the threads when
  /// parallel.
  void runPhase(std::size_t c, int phaseNo, Scratch& sc0, bool parallel) {
    (void)parallel;
    if (useLanes_) {
      // Four vertices of equal valence per kernel call, then the rest one
      // by one: all of one colour, so the order does not matter.
      const int g0 = lanePlan_.groupBegin[c], ng = lanePlan_.groupBegin[c + 1] - g0;
      const int* rest = lanePlan_.rest.data() + lanePlan_.restBegin[c];
      const int nr = lanePlan_.restBegin[c + 1] - lanePlan_.restBegin[c];
#ifdef _OPENMP
      if (parallel && lanes::kWidth * ng + nr >= minParallel_) {
#pragma omp parallel num_threads(threads_)
        {
          Scratch& sc = scratch_[omp_get_thread_num()];
          if (dynamicSchedule_) {
#pragma omp for schedule(dynamic, 16) nowait
            for (int g = 0; g < ng; ++g) visitGroup(g0 + g, g0 + ng, phaseNo, sc);
#pragma omp for schedule(dynamic, 32)
            for (int j = 0; j < nr; ++j) visitOne(rest[j], phaseNo, sc, nullptr, FullStep());
          } else {
#pragma omp for schedule(static) nowait
            for (int g = 0; g < ng; ++g) visitGroup(g0 + g, g0 + ng, phaseNo, sc);
#pragma omp for schedule(static)
            for (int j = 0; j < nr; ++j) visitOne(rest[j], phaseNo, sc, nullptr, FullStep());
          }
        }
        return;
      }
#endif
      for (int g = 0; g < ng; ++g) visitGroup(g0 + g, g0 + ng, phaseNo, sc0);
      for (int j = 0; j < nr; ++j) visitOne(rest[j], phaseNo, sc0, nullptr, FullStep());
      return;
    }
    const int* vs = plan_.order.data() + plan_.phaseBegin[c];
    const int n = plan_.phaseBegin[c + 1] - plan_.phaseBegin[c];
#ifdef _OPENMP
    if (parallel && n >= minParallel_) {
      if (dynamicSchedule_) {
#pragma omp parallel for num_threads(threads_) schedule(dynamic, 32)
        for (int j = 0; j < n; ++j) visitOne(vs[j], phaseNo, scratch_[omp_get_thread_num()], nullptr, FullStep());
      } else {
#pragma omp parallel for num_threads(threads_) schedule(static)
        for (int j = 0; j < n; ++j) visitOne(vs[j], phaseNo, scratch_[omp_get_thread_num()], nullptr, FullStep());
      }
      return;
    }
#endif
    for (int j = 0; j < n; ++j) visitOne(vs[j], phaseNo, sc0, nullptr, FullStep());
  }

  /// The sliding border vertices, one after the other in ascending order
  /// on the calling thread, as one phase numbered phaseNo after the
  /// interior ones: their order (and so the result) depends neither on the
  /// threads nor on the lane kernel, and there are few of them. They are
  /// visited every sweep (no still() shortcut). A move adds to the vertex's
  /// path length, which its interior neighbours' deviation margins read.
  void sweepBorder(int phaseNo) {
    Scratch& sc = scratch_[0];
    OpenStar& st = border_;
    for (std::size_t s = 0; s < slide_->vertex.size(); ++s) {
      const int v = slide_->vertex[s];
      const OpenFan& fan = slide_->fan[s];
      st.center = pos_[v];
      st.ring.resize(fan.ring.size());
      for (std::size_t k = 0; k < fan.ring.size(); ++k) st.ring[k] = pos_[fan.ring[k]];
      st.refNormal.clear();
      if (!faceNormal_.empty())
        for (int f : fan.faces) st.refNormal.push_back(faceNormal_[f]);
      const Vec3 from = pos_[v];
      const Outcome o = slideVisit<Scalar>(ctx_, *slide_, s, st, pos_[v], slideArc_[s], sc.queried);
      record(v, o, phaseNo, sc);
      if (moves(o) && deviationGuard_) odo_[v] += (pos_[v] - from).Norm();
      if (moves(o) && ctx_.cover) ctx_.cover->commitMove(v, from, pos_[v], fan.faces);
    }
  }

  /// A visit whose outcome did not move the vertex need not be repeated
  /// while nothing in its star has moved since.
  bool still(int i) const {
    if (lastVisit_[i] < 0 || moves(lastOutcome_[i])) return false;
    for (int k = topo_.ringBegin[i]; k < topo_.ringBegin[i + 1]; ++k)
      if (movedAt_[topo_.ringIdx[k]] >= lastVisit_[i]) return false;
    return true;
  }

  void skip(int i, Scratch& sc) const {
    ++sc.count[static_cast<int>(lastOutcome_[i])];
    ++sc.skipped;
  }

  void record(int i, Outcome o, int phaseNo, Scratch& sc) {
    ++sc.count[static_cast<int>(o)];
    lastVisit_[i] = phaseNo;
    lastOutcome_[i] = o;
    if (moves(o)) movedAt_[i] = phaseNo;
  }

  /// The deviation guard's view of vertex i's margins (see Budget).
  void prepareBudget(int i, Scratch& sc, Budget& budget) {
    const int b = topo_.ringBegin[i], e = topo_.ringBegin[i + 1];
    // Path lengths grow by rounding too: a margin of 1e-12 of them.
    const double eps = 1e-12 * (odo_[i] + ctx_.input->limit);
    sc.drift.resize(e - b);  // within the reserved size
    for (int k = b; k < e; ++k) {
      const double o = odo_[topo_.ringIdx[k]];
      sc.drift[k - b] = o - slotOdo_[k] + 1e-12 * o + eps;
    }
    sc.nextSlot.resize(e - b);
    budget.drift = sc.drift.data();
    budget.eps = eps;
    budget.last.point = pointMargin_[i];
    budget.last.slot = slotMargin_.data() + b;
    budget.next.slot = sc.nextSlot.data();
  }

  /// Keeps the margins of vertex i's accepted move from `from`.
  void commitMargins(int i, const Vec3& from, const Budget& budget) {
    odo_[i] += (pos_[i] - from).Norm();
    pointMargin_[i] = budget.next.point;
    for (int k = topo_.ringBegin[i]; k < topo_.ringBegin[i + 1]; ++k) {
      slotMargin_[k] = budget.next.slot[k - topo_.ringBegin[i]];
      slotOdo_[k] = InputSurface::floatBelow(odo_[topo_.ringIdx[k]]);
    }
  }

  /// Visits vertex i, with its proposal when one was computed already;
  /// false when the visit was answered from the previous one.
  bool visitOne(int i, int phaseNo, Scratch& sc, const Proposal* given, FullStep full) {
    if (still(i)) {
      skip(i, sc);
      return false;
    }
    Star& star = sc.star;
    const int b = topo_.ringBegin[i], e = topo_.ringBegin[i + 1];
    star.center = pos_[i];
    star.ring.resize(e - b);
    for (int k = b; k < e; ++k) star.ring[k - b] = pos_[topo_.ringIdx[k]];
    if (!faceNormal_.empty()) {
      star.refNormal.resize(e - b);
      for (int k = b; k < e; ++k) star.refNormal[k - b] = faceNormal_[topo_.ringFace[k]];
    }
    int* hints = deviationGuard_ ? slotHint_.data() + b : nullptr;
    Budget budget;
    if (deviationGuard_) prepareBudget(i, sc, budget);
    const Vec3 from = pos_[i];
    const VisitScratch vs{sc.foldRef, sc.ringEdge2, hints, pointHint_[i], ctx_.cover ? &sc.cover : nullptr};
    const Outcome o = Move::visit(ctx_, i, star, vs, budget, pos_[i], given, full);
    sc.queried += budget.queried;
    sc.reused += budget.reused;
    record(i, o, phaseNo, sc);
    if (moves(o) && deviationGuard_ && tuning_.reuseDeviationMargins) commitMargins(i, from, budget);
    if (moves(o) && ctx_.cover) ctx_.cover->commitMove(i, from, pos_[i], &sc.cover);
    return true;
  }

  /// When the margins of vertex i's last move answer the deviation test of
  /// its move to y with no distance query, commits the move as the visit
  /// would (InputSurface::keepsByMargins); false, with nothing changed,
  /// otherwise: the visit then runs in full.
  bool laneKeeps(int i, const Vec3& y, int phaseNo, Scratch& sc) {
    Budget budget;
    prepareBudget(i, sc, budget);
    const double step = (y - pos_[i]).Norm() + budget.eps;
    long long reused = 0;  // counted only when the move is taken here
    if (!ctx_.input->keepsByMargins(i, sc.drift.size(), step, budget.drift, budget.last, budget.next, reused))
      return false;
    if (ctx_.cover && !ctx_.cover->coveredAfterMove(i, y, &sc.cover)) return false;  // the full visit refuses it
    sc.reused += reused;
    const Vec3 from = pos_[i];
    pos_[i] = y;
    record(i, Outcome::Moved, phaseNo, sc);
    commitMargins(i, from, budget);
    if (ctx_.cover) ctx_.cover->commitMove(i, from, y, &sc.cover);
    return true;
  }

  /// Visits the four vertices of lane group g (groups of the phase end at
  /// gEnd): solved at once by the kernel, then committed, guarded or
  /// visited in full one by one.
  void visitGroup(int g, int gEnd, int phaseNo, Scratch& sc) {
#if defined(__GNUC__) || defined(__clang__)
    // What the visits of a group ahead will read. (Here, not in a function
    // of its own: GCC takes a function that only prefetches for one without
    // effects and drops its calls.)
    if (g + kPrefetchGroups < gEnd) {
      const int ahead = g + kPrefetchGroups;
      const int* table = lanePlan_.table.data() + lanePlan_.tableBegin[ahead];
      const int entries = lanes::kWidth * (lanePlan_.valence[ahead] + 1);
      for (int e = 0; e < entries; ++e) __builtin_prefetch(&pos_[0][0] + table[e]);
      const int* va = lanePlan_.vertex.data() + lanes::kWidth * ahead;
      if (laneMargins_) {  // the deviation guard's margins and path lengths
        for (int e = 0; e < entries; ++e) __builtin_prefetch(&odo_[table[e] / 3]);
        for (int l = 0; l < lanes::kWidth; ++l) {
          __builtin_prefetch(&slotMargin_[topo_.ringBegin[va[l]]]);
          __builtin_prefetch(&slotOdo_[topo_.ringBegin[va[l]]]);
        }
      }
      if (prefetchFaces_)  // the guard reads the input normals of the ring's faces
        for (int l = 0; l < lanes::kWidth; ++l)
          for (int k = topo_.ringBegin[va[l]]; k < topo_.ringBegin[va[l] + 1]; ++k)
            __builtin_prefetch(&faceNormal_[topo_.ringFace[k]]);
    }
#endif
    const int* vs = lanePlan_.vertex.data() + lanes::kWidth * g;
    lanes::Targets t;
    // The full-step test (see likelyNeeded_).
    int likely = 0;
    if (laneGuard_)
      for (int l = 0; l < lanes::kWidth; ++l) likely += lastOutcome_[vs[l]] == Outcome::Moved;
    lanes::StepVerdict v;
    lanes::targets4(&pos_[0][0], lanePlan_.table.data() + lanePlan_.tableBegin[g], lanePlan_.valence[g], t,
                    lanePrepare_ ? &laneGuardInput_ : nullptr, likely >= likelyNeeded_ ? &v : nullptr,
                    lanePrepare_ ? &sc.prepared : nullptr, denoiseLanes_ ? &laneDenoise_ : nullptr);
    if (likely < likelyNeeded_) v.allowed = v.refused = 0;
    for (int l = 0; l < lanes::kWidth; ++l) {
      const int i = vs[l];
      const bool ok = (t.ok >> l & 1) != 0;
      if (p_.guard == Guard::None) {
        if (still(i)) {
          skip(i, sc);  // the kernel's answer is the one recorded last time
          continue;
        }
        const Outcome o = ok ? Move::commitUnguarded(Vec3(t.x[l], t.y[l], t.z[l]), pos_[i]) : Outcome::Failed;
        record(i, o, phaseNo, sc);
        ++sc.laneVisits;
        continue;
      }
      if ((v.allowed >> l & 1) && withinReach(ctx_, pos_[i], Vec3(v.x[l], v.y[l], v.z[l]), topo_.ringSize(i),
                                              [&](std::size_t k) -> const Vec3& {
                                                return pos_[topo_.ringIdx[topo_.ringBegin[i] + k]];
                                              })) {
        // The visit moves the vertex by the full step when nothing else is
        // to be tested: no deviation bound, or margins that answer it. It
        // cannot be one still() would answer: that visit, on the same star
        // with the same margins, did not move the vertex.
        const Vec3 y(v.x[l], v.y[l], v.z[l]);
        if (!deviationGuard_) {
          pos_[i] = y;
          record(i, Outcome::Moved, phaseNo, sc);
          ++sc.laneVisits;
          continue;
        }
        if (laneKeeps(i, y, phaseNo, sc)) {
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
        if (denoiseLanes_)
          pr.fallback = Vec3(t.fx[l], t.fy[l], t.fz[l]);
        else
          pr.tangentialFallback = true;
      }
      sc.laneVisits += visitOne(i, phaseNo, sc, &pr, full);
    }
  }

  const VisitContext& ctx_;
  const SodtParams& p_;
  const SweepTuning tuning_;
  std::vector<Vec3>& pos_;
  const RingTopology& topo_;
  const std::vector<Vec3>& faceNormal_;
  const std::vector<int>& active_;
  const int threads_;
  bool deviationGuard_ = false;
  int tile_ = 0;
  SweepPlan plan_;
  int phase_ = 0;  ///< phases swept so far, over all sweeps
  std::vector<int> lastVisit_, movedAt_;
  std::vector<Outcome> lastOutcome_;
  /// Per vertex, the input face its position was last found near (a hint
  /// for the deviation guard; every vertex writes only its own).
  std::vector<int> pointHint_;
  std::vector<double> odo_;        ///< see initMargins
  std::vector<float> pointMargin_, slotMargin_, slotOdo_;
  std::vector<int> slotHint_;
  std::vector<Scratch> scratch_;
  const BoundarySlide* slide_;
  OpenStar border_;  ///< the star of the border vertex being visited
  std::vector<double> slideArc_;  ///< per sliding vertex, its parameter on its path (BoundarySlide::pointAt)
  int maxValence_ = 0;
  // The lane kernel (see planKernel).
  bool useLanes_ = false, denoiseLanes_ = false, laneGuard_ = false, lanePrepare_ = false;
  bool prefetchFaces_ = false, laneMargins_ = false, dynamicSchedule_ = false;
  int likelyNeeded_ = 0, minParallel_ = 0;
  std::vector<char> laneable_;
  lanes::DenoiseInput laneDenoise_;
  lanes::GuardInput laneGuardInput_;
  LanePlan lanePlan_;
};

}  // namespace sodt
