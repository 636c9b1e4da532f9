// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the pure S-ODT kernels: the closed form against brute-force
// minimisation of Eq. 5, Appendix B's invariant, equivariance, degeneracy, guards.
#include "test_mesh.h"

#include <sodt/maths/local_solve.h>
#include <sodt/maths/odt.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

using sodt::Star;
using sodt::Vec3;

namespace {

// The fold test written out plainly, triangle by triangle, as the
// definition prepareGuard and moveAllowed are checked against.
void foldReferences(const Star& st, const Vec3& n, std::vector<Vec3>& cur) {
  cur.resize(st.size());
  for (std::size_t k = 0; k < st.size(); ++k) {
    const Vec3& a = st.at(k);
    const Vec3& b = st.at(k + 1);
    const Vec3 now = sodt::doubleAreaVector(st.center, a, b);
    const double l2now = std::max({(a - st.center).SquaredNorm(), (b - st.center).SquaredNorm(),
                                   (b - a).SquaredNorm()});
    cur[k] = now.Norm() > sodt::kCollapse * l2now ? now : n;
  }
}

bool moveFolds(const Star& st, const Vec3& p, const std::vector<Vec3>& cur) {
  const bool haveRef = st.refNormal.size() == st.size();
  for (std::size_t k = 0; k < st.size(); ++k) {
    const Vec3& a = st.at(k);
    const Vec3& b = st.at(k + 1);
    const Vec3 next = sodt::doubleAreaVector(p, a, b);
    if (!(next * cur[k] > 0)) return true;
    if (haveRef && next * st.refNormal[k] < 0) return true;
    const double l2 = std::max({(a - p).SquaredNorm(), (b - p).SquaredNorm(), (b - a).SquaredNorm()});
    if (!(next.SquaredNorm() > sodt::kCollapse * sodt::kCollapse * l2 * l2)) return true;
  }
  return false;
}

/// A random star-shaped ring around the origin, roughly in the z = 0 plane,
/// with the centre displaced inside it; radii and angular gaps vary widely.
Star randomStar(std::mt19937& g, double zNoise) {
  Star st;
  const int n = 4 + static_cast<int>(sodt_test::uniform01(g) * 6);  // 4..9
  std::vector<double> ang(n);
  double a = 0;
  for (int k = 0; k < n; ++k) {
    a += sodt_test::uniform(g, 0.3, 1.0);
    ang[k] = a;
  }
  for (int k = 0; k < n; ++k) {
    const double t = ang[k] / a * 2 * sodt::kPi;
    const double r = sodt_test::uniform(g, 0.5, 2.0);
    st.ring.emplace_back(r * std::cos(t), r * std::sin(t), sodt_test::uniform(g, -zNoise, zNoise));
  }
  st.center = Vec3(sodt_test::uniform(g, -0.2, 0.2), sodt_test::uniform(g, -0.2, 0.2),
                   sodt_test::uniform(g, -zNoise, zNoise));
  return st;
}

/// Minimises the energy of Eq. 5 over the tangent plane by compass search,
/// starting from the centre: no use of the closed form.
Vec3 bruteForceMinimum(const Star& st, const Vec3& n) {
  Vec3 s, t;
  sodt::tangentFrame(n, s, t);
  double u = 0, v = 0, step = 1.0;
  auto energy = [&](double uu, double vv) { return sodt::sodtEnergy(st, st.center + s * uu + t * vv, n); };
  double best = energy(u, v);
  while (step > 1e-11) {
    bool improved = false;
    const double du[8] = {1, -1, 0, 0, 1, 1, -1, -1}, dv[8] = {0, 0, 1, -1, 1, -1, 1, -1};
    for (int d = 0; d < 8; ++d) {
      const double e = energy(u + step * du[d], v + step * dv[d]);
      if (e < best) {
        best = e;
        u += step * du[d];
        v += step * dv[d];
        improved = true;
        break;
      }
    }
    if (!improved) step *= 0.5;
  }
  return st.center + s * u + t * v;
}

}  // namespace

TEST(LocalSolve, ClosedFormMatchesBruteForceOnRandomStars) {
  std::mt19937 g(12345);
  int compared = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Star st = randomStar(g, trial % 2 ? 0.3 : 0.0);
    const sodt::LocalMove mv = sodt::solveStar(st);
    if (!mv.ok) continue;
    const Vec3 brute = bruteForceMinimum(st, mv.normal);
    EXPECT_LT((mv.target - brute).Norm(), 1e-6) << "trial " << trial;
    // The closed form is a stationary point: the energy rises in every direction.
    Vec3 s, t;
    sodt::tangentFrame(mv.normal, s, t);
    const double e0 = sodt::sodtEnergy(st, mv.target, mv.normal);
    for (int d = 0; d < 8; ++d) {
      const double ang = d * sodt::kPi / 4;
      const Vec3 q = mv.target + (s * std::cos(ang) + t * std::sin(ang)) * 1e-4;
      EXPECT_GE(sodt::sodtEnergy(st, q, mv.normal), e0 - 1e-12 * std::abs(e0));
    }
    // The target lies in the tangent plane through the centre.
    EXPECT_NEAR((mv.target - st.center) * mv.normal, 0.0, 1e-12);
    ++compared;
  }
  EXPECT_GT(compared, 250);  // almost every star-shaped ring gives a convex problem
}

TEST(LocalSolve, SumOfProjectedAreasIsInvariant) {
  std::mt19937 g(777);
  for (int trial = 0; trial < 100; ++trial) {
    const Star st = randomStar(g, 0.4);
    const Vec3 n = sodt::starNormal(st);
    Vec3 s, t;
    sodt::tangentFrame(n, s, t);
    auto sumD = [&](const Vec3& p) {
      double c = 0;
      for (std::size_t k = 0; k < st.size(); ++k) c += sodt::projectedDoubleArea(st, k, p, n);
      return c;
    };
    const double c0 = sumD(st.center);
    for (int j = 0; j < 10; ++j) {
      const Vec3 p = st.center + s * sodt_test::uniform(g, -3, 3) + t * sodt_test::uniform(g, -3, 3);
      EXPECT_NEAR(sumD(p), c0, 1e-12 * (1 + std::abs(c0)));
    }
  }
}

TEST(LocalSolve, RegularStarIsFixedPointAndPerturbedCentreIsPulledBack) {
  for (int n = 3; n <= 8; ++n) {
    Star st;
    for (int k = 0; k < n; ++k)
      st.ring.emplace_back(std::cos(2 * sodt::kPi * k / n), std::sin(2 * sodt::kPi * k / n), 0);
    st.center = Vec3(0, 0, 0);
    sodt::LocalMove mv = sodt::solveStar(st);
    ASSERT_TRUE(mv.ok) << n;
    EXPECT_LT(mv.target.Norm(), 1e-14) << n;
    st.center = Vec3(0.2, -0.1, 0);
    mv = sodt::solveStar(st);
    ASSERT_TRUE(mv.ok) << n;
    EXPECT_LT(mv.target.Norm(), 1e-12) << n;  // planar ring: the plane is exact, target is the centre
  }
}

TEST(LocalSolve, MoveIsEquivariantUnderRigidMotionAndScale) {
  std::mt19937 g(99);
  for (int trial = 0; trial < 50; ++trial) {
    const Star st = randomStar(g, 0.3);
    const sodt::LocalMove mv = sodt::solveStar(st);
    if (!mv.ok) continue;
    // rotation about an oblique axis, then scale and translation
    const Vec3 axis = Vec3(1, 2, 3).Normalize();
    const double ang = 0.7, scale = 3.5;
    const Vec3 shift(10, -4, 2);
    auto xf = [&](const Vec3& p) {
      const Vec3 r = p * std::cos(ang) + (axis ^ p) * std::sin(ang) + axis * (axis * p) * (1 - std::cos(ang));
      return r * scale + shift;
    };
    Star moved;
    moved.center = xf(st.center);
    for (const Vec3& p : st.ring) moved.ring.push_back(xf(p));
    const sodt::LocalMove mv2 = sodt::solveStar(moved);
    ASSERT_TRUE(mv2.ok);
    EXPECT_LT((mv2.target - xf(mv.target)).Norm(), 1e-9 * scale);
  }
}

TEST(LocalSolve, DegenerateStarsFailCleanly) {
  Star collapsed;  // every ring point on the centre
  collapsed.center = Vec3(1, 1, 1);
  collapsed.ring.assign(5, Vec3(1, 1, 1));
  sodt::LocalMove mv = sodt::solveStar(collapsed);
  EXPECT_FALSE(mv.ok);
  EXPECT_TRUE(sodt::isFinite(mv.target));
  EXPECT_EQ(mv.target, collapsed.center);

  Star line;  // collinear ring: zero area everywhere
  line.center = Vec3(0, 0, 0);
  for (int k = 0; k < 4; ++k) line.ring.emplace_back(k - 1.5, 0, 0);
  mv = sodt::solveStar(line);
  EXPECT_FALSE(mv.ok);
  EXPECT_TRUE(sodt::isFinite(mv.target));

  Star tiny;  // fewer than three neighbours
  tiny.ring = {Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_FALSE(sodt::solveStar(tiny).ok);
}

TEST(Guards, FoldedPositionsAreRejected) {
  Star st;  // regular hexagon around the origin, plane z = 0
  for (int k = 0; k < 6; ++k)
    st.ring.emplace_back(std::cos(sodt::kPi * k / 3), std::sin(sodt::kPi * k / 3), 0);
  st.center = Vec3(0, 0, 0);
  const Vec3 n(0, 0, 1);
  EXPECT_FALSE(sodt::moveFolds(st, Vec3(0.3, 0.2, 0), n));
  EXPECT_TRUE(sodt::moveFolds(st, Vec3(1.5, 0, 0), n));     // outside the ring: triangles flip
  EXPECT_TRUE(sodt::moveFolds(st, (st.ring[0] + st.ring[1]) * 0.5, n));  // on a ring edge: collapses
  EXPECT_TRUE(sodt::moveFolds(st, st.ring[2], n));          // onto a neighbour
  // Any position outside the hexagon's kernel folds some triangle.
  std::mt19937 g(5);
  for (int j = 0; j < 1000; ++j) {
    const Vec3 p(sodt_test::uniform(g, -2, 2), sodt_test::uniform(g, -2, 2), 0);
    bool inside = true;
    for (int k = 0; k < 6; ++k) {
      const Vec3 a = st.at(k), b = st.at(k + 1);
      if (((b - a) ^ (p - a))[2] <= 1e-9) inside = false;
    }
    if (!inside) {
      EXPECT_TRUE(sodt::moveFolds(st, p, n)) << p[0] << " " << p[1];
    }
  }
}

TEST(Guards, FacesMayNotTurnBeyondTheBoundFromTheirInputNormal) {
  // A flat regular hexagon with input normals +z: lifting the centre by h
  // tilts every triangle by atan(h / cos 30), 27.5 degrees for h = 0.45 and
  // 32.4 for h = 0.55. With a 30-degree bound the first is allowed and the
  // second refused; with none (90 degrees) both are, and a turned-over
  // triangle is refused either way.
  Star st;
  for (int k = 0; k < 6; ++k)
    st.ring.emplace_back(std::cos(sodt::kPi * k / 3), std::sin(sodt::kPi * k / 3), 0);
  st.center = Vec3(0, 0, 0);
  st.refNormal.assign(6, Vec3(0, 0, 1));
  const Vec3 n(0, 0, 1);
  EXPECT_EQ(sodt::faceTurnCos2(90), 0.0);
  EXPECT_EQ(sodt::faceTurnCos2(120), 0.0);
  st.maxTurnCos2 = sodt::faceTurnCos2(30);
  EXPECT_FALSE(sodt::moveFolds(st, Vec3(0, 0, 0.45), n));
  EXPECT_TRUE(sodt::moveFolds(st, Vec3(0, 0, 0.55), n));
  EXPECT_TRUE(sodt::moveFolds(st, Vec3(0, 0, -0.55), n));
  st.maxTurnCos2 = 0;
  EXPECT_FALSE(sodt::moveFolds(st, Vec3(0, 0, 0.55), n));
  EXPECT_FALSE(sodt::moveFolds(st, Vec3(0, 0, 20), n));
  // A zero input normal (a face without one) bounds nothing.
  st.maxTurnCos2 = sodt::faceTurnCos2(30);
  st.refNormal.assign(6, Vec3(0, 0, 0));
  EXPECT_FALSE(sodt::moveFolds(st, Vec3(0, 0, 0.55), n));
  // turnsBeyond is the angle test itself, for any length of the area vector.
  std::mt19937 g(77);
  for (int j = 0; j < 10000; ++j) {
    const Vec3 a(sodt_test::uniform(g, -1, 1), sodt_test::uniform(g, -1, 1), sodt_test::uniform(g, -1, 1));
    const double deg = sodt_test::uniform(g, 1, 89), turn = sodt::angleBetween(a, n) * sodt::kRadToDeg;
    if (std::abs(turn - deg) < 1e-6) continue;
    EXPECT_EQ(sodt::turnsBeyond(a * 1e-3, n, sodt::faceTurnCos2(deg)), turn > deg) << turn << " " << deg;
  }
}

TEST(Guards, QualityMeasureIsTheStarsSmallestAngle) {
  Star st;
  for (int k = 0; k < 6; ++k)
    st.ring.emplace_back(std::cos(sodt::kPi * k / 3), std::sin(sodt::kPi * k / 3), 0);
  EXPECT_NEAR(sodt::starMinAngle(st, Vec3(0, 0, 0)) * sodt::kRadToDeg, 60.0, 1e-9);
  EXPECT_LT(sodt::starMinAngle(st, Vec3(0.5, 0, 0)) * sodt::kRadToDeg, 60.0);
}

TEST(Guards, MoveAllowedAgreesWithItsDefinitionWhateverTheWitness) {
  // moveAllowed = no triangle folds (moveFolds) and, with quality, none gets
  // a smaller smallest angle (starKeepsMinAngle); the triangle tested first
  // (witness) changes only the time, and a false answer names a culprit.
  std::mt19937 g(31);
  int allowed = 0, refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Star st = randomStar(g, 0.3);
    const Vec3 n = sodt::starNormal(st);
    std::vector<Vec3> cur;
    std::vector<double> edge2;
    foldReferences(st, n, cur);
    sodt::ringEdgeLengths2(st, edge2);
    const bool quality = trial % 2 == 0;
    const double limit = sodt::starMinAngleCos2(st, st.center);
    const Vec3 p = st.center + Vec3(sodt_test::uniform(g, -0.8, 0.8), sodt_test::uniform(g, -0.8, 0.8), 0);
    const bool expected = !moveFolds(st, p, cur) && (!quality || sodt::starKeepsMinAngle(st, p, limit));
    const int n0 = static_cast<int>(st.size());
    for (int w = -1; w <= n0; ++w) {
      int witness = w;
      ASSERT_EQ(sodt::moveAllowed(st, p, cur, edge2, quality, limit, &witness), expected) << trial << " " << w;
      if (!expected) {
        ASSERT_GE(witness, 0);
        ASSERT_LT(witness, n0);
        // The culprit alone refuses the move: a one-triangle star of it does.
        Star one;
        one.center = st.center;
        one.ring = {st.at(witness), st.at(witness + 1)};
        const Vec3 a = sodt::doubleAreaVector(p, one.ring[0], one.ring[1]);
        const bool folds = !(a * cur[witness] > 0) ||
                           !(a.SquaredNorm() > 1e-24 * std::pow(std::max({(one.ring[0] - p).SquaredNorm(),
                                                                           (one.ring[1] - p).SquaredNorm(),
                                                                           edge2[witness]}), 2));
        const bool worse = quality && sodt::triangleMinAngleCos2(p, one.ring[0], one.ring[1]) > limit;
        ASSERT_TRUE(folds || worse) << trial << " " << w;
      }
    }
    (expected ? allowed : refused)++;
  }
  EXPECT_GT(allowed, 500);
  EXPECT_GT(refused, 500);
}

TEST(Guards, PrepareGuardIsTheSeparateFunctionsBitForBit) {
  // prepareGuard fuses the fold references, ringEdgeLengths2 and
  // starMinAngleCos2: every value must be the same bits as theirs, on general stars,
  // on stars with tied edge lengths (every corner choice and its ties),
  // collapsed and nearly collapsed triangles, a centre on the ring and
  // collinear rings.
  std::mt19937 g(57);
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int collapsed = 0, corners[3] = {0, 0, 0};
  for (int trial = 0; trial < 20000; ++trial) {
    Star st = randomStar(g, trial % 3 == 0 ? 0.0 : 0.3);
    const int n = static_cast<int>(st.size());
    switch (trial % 6) {
      case 1:  // integer grid: many exactly tied lengths
        for (Vec3& q : st.ring) q = Vec3(std::round(q[0] * 2), std::round(q[1] * 2), std::round(q[2] * 2));
        st.center = Vec3(0, 0, 0);
        break;
      case 2:  // the centre on a ring vertex or ring vertices repeated
        if (trial % 4 == 0) st.center = st.ring[trial % n];
        else st.ring[(trial + 1) % n] = st.ring[trial % n];
        break;
      case 3:  // collinear
        for (int k = 0; k < n; ++k) st.ring[k] = Vec3(k - n / 2.0, 0, 0);
        break;
      case 4: {  // the centre just off a ring edge, at the collapse threshold of its triangle
        const Vec3 &a = st.ring[trial % n], &b = st.at(trial % n + 1);
        Vec3 d = (b - a) ^ Vec3(0, 0, 1);
        d /= d.Norm();
        st.center = (a + b) * 0.5 + d * ((trial % 4 == 0 ? 0.5e-12 : -0.5e-12) * (b - a).Norm());
        break;
      }
      default: break;
    }
    const Vec3 nrm = sodt::starNormal(st);
    std::vector<Vec3> cur, cur2;
    std::vector<double> edge2, edge22;
    foldReferences(st, nrm, cur);
    sodt::ringEdgeLengths2(st, edge2);
    const bool quality = trial % 5 != 4;
    const double worst = quality ? sodt::starMinAngleCos2(st, st.center) : 1.0;
    ASSERT_TRUE(same(sodt::prepareGuard(st, nrm, quality, cur2, edge22), worst)) << trial;
    ASSERT_EQ(cur2.size(), cur.size());
    ASSERT_EQ(edge22.size(), edge2.size());
    for (int k = 0; k < n; ++k) {
      ASSERT_TRUE(same(edge22[k], edge2[k])) << trial << " " << k;
      for (int j = 0; j < 3; ++j) ASSERT_TRUE(same(cur2[k][j], cur[k][j])) << trial << " " << k;
      collapsed += cur[k] == nrm;
      // Which corner holds the smallest angle (as triangleMinAngleCos2 picks it).
      const double uu = (st.at(k) - st.center).SquaredNorm(), ww = (st.at(k + 1) - st.center).SquaredNorm();
      ++corners[edge2[k] <= uu && edge2[k] <= ww ? 0 : ww <= uu ? 1 : 2];
    }
  }
  EXPECT_GT(collapsed, 1000);
  for (int c : corners) EXPECT_GT(c, 10000);
}

namespace {

/// Minimises the energy of Eq. 5 (normal n) along the line c + d e by
/// bracketing and golden-section search: no use of the closed form.
double bruteForceOnLine(const Star& st, const Vec3& n, const Vec3& c, const Vec3& e) {
  auto f = [&](double d) { return sodt::sodtEnergy(st, c + e * d, n); };
  double lo = -8, hi = 8;
  const double r = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo), f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < 200; ++it) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1, x1 = hi - r * (hi - lo), f1 = f(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2, x2 = lo + r * (hi - lo), f2 = f(x2);
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST(LocalSolve, QuadraticFormReproducesTheEnergy) {
  std::mt19937 g(31);
  for (int trial = 0; trial < 50; ++trial) {
    const Star st = randomStar(g, 0.4);
    const Vec3 n = sodt::starNormal(st);
    const sodt::StarQuadratic q = sodt::sodtQuadratic(st, n);
    const double e0 = sodt::sodtEnergy(st, st.center, n);
    for (int j = 0; j < 5; ++j) {  // anywhere in space, not only in the plane
      const Vec3 p(sodt_test::uniform(g, -1, 1), sodt_test::uniform(g, -1, 1), sodt_test::uniform(g, -1, 1));
      const double want = sodt::sodtEnergy(st, st.center + p, n) - e0;
      EXPECT_NEAR(q.quad(p, p) + q.g * p, want, 1e-9 * (1 + std::abs(want)));
    }
  }
}

TEST(LocalSolve, CreaseMinimiserMatchesBruteForceAndCorrectsEq11Sign) {
  std::mt19937 g(4242);
  int compared = 0, printedSignGoesUphill = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Star st = randomStar(g, 0.3);
    const Vec3 n = sodt::starNormal(st);
    Vec3 s, t;
    sodt::tangentFrame(n, s, t);
    const double a = sodt_test::uniform(g, 0, 2 * sodt::kPi);
    const Vec3 e = s * std::cos(a) + t * std::sin(a);  // a crease direction in the tangent plane
    const sodt::StarQuadratic q = sodt::sodtQuadratic(st, n);
    Vec3 p;
    if (!sodt::minimizeOnLine(q, Vec3(0, 0, 0), e, p)) continue;
    const double d = p * e;
    EXPECT_NEAR(d, bruteForceOnLine(st, n, st.center, e), 1e-6) << trial;
    // The paper's Eq. 11 coefficients, summed exactly as printed.
    double A = 0, B = 0, C = 0;
    for (std::size_t k = 0; k < st.size(); ++k) {
      const Vec3 Xa = st.at(k) - st.center, Xb = st.at(k + 1) - st.center;
      const double detE = (e ^ (Xb - Xa)) * n;  // det(e3, X_{k+1} - X_k, n)
      const double detX = (Xa ^ Xb) * n;        // det(X_k, X_{k+1}, n)
      C += detX;
      A += (e * (Xa + Xb)) * detE;
      B += (e * (Xa + Xb)) * detX + (Xa.SquaredNorm() - Xa * Xb + Xb.SquaredNorm()) * detE;
    }
    A += C;
    EXPECT_NEAR(d, B / (2 * A), 1e-9 * (1 + std::abs(d)));  // the corrected sign
    const double e0 = sodt::sodtEnergy(st, st.center, n);
    if (std::abs(d) > 1e-6) {
      const double printed = -B / (2 * A);
      EXPECT_LT(sodt::sodtEnergy(st, st.center + e * d, n), e0);
      printedSignGoesUphill += sodt::sodtEnergy(st, st.center + e * printed, n) > e0;
    }
    ++compared;
  }
  EXPECT_GT(compared, 150);
  EXPECT_GT(printedSignGoesUphill, compared * 9 / 10);
}

TEST(LocalSolve, OffsetPlaneMinimiserMatchesBruteForce) {
  // Algorithm 3 minimises over a fitted plane that need not pass through the centre.
  std::mt19937 g(515);
  int compared = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Star st = randomStar(g, 0.3);
    Vec3 nf = sodt::starNormal(st) + Vec3(sodt_test::uniform(g, -0.1, 0.1), sodt_test::uniform(g, -0.1, 0.1), 0);
    nf.Normalize();
    const Vec3 p0 = nf * sodt_test::uniform(g, -0.2, 0.2);
    Vec3 s, t;
    sodt::tangentFrame(nf, s, t);
    const sodt::StarQuadratic q = sodt::sodtQuadratic(st, nf);
    Vec3 p;
    if (!sodt::minimizeOnPlane(q, p0, s, t, p)) continue;
    EXPECT_NEAR((p - p0) * nf, 0.0, 1e-12);
    // compass search in the plane
    double u = 0, v = 0, step = 1;
    auto energy = [&](double uu, double vv) { return sodt::sodtEnergy(st, st.center + p0 + s * uu + t * vv, nf); };
    double best = energy(0, 0);
    while (step > 1e-11) {
      bool moved = false;
      for (int d = 0; d < 4 && !moved; ++d) {
        const double du = d == 0 ? step : d == 1 ? -step : 0, dv = d == 2 ? step : d == 3 ? -step : 0;
        const double e = energy(u + du, v + dv);
        if (e < best) best = e, u += du, v += dv, moved = true;
      }
      if (!moved) step *= 0.5;
    }
    EXPECT_LT((p - (p0 + s * u + t * v)).Norm(), 1e-6) << trial;
    ++compared;
  }
  EXPECT_GT(compared, 80);
}

TEST(Odt, GradientMatchesFiniteDifferences) {
  std::mt19937 g(606);
  for (int trial = 0; trial < 50; ++trial) {
    const Star st = randomStar(g, 0.3);
    const Vec3 p = st.center + Vec3(sodt_test::uniform(g, -0.1, 0.1), sodt_test::uniform(g, -0.1, 0.1), 0);
    const Vec3 grad = sodt::odtGradient(st, p);
    for (int k = 0; k < 3; ++k) {
      Vec3 d(0, 0, 0);
      d[k] = 1e-6;
      const double fd = (sodt::odtEnergy(st, p + d) - sodt::odtEnergy(st, p - d)) / 2e-6;
      EXPECT_NEAR(grad[k], fd, 1e-5 * (1 + std::abs(fd)));
    }
  }
}

TEST(Odt, EqualsSodtOnPlanarStarsAndMinimisesEq3) {
  // In a plane every D'_k is twice the true area S'_k, so Eq. 3 and Eq. 5 agree.
  std::mt19937 g(707);
  int compared = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Star st = randomStar(g, 0.0);
    const sodt::LocalMove sodtMove = sodt::solveStar(st);
    const sodt::LocalMove odtMove = sodt::solveStarOdt(st);
    if (!sodtMove.ok || !odtMove.ok) continue;
    // only where no triangle folds at the S-ODT optimum (there the two energies differ)
    bool folds = false;
    for (std::size_t k = 0; k < st.size(); ++k)
      folds |= sodt::projectedDoubleArea(st, k, sodtMove.target, sodtMove.normal) <= 0;
    if (folds) continue;
    EXPECT_LT((odtMove.target - sodtMove.target).Norm(), 1e-6) << trial;
    ++compared;
  }
  EXPECT_GT(compared, 50);
  // Off the plane, the numerical optimum is a local minimum of Eq. 3 in the tangent plane.
  for (int trial = 0; trial < 50; ++trial) {
    const Star st = randomStar(g, 0.4);
    const sodt::LocalMove mv = sodt::solveStarOdt(st);
    if (!mv.ok) continue;
    Vec3 s, t;
    sodt::tangentFrame(mv.normal, s, t);
    const double e0 = sodt::odtEnergy(st, mv.target);
    for (int d = 0; d < 8; ++d) {
      const double ang = d * sodt::kPi / 4;
      EXPECT_GE(sodt::odtEnergy(st, mv.target + (s * std::cos(ang) + t * std::sin(ang)) * 1e-4),
                e0 - 1e-10 * std::abs(e0));
    }
  }
}

namespace {

/// True when x is a float value (finite, normal or zero): at most 24
/// significant bits. Checked on the bits, with no float conversion an
/// optimiser could fold away.
bool isFloatValue(double x) {
  if (x == 0) return true;
  int e = 0;
  const double m = std::ldexp(std::frexp(x, &e), 24);  // |m| in [2^23, 2^24)
  return m == std::trunc(m) && e <= 128 && e >= -125;
}

/// The step of a guarded move as the smoother computes it: a point moved by
/// a fraction of a step, rounded to float. Not inlined, so that each call
/// is compiled the way the smoother's own code is (two neighbouring
/// conversions that a vectorizer may pair).
__attribute__((noinline)) Vec3 steppedToFloat(const Vec3& c, const Vec3& step, double f) {
  return sodt::roundedTo<float>(c + step * f);
}

}  // namespace

TEST(Geometry, RoundedToFloatRoundsEveryCoordinate) {
  std::mt19937 g(31);
  int unrounded = 0, far = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    const Vec3 c(sodt_test::uniform(g, -2, 2), sodt_test::uniform(g, -2, 2), sodt_test::uniform(g, -2, 2));
    const Vec3 step(sodt_test::uniform(g, -0.1, 0.1), sodt_test::uniform(g, -0.1, 0.1), sodt_test::uniform(g, -0.1, 0.1));
    const double f = std::ldexp(1.0, -static_cast<int>(g() % 5));
    const Vec3 x = c + step * f;
    const Vec3 y = steppedToFloat(c, step, f);
    for (int j = 0; j < 3; ++j) {
      unrounded += !isFloatValue(y[j]);
      // The nearest float: within half a float unit in the last place.
      far += !(std::abs(y[j] - x[j]) <= std::ldexp(std::abs(x[j]), -24));
    }
  }
  EXPECT_EQ(unrounded, 0);
  EXPECT_EQ(far, 0);
  // A double is kept as it is.
  const Vec3 p(0.1, 0.2, 0.3);
  const Vec3 q = sodt::roundedTo<double>(p);
  EXPECT_EQ(std::memcmp(&p, &q, sizeof p), 0);
  EXPECT_FALSE(isFloatValue(0.1));
  EXPECT_TRUE(isFloatValue(static_cast<double>(0.1f)));
}
