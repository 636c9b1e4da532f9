// SPDX-License-Identifier: GPL-3.0-or-later
// What a run fixes before its first sweep, from the input: the vertex
// classes, the vertices that move, the faces' input orientation, Algorithm
// 3's fitted planes and lines, and the input surface of the deviation bound.
#pragma once

#include "../maths/classify.h"
#include "../guards/deviation.h"
#include "../maths/fitting.h"
#include "../params.h"
#include "../maths/topology.h"

#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace sodt {

/// Projection passes that pre-smooth the input before the denoising planes are fitted.
constexpr int kDenoisePrePasses = 2;

/// Every interior vertex projected on its weighted least-squares plane
/// (Eq. 12-13) computed from the given positions; others unchanged.
inline std::vector<Vec3> projectOnFittedPlanes(const RingTopology& topo, const std::vector<Vec3>& pos, int threads) {
  const std::vector<Vec3> nrm = vertexNormals(topo, pos, threads);
  std::vector<Vec3> out = pos;
  forEachInterior(topo, threads, [&](int i) {
    const FittedFrame f = fitPlane(i, topo, pos, nrm);
    if (f.ok) out[i] = pos[i] - f.dir * ((pos[i] - f.point) * f.dir);
  });
  return out;
}

/// The classes the algorithm works with. Basic and the references have no
/// creases: every interior vertex is smooth. Feature classifies the input
/// (Eq. 9-10). Denoise classifies the input projected once on its fitted
/// planes, returned in projected: noise turns single spikes into false
/// corners and creases, and a vertex on a true crease or corner has too few
/// agreeing neighbours to fit and stays.
inline Classification classifyForAlgorithm(const SodtParams& p, const RingTopology& topo,
                                           const std::vector<Vec3>& pos, double meanEdge, int threads,
                                           std::vector<Vec3>& projected) {
  if (p.algorithm == Algorithm::Feature) return classifyRings(topo, pos, meanEdge, p.epsilon, p.eta, threads);
  if (p.algorithm == Algorithm::Denoise) {
    projected = projectOnFittedPlanes(topo, pos, threads);
    return classifyRings(topo, projected, meanEdge, p.epsilon, p.eta, threads);
  }
  Classification cls;
  cls.cls.assign(pos.size(), VertexClass::Fixed);  // no crease directions: there are no creases
  for (std::size_t i = 0; i < pos.size(); ++i) {
    if (topo.kind[i] == VertexKind::Deleted) continue;
    cls.cls[i] = topo.kind[i] == VertexKind::Interior ? VertexClass::Smooth : VertexClass::Fixed;
    ++cls.count[static_cast<int>(cls.cls[i])];
  }
  return cls;
}

/// The vertices the sweeps visit: interior, not corners, selected when
/// p.selectedOnly. Counts the fixed border and non-manifold ones in stats.
inline std::vector<int> activeVertices(const SodtParams& p, const RingTopology& topo, const Classification& cls,
                                       const std::vector<char>& selected, SodtStats& stats) {
  std::vector<int> active;
  for (std::size_t i = 0; i < topo.kind.size(); ++i) {
    switch (topo.kind[i]) {
      case VertexKind::Interior:
        if (cls.cls[i] != VertexClass::Corner && (!p.selectedOnly || selected[i])) active.push_back(int(i));
        break;
      case VertexKind::Boundary: ++stats.fixedBoundary; break;
      case VertexKind::NonManifold: ++stats.fixedNonManifold; break;
      default: break;
    }
  }
  stats.activeVertices = static_cast<int>(active.size());
  return active;
}

namespace detail {

/// The unit vector at most maxRad from the unit vector from, towards the
/// unit vector to, on the great circle through both.
inline Vec3 turnTowards(const Vec3& from, const Vec3& to, double maxRad) {
  if (!(angleBetween(from, to) > maxRad)) return to;
  Vec3 w = to - from * (from * to);
  const double len = w.Norm();
  if (!(len > 0)) return from;
  w /= len;
  const Vec3 r = from * std::cos(maxRad) + w * std::sin(maxRad);
  return r / r.Norm();
}

}  // namespace detail

/// The input orientation of every live face, as a unit normal (zero for
/// none): guarded moves keep each face within 90 degrees and maxTurnDeg
/// (SodtParams::maxFaceTurnDeg) of it, so no face ends up inverted however
/// far it drifts, nor turned into a sharp edge. A face's own normal,
/// except for slivers (smallest angle below kSliverNormalDeg) and
/// degenerate faces, whose own normal is noise: they get the mean normal
/// of the surface at their corners (the normalised sum of the area vectors
/// of the faces around its three vertices, where slivers weigh little), or
/// as near it as maxTurnDeg from their own normal allows, so that every
/// face starts within the bound and a sliver may still turn into the
/// surface. A sliver folded against that surface (normals more than 90
/// degrees apart) gets none: its input orientation is no reference for
/// either side; the fold test against its current orientation remains.
/// Without a bound (maxTurnDeg 90 or more) every face keeps its own normal,
/// as the fold test always had it: the Denoise runs on bunny_closed lose
/// most of their smallest angle with the slivers' references replaced.
inline std::vector<Vec3> faceNormals(const FaceList& faces, const std::vector<Vec3>& pos, double maxTurnDeg = 90) {
  std::vector<Vec3> normal(faces.tri.size(), Vec3(0, 0, 0));
  std::vector<Vec3> around;  // vertexAreaSums, when a sliver needs it
  const double sliverRad = kSliverNormalDeg * kPi / 180.0;
  const double turnRad = std::min(maxTurnDeg, 90.0) * kPi / 180.0;
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    const std::array<int, 3>& t = faces.tri[f];
    const Vec3 a = doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]);
    const double len = a.Norm();
    const bool own = len > 0 && std::isfinite(len);
    if (own && (!(maxTurnDeg < 90) || triangleMinAngle(pos[t[0]], pos[t[1]], pos[t[2]]) >= sliverRad)) {
      normal[f] = a / len;
      continue;
    }
    if (around.empty()) around = vertexAreaSums(faces, pos);
    const Vec3 mean = around[t[0]] + around[t[1]] + around[t[2]];
    const double m = mean.Norm();
    if (!(maxTurnDeg < 90) || !(m > 0 && std::isfinite(m)))
      normal[f] = own ? a / len : Vec3(0, 0, 0);
    else if (!own)
      normal[f] = mean / m;
    else if (!(mean * a < 0))
      normal[f] = detail::turnTowards(a / len, mean / m, turnRad);
  }
  return normal;
}

/// Algorithm 3's fitted plane (smooth vertices) or crease line (crease
/// vertices) of every active vertex, from the input pos; projected is the
/// input projected once on its planes (classifyForAlgorithm), consumed.
/// Planes are fitted to the input after kDenoisePrePasses projection
/// passes: a plane fitted to raw noisy neighbours keeps about half the
/// noise, one fitted to pre-smoothed neighbours much less. Crease lines use
/// the input, whose crease vertices the projections leave (nearly) in place
/// anyway.
inline std::vector<FittedFrame> fitDenoiseFrames(const RingTopology& topo, const std::vector<Vec3>& pos,
                                                 std::vector<Vec3>&& projected, const Classification& cls,
                                                 const std::vector<int>& active, int threads) {
  std::vector<FittedFrame> fit(pos.size());
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
  return fit;
}

/// The input surface as the deviation guard reads it. Flips change the
/// working connectivity, so only then does it keep copies of the input's.
/// Not copyable: the InputSurface points into it.
struct DeviationInput {
  DeviationInput() = default;
  DeviationInput(const DeviationInput&) = delete;
  DeviationInput& operator=(const DeviationInput&) = delete;

  /// True when the run has the deviation bound: a guard, an algorithm that
  /// stays on the input (not Denoise) and a bound.
  static bool applies(const SodtParams& p) {
    return p.guard != Guard::None && p.algorithm != Algorithm::Denoise && p.maxDeviationRel > 0;
  }

  /// Takes the input (the working mesh before the first sweep); a no-op
  /// when the run has no bound.
  void prepare(const SodtParams& p, const std::vector<Vec3>& pos, const RingTopology& topo, const FaceList& faces) {
    if (!applies(p)) return;
    pos0 = pos;
    if (p.flips) {
      topo0 = topo;
      faces0 = faces;
    }
    surface.faces = p.flips ? &faces0 : &faces;
    surface.topo = p.flips ? &topo0 : &topo;
    surface.pos = &pos0;
    surface.prepare(p.maxDeviationRel * surfaceDiagonal(pos, topo));
    on = true;
  }

  /// The guard's view, or null without a bound.
  const InputSurface* get() const { return on ? &surface : nullptr; }

 private:
  std::vector<Vec3> pos0;
  RingTopology topo0;
  FaceList faces0;
  InputSurface surface;
  bool on = false;
};

}  // namespace sodt
