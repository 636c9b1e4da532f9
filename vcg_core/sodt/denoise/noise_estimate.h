// SPDX-License-Identifier: GPL-3.0-or-later
// How noisy a mesh is, in mean edge lengths: each sampled interior vertex
// is predicted from a quadric height field fitted to its two-ring without
// it, and the robust spread of the prediction errors estimates the noise's
// standard deviation along the normals. A quadric follows curvature, so on
// a clean coarse torus (16 segments around its tube) its errors alone read
// 0.04 mean edges, while normal noise of sigma s edges reads about s. It
// does not follow a sharp edge, and on a clean CAD export most vertices lie
// on one (the flat sides between them have no vertices inside): a vertex
// whose faces lie flat in pairs reads as clean without a fit.
#pragma once

#include "../maths/geometry.h"
#include "../maths/topology.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace sodt {

/// Below this many mean edges the input counts as nearly noise-free: the
/// denoisers then mostly smooth its shape (spot reads 0.015, the bunny
/// 0.022, clean CAD exports 0-0.004; normal noise of 0.1 edges reads
/// 0.10-0.13).
constexpr double kLittleNoiseEdges = 0.05;

/// At most this many vertices are sampled (evenly over the vertex order).
constexpr int kNoiseSamples = 20000;
/// A vertex whose two-ring spans more faces than this (its own and its
/// neighbours' faces, counted with repeats) is not sampled: each sample
/// then costs a bounded amount, so a vertex of valence n, which lies in the
/// two-ring of each of its n neighbours, costs O(n) and not O(n^2 log n).
/// On ordinary meshes a two-ring spans 30-60 faces and never reaches it; a
/// neighbour of a 360-valence cylinder cap centre is still sampled.
constexpr int kNoiseMaxTwoRingFaces = 1024;

/// A vertex with this many edges whose two faces are coplanar (within
/// kNoiseFlatPairDeg) reads as clean: the faces (x, w, a) and (x, w, b)
/// are coplanar only when x lies in the plane of its neighbours w, a and
/// b, and noise along the normals takes it out of that plane. On a clean
/// CAD export nearly every vertex has two such edges, on the flat sides
/// or the flat strips of a cylinder meeting at it; on the noise
/// benchmark's meshes with noise of 0.1 mean edges or more, at most 1.4%
/// of the vertices have.
constexpr int kNoiseFlatPairs = 2;
constexpr double kNoiseFlatPairDeg = 0.5;

struct NoiseEstimate {
  double sigmaEdges = std::numeric_limits<double>::quiet_NaN();  ///< NaN: too few usable vertices
  int samples = 0;                                                ///< vertices whose prediction counted
};

namespace detail {

/// The prediction errors of single vertices, for estimateNoise: fits on
/// two-rings gathered from the live faces around each vertex.
template <class PosFn>
class NoiseProbe {
 public:
  NoiseProbe(const FaceList& faces, int nv, PosFn pos) : faces_(faces), inc_(faces, nv), pos_(pos) {}

  /// The error of predicting vertex i from its two-ring without it (see
  /// estimateNoise), in units of `length`; negative when i is passed over.
  double error(int i, double length) {
    const std::vector<int>& vb = inc_.begin;
    ring1_.clear();
    if (vb[i] == vb[i + 1] || vb[i + 1] - vb[i] > kNoiseMaxTwoRingFaces || !ring(i, ring1_)) return -1;
    if (liesFlat(i)) return 0;
    long long spanned = vb[i + 1] - vb[i];
    for (int j : ring1_) spanned += vb[j + 1] - vb[j];
    if (spanned > kNoiseMaxTwoRingFaces) return -1;
    ring2_ = ring1_;
    for (int j : ring1_) ring(j, ring2_);
    std::sort(ring2_.begin(), ring2_.end());
    ring2_.erase(std::unique(ring2_.begin(), ring2_.end()), ring2_.end());
    ring2_.erase(std::remove(ring2_.begin(), ring2_.end(), i), ring2_.end());
    const int n = static_cast<int>(ring2_.size());
    if (n < 9) return -1;
    // The frame: the plane of the neighbours (least-variance direction).
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int j : ring2_) c += at(j);
    c /= n;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int j : ring2_) {
      const Eigen::Vector3d d = at(j) - c;
      cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d nrm = es.eigenvectors().col(0), u = es.eigenvectors().col(2), v = es.eigenvectors().col(1);
    // Height field z = a + bx + cy + dx^2 + exy + fy^2 around x_i, in
    // units of length; the prediction error at x_i is |a|.
    const Eigen::Vector3d xi = at(i);
    Eigen::MatrixXd A(n, 6);
    Eigen::VectorXd z(n);
    for (int r = 0; r < n; ++r) {
      const Eigen::Vector3d d = (at(ring2_[r]) - xi) / length;
      const double x = d.dot(u), y = d.dot(v);
      A.row(r) << 1.0, x, y, x * x, x * y, y * y;
      z[r] = d.dot(nrm);
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    if (qr.rank() < 6) return -1;
    const double a = qr.solve(z)[0];
    // The fitted quadric's own noise adds to the error at x_i: its
    // variance at the prediction point is s^2 (A^T A)^-1_00 for noise s at
    // the neighbours, so the error's variance is s^2 (1 + that).
    const Eigen::Matrix<double, 6, 6> ata = A.transpose() * A;
    const double lever = ata.inverse()(0, 0);
    if (!std::isfinite(a) || !std::isfinite(lever) || lever < 0) return -1;
    return std::abs(a) / std::sqrt(1 + lever);
  }

 private:
  Eigen::Vector3d at(int j) const {
    const Vec3 p = pos_(j);
    return Eigen::Vector3d(p[0], p[1], p[2]);
  }

  /// The one-ring of v appended to nb; false unless every neighbour is in
  /// exactly two of v's faces (an interior vertex of a manifold).
  bool ring(int v, std::vector<int>& nb) {
    pairs_.clear();
    for (int k = inc_.begin[v]; k < inc_.begin[v + 1]; ++k)
      for (int w : faces_.tri[inc_.face[k]])
        if (w != v) pairs_.push_back(w);
    std::sort(pairs_.begin(), pairs_.end());
    bool closed = !pairs_.empty();
    for (std::size_t a = 0; a < pairs_.size(); a += 2)
      closed = closed && a + 1 < pairs_.size() && pairs_[a] == pairs_[a + 1] &&
               (a + 2 >= pairs_.size() || pairs_[a + 2] != pairs_[a]);
    pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
    nb.insert(nb.end(), pairs_.begin(), pairs_.end());
    return closed;
  }

  /// True when kNoiseFlatPairs of the edges of i (whose fan is closed)
  /// have coplanar faces.
  bool liesFlat(int i) {
    static const double flatCos = std::cos(kNoiseFlatPairDeg * kPi / 180.0);
    normal_.clear();
    edge_.clear();
    for (int k = inc_.begin[i]; k < inc_.begin[i + 1]; ++k) {
      const std::array<int, 3>& t = faces_.tri[inc_.face[k]];
      const Vec3 a = doubleAreaVector(pos_(t[0]), pos_(t[1]), pos_(t[2]));
      const double len = a.Norm();
      normal_.push_back(len > 0 && std::isfinite(len) ? a / len : Vec3(0, 0, 0));
      for (int w : t)
        if (w != i) edge_.emplace_back(w, static_cast<int>(normal_.size()) - 1);
    }
    // Every neighbour is in exactly two faces (a closed fan): after
    // sorting, the two faces of edge (i, w) are side by side.
    std::sort(edge_.begin(), edge_.end());
    int flat = 0;
    for (std::size_t e = 0; e + 1 < edge_.size(); e += 2)
      if (normal_[edge_[e].second] * normal_[edge_[e + 1].second] >= flatCos) ++flat;
    return flat >= kNoiseFlatPairs;
  }

  const FaceList& faces_;
  const IncidentFaces inc_;
  PosFn pos_;
  std::vector<int> pairs_, ring1_, ring2_;
  std::vector<Vec3> normal_;
  std::vector<std::pair<int, int>> edge_;  ///< (neighbour, star face)
};

/// The estimate from the errors of the vertices that were not passed over
/// (errors is reordered).
inline NoiseEstimate fromErrors(std::vector<double>& errors) {
  NoiseEstimate out;
  out.samples = static_cast<int>(errors.size());
  if (out.samples < 10) return out;
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  // The median absolute value of a centred normal variable is 0.6745 of
  // its standard deviation.
  out.sigmaEdges = errors[errors.size() / 2] / 0.6745;
  return out;
}

}  // namespace detail

/// The noise level of the surface of the live faces, with the position of
/// vertex i given by pos(i) (a Vec3). Only vertices with a closed manifold
/// fan (each neighbour in exactly two of its faces) are sampled, and only
/// their two-rings are gathered, so a large mesh costs one pass over its
/// faces. A vertex with kNoiseFlatPairs edges between coplanar faces counts
/// as clean (error 0). Vertices with fewer than 9 two-ring neighbours, with
/// a two-ring larger than kNoiseMaxTwoRingFaces, or whose fit is
/// degenerate, are passed over; fewer than 10 usable vertices give NaN.
template <class PosFn>
NoiseEstimate estimateNoise(const FaceList& faces, int nv, PosFn pos) {
  double edgeSum = 0;
  long long edges = 0;
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    for (int k = 0; k < 3; ++k) {
      edgeSum += (pos(faces.tri[f][k]) - pos(faces.tri[f][(k + 1) % 3])).Norm();
      ++edges;
    }
  }
  const double meanEdge = edges ? edgeSum / double(edges) : 0.0;
  if (!(meanEdge > 0) || !std::isfinite(meanEdge)) return NoiseEstimate();
  detail::NoiseProbe<PosFn> probe(faces, nv, pos);
  const int sampled = std::min(nv, kNoiseSamples);
  std::vector<double> errors;
  for (int s = 0; s < sampled; ++s) {
    const int i = static_cast<int>((static_cast<long long>(s) * nv) / sampled);
    const double e = probe.error(i, meanEdge);
    if (e >= 0) errors.push_back(e);
  }
  return detail::fromErrors(errors);
}

/// At most this many vertices of each component are sampled by
/// estimateNoiseByComponent: the median of 2000 errors is within about 3%
/// of that of all of them.
constexpr int kComponentNoiseSamples = 2000;

/// The noise estimate of one connected component.
struct ComponentNoise {
  int faces = 0;     ///< live faces of the component
  int vertices = 0;  ///< vertices of those faces
  NoiseEstimate noise;
};

/// estimateNoise for each connected component of the live faces (faces
/// joined by a shared vertex) on its own, in mean edges of that component,
/// sampling at most kComponentNoiseSamples of its vertices: a small noisy
/// part beside a large clean one reads noisy here, where the median over
/// the whole mesh reads clean. The components with the most faces come
/// first (on a tie, the one whose first face comes first); only the first
/// maxComponents are estimated and returned, and *count, when given, gets
/// how many there are.
template <class PosFn>
std::vector<ComponentNoise> estimateNoiseByComponent(const FaceList& faces, int nv, PosFn pos, int maxComponents,
                                                     int* count = nullptr) {
  // Union-find over the vertices of each face.
  std::vector<int> parent(static_cast<std::size_t>(nv));
  for (int v = 0; v < nv; ++v) parent[v] = v;
  const auto root = [&parent](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (std::size_t f = 0; f < faces.tri.size(); ++f)
    if (faces.live[f])
      for (int k = 1; k < 3; ++k) {
        const int a = root(faces.tri[f][0]), b = root(faces.tri[f][k]);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
  // Components in the order of their first face, with their face counts
  // and edge lengths.
  std::vector<int> id(static_cast<std::size_t>(nv), -1);
  std::vector<ComponentNoise> comp;
  std::vector<double> edgeSum;
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    const int r = root(faces.tri[f][0]);
    if (id[r] < 0) {
      id[r] = static_cast<int>(comp.size());
      comp.emplace_back();
      edgeSum.push_back(0);
    }
    ++comp[id[r]].faces;
    for (int k = 0; k < 3; ++k) edgeSum[id[r]] += (pos(faces.tri[f][k]) - pos(faces.tri[f][(k + 1) % 3])).Norm();
  }
  std::vector<std::vector<int>> verts(comp.size());
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  for (std::size_t f = 0; f < faces.tri.size(); ++f)
    if (faces.live[f])
      for (int v : faces.tri[f]) used[v] = 1;
  for (int v = 0; v < nv; ++v)
    if (used[v]) verts[id[root(v)]].push_back(v);
  std::vector<int> order(comp.size());
  for (std::size_t c = 0; c < comp.size(); ++c) {
    order[c] = static_cast<int>(c);
    comp[c].vertices = static_cast<int>(verts[c].size());
  }
  std::stable_sort(order.begin(), order.end(), [&comp](int a, int b) { return comp[a].faces > comp[b].faces; });
  if (count) *count = static_cast<int>(comp.size());
  if (static_cast<int>(order.size()) > maxComponents) order.resize(std::max(0, maxComponents));
  detail::NoiseProbe<PosFn> probe(faces, nv, pos);
  std::vector<ComponentNoise> out;
  std::vector<double> errors;
  for (int c : order) {
    const double meanEdge = edgeSum[c] / (3.0 * comp[c].faces);
    errors.clear();
    const int n = comp[c].vertices, sampled = std::min(n, kComponentNoiseSamples);
    if (meanEdge > 0 && std::isfinite(meanEdge))
      for (int s = 0; s < sampled; ++s) {
        const double e = probe.error(verts[c][static_cast<std::size_t>((static_cast<long long>(s) * n) / sampled)],
                                     meanEdge);
        if (e >= 0) errors.push_back(e);
      }
    comp[c].noise = detail::fromErrors(errors);
    out.push_back(comp[c]);
  }
  return out;
}

/// estimateNoise on a vcglib mesh (any scalar type); deleted faces are
/// left out.
template <class MeshType>
NoiseEstimate estimateNoiseOf(const MeshType& m) {
  const FaceList faces = makeFaceList(m);
  return estimateNoise(faces, static_cast<int>(m.vert.size()), [&m](int i) {
    const auto& p = m.vert[i].cP();
    return Vec3(p[0], p[1], p[2]);
  });
}

/// estimateNoiseByComponent on a vcglib mesh; deleted faces are left out.
template <class MeshType>
std::vector<ComponentNoise> estimateNoiseByComponentOf(const MeshType& m, int maxComponents, int* count = nullptr) {
  const FaceList faces = makeFaceList(m);
  return estimateNoiseByComponent(
      faces, static_cast<int>(m.vert.size()),
      [&m](int i) {
        const auto& p = m.vert[i].cP();
        return Vec3(p[0], p[1], p[2]);
      },
      maxComponents, count);
}

}  // namespace sodt
