// SPDX-License-Identifier: GPL-3.0-or-later
// How noisy a mesh is, in mean edge lengths: each sampled interior vertex
// is predicted from a quadric height field fitted to its two-ring without
// it, and the robust spread of the prediction errors estimates the noise's
// standard deviation along the normals. A quadric follows curvature, so a
// clean coarse mesh (a 16-segment torus) reads 0.04 and a flat-sided CAD
// part 0, while normal noise of sigma s edges reads about s.
#pragma once

#include "../maths/geometry.h"
#include "../maths/topology.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace sodt {

/// Below this many mean edges the input counts as nearly noise-free: the
/// denoisers then mostly smooth its shape (the clean 16-segment torus reads
/// 0.04, spot 0.02; normal noise of 0.1 edges reads 0.11).
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

struct NoiseEstimate {
  double sigmaEdges = std::numeric_limits<double>::quiet_NaN();  ///< NaN: too few usable vertices
  int samples = 0;                                                ///< vertices whose prediction counted
};

/// The noise level of the surface of the live faces, with the position of
/// vertex i given by pos(i) (a Vec3). Only vertices with a closed manifold
/// fan (each neighbour in exactly two of its faces) are sampled, and only
/// their two-rings are gathered, so a large mesh costs one pass over its
/// faces. Vertices with fewer than 9 two-ring neighbours, with a two-ring
/// larger than kNoiseMaxTwoRingFaces, or whose fit is degenerate, are
/// passed over; fewer than 10 usable vertices give NaN.
template <class PosFn>
NoiseEstimate estimateNoise(const FaceList& faces, int nv, PosFn pos) {
  NoiseEstimate out;
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
  if (!(meanEdge > 0) || !std::isfinite(meanEdge)) return out;
  const IncidentFaces inc(faces, nv);
  const std::vector<int>& vb = inc.begin;
  const std::vector<int>& vf = inc.face;
  // The one-ring of v; false unless every neighbour is in exactly two of
  // v's faces (an interior vertex of a manifold).
  std::vector<int> pairs;
  auto ring = [&](int v, std::vector<int>& nb) {
    pairs.clear();
    for (int k = vb[v]; k < vb[v + 1]; ++k)
      for (int w : faces.tri[vf[k]])
        if (w != v) pairs.push_back(w);
    std::sort(pairs.begin(), pairs.end());
    bool closed = !pairs.empty();
    for (std::size_t a = 0; a < pairs.size(); a += 2) closed = closed && a + 1 < pairs.size() &&
                                                                  pairs[a] == pairs[a + 1] &&
                                                                  (a + 2 >= pairs.size() || pairs[a + 2] != pairs[a]);
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    nb.insert(nb.end(), pairs.begin(), pairs.end());
    return closed;
  };

  const int sampled = std::min(nv, kNoiseSamples);
  std::vector<double> errors;
  std::vector<int> ring1, ring2;
  for (int s = 0; s < sampled; ++s) {
    const int i = static_cast<int>((static_cast<long long>(s) * nv) / sampled);
    ring1.clear();
    if (vb[i] == vb[i + 1] || vb[i + 1] - vb[i] > kNoiseMaxTwoRingFaces || !ring(i, ring1)) continue;
    long long spanned = vb[i + 1] - vb[i];
    for (int j : ring1) spanned += vb[j + 1] - vb[j];
    if (spanned > kNoiseMaxTwoRingFaces) continue;
    ring2 = ring1;
    for (int j : ring1) ring(j, ring2);
    std::sort(ring2.begin(), ring2.end());
    ring2.erase(std::unique(ring2.begin(), ring2.end()), ring2.end());
    ring2.erase(std::remove(ring2.begin(), ring2.end(), i), ring2.end());
    const int n = static_cast<int>(ring2.size());
    if (n < 9) continue;
    // The frame: the plane of the neighbours (least-variance direction).
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int j : ring2) c += Eigen::Vector3d(pos(j)[0], pos(j)[1], pos(j)[2]);
    c /= n;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int j : ring2) {
      const Eigen::Vector3d d = Eigen::Vector3d(pos(j)[0], pos(j)[1], pos(j)[2]) - c;
      cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d nrm = es.eigenvectors().col(0), u = es.eigenvectors().col(2), v = es.eigenvectors().col(1);
    // Height field z = a + bx + cy + dx^2 + exy + fy^2 around x_i, in
    // mean edges; the prediction error at x_i is |a|.
    const Eigen::Vector3d xi(pos(i)[0], pos(i)[1], pos(i)[2]);
    Eigen::MatrixXd A(n, 6);
    Eigen::VectorXd z(n);
    for (int r = 0; r < n; ++r) {
      const int j = ring2[r];
      const Eigen::Vector3d d = (Eigen::Vector3d(pos(j)[0], pos(j)[1], pos(j)[2]) - xi) / meanEdge;
      const double x = d.dot(u), y = d.dot(v);
      A.row(r) << 1.0, x, y, x * x, x * y, y * y;
      z[r] = d.dot(nrm);
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    if (qr.rank() < 6) continue;
    const double a = qr.solve(z)[0];
    // The fitted quadric's own noise adds to the error at x_i: its
    // variance at the prediction point is s^2 (A^T A)^-1_00 for noise s at
    // the neighbours, so the error's variance is s^2 (1 + that).
    const Eigen::Matrix<double, 6, 6> ata = A.transpose() * A;
    const double lever = ata.inverse()(0, 0);
    if (std::isfinite(a) && std::isfinite(lever) && lever >= 0) errors.push_back(std::abs(a) / std::sqrt(1 + lever));
  }
  out.samples = static_cast<int>(errors.size());
  if (out.samples < 10) return out;
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  // The median absolute value of a centred normal variable is 0.6745 of
  // its standard deviation.
  out.sigmaEdges = errors[errors.size() / 2] / 0.6745;
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

}  // namespace sodt
