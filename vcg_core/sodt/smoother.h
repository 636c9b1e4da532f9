// SPDX-License-Identifier: GPL-3.0-or-later
// Gauss-Seidel S-ODT sweeps over a vcg triangle mesh (paper Algorithm 1), with
// the fold / quality safeguards applied to every move before it is committed.
#pragma once

#include "local_solve.h"
#include "params.h"
#include "topology.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/complex.h>
#include <wrap/callback.h>

#include <string>
#include <vector>

namespace sodt {

/// Smooths a vcg triangle mesh in place with S-ODT.
template <class MeshType>
struct SodtSmoother {
  using ScalarType = typename MeshType::ScalarType;
  using CoordType = typename MeshType::CoordType;

  /// Runs p.iterations Gauss-Seidel sweeps of Algorithm 1 (paper Sec. 2.3).
  ///
  /// Each vertex with a closed, manifold one-ring moves in its tangent plane
  /// (Eq. 4) towards the closed-form minimiser of Eq. 5. The local solve is
  /// done in double; the committed position is the one representable in
  /// ScalarType, and that rounded position is what the guard checks. With
  /// Guard::None and a double mesh the enclosed volume of a closed mesh is
  /// kept to rounding (Appendix D). Boundary, non-manifold, isolated and
  /// deleted vertices never move; with p.selectedOnly only selected vertices
  /// move. Updates the bounding box, and face/vertex normals when present.
  ///
  /// \param m  mesh to smooth; needs per-vertex flags (deleted, selected).
  /// \param p  validated by this call.
  /// \param cb optional progress callback (0..100), called once per sweep;
  ///           returning false stops after the current sweep.
  /// \throw InvalidInput for bad parameters or a non-finite coordinate; the
  ///        mesh is untouched then.
  static SodtStats Apply(MeshType& m, const SodtParams& p, vcg::CallBackPos* cb = nullptr) {
    p.validate();
    SodtStats stats;
    const int nv = static_cast<int>(m.vert.size());
    std::vector<Vec3> pos(nv);
    for (int i = 0; i < nv; ++i) {
      if (m.vert[i].IsD()) continue;
      const CoordType& c = m.vert[i].cP();
      pos[i] = Vec3(c[0], c[1], c[2]);
      if (!isFinite(pos[i]))
        throw InvalidInput("vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
    const RingTopology topo = buildRingTopology(m);

    std::vector<int> active;
    for (int i = 0; i < nv; ++i) {
      switch (topo.kind[i]) {
        case VertexKind::Interior:
          if (!p.selectedOnly || m.vert[i].IsS()) active.push_back(i);
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
    if (p.guard != Guard::None) {
      faceNormal.assign(m.face.size(), Vec3(0, 0, 0));
      for (std::size_t f = 0; f < m.face.size(); ++f) {
        const auto& F = m.face[f];
        if (F.IsD()) continue;
        const auto vi = [&](int j) { return static_cast<int>(F.cV(j) - &m.vert[0]); };
        const Vec3 a = doubleAreaVector(pos[vi(0)], pos[vi(1)], pos[vi(2)]);
        const double len = a.Norm();
        if (len > 0 && std::isfinite(len)) faceNormal[f] = a / len;
      }
    }

    Star star;
    for (int it = 0; it < p.iterations && !active.empty(); ++it) {
      for (int i : active) {
        star.center = pos[i];
        star.ring.clear();
        star.refNormal.clear();
        for (int k = topo.ringBegin[i]; k < topo.ringBegin[i + 1]; ++k) {
          star.ring.push_back(pos[topo.ringIdx[k]]);
          if (!faceNormal.empty()) star.refNormal.push_back(faceNormal[topo.ringFace[k]]);
        }
        visitVertex(star, p, stats, pos[i]);
      }
      ++stats.iterations;
      if (cb && !cb(100 * (it + 1) / p.iterations,
                    ("S-ODT sweep " + std::to_string(it + 1) + "/" + std::to_string(p.iterations))
                        .c_str())) {
        stats.cancelled = true;
        break;
      }
    }

    for (int i : active)
      m.vert[i].P() = CoordType(ScalarType(pos[i][0]), ScalarType(pos[i][1]), ScalarType(pos[i][2]));
    vcg::tri::UpdateBounding<MeshType>::Box(m);
    if (vcg::tri::HasPerFaceNormal(m)) vcg::tri::UpdateNormal<MeshType>::PerFaceNormalized(m);
    if (vcg::tri::HasPerVertexNormal(m)) vcg::tri::UpdateNormal<MeshType>::PerVertexNormalizedPerFace(m);
    return stats;
  }

 private:
  /// Rounds a double position to what the mesh can store.
  static Vec3 representable(const Vec3& x) {
    return Vec3(double(ScalarType(x[0])), double(ScalarType(x[1])), double(ScalarType(x[2])));
  }

  /// Tries the step from the centre towards target, shortened by halvings,
  /// under the guard. Returns the number of halvings used, -1 when every
  /// length was vetoed, -2 when the step rounds to no move at all.
  static int tryStep(const Star& star, const Vec3& target, const Vec3& n, const SodtParams& p,
                     double minAngleCos2Before, Vec3& x) {
    const Vec3 step = target - star.center;
    double f = 1.0;
    for (int j = 0; j <= p.maxBacktracks; ++j, f *= 0.5) {
      const Vec3 y = representable(star.center + step * f);
      if (y == x) return j == 0 ? -2 : -1;  // shorter steps round to nothing as well
      if (moveFolds(star, y, n)) continue;
      if (p.guard == Guard::Quality && !starKeepsMinAngle(star, y, minAngleCos2Before)) continue;
      x = y;
      return j;
    }
    return -1;
  }

  /// Solves, guards and commits the move of one vertex into x.
  static void visitVertex(const Star& star, const SodtParams& p, SodtStats& stats, Vec3& x) {
    const LocalMove mv = solveStar(star);
    if (!mv.ok) {
      ++stats.failedSolves;
      return;
    }
    if (p.guard == Guard::None) {
      const Vec3 y = representable(mv.target);
      if (y == x) {
        ++stats.unchanged;
      } else {
        x = y;
        ++stats.moved;
      }
      return;
    }
    const double before = p.guard == Guard::Quality ? starMinAngleCos2(star, star.center) : 1.0;
    const int r = tryStep(star, mv.target, mv.normal, p, before, x);
    if (r == 0) {
      ++stats.moved;
      return;
    }
    if (r > 0) {
      ++stats.backtracked;
      return;
    }
    if (p.laplacianFallback) {
      const Vec3 lap = tangentialLaplacianTarget(star, mv.normal);
      if (tryStep(star, lap, mv.normal, p, before, x) >= 0) {
        ++stats.fallbackMoves;
        return;
      }
    }
    ++(r == -2 ? stats.unchanged : stats.rejected);
  }
};

}  // namespace sodt
