// SPDX-License-Identifier: GPL-3.0-or-later
// The first stage of Algorithm::Filtered: feature-preserving filtering of
// the face normals (a bilateral filter whose range weights compare guidance
// normals, after Zheng et al. 2011 and Zhang et al. 2015), then vertex
// updates that make the faces follow the filtered normals, under a fold
// guard. filter_select.h decides how many rounds run; the S-ODT sweeps
// that follow (smoother.h) then improve the triangles on the denoised
// surface.
#pragma once

#include "geometry.h"
#include "params.h"
#include "topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace sodt {

/// Filtering passes over the face normals per round of the normal filter
/// (how many rounds run is chosen per mesh, see filter_select.h).
constexpr int kNormalPasses = 5;
/// Vertex-update iterations per round.
constexpr int kVertexPasses = 10;
/// A vertex update may leave a face's smallest angle below this only where
/// it already was, and never lower than before. Without it the updates
/// squeeze faces near the corners of noisy CAD parts into slivers whose
/// normals flip with a tiny move, and the sweeps' guards, which take those
/// normals as the surface's orientation, cannot unfold them (a cube with
/// noise of half an edge: smallest angle 0.3 degrees without, 22.6 with).
constexpr double kFilterAngleFloorDeg = 10.0;
/// Share of the tangential Laplacian step added to the vertex update of a
/// vertex whose faces' target normals all lie within half the feature
/// angle of their mean: it keeps the triangles from degenerating while the
/// vertices follow the normals.
constexpr double kTangentialStep = 0.5;

/// The face normals, areas, centroids of the live faces at pos (zero for
/// dead or degenerate faces).
struct FaceFrame {
  std::vector<Vec3> normal, centroid;
  std::vector<double> area;

  void compute(const FaceList& faces, const std::vector<Vec3>& pos) {
    const std::size_t nf = faces.tri.size();
    normal.assign(nf, Vec3(0, 0, 0));
    centroid.assign(nf, Vec3(0, 0, 0));
    area.assign(nf, 0.0);
    for (std::size_t f = 0; f < nf; ++f) {
      if (!faces.live[f]) continue;
      const std::array<int, 3>& t = faces.tri[f];
      const Vec3 a = doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]);
      const double len = a.Norm();
      centroid[f] = (pos[t[0]] + pos[t[1]] + pos[t[2]]) / 3.0;
      if (len > 0 && std::isfinite(len)) {
        normal[f] = a / len;
        area[f] = 0.5 * len;
      }
    }
  }
};

/// The faces around each face: every face sharing a vertex with it (itself
/// included), and its up to three neighbours across an edge.
struct FaceNeighbourhoods {
  std::vector<int> begin, idx;           ///< vertex-sharing neighbours of face f: idx[begin[f] .. begin[f+1])
  std::vector<std::array<int, 3>> edge;  ///< the face across each edge, or -1

  void build(const FaceList& faces, int nv) {
    const int nf = static_cast<int>(faces.tri.size());
    const IncidentFaces inc(faces, nv);  // faces of each vertex
    const std::vector<int>& vb = inc.begin;
    const std::vector<int>& vf = inc.face;
    begin.assign(nf + 1, 0);
    idx.clear();
    edge.assign(nf, {-1, -1, -1});
    std::vector<int> around;
    for (int f = 0; f < nf; ++f) {
      begin[f] = static_cast<int>(idx.size());
      if (!faces.live[f]) continue;
      around.clear();
      for (int v : faces.tri[f]) around.insert(around.end(), vf.begin() + vb[v], vf.begin() + vb[v + 1]);
      std::sort(around.begin(), around.end());
      around.erase(std::unique(around.begin(), around.end()), around.end());
      idx.insert(idx.end(), around.begin(), around.end());
      // Neighbours across edge (t[k], t[k+1]): faces with both vertices.
      const std::array<int, 3>& t = faces.tri[f];
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3];
        for (int g : around) {
          if (g == f) continue;
          const std::array<int, 3>& u = faces.tri[g];
          const bool hasA = u[0] == a || u[1] == a || u[2] == a, hasB = u[0] == b || u[1] == b || u[2] == b;
          if (hasA && hasB) {
            edge[f][k] = g;
            break;
          }
        }
      }
    }
    begin[nf] = static_cast<int>(idx.size());
  }
};

/// Settings of the normal filter, all derived from the mesh and the
/// user's feature angle (see NormalFilterRounds).
struct NormalFilterSettings {
  double sigmaSpatial = 0;  ///< of the Gaussian of centroid distances
  double sigmaRange = 0;    ///< of the Gaussian of guidance-normal differences
  int normalPasses = kNormalPasses, vertexPasses = kVertexPasses;
};

namespace detail {

/// How consistent the normals of a patch (the faces around a face) are,
/// after Zhang et al. 2015: the largest normal difference within the patch
/// times the largest normal difference across one of its inner edges over
/// the sum of those. Small for flat patches, and for patches a single
/// sharp edge crosses less than for those that straddle noise everywhere.
inline double patchInconsistency(const FaceNeighbourhoods& nb, const std::vector<Vec3>& n, int f) {
  const int b = nb.begin[f], e = nb.begin[f + 1];
  double spread = 0;
  for (int a = b; a < e; ++a)
    for (int c = a + 1; c < e; ++c) spread = std::max(spread, (n[nb.idx[a]] - n[nb.idx[c]]).Norm());
  double largest = 0, sum = 0;
  for (int a = b; a < e; ++a) {
    const int g = nb.idx[a];
    for (int h : nb.edge[g]) {
      if (h <= g || !std::binary_search(nb.idx.begin() + b, nb.idx.begin() + e, h)) continue;
      const double d = (n[g] - n[h]).Norm();
      largest = std::max(largest, d);
      sum += d;
    }
  }
  return spread * largest / (1e-9 + sum);
}

}  // namespace detail

/// One pass of the guided bilateral filter: each face's normal becomes the
/// normalised sum over the faces around it of A_j Ws(|c_i - c_j|)
/// Wr(|g_i - g_j|) n_j, where g is the guidance normal of a face: the
/// area-weighted mean normal of the most consistent patch among those that
/// contain the face.
inline std::vector<Vec3> filterNormalsOnce(const FaceNeighbourhoods& nb, const FaceFrame& fr,
                                           const std::vector<Vec3>& n, const NormalFilterSettings& s,
                                           int threads) {
  const long nf = static_cast<long>(n.size());
  std::vector<double> h(nf, 0.0);
  std::vector<Vec3> mean(nf, Vec3(0, 0, 0));
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
#else
  (void)threads;
#endif
  for (long f = 0; f < nf; ++f) {
    if (nb.begin[f] == nb.begin[f + 1]) continue;
    h[f] = detail::patchInconsistency(nb, n, static_cast<int>(f));
    Vec3 m(0, 0, 0);
    for (int a = nb.begin[f]; a < nb.begin[f + 1]; ++a) m += n[nb.idx[a]] * fr.area[nb.idx[a]];
    const double len = m.Norm();
    mean[f] = len > 0 ? m / len : Vec3(0, 0, 0);
  }
  std::vector<Vec3> guide(nf, Vec3(0, 0, 0));
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
#endif
  for (long f = 0; f < nf; ++f) {
    double best = 0;
    int arg = -1;
    for (int a = nb.begin[f]; a < nb.begin[f + 1]; ++a) {
      const int g = nb.idx[a];
      if (arg < 0 || h[g] < best) {
        best = h[g];
        arg = g;
      }
    }
    if (arg >= 0) guide[f] = mean[arg];
  }
  const double ks = 1.0 / (2 * s.sigmaSpatial * s.sigmaSpatial), kr = 1.0 / (2 * s.sigmaRange * s.sigmaRange);
  std::vector<Vec3> out(n);
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
#endif
  for (long f = 0; f < nf; ++f) {
    Vec3 sum(0, 0, 0);
    for (int a = nb.begin[f]; a < nb.begin[f + 1]; ++a) {
      const int g = nb.idx[a];
      const double w = fr.area[g] * std::exp(-(fr.centroid[f] - fr.centroid[g]).SquaredNorm() * ks -
                                             (guide[f] - guide[g]).SquaredNorm() * kr);
      sum += n[g] * w;
    }
    const double len = sum.Norm();
    if (len > 0 && std::isfinite(len)) out[f] = sum / len;
  }
  return out;
}

/// Moves the movable vertices so that their faces follow the target
/// normals t (Gauss-Seidel, passes times): x_i += 1/|F_i| sum_f t_f (t_f .
/// (c_f - x_i)) over the faces f of x_i with centroids c_f; where all
/// t_f lie within acos(flatCos) of their mean m, plus tangential times the
/// part of (mean of the c_f - x_i) orthogonal to m. A step that
/// would turn one of the vertex's faces against its target normal (or
/// further against it than before), or take a face's smallest angle below
/// both its current one and kFilterAngleFloorDeg, is halved, up to four
/// times, then dropped: no face inverts or turns into a sliver.
inline void matchNormals(const FaceList& faces, const std::vector<int>& vb, const std::vector<int>& vf,
                         const std::vector<Vec3>& t, const std::vector<char>& movable, int passes,
                         double tangential, double flatCos, std::vector<Vec3>& pos) {
  const int nv = static_cast<int>(pos.size());
  auto centroid = [&](int f) {
    const std::array<int, 3>& u = faces.tri[f];
    return (pos[u[0]] + pos[u[1]] + pos[u[2]]) / 3.0;
  };
  auto facing = [&](int f) {
    const std::array<int, 3>& u = faces.tri[f];
    return doubleAreaVector(pos[u[0]], pos[u[1]], pos[u[2]]) * t[f];
  };
  // Smallest angles as squared cosines (larger: smaller angle).
  auto minAngleCos2 = [&](int f) {
    const std::array<int, 3>& u = faces.tri[f];
    return triangleMinAngleCos2(pos[u[0]], pos[u[1]], pos[u[2]]);
  };
  const double floorCos = std::cos(kFilterAngleFloorDeg * kPi / 180), floorCos2 = floorCos * floorCos;
  std::vector<double> before, beforeCos2;
  for (int pass = 0; pass < passes; ++pass) {
    for (int i = 0; i < nv; ++i) {
      if (!movable[i] || vb[i] == vb[i + 1]) continue;
      Vec3 d(0, 0, 0);
      for (int k = vb[i]; k < vb[i + 1]; ++k) {
        const int f = vf[k];
        d += t[f] * (t[f] * (centroid(f) - pos[i]));
      }
      d /= double(vb[i + 1] - vb[i]);
      if (tangential > 0) {
        Vec3 m(0, 0, 0), c(0, 0, 0);
        for (int k = vb[i]; k < vb[i + 1]; ++k) {
          m += t[vf[k]];
          c += centroid(vf[k]);
        }
        const double len = m.Norm();
        bool flat = len > 0;
        if (flat) m /= len;
        for (int k = vb[i]; k < vb[i + 1] && flat; ++k) flat = t[vf[k]] * m >= flatCos;
        if (flat) {
          const Vec3 l = c / double(vb[i + 1] - vb[i]) - pos[i];
          d += (l - m * (m * l)) * tangential;
        }
      }
      if (!isFinite(d)) continue;
      before.clear();
      beforeCos2.clear();
      for (int k = vb[i]; k < vb[i + 1]; ++k) {
        before.push_back(facing(vf[k]));
        beforeCos2.push_back(std::max(minAngleCos2(vf[k]), floorCos2));
      }
      const Vec3 x0 = pos[i];
      bool ok = false;
      for (int half = 0; half <= 4 && !ok; ++half, d /= 2.0) {
        pos[i] = x0 + d;
        ok = true;
        for (int k = vb[i]; k < vb[i + 1] && ok; ++k) {
          const double now = facing(vf[k]), was = before[k - vb[i]];
          ok = (now > 0 || (was <= 0 && now >= was)) && !(minAngleCos2(vf[k]) > beforeCos2[k - vb[i]]);
        }
      }
      if (!ok) pos[i] = x0;
    }
  }
}

/// Rounds of guided bilateral filtering of the face normals (each round
/// starts from the current faces) followed by vertex updates towards the
/// filtered normals. Only vertices marked movable move. The settings come
/// from the positions given at construction: the spatial sigma is the mean
/// distance between the centroids of faces sharing an edge; the range
/// sigma is the difference of two unit normals half the feature angle
/// apart, 2 sin(angle / 4): guidance normals the feature angle apart mix
/// with weight exp(-2) or less.
class NormalFilterRounds {
 public:
  NormalFilterRounds(const FaceList& faces, const std::vector<char>& movable, double featureAngleDeg,
                     const std::vector<Vec3>& pos, int threads)
      : faces_(faces), movable_(movable), inc_(faces, static_cast<int>(pos.size())), threads_(threads),
        flatCos_(std::cos(featureAngleDeg * kPi / 360.0)) {
    nb_.build(faces, static_cast<int>(pos.size()));
    FaceFrame fr;
    fr.compute(faces, pos);
    double dsum = 0;
    long long dcnt = 0;
    for (std::size_t f = 0; f < faces.tri.size(); ++f)
      for (int g : nb_.edge[f])
        if (g > static_cast<int>(f)) {
          dsum += (fr.centroid[f] - fr.centroid[g]).Norm();
          ++dcnt;
        }
    s_.sigmaSpatial = dcnt ? dsum / double(dcnt) : 0.0;
    s_.sigmaRange = 2 * std::sin(std::min(std::max(featureAngleDeg, 1.0), 180.0) * kPi / 720.0);
  }

  const NormalFilterSettings& settings() const { return s_; }
  /// False when the mesh has no two faces sharing an edge at a distance:
  /// rounds would change nothing.
  bool usable() const { return s_.sigmaSpatial > 0; }

  /// One round on pos.
  void round(std::vector<Vec3>& pos) const {
    if (!usable()) return;
    FaceFrame fr;
    fr.compute(faces_, pos);
    std::vector<Vec3> n = fr.normal;
    for (int pass = 0; pass < s_.normalPasses; ++pass) n = filterNormalsOnce(nb_, fr, n, s_, threads_);
    matchNormals(faces_, inc_.begin, inc_.face, n, movable_, s_.vertexPasses, kTangentialStep, flatCos_, pos);
  }

 private:
  const FaceList& faces_;
  const std::vector<char>& movable_;
  FaceNeighbourhoods nb_;
  IncidentFaces inc_;
  NormalFilterSettings s_;
  int threads_;
  double flatCos_;
};

}  // namespace sodt
