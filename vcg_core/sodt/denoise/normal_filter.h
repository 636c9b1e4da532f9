// SPDX-License-Identifier: GPL-3.0-or-later
// The first stage of Algorithm::Filtered: feature-preserving filtering of
// the face normals (a bilateral filter whose range weights compare guidance
// normals, after Zheng et al. 2011 and Zhang et al. 2015), then vertex
// updates that make the faces follow the filtered normals, under a fold
// guard. filter_select.h decides how many rounds run; the S-ODT sweeps
// that follow (smoother.h) then improve the triangles on the denoised
// surface.
#pragma once

#include "../maths/geometry.h"
#include "../params.h"
#include "../maths/topology.h"

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

/// A vertex with more faces than this lends a face's patch only the
/// kFilterWindow faces of its star around that face (as the deviation
/// guard's windows do, deviation.h), so that a patch never grows with the
/// valence: a vertex of valence n would otherwise put n faces in each of
/// its n faces' patches, n^2 in all, and the filter's patch measures are
/// quadratic in the patch size. The stars of the bundled and shared meshes
/// have at most 22 faces; the window changes nothing there.
constexpr int kFilterWindow = 24;

/// The faces around each face: every face sharing a vertex with it (itself
/// included), from a vertex with more than kFilterWindow faces only the
/// window of them around the face, and its up to three neighbours across
/// an edge.
struct FaceNeighbourhoods {
  std::vector<int> begin, idx;           ///< vertex-sharing neighbours of face f: idx[begin[f] .. begin[f+1])
  std::vector<std::array<int, 3>> edge;  ///< the face across each edge (the first by index when several), or -1

  void build(const FaceList& faces, int nv) {
    const int nf = static_cast<int>(faces.tri.size());
    IncidentFaces inc(faces, nv);  // faces of each vertex; large stars reordered around the vertex
    std::vector<int> at(3 * static_cast<std::size_t>(nf), -1), chainBegin, chainEnd;
    orderLargeStars(faces, nv, inc, at, chainBegin, chainEnd);
    begin.assign(nf + 1, 0);
    idx.clear();
    std::vector<int> around;
    for (int f = 0; f < nf; ++f) {
      begin[f] = static_cast<int>(idx.size());
      if (!faces.live[f]) continue;
      around.clear();
      for (int j = 0; j < 3; ++j) {
        const int v = faces.tri[f][j];
        int b = inc.begin[v], e = inc.begin[v + 1];
        const int k = at[3 * static_cast<std::size_t>(f) + j];
        if (e - b > kFilterWindow && k >= 0) {
          window(k, chainBegin[k], chainEnd[k], inc.face, around);
          continue;
        }
        around.insert(around.end(), inc.face.begin() + b, inc.face.begin() + e);
      }
      std::sort(around.begin(), around.end());
      around.erase(std::unique(around.begin(), around.end()), around.end());
      idx.insert(idx.end(), around.begin(), around.end());
    }
    begin[nf] = static_cast<int>(idx.size());
    acrossEdges(faces);
  }

 private:
  /// The kFilterWindow faces of a chain [cb, ce) of a star's faces around
  /// position k, wrapping round a closed chain (cb < 0 marks one: -cb - 1
  /// is its start), shifted to fit in an open one.
  static void window(int k, int cb, int ce, const std::vector<int>& face, std::vector<int>& out) {
    const int w = kFilterWindow;
    if (cb < 0) {
      cb = -cb - 1;
      const int len = ce - cb;
      for (int d = -w / 2; d < w - w / 2; ++d) out.push_back(face[cb + ((k - cb + d) % len + len) % len]);
      return;
    }
    const int first = std::max(cb, std::min(k - w / 2, ce - w));
    for (int q = first; q < std::min(first + w, ce); ++q) out.push_back(face[q]);
  }

  /// Reorders the faces of every star larger than kFilterWindow into
  /// chains around its vertex (face (v, x, y) is followed by the face
  /// (v, y, z)); at[3 f + j] gets the position of face f in the star of its
  /// corner j, chainBegin and chainEnd (indexed by position) the chain's
  /// range, chainBegin as -start - 1 for a closed chain. Faces that do
  /// not chain (non-manifold or inconsistently wound stars) form chains of
  /// their own.
  static void orderLargeStars(const FaceList& faces, int nv, IncidentFaces& inc, std::vector<int>& at,
                              std::vector<int>& chainBegin, std::vector<int>& chainEnd) {
    chainBegin.assign(inc.face.size(), 0);
    chainEnd.assign(inc.face.size(), 0);
    std::vector<std::pair<int, int>> byFirst;  // (x, local face) of the faces (v, x, y)
    std::vector<int> ordered, second;
    std::vector<char> used;
    for (int v = 0; v < nv; ++v) {
      const int b = inc.begin[v], n = inc.begin[v + 1] - b;
      if (n <= kFilterWindow) continue;
      byFirst.clear();
      second.assign(n, -1);
      for (int l = 0; l < n; ++l) {
        const std::array<int, 3>& t = faces.tri[inc.face[b + l]];
        const int j = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        byFirst.push_back({t[(j + 1) % 3], l});
        second[l] = t[(j + 2) % 3];
      }
      std::sort(byFirst.begin(), byFirst.end());
      const auto successor = [&](int l) {  // the one face (v, second[l], z), or -1
        const auto r = std::equal_range(byFirst.begin(), byFirst.end(), std::make_pair(second[l], -1),
                                        [](const std::pair<int, int>& p, const std::pair<int, int>& q) {
                                          return p.first < q.first;
                                        });
        return r.second - r.first == 1 ? r.first->second : -1;
      };
      std::vector<int> next(n), prevCount(n, 0);
      for (int l = 0; l < n; ++l) {
        next[l] = successor(l);
        if (next[l] >= 0) ++prevCount[next[l]];
      }
      ordered.clear();
      used.assign(n, 0);
      const auto chainFrom = [&](int l, bool closedIfBack) {
        const int start = static_cast<int>(ordered.size());
        bool closed = false;
        for (int cur = l;;) {
          used[cur] = 1;
          ordered.push_back(cur);
          const int nx = next[cur];
          if (nx < 0 || used[nx] || prevCount[nx] != 1) {
            closed = closedIfBack && nx == l;
            break;
          }
          cur = nx;
        }
        for (int q = start; q < static_cast<int>(ordered.size()); ++q) {
          chainBegin[b + q] = closed ? -(b + start) - 1 : b + start;
          chainEnd[b + q] = b + static_cast<int>(ordered.size());
        }
      };
      for (int l = 0; l < n; ++l)  // open chains from their first face
        if (!used[l] && prevCount[l] != 1) chainFrom(l, false);
      for (int l = 0; l < n; ++l)  // the rest are cycles
        if (!used[l]) chainFrom(l, true);
      std::vector<int> faceOf(n);
      for (int q = 0; q < n; ++q) faceOf[q] = inc.face[b + ordered[q]];
      for (int q = 0; q < n; ++q) {
        const int f = faceOf[q];
        inc.face[b + q] = f;
        for (int j = 0; j < 3; ++j)
          if (faces.tri[f][j] == v) at[3 * static_cast<std::size_t>(f) + j] = b + q;
      }
    }
  }

  /// edge[f][k]: the face with the smallest index other than f with both
  /// ends of f's edge (t[k], t[k+1]), from one sort of all edges.
  void acrossEdges(const FaceList& faces) {
    const int nf = static_cast<int>(faces.tri.size());
    edge.assign(nf, {-1, -1, -1});
    std::vector<std::array<int, 4>> e;  // (low, high, face, k)
    for (int f = 0; f < nf; ++f) {
      if (!faces.live[f]) continue;
      const std::array<int, 3>& t = faces.tri[f];
      for (int k = 0; k < 3; ++k)
        e.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]), f, k});
    }
    std::sort(e.begin(), e.end());
    for (std::size_t r = 0; r < e.size();) {
      std::size_t s = r + 1;
      while (s < e.size() && e[s][0] == e[r][0] && e[s][1] == e[r][1]) ++s;
      for (std::size_t q = r; q < s; ++q) {
        const int f = e[q][2];
        for (std::size_t u = r; u < s && edge[f][e[q][3]] < 0; ++u)
          if (e[u][2] != f) edge[f][e[q][3]] = e[u][2];
      }
      r = s;
    }
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
