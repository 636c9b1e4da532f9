// SPDX-License-Identifier: GPL-3.0-or-later
// Where each algorithm wants one vertex to go: the per-vertex moves of the
// paper's Algorithms 1-3 and of the two reference updates, each a function
// of the vertex's star alone. Whether a move is taken is the guard's
// business (guarded_move.h); the sweeps that apply the moves are sweeper.h's.
#pragma once

#include "classify.h"
#include "fitting.h"
#include "local_solve.h"
#include "odt.h"
#include "../params.h"

#include <vector>

namespace sodt {

/// A proposed move: the target and the Laplacian fallback target, both on
/// the same plane or line.
struct Proposal {
  bool ok = false;
  Vec3 target = Vec3(0, 0, 0), fallback = Vec3(0, 0, 0);
  Vec3 normal = Vec3(0, 0, 0);  ///< tangent-plane normal, for the fold test of degenerate faces
  /// The fallback is the tangential Laplacian target in the plane of
  /// normal, computed only if needed (fallback is unset then).
  bool tangentialFallback = false;
};

/// What the moves read besides the star: fixed for the whole run.
struct MoveInputs {
  const SodtParams& p;
  const Classification& cls;
  const std::vector<FittedFrame>& fit;  ///< Denoise only: per vertex, its fitted plane or crease line
  double meanEdge;                      ///< the mesh's length scale (Feature, Denoise)
};

/// Algorithm 1 (Sec. 2.3), also the smooth vertices of Algorithm 2: the
/// closed-form S-ODT minimiser in the tangent plane of normal pr.normal
/// (Eq. 4-8); with Odt or Laplacian the reference updates instead (Eq. 3
/// with true areas, minimised numerically; the one-ring centroid). The
/// fallback is the tangential Laplacian step.
inline void smoothMove(Algorithm a, const Star& star, Proposal& pr) {
  pr.tangentialFallback = true;
  if (a == Algorithm::Odt) {
    const LocalMove mv = solveStarOdt(star);
    if (!mv.ok) return;
    pr.target = mv.target;
  } else if (a == Algorithm::Laplacian) {
    Vec3 centroid(0, 0, 0);
    for (const Vec3& q : star.ring) centroid += q;
    pr.target = centroid / double(star.size());  // Eq. 3 with every S'_k = 1: not restricted to the tangent plane
  } else {
    const LocalMove mv = solveStar(star, pr.normal);
    if (!mv.ok) return;
    pr.target = mv.target;
  }
  pr.ok = true;
}

/// Algorithm 2's crease vertex (Sec. 2.4): slides along the crease
/// direction e3 of its current star (so it follows curved creases) to the
/// minimiser of Eq. 5 on that line; the fallback is the ring centroid
/// projected on the line.
inline void creaseMove(const Star& star, double meanEdge, double epsilon, double eta, Proposal& pr) {
  const Vec3 centroid = ringCentroid(star);
  const TensorClass t = classifyStar(star.center, star.ring, meanEdge, epsilon, eta);
  const Vec3 e = t.creaseDir;
  if (e.SquaredNorm() == 0) return;
  const StarQuadratic q = sodtQuadratic(star, pr.normal);
  Vec3 p;
  if (!minimizeOnLine(q, Vec3(0, 0, 0), e, p)) return;
  pr.target = star.center + p;
  pr.fallback = star.center + e * ((centroid - star.center) * e);
  pr.ok = isFinite(pr.target);
}

/// Algorithm 3's smooth vertex (Sec. 2.5): the S-ODT minimiser on its
/// fitted plane, at most lim along the plane's normal (denoiseTargets).
inline void fittedPlaneMove(const Star& star, const FittedFrame& plane, double lim, Proposal& pr) {
  pr.ok = denoiseTargets(star, plane.point, plane.dir, lim, pr.target, pr.fallback);
}

/// Algorithm 3's crease vertex: the S-ODT minimiser on its fitted crease
/// line, and the ring centroid projected on the line, each moved back to
/// within lim of the line's direction through the vertex.
inline void fittedLineMove(const Star& star, const FittedFrame& line, double lim, Proposal& pr) {
  const Vec3 centroid = ringCentroid(star);
  const StarQuadratic q = sodtQuadratic(star, pr.normal);
  const Vec3 p0 = line.point - star.center;
  Vec3 p;
  if (!minimizeOnLine(q, p0, line.dir, p)) return;
  pr.target = star.center + p;
  pr.fallback = line.point + line.dir * ((centroid - line.point) * line.dir);
  for (Vec3* x : {&pr.target, &pr.fallback}) {
    const Vec3 d = *x - star.center;
    const Vec3 across = d - line.dir * (d * line.dir);
    const double h = across.Norm();
    if (h > lim) *x -= across * (1 - lim / h);
  }
  pr.ok = isFinite(pr.target) && isFinite(pr.fallback);
}

/// Where the run's algorithm wants vertex i, the centre of star, to go:
/// the move of its class (smooth, crease) and algorithm. Not ok for a
/// degenerate star, a failed solve, or a vertex that has no move (corners).
inline Proposal propose(const MoveInputs& c, int i, const Star& star) {
  Proposal pr;
  pr.normal = starNormal(star);
  if (pr.normal.SquaredNorm() == 0 || star.size() < 3) return pr;
  const VertexClass vc = c.cls.cls[i];
  const bool fitted = c.p.algorithm == Algorithm::Denoise && c.fit[i].ok;
  if (vc != VertexClass::Crease && !fitted) {
    smoothMove(c.p.algorithm, star, pr);  // the hot path
  } else if (fitted) {
    const double lim = c.p.maxNormalStepRel * c.meanEdge;
    if (vc == VertexClass::Smooth)
      fittedPlaneMove(star, c.fit[i], lim, pr);
    else
      fittedLineMove(star, c.fit[i], lim, pr);
  } else {
    creaseMove(star, c.meanEdge, c.p.epsilon, c.p.eta, pr);
  }
  return pr;
}

}  // namespace sodt
