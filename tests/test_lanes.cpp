// SPDX-License-Identifier: GPL-3.0-or-later
// The 4-lane Algorithm 1 kernel: bit for bit the scalar solve, star by star
// and over whole runs.
#include "full_fixture.h"
#include "test_mesh.h"

#include <sodt_io/io.h>
#include <sodt/maths/lanes.h>
#include <sodt/maths/local_solve.h>
#include <sodt_io/prebuilt.h>
#include <sodt/guards/sweep_quality.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

using sodt::Vec3;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Kinds of star the kernel must agree on, the degenerate ones included.
enum class Kind { Jittered, FlatOnAxis, TiedAxes, IntegerGrid, Collinear, Collapsed, Scrambled, Overflowing, Count };

/// A star of valence n of the given kind: centre first, then the ring.
std::vector<Vec3> makeStar(Kind kind, int n, std::mt19937& g) {
  using sodt_test::uniform;
  std::vector<Vec3> pts(n + 1);
  const double scale = std::pow(10.0, uniform(g, -6, 6));
  const Vec3 offset(uniform(g, -1e3, 1e3) * scale, uniform(g, -1e3, 1e3) * scale, uniform(g, -1e3, 1e3) * scale);
  // An orthonormal frame in a random direction.
  Vec3 a(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
  if (a.SquaredNorm() < 1e-3) a = Vec3(0.3, -0.5, 0.8);
  a.Normalize();
  Vec3 b = a ^ Vec3(0.36, 0.48, 0.8);
  b.Normalize();
  const Vec3 h = a ^ b;
  switch (kind) {
    case Kind::Jittered:
    case Kind::FlatOnAxis:
    case Kind::TiedAxes:
    case Kind::Overflowing: {
      if (kind == Kind::FlatOnAxis) a = Vec3(1, 0, 0), b = Vec3(0, 1, 0);
      if (kind == Kind::TiedAxes) a = Vec3(0, 0, 1), b = Vec3(std::sqrt(0.5), -std::sqrt(0.5), 0);
      const double height = kind == Kind::Jittered ? 0.4 : 0.0;
      pts[0] = Vec3(uniform(g, -0.3, 0.3), uniform(g, -0.3, 0.3), 0);
      for (int k = 0; k < n; ++k) {
        const double t = 2 * sodt::kPi * (k + uniform(g, -0.35, 0.35)) / n, r = uniform(g, 0.5, 1.5);
        pts[k + 1] = Vec3(r * std::cos(t), r * std::sin(t), uniform(g, -height, height));
      }
      for (Vec3& p : pts) p = a * p[0] + b * p[1] + h * p[2];
      const double s = kind == Kind::Overflowing ? 1e200 : scale;
      for (Vec3& p : pts) p = p * s + (kind == Kind::Overflowing ? Vec3(0, 0, 0) : offset);
      break;
    }
    case Kind::IntegerGrid:
      for (Vec3& p : pts) p = Vec3(std::floor(uniform(g, -3, 4)), std::floor(uniform(g, -3, 4)), std::floor(uniform(g, -1, 2)));
      break;
    case Kind::Collinear:
      for (Vec3& p : pts) p = offset + a * (uniform(g, -1, 1) * scale);
      break;
    case Kind::Collapsed:
      for (Vec3& p : pts) p = offset;
      break;
    case Kind::Scrambled:  // not star-shaped: the quadratic may be indefinite
      for (Vec3& p : pts) p = offset + Vec3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -0.2, 0.2)) * scale;
      break;
    case Kind::Count: break;
  }
  return pts;
}

}  // namespace

TEST(Lanes, KernelMatchesTheScalarSolveBitForBit) {
  if (!sodt::lanes::available()) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  std::mt19937 g(4242);
  int solved = 0, failed = 0, mismatches = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int n = 3 + trial % (sodt::lanes::kMaxValence - 2);
    std::vector<Vec3> pos;
    std::vector<int> ringIdx, begin, centre;
    std::vector<sodt::Star> stars(sodt::lanes::kWidth);
    for (int l = 0; l < sodt::lanes::kWidth; ++l) {
      const Kind kind = static_cast<Kind>(g() % static_cast<unsigned>(Kind::Count));
      const std::vector<Vec3> pts = makeStar(kind, n, g);
      centre.push_back(static_cast<int>(pos.size()));
      begin.push_back(static_cast<int>(ringIdx.size()));
      for (int k = 0; k < n; ++k) ringIdx.push_back(static_cast<int>(pos.size()) + 1 + k);
      pos.insert(pos.end(), pts.begin(), pts.end());
      stars[l].center = pts[0];
      stars[l].ring.assign(pts.begin() + 1, pts.end());
    }
    sodt::lanes::Targets t;
    std::vector<int> table(sodt::lanes::kWidth * (n + 1));
    sodt::lanes::packGroup(centre.data(), ringIdx.data(), begin.data(), n, table.data());
    sodt::lanes::targets4(&pos[0][0], table.data(), n, t);
    for (int l = 0; l < sodt::lanes::kWidth; ++l) {
      const sodt::LocalMove mv = sodt::solveStar(stars[l]);
      const Vec3 nrm = sodt::starNormal(stars[l]);
      const bool ok = (t.ok >> l & 1) != 0;
      (mv.ok ? solved : failed)++;
      const bool sameTarget =
          sameBits(t.x[l], mv.target[0]) && sameBits(t.y[l], mv.target[1]) && sameBits(t.z[l], mv.target[2]);
      const bool sameNormal = sameBits(t.nx[l], nrm[0]) && sameBits(t.ny[l], nrm[1]) && sameBits(t.nz[l], nrm[2]);
      if (ok != mv.ok || (ok && !(sameTarget && sameNormal))) {
        if (++mismatches <= 5)
          ADD_FAILURE() << "trial " << trial << " lane " << l << ": kernel ok " << ok << " (" << t.x[l] << ", " << t.y[l]
                        << ", " << t.z[l] << "), scalar ok " << mv.ok << " (" << mv.target[0] << ", "
                        << mv.target[1] << ", " << mv.target[2] << ")";
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
  // Both outcomes occur often enough for the comparison to mean something.
  EXPECT_GT(solved, 20000);
  EXPECT_GT(failed, 10000);
}

TEST(Lanes, DenoiseKernelMatchesTheScalarSolveBitForBit) {
  // Algorithm 3's targets (denoiseTargets): random stars, degenerate ones
  // included, each with a fitted plane near its centre whose normal is the
  // star's own, a tilted one or any direction, and bounds on the move along
  // it that cut the targets or do not.
  if (!sodt::lanes::available()) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  using sodt_test::uniform;
  std::mt19937 g(5151);
  int solved = 0, failed = 0, bounded = 0, mismatches = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int n = 3 + trial % (sodt::lanes::kMaxValence - 2);
    std::vector<Vec3> pos;
    std::vector<int> ringIdx, begin, centre;
    std::vector<sodt::Star> stars(sodt::lanes::kWidth);
    for (int l = 0; l < sodt::lanes::kWidth; ++l) {
      const Kind kind = static_cast<Kind>(g() % static_cast<unsigned>(Kind::Count));
      const std::vector<Vec3> pts = makeStar(kind, n, g);
      centre.push_back(static_cast<int>(pos.size()));
      begin.push_back(static_cast<int>(ringIdx.size()));
      for (int k = 0; k < n; ++k) ringIdx.push_back(static_cast<int>(pos.size()) + 1 + k);
      pos.insert(pos.end(), pts.begin(), pts.end());
      stars[l].center = pts[0];
      stars[l].ring.assign(pts.begin() + 1, pts.end());
    }
    // Frames per vertex, laid out as the smoother's (point and unit normal).
    std::vector<sodt::FittedFrame> frame(pos.size());
    double size = 0;
    for (const sodt::Star& st : stars)
      for (const Vec3& q : st.ring) size = std::max(size, (q - st.center).Norm());
    for (int l = 0; l < sodt::lanes::kWidth; ++l) {
      const sodt::Star& st = stars[l];
      Vec3 dir = sodt::starNormal(st);
      const int r = static_cast<int>(g() % 3);
      const Vec3 any(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
      if (r == 1 || dir.SquaredNorm() == 0) dir = dir + any * 0.3;
      if (r == 2) dir = any;
      if (dir.SquaredNorm() == 0) dir = Vec3(0, 0, 1);
      dir.Normalize();
      sodt::FittedFrame& f = frame[centre[l]];
      f.ok = true;
      f.dir = dir;
      f.point = st.center + Vec3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1)) * (0.2 * size);
    }
    sodt::lanes::DenoiseInput in;
    in.point = &frame[0].point[0];
    in.dir = &frame[0].dir[0];
    in.stride = static_cast<int>(sizeof(sodt::FittedFrame) / sizeof(double));
    in.lim = g() % 2 ? 1e300 : size * std::pow(10.0, uniform(g, -4, 0));
    sodt::lanes::Targets t;
    std::vector<int> table(sodt::lanes::kWidth * (n + 1));
    sodt::lanes::packGroup(centre.data(), ringIdx.data(), begin.data(), n, table.data());
    sodt::lanes::targets4(&pos[0][0], table.data(), n, t, nullptr, nullptr, nullptr, &in);
    for (int l = 0; l < sodt::lanes::kWidth; ++l) {
      const sodt::Star& st = stars[l];
      const sodt::FittedFrame& f = frame[centre[l]];
      const Vec3 nrm = sodt::starNormal(st);
      Vec3 target(0, 0, 0), fallback(0, 0, 0);
      // As the smoother's propose(): no move without a tangent plane.
      const bool want = nrm.SquaredNorm() != 0 && sodt::denoiseTargets(st, f.point, f.dir, in.lim, target, fallback);
      const bool ok = (t.ok >> l & 1) != 0;
      (want ? solved : failed)++;
      if (want) {
        Vec3 unbounded(0, 0, 0), dummy(0, 0, 0);
        sodt::denoiseTargets(st, f.point, f.dir, 1e300, unbounded, dummy);
        bounded += !(unbounded == target);
      }
      const bool same = sameBits(t.x[l], target[0]) && sameBits(t.y[l], target[1]) && sameBits(t.z[l], target[2]) &&
                        sameBits(t.fx[l], fallback[0]) && sameBits(t.fy[l], fallback[1]) &&
                        sameBits(t.fz[l], fallback[2]) && sameBits(t.nx[l], nrm[0]) && sameBits(t.ny[l], nrm[1]) &&
                        sameBits(t.nz[l], nrm[2]);
      if (ok != want || (ok && !same)) {
        if (++mismatches <= 5)
          ADD_FAILURE() << "trial " << trial << " lane " << l << ": kernel ok " << ok << " (" << t.x[l] << ", " << t.y[l]
                        << ", " << t.z[l] << "), scalar ok " << want << " (" << target[0] << ", " << target[1]
                        << ", " << target[2] << ")";
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(solved, 20000);
  EXPECT_GT(failed, 5000);
  EXPECT_GT(bounded, 5000);  // the bound along the normal was applied often
}

TEST(Lanes, FullStepVerdictMatchesTheScalarGuardBitForBit) {
  if (!sodt::lanes::available()) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  using sodt_test::uniform;
  std::mt19937 g(9090);
  int mismatches = 0, allowed = 0, refused = 0, undecided = 0, laterFirst = 0, turnedOnly = 0;
  for (int trial = 0; trial < 24000; ++trial) {
    const int n = 3 + trial % (sodt::lanes::kMaxValence - 2);
    sodt::lanes::GuardInput in;
    in.quality = trial / 3 % 2 == 0;
    in.roundToFloat = trial / 6 % 2 == 0;
    const bool withRef = trial / 12 % 4 != 0;
    // The largest face turn: 90 degrees (the fold test alone), 40 or 10.
    const double turnDeg[3] = {90, 40, 10};
    in.maxTurnCos2 = sodt::faceTurnCos2(turnDeg[trial / 48 % 3]);
    std::vector<Vec3> pos, faceNormal;
    std::vector<int> ringIdx, ringFace, begin, centre;
    std::vector<sodt::Star> stars(sodt::lanes::kWidth);
    for (int l = 0; l < sodt::lanes::kWidth; ++l) {
      // Mostly well-shaped stars, so that full steps are both accepted and refused.
      const Kind kind = g() % 2 ? Kind::Jittered : static_cast<Kind>(g() % static_cast<unsigned>(Kind::Count));
      std::vector<Vec3> pts = makeStar(kind, n, g);
      if (g() % 6 == 0) {
        // A regular star with its centre at the middle, away from the
        // origin: the target is the centre up to rounding, so the step
        // rounds to no move at all.
        pts[0] = Vec3(1, 2, 3);
        for (int k = 0; k < n; ++k)
          pts[k + 1] = pts[0] + Vec3(std::cos(2 * sodt::kPi * k / n), std::sin(2 * sodt::kPi * k / n), 0) * 0.5;
      }
      if (g() % 4 == 0) {
        // One star triangle nearly flat now, about as flat as the fold
        // test's threshold for using the plane normal instead.
        const int k = static_cast<int>(g() % static_cast<unsigned>(n)), k1 = (k + 1) % n;
        const Vec3 u = pts[1 + k] - pts[0];
        Vec3 side = u ^ Vec3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
        const Vec3 w = u * uniform(g, 0.3, 1.5);
        const double big = std::max({u.SquaredNorm(), w.SquaredNorm(), (w - u).SquaredNorm()});
        if (side.Norm() > 0 && u.Norm() > 0) {
          side /= side.Norm();
          pts[1 + k1] = pts[0] + w + side * (1e-12 * big / u.Norm() * uniform(g, 0.3, 3));
        }
      }
      if (n % 2 == 0 && n >= 6 && g() % 3 == 0) {
        // A ring symmetric about the origin, so the target is the origin up
        // to rounding, with ring vertices 0 and 1 nearly in line with it:
        // the move flattens that triangle to about the fold test's collapse
        // threshold, and so does the opposite one. The centre starts on
        // the line of that pair, where both triangles are as flat already
        // and keep the ring's orientation.
        const int m = n / 2;
        const double r0 = uniform(g, 0.5, 1.5), t = uniform(g, 0.2, 0.9);
        const double eps = 1e-12 * r0 * uniform(g, 0.5, 2);
        std::vector<Vec3> half{Vec3(r0, 0, 0), Vec3(t * r0, eps, 0)};
        for (int j = 1; j <= m - 2; ++j) {
          const double ang = sodt::kPi * j / (m - 1), r = uniform(g, 0.5, 1.5);
          half.push_back(Vec3(r * std::cos(ang), r * std::sin(ang), 0));
        }
        pts[0] = Vec3(0.1 * r0, 0, 0);
        for (int k = 0; k < m; ++k) pts[1 + k] = half[k], pts[1 + m + k] = -half[k];
      }
      if (in.roundToFloat)  // a float mesh holds float positions
        for (Vec3& q : pts) q = sodt::roundedTo<float>(q);
      centre.push_back(static_cast<int>(pos.size()));
      begin.push_back(static_cast<int>(ringIdx.size()));
      for (int k = 0; k < n; ++k) {
        ringIdx.push_back(static_cast<int>(pos.size()) + 1 + k);
        // The input normal of each star triangle: its own, turned over, any direction, or none.
        const Vec3 area = sodt::doubleAreaVector(pts[0], pts[1 + k], pts[1 + (k + 1) % n]);
        const double len = area.Norm();
        const unsigned r = g() % 8;
        Vec3 ref = r < 5 && len > 0 ? area / len : r == 5 && len > 0 ? area / -len : Vec3(0, 0, 0);
        if (r == 6) ref = Vec3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
        ringFace.push_back(static_cast<int>(faceNormal.size()));
        faceNormal.push_back(ref);
      }
      pos.insert(pos.end(), pts.begin(), pts.end());
      stars[l].center = pts[0];
      stars[l].ring.assign(pts.begin() + 1, pts.end());
      stars[l].maxTurnCos2 = in.maxTurnCos2;
      if (withRef)
        for (int k = 0; k < n; ++k) stars[l].refNormal.push_back(faceNormal[ringFace[begin[l] + k]]);
    }
    in.faceNormal = withRef ? &faceNormal[0][0] : nullptr;
    std::vector<int> table(sodt::lanes::kWidth * (2 * n + 1));
    sodt::lanes::packGroup(centre.data(), ringIdx.data(), begin.data(), n, table.data(), ringFace.data());
    sodt::lanes::Targets t;
    sodt::lanes::StepVerdict v;
    sodt::lanes::Prepared prep;
    sodt::lanes::targets4(&pos[0][0], table.data(), n, t, &in, &v, &prep);
    {
      // Without the verdict, the kernel prepares the same.
      sodt::lanes::Targets t2;
      sodt::lanes::Prepared prep2;
      sodt::lanes::targets4(&pos[0][0], table.data(), n, t2, &in, nullptr, &prep2);
      const std::size_t row = sizeof(double) * sodt::lanes::kWidth;
      EXPECT_EQ(std::memcmp(prep.cx, prep2.cx, n * row) | std::memcmp(prep.cy, prep2.cy, n * row) |
                    std::memcmp(prep.cz, prep2.cz, n * row) | std::memcmp(prep.ee, prep2.ee, n * row) |
                    std::memcmp(prep.limit, prep2.limit, row),
                0)
          << "trial " << trial;
    }
    for (int l = 0; l < sodt::lanes::kWidth; ++l) {
      const bool a = (v.allowed >> l & 1) != 0, r = (v.refused >> l & 1) != 0;
      if (!(t.ok >> l & 1)) {
        mismatches += a || r;
        continue;
      }
      // The scalar guard of a visit, on the kernel's target and normal.
      const sodt::Star& st = stars[l];
      const Vec3 target(t.x[l], t.y[l], t.z[l]), normal(t.nx[l], t.ny[l], t.nz[l]);
      std::vector<Vec3> cur;
      std::vector<double> ee;
      const double limit = sodt::prepareGuard(st, normal, in.quality, cur, ee);
      // What the kernel prepared for the rest of the visit is prepareGuard's.
      bool samePrepared = sameBits(prep.limit[l], limit);
      for (int k = 0; k < n; ++k)
        samePrepared = samePrepared && sameBits(prep.cx[k][l], cur[k][0]) && sameBits(prep.cy[k][l], cur[k][1]) &&
                       sameBits(prep.cz[k][l], cur[k][2]) && sameBits(prep.ee[k][l], ee[k]);
      if (!samePrepared && ++mismatches <= 5) ADD_FAILURE() << "trial " << trial << " lane " << l << ": prepared differs";
      Vec3 y = st.center + (target - st.center) * 1.0;
      if (in.roundToFloat) y = sodt::roundedTo<float>(y);
      const bool decided = sodt::isFinite(y) && !(y == st.center);
      int first = 0;
      const bool pass = sodt::moveAllowed(st, y, cur, ee, in.quality, limit, &first);
      if (decided && !pass && withRef && in.maxTurnCos2 > 0) {
        sodt::Star foldOnly = st;
        foldOnly.maxTurnCos2 = 0;
        turnedOnly += sodt::moveAllowed(foldOnly, y, cur, ee, in.quality, limit);
      }
      const bool same = decided ? a == pass && r == !pass && (pass || v.first[l] == first) && sameBits(v.x[l], y[0]) &&
                                      sameBits(v.y[l], y[1]) && sameBits(v.z[l], y[2])
                                : !a && !r;
      if (!same && ++mismatches <= 5)
        ADD_FAILURE() << "trial " << trial << " lane " << l << ": kernel allowed " << a << " refused " << r
                      << " first " << v.first[l] << ", scalar decided " << decided << " allowed " << pass
                      << " first " << first;
      if (!decided) ++undecided;
      else if (pass) ++allowed;
      else ++refused, laterFirst += first > 0;
    }
  }
  EXPECT_EQ(mismatches, 0);
  // Each verdict occurs often enough for the comparison to mean something,
  // and refusals are not all on the first triangle.
  EXPECT_GT(allowed, 10000);
  EXPECT_GT(refused, 10000);
  EXPECT_GT(undecided, 1000);
  EXPECT_GT(laterFirst, 3000);
  EXPECT_GT(turnedOnly, 500);  // refused for the face turn alone
}

TEST(Lanes, StepLengthsTestedAtOnceMatchTheScalarGuard) {
  if (!sodt::lanes::available()) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  using sodt_test::uniform;
  std::mt19937 g(4711);
  int mismatches = 0, allowed = 0, refused = 0, mixed = 0, badWitness = 0, turnedOnly = 0;
  for (int trial = 0; trial < 60000; ++trial) {
    // Any valence: the test of step lengths is not limited to the kernel's.
    const int n = 3 + trial % 14;
    const bool quality = trial / 2 % 2 == 0, withRef = trial / 4 % 3 != 0;
    const Kind kind = g() % 4 ? Kind::Jittered : static_cast<Kind>(g() % static_cast<unsigned>(Kind::Count));
    const std::vector<Vec3> pts = makeStar(kind, n, g);
    sodt::Star st;
    const double turnDeg[3] = {90, 40, 10};  // the largest face turn
    st.maxTurnCos2 = sodt::faceTurnCos2(turnDeg[trial / 12 % 3]);
    st.center = pts[0];
    st.ring.assign(pts.begin() + 1, pts.end());
    if (withRef) {
      for (int k = 0; k < n; ++k) {
        const Vec3 area = sodt::doubleAreaVector(pts[0], pts[1 + k], pts[1 + (k + 1) % n]);
        const unsigned r = g() % 6;
        const Vec3 any(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
        st.refNormal.push_back(r < 4 ? area : r == 4 ? -area : any);
      }
    }
    Vec3 normal = sodt::starNormal(st);
    if (normal.SquaredNorm() == 0) normal = Vec3(0, 0, 1);
    std::vector<Vec3> cur;
    std::vector<double> ee;
    const double limit = sodt::prepareGuard(st, normal, quality, cur, ee);
    // A step as a visit tries it: towards a target in the star's
    // neighbourhood (or the S-ODT target), halved again and again.
    double size = 0;
    for (const Vec3& q : st.ring) size = std::max(size, (q - st.center).Norm());
    const sodt::LocalMove mv = sodt::solveStar(st, normal);
    const Vec3 target = mv.ok && g() % 2 ? mv.target
                                         : st.center + Vec3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1)) *
                                                           (size * std::pow(10.0, uniform(g, -1.5, 0.5)));
    const int count = 1 + static_cast<int>(g() % sodt::lanes::kWidth);
    const int halvings = static_cast<int>(g() % 3);
    Vec3 y[sodt::lanes::kWidth];
    double f = std::ldexp(1.0, -halvings);
    for (int l = 0; l < count; ++l, f *= 0.5) y[l] = st.center + (target - st.center) * f;
    if (g() % 2)
      for (int l = 0; l < count; ++l) y[l] = sodt::roundedTo<float>(y[l]);
    int witness = static_cast<int>(g() % static_cast<unsigned>(n + 3)) - 1;  // out of range too
    const Vec3* ref = withRef ? st.refNormal.data() : nullptr;
    const int pass = sodt::lanes::allowedAt(st.ring.data(), n, cur.data(), ee.data(), ref, st.maxTurnCos2, quality,
                                            limit, y, count, &witness);
    int expected = 0;
    for (int l = 0; l < count; ++l) expected |= sodt::moveAllowed(st, y[l], cur, ee, quality, limit) ? 1 << l : 0;
    if (withRef && st.maxTurnCos2 > 0) {
      sodt::Star foldOnly = st;
      foldOnly.maxTurnCos2 = 0;
      for (int l = 0; l < count; ++l)
        turnedOnly += !(expected >> l & 1) && sodt::moveAllowed(foldOnly, y[l], cur, ee, quality, limit);
    }
    if (pass != expected && ++mismatches <= 5)
      ADD_FAILURE() << "trial " << trial << ": lanes " << pass << ", scalar " << expected << " of " << count;
    if (expected != (1 << count) - 1) {
      // The witness is a triangle that refuses one of the refused positions:
      // the scalar test started there fails there.
      bool found = false;
      for (int l = 0; l < count && !found; ++l) {
        if (expected >> l & 1) continue;
        int w = witness;
        found = witness >= 0 && witness < n && !sodt::moveAllowed(st, y[l], cur, ee, quality, limit, &w) &&
                w == witness;
      }
      badWitness += !found;
    }
    allowed += __builtin_popcount(static_cast<unsigned>(expected));
    refused += count - __builtin_popcount(static_cast<unsigned>(expected));
    mixed += expected != 0 && expected != (1 << count) - 1;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(badWitness, 0);
  // Both answers, and groups with both, occur often enough to mean something.
  EXPECT_GT(allowed, 10000);
  EXPECT_GT(refused, 10000);
  EXPECT_GT(mixed, 1000) << allowed << " allowed, " << refused << " refused";
  EXPECT_GT(turnedOnly, 1000);  // refused for the face turn alone
}

namespace {

template <class M>
void load(M& m, const std::string& name) {
  const std::string path = std::string(SODT_MESH_DIR) + "/" + name;
  ASSERT_TRUE(sodt_test::fileExists(path)) << path;
  sodt::loadMesh(path, m);
}

std::vector<long long> counters(const sodt::SodtStats& s) {
  return {s.iterations, s.moved,         s.backtracked, s.rejected, s.failedSolves,  s.unchanged,
          s.fallbackMoves, s.activeVertices, s.flips,    s.skipped,  s.returnedSweep};
}

/// Runs Algorithm 1 with and without the kernel and compares positions and
/// faces bit for bit, and every counter.
template <class M>
void expectSameRuns(const std::string& name, sodt::Guard guard, bool flips, int threads, int iterations,
                    double maxDeviationRel = sodt::SodtParams().maxDeviationRel,
                    sodt::Algorithm algorithm = sodt::Algorithm::Basic) {
  SCOPED_TRACE(name + ", " + sodt::toString(algorithm) + ", guard " + sodt::toString(guard) +
               (flips ? ", flips" : "") + ", threads " + std::to_string(threads) + ", deviation bound " +
               std::to_string(maxDeviationRel));
  M with, without;
  load(with, name);
  load(without, name);
  sodt::SodtParams p;
  p.algorithm = algorithm;
  p.guard = guard;
  p.iterations = iterations;
  p.flips = flips;
  p.threads = threads;
  p.maxDeviationRel = maxDeviationRel;
  const sodt::SodtStats a = sodt::SodtSmoother<M>::Apply(with, p);
  sodt::SweepTuning scalar;
  scalar.simd = false;
  const sodt::SodtStats b = sodt::SodtSmoother<M>::Apply(without, p, nullptr, nullptr, scalar);
  EXPECT_EQ(counters(a), counters(b));
  EXPECT_EQ(a.deviationQueries, b.deviationQueries);
  EXPECT_EQ(a.deviationReused, b.deviationReused);
  EXPECT_EQ(b.laneVisits, 0);
  // Most visits of smooth vertices go through the kernel (the others have a
  // rare valence or are left over from an incomplete group of four); crease
  // vertices never do.
  const long long visits = static_cast<long long>(a.activeVertices) * a.iterations - a.skipped;
  const long long creaseVisits = static_cast<long long>(a.creaseVertices) * a.iterations;
  EXPECT_GT(a.laneVisits, (visits - creaseVisits) * 3 / 4);
  EXPECT_LE(a.laneVisits, static_cast<long long>(a.activeVertices) * a.iterations - creaseVisits);
  const auto pa = sodt_test::positions(with), pb = sodt_test::positions(without);
  ASSERT_EQ(pa.size(), pb.size());
  int differ = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) differ += std::memcmp(&pa[i], &pb[i], sizeof pa[i]) != 0;
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(sodt_test::faceIndices(with), sodt_test::faceIndices(without));
}

}  // namespace

TEST(Lanes, FaceKeysMatchTheScalarPassBitForBit) {
  if (!sodt::lanes::available()) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  using sodt_test::uniform;
  std::mt19937 g(77);
  int mismatches = 0, inverted = 0, degenerate = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<Vec3> pos, ref;
    std::vector<int> tri;
    for (int l = 0; l < sodt::lanes::kWidth; ++l) {
      const double scale = std::pow(10.0, uniform(g, -6, 6));
      Vec3 p[3];
      for (Vec3& q : p) q = Vec3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1)) * scale;
      switch (g() % 6) {
        case 0:  // any triangle
          break;
        case 1:  // collinear
          p[2] = p[0] + (p[1] - p[0]) * 0.25;
          break;
        case 2:  // a zero-length edge
          p[1] = p[0];
          break;
        case 3:  // a single point
          p[1] = p[2] = p[0];
          break;
        case 4:  // equilateral: three tied edges
          p[0] = Vec3(1, 0, 0) * scale, p[1] = Vec3(0, 1, 0) * scale, p[2] = Vec3(0, 0, 1) * scale;
          break;
        case 5:  // integer coordinates, ties between edges
          for (Vec3& q : p) q = Vec3(double(g() % 4), double(g() % 4), double(g() % 4));
          break;
      }
      for (int j = 0; j < 3; ++j) {
        tri.push_back(static_cast<int>(pos.size()));
        pos.push_back(p[j]);
      }
      const Vec3 area = sodt::doubleAreaVector(p[0], p[1], p[2]);
      const unsigned r = g() % 3;
      ref.push_back(r == 0 ? area : r == 1 ? -area : Vec3(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1)));
    }
    // The faces' vertices scattered over pos.
    std::vector<int> perm(pos.size());
    for (std::size_t v = 0; v < perm.size(); ++v) perm[v] = static_cast<int>(v);
    std::shuffle(perm.begin(), perm.end(), g);
    std::vector<Vec3> scattered(pos.size());
    for (std::size_t v = 0; v < pos.size(); ++v) scattered[perm[v]] = pos[v];
    for (int& v : tri) v = perm[v];
    pos.swap(scattered);
    sodt::lanes::FaceKeys out;
    sodt::lanes::faceKeys4(&pos[0][0], tri.data(), &ref[0][0], out);
    for (int l = 0; l < sodt::lanes::kWidth; ++l) {
      Vec3 area;
      const double want = sodt::detail::minAngleSin2(pos[tri[3 * l]], pos[tri[3 * l + 1]], pos[tri[3 * l + 2]], area);
      const bool inv = area * ref[l] < 0;
      mismatches += !sameBits(out.key[l], want) || ((out.inverted >> l & 1) != 0) != inv;
      inverted += inv;
      degenerate += want == 0;
    }
    sodt::lanes::FaceKeys none;
    none.inverted = -1;
    sodt::lanes::faceKeys4(&pos[0][0], tri.data(), nullptr, none);
    EXPECT_EQ(none.inverted, 0);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(inverted, 10000) << "the trials should turn faces over";
  EXPECT_GT(degenerate, 10000) << "the trials should hold degenerate faces";
}

SODT_FULL_FIXTURE_TEST(Lanes, SweepsAreTheSameWithAndWithoutTheKernel) {
  if (!sodt::lanes::available()) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  using sodt::Guard;
  // Every case of the full fixture, with fewer sweeps in the small one.
  const int many = sodt_test::fullFixture() ? 10 : 3, few = sodt_test::fullFixture() ? 6 : 2;
  expectSameRuns<sodt::MeshD>("blobs_mc.ply", Guard::None, false, 1, many);
  expectSameRuns<sodt::MeshD>("blobs_mc.ply", Guard::None, false, 2, many);
  expectSameRuns<sodt::MeshF>("blobs_mc.ply", Guard::None, false, 2, many);
  expectSameRuns<sodt::MeshF>("sphere_jitter.ply", Guard::None, false, 1, many);
  expectSameRuns<sodt::MeshD>("torus.off", Guard::None, true, 2, few);
  expectSameRuns<sodt::MeshD>("cube_noisy.ply", Guard::None, true, 1, few);
  expectSameRuns<sodt::MeshF>("blobs_mc.ply", Guard::Quality, false, 2, many);
  expectSameRuns<sodt::MeshD>("blobs_mc.ply", Guard::Fold, false, 1, many);
  expectSameRuns<sodt::MeshD>("cube_noisy.ply", Guard::Quality, true, 2, few);
  expectSameRuns<sodt::MeshF>("plane_grid_open.ply", Guard::Quality, false, 1, few);
  // With the bound, the kernel's accepted full steps are committed when the
  // margins answer the deviation test; a tight bound leaves many to the
  // scalar visit's distance queries, a loose one few.
  expectSameRuns<sodt::MeshF>("sphere_jitter.ply", Guard::Quality, false, 2, many, 1e-4);
  expectSameRuns<sodt::MeshD>("blobs_mc.ply", Guard::Fold, false, 1, many, 1e-2);
  // Without the deviation bound the kernel's accepted full steps are committed directly.
  expectSameRuns<sodt::MeshF>("blobs_mc.ply", Guard::Fold, false, 1, many, 0.0);
  expectSameRuns<sodt::MeshD>("blobs_mc.ply", Guard::Quality, false, 2, many, 0.0);
  expectSameRuns<sodt::MeshF>("sphere_jitter.ply", Guard::Quality, false, 1, many, 0.0);
  expectSameRuns<sodt::MeshD>("cube_noisy.ply", Guard::Fold, true, 2, few, 0.0);
}

SODT_FULL_FIXTURE_TEST(Lanes, FeatureSweepsAreTheSameWithAndWithoutTheKernel) {
  // Algorithm 2 moves its smooth vertices as Algorithm 1 does, through the
  // kernel; its crease vertices, with the kernel's smooth neighbours around
  // them, go through the scalar visit.
  if (!sodt::lanes::available()) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  using sodt::Algorithm;
  using sodt::Guard;
  const double bound = sodt::SodtParams().maxDeviationRel;
  const int many = sodt_test::fullFixture() ? 10 : 3, few = sodt_test::fullFixture() ? 6 : 2;
  expectSameRuns<sodt::MeshF>("cube_noisy.ply", Guard::Quality, false, 1, many, bound, Algorithm::Feature);
  expectSameRuns<sodt::MeshD>("cube_jitter.ply", Guard::Quality, false, 2, many, bound, Algorithm::Feature);
  expectSameRuns<sodt::MeshD>("cube_noisy.ply", Guard::Fold, true, 2, few, bound, Algorithm::Feature);
  expectSameRuns<sodt::MeshF>("cube_jitter.ply", Guard::Quality, false, 1, many, 0.0, Algorithm::Feature);
  expectSameRuns<sodt::MeshD>("cube_noisy.ply", Guard::None, false, 2, few, bound, Algorithm::Feature);
  expectSameRuns<sodt::MeshF>("blobs_mc.ply", Guard::Quality, false, 2, many, 1e-4, Algorithm::Feature);
  // The cubes have creases, so both kinds of visit were compared.
  sodt::MeshD m;
  load(m, "cube_noisy.ply");
  sodt::SodtParams p;
  p.algorithm = Algorithm::Feature;
  p.iterations = 1;
  EXPECT_GT(sodt::SodtSmoother<sodt::MeshD>::Apply(m, p).creaseVertices, 0);
}

TEST(Lanes, DenoiseSweepsAreTheSameWithAndWithoutTheKernel) {
  // Algorithm 3's smooth vertices with a fitted plane go through the kernel
  // (denoiseTargets in the lanes), its crease vertices through the scalar visit.
  if (!sodt::lanes::available()) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  using sodt::Algorithm;
  using sodt::Guard;
  const double bound = sodt::SodtParams().maxDeviationRel;  // not used by Algorithm 3
  expectSameRuns<sodt::MeshF>("cube_noisy.ply", Guard::Quality, false, 1, 10, bound, Algorithm::Denoise);
  expectSameRuns<sodt::MeshD>("cube_noisy.ply", Guard::Quality, false, 2, 10, bound, Algorithm::Denoise);
  expectSameRuns<sodt::MeshD>("cube_jitter.ply", Guard::Fold, true, 2, 6, bound, Algorithm::Denoise);
  expectSameRuns<sodt::MeshF>("sphere_jitter.ply", Guard::Quality, false, 2, 10, bound, Algorithm::Denoise);
  expectSameRuns<sodt::MeshD>("blobs_mc.ply", Guard::None, false, 1, 6, bound, Algorithm::Denoise);
  expectSameRuns<sodt::MeshF>("torus.off", Guard::Fold, false, 1, 10, bound, Algorithm::Denoise);
}

SODT_FULL_FIXTURE_TEST(Lanes, EveryAlgorithmIsTheSameWithAndWithoutTheStepLengthTest) {
  // The lanes test step lengths four at once for every algorithm, not only
  // for the Algorithm 1 kernel's vertices.
  if (!sodt::lanes::available()) GTEST_SKIP() << "no AVX2 kernel in this build or on this processor";
  using sodt::Algorithm;
  const struct {
    const char* mesh;
    Algorithm algorithm;
    sodt::Guard guard;
    int threads;
  } runs[] = {{"cube_noisy.ply", Algorithm::Feature, sodt::Guard::Quality, 1},
              {"cube_noisy.ply", Algorithm::Denoise, sodt::Guard::Quality, 2},
              {"cube_jitter.ply", Algorithm::Feature, sodt::Guard::Fold, 2},
              {"blobs_mc.ply", Algorithm::Odt, sodt::Guard::Quality, 1},
              {"sphere_jitter.ply", Algorithm::Laplacian, sodt::Guard::Quality, 2}};
  for (const auto& r : runs) {
    SCOPED_TRACE(std::string(r.mesh) + ", " + sodt::toString(r.algorithm) + ", guard " + sodt::toString(r.guard));
    sodt::MeshF with, without;
    load(with, r.mesh);
    load(without, r.mesh);
    sodt::SodtParams p;
    p.algorithm = r.algorithm;
    p.guard = r.guard;
    p.iterations = sodt_test::fullFixture() ? 8 : 3;
    p.threads = r.threads;
    const sodt::SodtStats a = sodt::SodtSmoother<sodt::MeshF>::Apply(with, p);
    sodt::SweepTuning scalar;
    scalar.simd = false;
    const sodt::SodtStats b = sodt::SodtSmoother<sodt::MeshF>::Apply(without, p, nullptr, nullptr, scalar);
    EXPECT_EQ(counters(a), counters(b));
    EXPECT_EQ(a.deviationQueries, b.deviationQueries);
    EXPECT_EQ(a.deviationReused, b.deviationReused);
    // Shortened steps and rejections happen, so lengths were tested in groups.
    EXPECT_GT(a.backtracked + a.rejected, 0);
    EXPECT_EQ(sodt_test::positions(with), sodt_test::positions(without));
  }
}
