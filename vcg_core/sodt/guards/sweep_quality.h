// SPDX-License-Identifier: GPL-3.0-or-later
// The quality of one state of the sweeps, for keepBest and toleranceDeg:
// measured after every sweep, so it has to cost little next to one.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "../maths/geometry.h"
#include "../maths/lanes.h"
#include "../maths/topology.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sodt {

/// Inverted faces, smallest angle and 1st percentile of the per-triangle
/// smallest angle (degrees) of one state. A state is better with fewer
/// inverted faces, then a larger minimum, then a larger percentile, so
/// keepBest never prefers a folded mesh.
struct SweepQuality {
  long long inverted = 0;
  double minDeg = 0, p1Deg = 0;
  bool better(const SweepQuality& o) const {
    if (inverted != o.inverted) return inverted < o.inverted;
    return minDeg > o.minDeg || (minDeg == o.minDeg && p1Deg > o.p1Deg);
  }
};

namespace detail {

/// The squared sine of the smallest angle of triangle (a, b, c), which
/// grows with that angle (at most 60 degrees), and its doubled area vector
/// doubleAreaVector(a, b, c). The smallest angle lies between the two
/// longest edges, so its sine is |area vector| / (their lengths'
/// product): no branch (the faces of a mesh pick their corner at random)
/// and the cross product is the one the inversion test needs anyway. A
/// triangle with two zero-length edges gets 0.
inline double minAngleSin2(const Vec3& a, const Vec3& b, const Vec3& c, Vec3& area) {
  const Vec3 ab = b - a, ac = c - a, bc = c - b;
  area = ab ^ ac;
  const double l1 = ab.SquaredNorm(), l2 = ac.SquaredNorm(), l3 = bc.SquaredNorm();
  const double longest = std::max(std::max(l1, l2), l3);
  const double middle = std::max(std::min(l1, l2), std::min(std::max(l1, l2), l3));
  const double den = longest * middle;
  const double s2 = std::min(1.0, area.SquaredNorm() / den);
  return den > 0 ? s2 : 0.0;
}

}  // namespace detail

/// Measures SweepQuality, keeping its buffers from one call to the next.
class SweepQualityMeter {
 public:
  /// The quality of the live faces of faces at positions pos. A face is
  /// inverted when its area vector points against refNormal[f] (none are
  /// when refNormal is empty). p1Deg is the value at index
  /// floor(0.01 (n - 1)) of the n per-face smallest angles sorted upwards,
  /// minDeg the first; each angle is triangleMinAngle() in degrees. The
  /// positions must be finite.
  ///
  /// The result is the same as computing every face's angle, but only the
  /// faces near the lowest percentile get one: every face gets the squared
  /// sine of its smallest angle (no trigonometry), a 4096-bin histogram of
  /// those picks a cut-off below which lie the n/100 smallest, and the
  /// faces below the cut-off plus a margin of 1e-9 (far above the rounding
  /// of either formula) get an angle. Every face left out has a larger
  /// angle than all of those, so the ordered values up to the percentile
  /// are the same. Both passes over the faces run on threads threads;
  /// counts are integers, so the result does not depend on their number.
  /// With simd, the first pass takes four faces at a time in AVX2 lanes
  /// when the processor has them, with the same result.
  SweepQuality operator()(const FaceList& faces, const std::vector<Vec3>& pos, const std::vector<Vec3>& refNormal,
                          int threads = 1, bool simd = true) {
    constexpr int kBins = 4096;  // a power of two: key * kBins is exact
    constexpr double kMargin = 1e-9;
    const long long nf = static_cast<long long>(faces.tri.size());
    const bool checkInverted = !refNormal.empty();
    key_.resize(static_cast<std::size_t>(nf));
    histogram_.assign(kBins, 0);
    long long live = 0;
    SweepQuality q;
    threads = std::max(1, std::min(threads, 1024));
    const bool parallel = threads > 1 && nf >= 20000;
    // Four faces at a time in AVX2 lanes when the processor has them (the
    // same bits as the scalar code, see lanes::faceKeys4).
    const bool useLanes = simd && lanes::available();
    const long long groups = (nf + lanes::kWidth - 1) / lanes::kWidth;
    if (!parallel) threads = 1;
    picked_.resize(threads);
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) if (parallel)
#endif
    {
      std::vector<long long> bins(kBins, 0);
      long long inverted = 0, count = 0;
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
      for (long long g = 0; g < groups; ++g) {
        const long long f0 = lanes::kWidth * g, f1 = std::min(nf, f0 + lanes::kWidth);
        if (useLanes && f1 - f0 == lanes::kWidth && faces.live[f0] && faces.live[f0 + 1] && faces.live[f0 + 2] &&
            faces.live[f0 + 3]) {
          lanes::FaceKeys out;
          lanes::faceKeys4(&pos[0][0], &faces.tri[f0][0], checkInverted ? &refNormal[f0][0] : nullptr, out);
          for (int l = 0; l < lanes::kWidth; ++l) {
            const double k = out.key[l];
            key_[f0 + l] = k;
            ++bins[k < 1 ? static_cast<int>(k * kBins) : kBins - 1];
            inverted += out.inverted >> l & 1;
          }
          count += lanes::kWidth;
          continue;
        }
        for (long long f = f0; f < f1; ++f) {
          if (!faces.live[f]) {
            key_[f] = 2;
            continue;
          }
          const auto& t = faces.tri[f];
          const Vec3 &a = pos[t[0]], &b = pos[t[1]], &c = pos[t[2]];
          Vec3 area;
          const double k = detail::minAngleSin2(a, b, c, area);  // in [0, 1]
          key_[f] = k;
          ++bins[k < 1 ? static_cast<int>(k * kBins) : kBins - 1];
          ++count;
          if (checkInverted) inverted += area * refNormal[f] < 0;
        }
      }
#ifdef _OPENMP
#pragma omp critical(sodt_sweep_quality)
#endif
      {
        for (int j = 0; j < kBins; ++j) histogram_[j] += bins[j];
        q.inverted += inverted;
        live += count;
      }
    }
    if (live == 0) return q;
    const long long idx = static_cast<long long>(std::floor(0.01 * double(live - 1)));
    // The lowest bin j such that bins ..j hold at least idx + 1 faces.
    int j = 0;
    for (long long below = histogram_[0]; below < idx + 1; below += histogram_[j]) ++j;
    const double cut = double(j + 1) / kBins + kMargin;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) if (parallel)
#endif
    {
#ifdef _OPENMP
      std::vector<double>& mine = picked_[omp_get_thread_num()];
#else
      std::vector<double>& mine = picked_[0];
#endif
      mine.clear();
#ifdef _OPENMP
#pragma omp for schedule(static) nowait
#endif
      for (long long f = 0; f < nf; ++f)
        if (key_[f] <= cut) {
          const auto& t = faces.tri[f];
          mine.push_back(triangleMinAngle(pos[t[0]], pos[t[1]], pos[t[2]]) * kRadToDeg);
        }
    }
    deg_.clear();
    for (const std::vector<double>& v : picked_) deg_.insert(deg_.end(), v.begin(), v.end());
    std::nth_element(deg_.begin(), deg_.begin() + idx, deg_.end());
    q.p1Deg = deg_[idx];
    q.minDeg = *std::min_element(deg_.begin(), deg_.begin() + idx + 1);
    return q;
  }

 private:
  std::vector<double> key_;
  std::vector<long long> histogram_;
  std::vector<std::vector<double>> picked_;  ///< per thread
  std::vector<double> deg_;
};

/// SweepQualityMeter()(faces, pos, refNormal, threads, simd), for a single call.
inline SweepQuality measureSweepQuality(const FaceList& faces, const std::vector<Vec3>& pos,
                                        const std::vector<Vec3>& refNormal, int threads = 1, bool simd = true) {
  return SweepQualityMeter()(faces, pos, refNormal, threads, simd);
}

/// The largest angle, in degrees, between the area vector of a live face
/// and its refNormal (SodtStats::maxFaceTurnDeg); faces whose area vector or
/// refNormal is zero are left out, and an empty refNormal gives 0.
inline double largestFaceTurnDeg(const FaceList& faces, const std::vector<Vec3>& pos,
                                 const std::vector<Vec3>& refNormal) {
  if (refNormal.empty()) return 0.0;
  double worst = 0;
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f] || refNormal[f].SquaredNorm() == 0) continue;
    const std::array<int, 3>& t = faces.tri[f];
    const Vec3 area = doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]);
    if (area.SquaredNorm() == 0) continue;
    worst = std::max(worst, angleBetween(area, refNormal[f]));
  }
  return worst * kRadToDeg;
}

/// The states a run measures after its sweeps, for keepBest (the best
/// state seen, the input being state 0) and toleranceDeg (the quality of the
/// last sweep). Measures nothing when neither is asked for.
class BestState {
 public:
  /// Measures the input. refNormal: as SweepQualityMeter.
  BestState(bool keepBest, double toleranceDeg, bool flips, const FaceList& faces, const std::vector<Vec3>& pos,
            const std::vector<Vec3>& refNormal, int threads, bool simd)
      : keep_(keepBest), flips_(flips), tolerance_(toleranceDeg), threads_(threads), simd_(simd) {
    if (!keep_ && !(tolerance_ > 0)) return;
    last_ = meter_(faces, pos, refNormal, threads, simd);
    best_ = last_;
    if (keep_) pos_ = pos;
    if (keep_ && flips_) faces_ = faces, ref_ = refNormal;
  }

  /// Measures the state after sweep `sweep` (1, 2, ...) and keeps it when
  /// it is the best yet. True when the sweep raised neither the smallest
  /// angle nor the 1st percentile by more than toleranceDeg.
  bool afterSweep(int sweep, const FaceList& faces, const std::vector<Vec3>& pos,
                  const std::vector<Vec3>& refNormal) {
    if (!keep_ && !(tolerance_ > 0)) return false;
    const SweepQuality q = meter_(faces, pos, refNormal, threads_, simd_);
    if (keep_ && q.better(best_)) {
      best_ = q;
      sweep_ = sweep;
      pos_ = pos;
      if (flips_) faces_ = faces, ref_ = refNormal;
    }
    const bool stop = tolerance_ > 0 && q.minDeg - last_.minDeg <= tolerance_ && q.p1Deg - last_.p1Deg <= tolerance_;
    last_ = q;
    return stop;
  }

  /// With keepBest, puts the best state into pos and faces, and the
  /// refNormal it was measured with into refNormal (flips merge them), when
  /// it is not the one after `sweeps` sweeps; returns the sweep of the state
  /// left there.
  int restore(int sweeps, std::vector<Vec3>& pos, FaceList& faces, std::vector<Vec3>& refNormal) const {
    if (!keep_ || sweep_ == sweeps) return sweeps;
    pos = pos_;
    if (flips_) faces = faces_, refNormal = ref_;
    return sweep_;
  }

 private:
  bool keep_, flips_;
  double tolerance_;
  int threads_;
  bool simd_;
  SweepQualityMeter meter_;
  SweepQuality last_, best_;
  std::vector<Vec3> pos_;
  FaceList faces_;
  std::vector<Vec3> ref_;
  int sweep_ = 0;
};

}  // namespace sodt
