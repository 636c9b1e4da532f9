// The per-sweep quality of keepBest and toleranceDeg against its definition:
// every face's smallest angle, sorted.
#include <gtest/gtest.h>
#include <sodt/guards/sweep_quality.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "test_mesh.h"

namespace {

using sodt::Vec3;

/// The definition: every live face's angle in degrees, the value at index
/// floor(0.01 (n - 1)) in upward order, the smallest, and the faces whose
/// area vector points against the reference.
sodt::SweepQuality everyFaceMeasured(const sodt::FaceList& faces, const std::vector<Vec3>& pos,
                                     const std::vector<Vec3>& ref) {
  std::vector<double> deg;
  sodt::SweepQuality q;
  for (std::size_t f = 0; f < faces.tri.size(); ++f) {
    if (!faces.live[f]) continue;
    const auto& t = faces.tri[f];
    deg.push_back(sodt::triangleMinAngle(pos[t[0]], pos[t[1]], pos[t[2]]) * sodt::kRadToDeg);
    if (!ref.empty() && sodt::doubleAreaVector(pos[t[0]], pos[t[1]], pos[t[2]]) * ref[f] < 0) ++q.inverted;
  }
  if (deg.empty()) return q;
  std::sort(deg.begin(), deg.end());
  q.minDeg = deg.front();
  q.p1Deg = deg[static_cast<std::size_t>(std::floor(0.01 * double(deg.size() - 1)))];
  return q;
}

/// An n x n grid of unit squares, two triangles each, in the plane z = 0,
/// every vertex moved by up to jitter in x and y; reference normals +z.
struct Grid {
  sodt::FaceList faces;
  std::vector<Vec3> pos;
  std::vector<Vec3> ref;
};

Grid makeGrid(int n, double jitter, unsigned seed) {
  std::mt19937 g(seed);
  Grid gr;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      gr.pos.emplace_back(x + sodt_test::uniform(g, -jitter, jitter), y + sodt_test::uniform(g, -jitter, jitter), 0);
  const auto id = [n](int x, int y) { return y * (n + 1) + x; };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      gr.faces.tri.push_back({id(x, y), id(x + 1, y), id(x + 1, y + 1)});
      gr.faces.tri.push_back({id(x, y), id(x + 1, y + 1), id(x, y + 1)});
    }
  gr.faces.live.assign(gr.faces.tri.size(), 1);
  gr.faces.flippable.assign(gr.faces.tri.size(), 1);
  gr.ref.assign(gr.faces.tri.size(), Vec3(0, 0, 1));
  return gr;
}

void expectSame(const Grid& gr, const char* what) {
  const sodt::SweepQuality want = everyFaceMeasured(gr.faces, gr.pos, gr.ref);
  for (bool simd : {false, true})
    for (int threads : {1, 2, 3}) {
      const sodt::SweepQuality got = sodt::measureSweepQuality(gr.faces, gr.pos, gr.ref, threads, simd);
      const std::string how = std::string(what) + ", " + std::to_string(threads) + " threads" + (simd ? ", lanes" : "");
      EXPECT_EQ(got.minDeg, want.minDeg) << how;
      EXPECT_EQ(got.p1Deg, want.p1Deg) << how;
      EXPECT_EQ(got.inverted, want.inverted) << how;
    }
}

TEST(SweepQuality, SameAsEveryFaceMeasured) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    // Small and large (the large one runs on threads), mild and wild.
    expectSame(makeGrid(7, 0.2, seed), "7x7, jitter 0.2");
    expectSame(makeGrid(120, 0.1, seed), "120x120, jitter 0.1");
    expectSame(makeGrid(120, 0.45, seed), "120x120, jitter 0.45 (some faces inverted)");
  }
}

TEST(SweepQuality, TiesAndNearTiesAtThePercentile) {
  // All faces alike: every one is a tie with the percentile face.
  expectSame(makeGrid(100, 0.0, 1), "regular grid");
  // Faces alike up to rounding: the angles differ in the last digits, where
  // the order of the squared cosines and of the angles could disagree.
  for (unsigned seed = 1; seed <= 5; ++seed) expectSame(makeGrid(100, 1e-13, seed), "near ties");
  // Two populations with the cut-off between them at the percentile.
  Grid gr = makeGrid(100, 0.0, 1);
  for (std::size_t v = 0; v < gr.pos.size(); v += 37) gr.pos[v][0] += 1e-11 * double(v % 5);
  expectSame(gr, "a few vertices off by 1e-11");
}

TEST(SweepQuality, PercentileAtTheEdgeOfAPopulation) {
  // 20000 separate isosceles triangles: m of them with a 5 degree apex,
  // the others 40 degrees. The percentile (index 199) is the last thin one
  // or the first fat one depending on m.
  const int n = 20000, idx = 199;
  for (int m : {idx - 1, idx, idx + 1}) {
    Grid gr;
    for (int f = 0; f < n; ++f) {
      const double half = (f < m ? 2.5 : 20.0) * sodt::kPi / 180.0;
      const Vec3 o(3.0 * f, 0, 0);
      gr.pos.push_back(o);
      gr.pos.push_back(o + Vec3(std::cos(half), -std::sin(half), 0));
      gr.pos.push_back(o + Vec3(std::cos(half), std::sin(half), 0));
      gr.faces.tri.push_back({3 * f, 3 * f + 1, 3 * f + 2});
    }
    gr.faces.live.assign(n, 1);
    gr.faces.flippable.assign(n, 1);
    gr.ref.assign(n, Vec3(0, 0, 1));
    const sodt::SweepQuality want = everyFaceMeasured(gr.faces, gr.pos, gr.ref);
    ASSERT_NEAR(want.p1Deg, m > idx ? 5.0 : 40.0, 1e-9) << "fixture: " << m << " thin faces";
    expectSame(gr, m < idx ? "fewer thin faces than the index" : m == idx ? "as many" : "more");
  }
}

TEST(SweepQuality, DegenerateDeadAndInvertedFaces) {
  Grid gr = makeGrid(60, 0.1, 3);
  // A zero-length edge, a flat (collinear) triangle, dead faces.
  gr.pos[5] = gr.pos[6];
  gr.pos[62] = gr.pos[0] + (gr.pos[1] - gr.pos[0]) * 2.0;  // face 0: (0, 1, 62)
  for (std::size_t f = 0; f < gr.faces.live.size(); f += 11) gr.faces.live[f] = 0;
  // Faces turned over.
  for (std::size_t f = 3; f < gr.ref.size(); f += 97) gr.ref[f] = Vec3(0, 0, -1);
  const sodt::SweepQuality want = everyFaceMeasured(gr.faces, gr.pos, gr.ref);
  ASSERT_EQ(want.minDeg, 0.0) << "fixture should hold a degenerate face";
  ASSERT_GT(want.inverted, 0) << "fixture should hold inverted faces";
  expectSame(gr, "degenerate, dead and inverted faces");
  // Without references nothing counts as inverted.
  EXPECT_EQ(sodt::measureSweepQuality(gr.faces, gr.pos, {}, 2).inverted, 0);
}

TEST(SweepQuality, FewOrNoLiveFaces) {
  Grid gr = makeGrid(3, 0.2, 9);
  expectSame(gr, "18 faces");
  std::fill(gr.faces.live.begin(), gr.faces.live.end(), 0);
  gr.faces.live[4] = 1;
  expectSame(gr, "one live face");
  gr.faces.live[4] = 0;
  const sodt::SweepQuality none = sodt::measureSweepQuality(gr.faces, gr.pos, gr.ref, 2);
  EXPECT_EQ(none.minDeg, 0.0);
  EXPECT_EQ(none.p1Deg, 0.0);
  EXPECT_EQ(none.inverted, 0);
}

TEST(SweepQuality, BetterPrefersFewerInvertedThenMinimumThenPercentile) {
  sodt::SweepQuality a, b;
  a.minDeg = 10, a.p1Deg = 20;
  b.minDeg = 12, b.p1Deg = 15;
  EXPECT_TRUE(b.better(a));
  EXPECT_FALSE(a.better(b));
  b.inverted = 1;
  EXPECT_TRUE(a.better(b));
  b = a;
  b.p1Deg = 21;
  EXPECT_TRUE(b.better(a));
  EXPECT_FALSE(a.better(a));
}

}  // namespace
