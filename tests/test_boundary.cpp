// SPDX-License-Identifier: GPL-3.0-or-later
// Border vertices that slide along the border (SodtParams::slideBoundary):
// they move, the rim's angles improve, corners stay, a straight border stays
// exactly on its line, the border keeps its length, selections are obeyed,
// and the result is the same for every thread count, with and without lanes.
#include "test_mesh.h"

#include <sodt_io/io.h>
#include <sodt_io/metrics.h>
#include <sodt_io/prebuilt.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace {

using sodt::MeshD;

/// A planar n x n grid over [0,1]^2 whose interior is jittered and whose
/// border vertices (corners aside) are shifted along the border by up to
/// 0.45 cells: thin triangles at the rim, the border still the square.
void makeBadRimGrid(MeshD& m, int n, unsigned seed) {
  sodt_test::makeGrid(m, n, 0.3, seed);
  std::mt19937 g(seed + 1);
  const double h = 1.0 / (n - 1);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const bool rowEnd = x == 0 || x == n - 1, colEnd = y == 0 || y == n - 1;
      if (rowEnd == colEnd) continue;  // interior, or a corner
      const double s = sodt_test::uniform(g, -0.45, 0.45) * h;
      vcg::Point3d& p = m.vert[y * n + x].P();
      if (colEnd)
        p[0] += s;  // bottom or top row: along x
      else
        p[1] += s;  // left or right column: along y
    }
}

bool isCorner(int i, int n) { return i == 0 || i == n - 1 || i == n * (n - 1) || i == n * n - 1; }

/// The smallest angle (degrees) of the faces with a vertex on the border
/// of the input topology.
double rimMinAngleDeg(const MeshD& m, const sodt::RingTopology& topo) {
  double lo = 180;
  for (const auto& f : m.face) {
    bool rim = false;
    for (int j = 0; j < 3; ++j) rim = rim || topo.kind[f.cV(j) - &m.vert[0]] == sodt::VertexKind::Boundary;
    if (!rim) continue;
    const auto P = [&](int j) { return sodt::Vec3(f.cP(j)[0], f.cP(j)[1], f.cP(j)[2]); };
    lo = std::min(lo, sodt::triangleMinAngle(P(0), P(1), P(2)) * sodt::kRadToDeg);
  }
  return lo;
}

sodt::SodtStats smooth(MeshD& m, bool slide, bool flips = false, int threads = 1, bool simd = true,
                       bool selectedOnly = false) {
  sodt::SodtParams p;
  p.slideBoundary = slide;
  p.flips = flips;
  p.threads = threads;
  p.selectedOnly = selectedOnly;
  sodt::SweepTuning tuning;
  tuning.simd = simd;
  return sodt::SodtSmoother<MeshD>::Apply(m, p, nullptr, nullptr, tuning);
}

}  // namespace

TEST(Boundary, BorderVerticesSlideAndTheRimAnglesImprove) {
  for (bool flips : {false, true}) {
    MeshD fixed, sliding;
    makeBadRimGrid(fixed, 12, 3);
    makeBadRimGrid(sliding, 12, 3);
    const sodt::RingTopology topo = sodt::buildRingTopology(fixed);
    const double before = rimMinAngleDeg(fixed, topo);
    smooth(fixed, false, flips);
    const sodt::SodtStats s = smooth(sliding, true, flips);
    EXPECT_EQ(s.slidingBoundary, 4 * 10);
    EXPECT_GT(s.movedBoundary, 20);
    EXPECT_EQ(s.fixedBoundary, 4);
    // Fixed, the rim keeps its thin triangles; sliding, they open up.
    const double kept = rimMinAngleDeg(fixed, topo), slid = rimMinAngleDeg(sliding, topo);
    EXPECT_GT(slid, kept + 5) << "flips " << flips << ", input " << before;
    EXPECT_GE(sodt::computeAngleStats(sliding).minDeg, sodt::computeAngleStats(fixed).minDeg);
  }
}

TEST(Boundary, CornersOfTheBorderNeverMove) {
  const int n = 12;
  for (bool flips : {false, true}) {
    MeshD in, m;
    makeBadRimGrid(in, n, 4);
    makeBadRimGrid(m, n, 4);
    const sodt::SodtStats s = smooth(m, true, flips);
    EXPECT_EQ(s.boundaryCorners, 4);
    for (int i = 0; i < n * n; ++i)
      if (isCorner(i, n)) { EXPECT_EQ(m.vert[i].cP(), in.vert[i].cP()) << i; }
  }
}

TEST(Boundary, AStraightBorderStaysExactlyOnItsLineAndKeepsItsLength) {
  const int n = 12;
  MeshD in, m;
  makeBadRimGrid(in, n, 5);
  makeBadRimGrid(m, n, 5);
  const sodt::SodtStats s = smooth(m, true, true);
  ASSERT_GT(s.movedBoundary, 20);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const vcg::Point3d& p = m.vert[y * n + x].cP();
      EXPECT_EQ(p[2], 0.0);
      // Exactly collinear: the coordinate across the border is its input value.
      if (y == 0 || y == n - 1) { EXPECT_EQ(p[1], in.vert[y * n + x].cP()[1]) << x << "," << y; }
      if (x == 0 || x == n - 1) { EXPECT_EQ(p[0], in.vert[y * n + x].cP()[0]) << x << "," << y; }
      // And within the side: no vertex slides past a corner.
      EXPECT_GE(p[0], 0.0);
      EXPECT_LE(p[0], 1.0);
      EXPECT_GE(p[1], 0.0);
      EXPECT_LE(p[1], 1.0);
    }
  // The border is the square's sides, in order: length 4 up to rounding.
  EXPECT_NEAR(sodt::borderLength(m), 4.0, 1e-12);
  const sodt::RingTopology after = sodt::buildRingTopology(m);
  for (int i = 0; i < n * n; ++i) {
    const int x = i % n, y = i / n;
    const bool border = x == 0 || y == 0 || x == n - 1 || y == n - 1;
    EXPECT_EQ(after.kind[i] == sodt::VertexKind::Boundary, border) << i;
  }
}

TEST(Boundary, ACurvedBorderKeepsItsLength) {
  // A half cylinder of radius 1 (the angle along x, the axis along y) with
  // 16 segments around, jittered along the arcs: its two semicircular
  // borders slide along their curve.
  MeshD m;
  sodt_test::makeHalfCylinder(m, 16, 0.4, 7);
  const double before = sodt::borderLength(m);
  MeshD fixed;
  vcg::tri::Append<MeshD, MeshD>::MeshCopy(fixed, m);
  const sodt::RingTopology topo = sodt::buildRingTopology(m);
  const sodt::SodtStats s = smooth(m, true, true);
  smooth(fixed, false, true);
  EXPECT_GT(s.movedBoundary, 10);
  EXPECT_LT(std::abs(sodt::borderLength(m) - before), 1e-3 * before);
  EXPECT_GT(rimMinAngleDeg(m, topo), rimMinAngleDeg(fixed, topo));
}

TEST(Boundary, OnlySelectedBorderVerticesSlide) {
  const int n = 12;
  MeshD in, m;
  makeBadRimGrid(in, n, 6);
  makeBadRimGrid(m, n, 6);
  for (auto& v : m.vert) v.ClearS();
  for (int i = 0; i < n * n; ++i)
    if (i % n < n / 2) m.vert[i].SetS();  // the left half
  const sodt::SodtStats s = smooth(m, true, false, 1, true, true);
  EXPECT_GT(s.movedBoundary, 5);
  int movedSelected = 0;
  for (int i = 0; i < n * n; ++i) {
    if (!m.vert[i].IsS()) {
      EXPECT_EQ(m.vert[i].cP(), in.vert[i].cP()) << i;
    } else if (m.vert[i].cP() != in.vert[i].cP()) {
      ++movedSelected;
    }
  }
  EXPECT_GT(movedSelected, 0);
}

TEST(Boundary, ResultsAreBitIdenticalForEveryThreadCountWithAndWithoutLanes) {
  // 120 x 120 vertices: several tiles, phases split between threads.
  MeshD input;
  makeBadRimGrid(input, 120, 8);
  for (bool flips : {false, true}) {
    std::vector<vcg::Point3d> ref;
    std::vector<std::array<int, 3>> refFaces;
    long long refMoved = -1;
    for (int threads : {1, 2, 3})
      for (bool simd : {true, false}) {
        MeshD m;
        vcg::tri::Append<MeshD, MeshD>::MeshCopy(m, input);
        const sodt::SodtStats s = smooth(m, true, flips, threads, simd);
        const std::string what = std::string(flips ? "flips, " : "") + std::to_string(threads) + " threads" +
                                 (simd ? "" : ", no lanes");
        if (ref.empty()) {
          ASSERT_GT(s.movedBoundary, 100) << what;
          ref = sodt_test::positions(m);
          refFaces = sodt_test::faceIndices(m);
          refMoved = s.moved + s.backtracked + s.fallbackMoves;
          continue;
        }
        EXPECT_TRUE(sodt_test::positions(m) == ref) << what;  // exact
        EXPECT_TRUE(sodt_test::faceIndices(m) == refFaces) << what;
        EXPECT_EQ(s.moved + s.backtracked + s.fallbackMoves, refMoved) << what;
      }
  }
}
