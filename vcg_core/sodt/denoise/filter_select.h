// SPDX-License-Identifier: GPL-3.0-or-later
// The first stage of Algorithm::Filtered: which filter, and how much of
// it, a mesh gets. No fixed strength serves every mesh: feature-preserving
// normal filtering (normal_filter.h) needs many rounds on a noisy CAD part
// or a finely sampled sphere, but it treats the curvature of a coarse
// smooth mesh (a 16-segment torus turns its faces 22 degrees per ring) as
// noise and flattens it within a round or two, where a lambda|mu umbrella
// filter (Taubin 1995) keeps the low frequencies. So both run, each as a
// sequence of growing lengths, and the length with the smallest Stein's
// unbiased risk estimate (SURE) of the mean squared error along the
// normals wins when it beats leaving the input as it is by a margin
// (kSureMargin), else no filter runs:
//
//   SURE = 1/n sum_i ( r_i^2 - s^2 + 2 s^2 d f_i / d y_i ),
//
// with y the input positions along the normals, f the filter's output,
// r_i = f_i - y_i, s the noise level (estimateNoise, or the user's), and the
// divergence estimated by running each filter once more on the input moved
// by eps b_i along the normals, b_i a fixed pseudo-random +-1 (Ramani, Blu
// and Unser 2008). SURE is the expected squared error to the unknown
// clean surface when the noise is Gaussian along the normals; it needs no
// constant tuned on a mesh.
#pragma once

#include "noise_estimate.h"
#include "normal_filter.h"
#include "../params.h"
#include "../maths/topology.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace sodt {

/// Taubin's lambda and mu (MeshLab's defaults too): a pair of steps keeps
/// frequencies below about 1/lambda + 1/mu = 0.11 of the umbrella operator.
constexpr double kTaubinLambda = 0.5, kTaubinMu = -0.53;
/// The umbrella filter is scored after every kUmbrellaCheck pairs, up to
/// kUmbrellaMaxPairs.
constexpr int kUmbrellaCheck = 5, kUmbrellaMaxPairs = 80;
/// The normal filter is scored after every round, up to kMaxNormalRounds.
constexpr int kMaxNormalRounds = 12;
/// A sequence stops once this many scores in a row were above its best.
constexpr int kWorseScoresToStop = 3;
/// The divergence probe moves the input by this share of the noise level.
/// The normal filter's output is not smooth in its input (the guidance
/// picks one patch among several, the fold guard halves steps): with 0.05
/// its estimated divergence on the noisy torus swung from 1.7 to -1.2
/// between rounds; with 0.5 and 1 it stays at 0.3-0.4.
constexpr double kProbeShare = 0.5;
/// A filter is applied only when its SURE is at most this share of no
/// filter's: SURE is an estimate, and where the noise level is misread or
/// the noise is not Gaussian along the normals (a clean CAD part whose
/// sharp edges read as noise) a small gain it promises is not there, while
/// the filter's move of the surface is. On the noise benchmark's meshes,
/// noise of 0.1-0.5 mean edges, the chosen filters scored below 0.2 of no
/// filter (most of them below 0).
constexpr double kSureMargin = 0.5;
/// After a filter, Filtered's sweeps keep within max(the deviation bound,
/// this share of the noise's standard deviation) of the denoised surface.
/// The filter leaves residual bumps of about a quarter of the noise; held
/// within 0.1% of the diagonal of them, the sweeps could not straighten
/// their slivers (noise benchmark: the cube's smallest angle at noise 0.3
/// mean edges 12.8 degrees against 27.9 with 0.5, the distance to the clean
/// cube the same within 0.3%).
constexpr double kFilteredNoiseShare = 0.5;

/// Jacobi steps of the uniform umbrella operator: x_i += factor (mean of
/// the one-ring - x_i) for the movable vertices. No fold guard: undoing a
/// step where a noisy face would turn over leaves that vertex behind its
/// smoothed neighbours, a spike that turns more faces over than it saved
/// (on spot with noise 0.3 mean edges, 24 faces against 0).
class UmbrellaSmoother {
 public:
  UmbrellaSmoother(const FaceList& faces, const std::vector<char>& movable, int nv, int threads)
      : movable_(movable), threads_(threads) {
    const IncidentFaces inc(faces, nv);
    begin_.assign(nv + 1, 0);
    std::vector<int> ring;
    for (int i = 0; i < nv; ++i) {
      begin_[i] = static_cast<int>(ring_.size());
      ring.clear();
      for (int k = inc.begin[i]; k < inc.begin[i + 1]; ++k)
        for (int j : faces.tri[inc.face[k]])
          if (j != i) ring.push_back(j);
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      ring_.insert(ring_.end(), ring.begin(), ring.end());
    }
    begin_[nv] = static_cast<int>(ring_.size());
  }

  /// One lambda step and one mu step.
  void pair(std::vector<Vec3>& pos) const {
    step(pos, kTaubinLambda);
    step(pos, kTaubinMu);
  }

 private:
  void step(std::vector<Vec3>& pos, double factor) const {
    const long nv = static_cast<long>(pos.size());
    const std::vector<Vec3> old = pos;
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads_) schedule(static) if (threads_ > 1)
#else
    (void)threads_;
#endif
    for (long i = 0; i < nv; ++i) {
      if (!movable_[i] || begin_[i] == begin_[i + 1]) continue;
      Vec3 c(0, 0, 0);
      for (int k = begin_[i]; k < begin_[i + 1]; ++k) c += old[ring_[k]];
      const Vec3 d = (c / double(begin_[i + 1] - begin_[i]) - old[i]) * factor;
      if (isFinite(d)) pos[i] = old[i] + d;
    }
  }

  const std::vector<char>& movable_;
  std::vector<int> begin_, ring_;
  int threads_;
};

namespace detail {

/// SURE of filter outputs along fixed unit normals (see the file comment).
class RiskProbe {
 public:
  /// normal: unit normals of the vertices (zero where unknown); only
  /// movable vertices with a normal count.
  RiskProbe(const std::vector<Vec3>& input, const std::vector<Vec3>& normal, const std::vector<char>& movable,
            double sigma)
      : y_(input), n_(normal), sigma2_(sigma * sigma), eps_(kProbeShare * sigma) {
    std::mt19937 gen(20130601u);  // fixed: the same mesh always gets the same probe
    sign_.assign(input.size(), 0.0);
    for (std::size_t i = 0; i < input.size(); ++i) {
      const double b = (gen() & 1u) ? 1.0 : -1.0;
      if (movable[i] && n_[i].SquaredNorm() > 0.5) {
        sign_[i] = b;
        ++count_;
      }
    }
  }

  bool usable() const { return count_ > 0 && eps_ > 0; }

  /// The input moved along the normals by the probe.
  std::vector<Vec3> probed() const {
    std::vector<Vec3> p = y_;
    for (std::size_t i = 0; i < p.size(); ++i) p[i] += n_[i] * (eps_ * sign_[i]);
    return p;
  }

  /// SURE of the output f, with fp the same filter's output on probed().
  double risk(const std::vector<Vec3>& f, const std::vector<Vec3>& fp) const {
    double sum = 0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (sign_[i] == 0) continue;
      const double r = n_[i] * (f[i] - y_[i]);
      const double div = sign_[i] * (n_[i] * (fp[i] - f[i])) / eps_;
      sum += r * r - sigma2_ + 2 * sigma2_ * div;
    }
    return sum / double(count_);
  }

  /// SURE of leaving the input as it is: the divergence is 1.
  double riskOfNone() const { return sigma2_; }

 private:
  const std::vector<Vec3>& y_;
  std::vector<Vec3> n_;
  std::vector<double> sign_;
  double sigma2_, eps_;
  long long count_ = 0;
};

/// Area-weighted vertex normals of pos (zero where they vanish).
inline std::vector<Vec3> vertexNormals(const FaceList& faces, const std::vector<Vec3>& pos) {
  std::vector<Vec3> n = vertexAreaSums(faces, pos);
  for (Vec3& v : n) {
    const double len = v.Norm();
    v = len > 0 && std::isfinite(len) ? v / len : Vec3(0, 0, 0);
  }
  return n;
}

/// Runs one filter as a growing sequence on the input and on the probed
/// input, scoring after every `every` steps up to `most`, and stops after
/// kWorseScoresToStop scores in a row above the best of the sequence, or
/// at once when the first score is not below no filter's; keeps the best.
/// tick(k) after each score; false stops, and so does the call (false).
template <class Step, class Tick>
bool scoreSequence(const RiskProbe& probe, const std::vector<Vec3>& input, FilterKind kind, int every, int most,
                   Step step, Tick tick, FilterChoice& best, std::vector<Vec3>& bestPos) {
  std::vector<Vec3> f = input, fp = probe.probed();
  double seqBest = probe.riskOfNone();
  int worse = 0;
  for (int k = every; k <= most && worse < kWorseScoresToStop; k += every) {
    for (int j = 0; j < every; ++j) {
      step(f);
      step(fp);
    }
    const double r = probe.risk(f, fp);
    if (r < seqBest) {
      seqBest = r;
      worse = 0;
    } else {
      // A first length that does not beat the input's own score ends the
      // sequence: longer ones only move the surface further (on a clean
      // mesh this saves most of the scoring).
      worse = k == every ? kWorseScoresToStop : worse + 1;
    }
    if (r < best.risk) {
      best.risk = r;
      best.kind = kind;
      best.steps = k;
      bestPos = f;
    }
    if (!tick(k)) return false;
  }
  return true;
}

}  // namespace detail

/// A progress callback as vcglib's CallBackPos: position 0..100 and a
/// message; false asks to stop.
using FilterProgress = bool (*)(int, const char*);

/// Filtered's first stage on the working positions: the filter and length
/// with the smallest SURE (see the file comment) replaces pos when that
/// SURE is at most kSureMargin of no filter's; only movable vertices move.
/// noiseEdges: the noise level in mean edges, or 0 to estimate it
/// (estimateNoise); when it cannot be estimated (NaN: too few vertices
/// with a closed two-ring, such as a 12-triangle box) nothing is scored and
/// pos stays as it is. cb, when given, hears of every score (at position
/// 0); when it returns false the scoring stops and the best length scored
/// so far is applied (under the same margin).
inline FilterChoice filteredDenoise(const FaceList& faces, const std::vector<char>& movable, double featureAngleDeg,
                                    double noiseEdges, int threads, std::vector<Vec3>& pos,
                                    FilterProgress cb = nullptr) {
  const int nv = static_cast<int>(pos.size());
  const std::vector<Vec3> input = pos;
  FilterChoice choice;
  choice.noiseEstimated = !(noiseEdges > 0);
  choice.noiseEdges = choice.noiseEstimated
                          ? estimateNoise(faces, nv, [&input](int i) { return input[i]; }).sigmaEdges
                          : noiseEdges;
  choice.risk = choice.riskNone = std::numeric_limits<double>::quiet_NaN();
  // Nothing to score with: a mesh whose noise is unknown or 0 keeps its
  // positions (and nothing of the filters is built).
  if (!(choice.noiseEdges > 0) || !std::isfinite(choice.noiseEdges)) return choice;
  double edgeSum = 0;
  long long edges = 0;
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const double l = (input[faces.tri[f][k]] - input[faces.tri[f][(k + 1) % 3]]).Norm();
      if (std::isfinite(l)) {
        edgeSum += l;
        ++edges;
      }
    }
  }
  const double meanEdge = edges ? edgeSum / double(edges) : 0.0;
  const UmbrellaSmoother umbrella(faces, movable, nv, threads);
  // Probe normals: those of a lightly smoothed copy, steadier than the
  // noisy input's.
  std::vector<Vec3> light = input;
  for (int k = 0; k < 2 * kUmbrellaCheck; ++k) umbrella.pair(light);
  const double sigma = choice.noiseEdges * meanEdge;
  const detail::RiskProbe probe(input, detail::vertexNormals(faces, light), movable,
                                std::isfinite(sigma) ? sigma : 0.0);
  if (!probe.usable()) return choice;
  const NormalFilterRounds normals(faces, movable, featureAngleDeg, input, threads);
  choice.risk = choice.riskNone = probe.riskOfNone();
  std::vector<Vec3> best = input;
  auto tick = [cb](const char* what, int k) {
    if (!cb) return true;
    const std::string msg = std::string("Filtered: scoring ") + what + " " + std::to_string(k);
    return cb(0, msg.c_str());
  };
  const bool goOn = !normals.usable() ||
                    detail::scoreSequence(probe, input, FilterKind::Normals, 1, kMaxNormalRounds,
                                          [&normals](std::vector<Vec3>& p) { normals.round(p); },
                                          [&tick](int k) { return tick("normal filter round", k); }, choice, best);
  if (goOn)
    detail::scoreSequence(probe, input, FilterKind::Taubin, kUmbrellaCheck, kUmbrellaMaxPairs,
                          [&umbrella](std::vector<Vec3>& p) { umbrella.pair(p); },
                          [&tick](int k) { return tick("Taubin step pairs", k); }, choice, best);
  const double e2 = meanEdge * meanEdge;
  choice.risk /= e2;
  choice.riskNone /= e2;
  if (choice.kind != FilterKind::None && choice.risk > kSureMargin * choice.riskNone) {
    // Scored, but not by enough: reported, not applied.
    choice.passedOver = choice.kind;
    choice.passedOverSteps = choice.steps;
    choice.kind = FilterKind::None;
    choice.steps = 0;
    return choice;
  }
  pos = best;
  return choice;
}

/// What ran: "none", "normal filter, 3 rounds", "Taubin smoothing, 10 step pairs".
inline std::string describeFilter(FilterKind kind, int steps) {
  switch (kind) {
    case FilterKind::None: return "none";
    case FilterKind::Normals: return "normal filter, " + std::to_string(steps) + (steps == 1 ? " round" : " rounds");
    case FilterKind::Taubin: return "Taubin smoothing, " + std::to_string(steps) + " step pairs";
  }
  return "?";
}

inline std::string describeFilter(const FilterChoice& c) { return describeFilter(c.kind, c.steps); }

/// One line for reports and logs: what ran and why.
inline std::string describe(const FilterChoice& c) {
  char why[320];
  const char* source = c.noiseEstimated ? "estimated" : "given";
  if (!std::isfinite(c.noiseEdges))
    std::snprintf(why, sizeof why, "the noise level could not be estimated: too few vertices with a closed two-ring");
  else if (!std::isfinite(c.risk))
    std::snprintf(why, sizeof why, "noise level %.3g mean edges, %s: nothing to remove", c.noiseEdges, source);
  else if (c.passedOver != FilterKind::None)
    std::snprintf(why, sizeof why,
                  "noise level %.3g mean edges, %s; the best filter, %s, has an estimated squared error of %.3g "
                  "against %.3g unfiltered, in squared mean edges: not below %g of it",
                  c.noiseEdges, source, describeFilter(c.passedOver, c.passedOverSteps).c_str(), c.risk, c.riskNone,
                  kSureMargin);
  else
    std::snprintf(why, sizeof why,
                  "noise level %.3g mean edges, %s; estimated squared error %.3g against %.3g unfiltered, in "
                  "squared mean edges",
                  c.noiseEdges, source, c.risk, c.riskNone);
  return describeFilter(c) + " (" + why + ")";
}

}  // namespace sodt
