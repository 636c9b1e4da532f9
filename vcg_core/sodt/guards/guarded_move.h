// SPDX-License-Identifier: GPL-3.0-or-later
// One vertex visit: the proposed move (moves.h) taken, shortened by halvings
// or replaced by its Laplacian fallback, only where the guard allows it: no
// face folds, collapses or turns against its input orientation or further
// from it than SodtParams::maxFaceTurnDeg (Guard::Fold),
// no smallest angle of the star shrinks (Guard::Quality), the vertex stays
// within reach of its star, and within the deviation bound of the input
// surface (deviation.h).
#pragma once

#include "../maths/classify.h"
#include "cover.h"
#include "deviation.h"
#include "../maths/lanes.h"
#include "../maths/local_solve.h"
#include "../maths/moves.h"
#include "../params.h"
#include "../maths/topology.h"

#include <vector>

namespace sodt {

/// The squared cosine of the largest face turn the run's guard allows
/// (faceTurnCos2 of SodtParams::maxFaceTurnDeg): 0, the fold test alone,
/// with Guard::None and for Denoise, whose moves exist to turn noisy faces
/// into the surface (it has no deviation bound either).
inline double runTurnCos2(const SodtParams& p) {
  return p.guard == Guard::None || p.algorithm == Algorithm::Denoise ? 0.0 : faceTurnCos2(p.maxFaceTurnDeg);
}

/// How one vertex visit ended.
enum class Outcome : unsigned char { Moved, Backtracked, Fallback, Rejected, Unchanged, Failed };

constexpr int kOutcomes = 6;

/// True for the outcomes that changed the vertex's position.
inline bool moves(Outcome o) { return o == Outcome::Moved || o == Outcome::Backtracked || o == Outcome::Fallback; }

/// Adds n visits that ended in o to the run's counters.
inline void count(SodtStats& s, Outcome o, long long n) {
  switch (o) {
    case Outcome::Moved: s.moved += n; break;
    case Outcome::Backtracked: s.backtracked += n; break;
    case Outcome::Fallback: s.fallbackMoves += n; break;
    case Outcome::Rejected: s.rejected += n; break;
    case Outcome::Unchanged: s.unchanged += n; break;
    case Outcome::Failed: s.failedSolves += n; break;
  }
}

/// State shared by all visits of a run; read-only but for the cover.
struct VisitContext {
  MoveInputs move;
  const InputSurface* input;  ///< deviation guard, or null
  /// tryStep tests step lengths four at once (lanes::allowedAt).
  bool lengthLanes;
  /// The box no guarded move may leave (see reachBox).
  Vec3 boxLo, boxHi;
  /// The deviation guard's other direction (with input), or null: the
  /// input points covered by the star must stay covered (see InputCover).
  /// A visit reads and writes only its star's share of it.
  InputCover* cover = nullptr;
};

/// The box a guarded move must stay in: the input surface's bounding box
/// grown by the deviation bound (by a mean edge length for Denoise, which
/// has none), plus 1e-9 of its diagonal for rounding. With the fold test
/// alone a star whose ring does not surround its centre in the tangent
/// plane (needles around a high-valence vertex) lets a move fly off
/// without folding anything; this and the star's reach (withinReach) stop
/// it, whatever the other options.
inline void reachBox(const SodtParams& p, const std::vector<Vec3>& pos, const RingTopology& topo, double meanEdge,
                     Vec3& lo, Vec3& hi) {
  const double diag = surfaceBox(pos, topo, lo, hi);
  double grow = p.algorithm == Algorithm::Denoise ? meanEdge : p.maxDeviationRel * diag;
  grow += 1e-9 * diag;
  for (int k = 0; k < 3; ++k) {
    lo[k] -= grow;
    hi[k] += grow;
  }
}

/// A guarded move from centre to y stays in the reach box and no farther
/// from the centre than the centre's farthest ring vertex, ring[0..n) (a
/// healthy star's S-ODT, Laplacian and crease targets all lie well inside
/// that). Ring vertices are read through at(k).
template <class RingAt>
bool withinReach(const VisitContext& c, const Vec3& centre, const Vec3& y, std::size_t n, RingAt at) {
  for (int k = 0; k < 3; ++k)
    if (!(y[k] >= c.boxLo[k] && y[k] <= c.boxHi[k])) return false;
  const double s2 = (y - centre).SquaredNorm();
  for (std::size_t k = 0; k < n; ++k)
    if (s2 <= (at(k) - centre).SquaredNorm()) return true;
  return false;
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

/// What a visit writes besides the vertex position: the guard's per-star
/// working arrays (prepareGuard) and the deviation guard's hints.
struct VisitScratch {
  std::vector<Vec3>& foldRef;
  std::vector<double>& ringEdge2;
  int* hints;      ///< per star triangle, an input face to try first (see InputSurface::keeps), or null
  int& pointHint;  ///< the input face the vertex was last found near
  CoverScratch* cover;  ///< what the cover measured for the accepted step (see CoverScratch), or null
};

/// The guarded visit for a mesh that stores coordinates as Scalar.
template <class Scalar>
struct GuardedMove {
  /// Rounds a double position to what the mesh can store.
  static Vec3 representable(const Vec3& x) { return roundedTo<Scalar>(x); }

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

  /// Proposes (unless given: propose()'s result, computed elsewhere),
  /// guards and commits the move of vertex i into x.
  static Outcome visit(const VisitContext& c, int i, const Star& star, VisitScratch s, Budget& budget, Vec3& x,
                       const Proposal* given = nullptr, FullStep full = FullStep()) {
    const Proposal pr = given ? *given : propose(c.move, i, star);
    if (!pr.ok) return Outcome::Failed;
    const SodtParams& p = c.move.p;
    if (p.guard == Guard::None) return commitUnguarded(pr.target, x);
    double before;
    if (full.prepared) {
      const lanes::Prepared& pg = *full.prepared;
      const int l = full.lane, n = static_cast<int>(star.size());
      s.foldRef.resize(n);
      s.ringEdge2.resize(n);
      for (int k = 0; k < n; ++k) {
        s.foldRef[k] = Vec3(pg.cx[k][l], pg.cy[k][l], pg.cz[k][l]);
        s.ringEdge2[k] = pg.ee[k][l];
      }
      before = pg.limit[l];
    } else {
      before = prepareGuard(star, pr.normal, p.guard == Guard::Quality, s.foldRef, s.ringEdge2);
    }
    int witness = full.refused ? full.first : 0;
    const int r = tryStep(c, i, star, s, pr.target, before, budget, witness, x, full.refused, full.allowed);
    if (r == 0) return Outcome::Moved;
    if (r > 0) return Outcome::Backtracked;
    if (p.laplacianFallback) {
      const Vec3 fallback = pr.tangentialFallback ? tangentialLaplacianTarget(star, pr.normal) : pr.fallback;
      if (tryStep(c, i, star, s, fallback, before, budget, witness, x) >= 0) return Outcome::Fallback;
    }
    return r == -2 ? Outcome::Unchanged : Outcome::Rejected;
  }

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
  static int tryStep(const VisitContext& c, int i, const Star& star, const VisitScratch& s, const Vec3& target,
                     double minAngleCos2Before, Budget& budget, int& witness, Vec3& x, bool fullRefused = false,
                     bool fullAllowed = false) {
    const SodtParams& p = c.move.p;
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
        pass = moveAllowed(star, y[0], s.foldRef, s.ringEdge2, quality, minAngleCos2Before, &witness) ? 1 : 0;
      } else if (m > 1) {
        pass = lanes::allowedAt(star.ring.data(), static_cast<int>(star.size()), s.foldRef.data(),
                                s.ringEdge2.data(), star.refNormal.size() == star.size() ? star.refNormal.data() : nullptr,
                                star.maxTurnCos2, quality, minAngleCos2Before, y, m, &witness);
      }
      for (int l = 0; l < m; ++l) {
        if (!(pass >> l & 1)) continue;
        if (!withinReach(c, star.center, y[l], star.size(), [&](std::size_t k) -> const Vec3& { return star.ring[k]; }))
          continue;
        if (c.input && !c.input->keeps(i, star, y[l], s.hints, s.pointHint, (y[l] - star.center).Norm() + budget.eps,
                                       budget.drift, budget.last, budget.next, budget.queried, budget.reused))
          continue;
        if (c.cover && !c.cover->coveredAfterMove(i, y[l], s.cover)) continue;
        x = y[l];
        return yj[l];
      }
      if (end < 0) return end;
    }
    return -1;
  }
};

}  // namespace sodt
