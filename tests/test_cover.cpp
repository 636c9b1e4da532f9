// SPDX-License-Identifier: GPL-3.0-or-later
// The deviation bound's other direction (cover.h): the input stays near the
// output, so the sweeps cannot cut off a tip, and the two-way distance stays
// near the bound.
#include <sodt/guards/cover.h>
#include <sodt/guards/input_grid.h>
#include <sodt_io/metrics.h>
#include <sodt_io/mesh.h>
#include <sodt_io/prebuilt.h>

#include <vcg/complex/append.h>

#include "test_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

namespace {

using sodt::Vec3;

/// Distance from q to the nearest live face of m.
double distanceToSurface(const sodt::MeshD& m, const Vec3& q) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    const auto at = [&](int j) { return Vec3(f.cP(j)[0], f.cP(j)[1], f.cP(j)[2]); };
    best = std::min(best, sodt::pointTriangleDistance2(q, at(0), at(1), at(2)));
  }
  return std::sqrt(best);
}

double diagonal(sodt::MeshD& m) {
  vcg::tri::UpdateBounding<sodt::MeshD>::Box(m);
  return m.bbox.Diag();
}

/// A unit icosphere (subdivision 3) jittered tangentially, with vertex 0
/// moved sideways by 0.4 edge lengths and then pulled out along its radius
/// into a gentle tip (5% of the radius; its ring stays on the sphere). The
/// sweeps slide the tip back to the middle of its ring in its tangent
/// plane; the one-way bound (output near input) lets that cut the tip by
/// about twice the bound (1.95 bounds before the cover).
void makeTippedSphere(sodt::MeshD& m) {
  sodt_test::makeSphere(m, 3);
  sodt_test::jitterOnSphere(m, 0.3, 7);
  const double edge = vcg::Distance(m.face[0].cP(0), m.face[0].cP(1));
  vcg::Point3d& tip = m.vert[0].P();
  vcg::Point3d side = tip ^ vcg::Point3d(0.3, 0.5, 0.8);
  side.Normalize();
  tip = tip + side * (0.4 * edge);
  tip.Normalize();
  tip *= 1.05;
}

constexpr double kBound = 0.001;  // maxDeviationRel of the tests
// What the cover guarantees for its points, with room for the rounding of
// the relative bound.
const double kCovered = sodt::kCoverLimitFactor * kBound * (1 + 1e-6);

TEST(InputCover, TipOfTheInputStaysWithinTheBoundOfTheOutput) {
  for (bool flips : {false, true}) {
    for (sodt::Algorithm a : {sodt::Algorithm::Basic, sodt::Algorithm::Feature}) {
      sodt::MeshD input, out;
      makeTippedSphere(input);
      vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(out, input);
      sodt::SodtParams p;
      p.algorithm = a;
      p.flips = flips;
      p.maxDeviationRel = kBound;
      p.iterations = 20;
      sodt::SodtSmoother<sodt::MeshD>::Apply(out, p);
      const double diag = diagonal(input);
      const vcg::Point3d tip = input.vert[0].cP();
      const double d = distanceToSurface(out, Vec3(tip[0], tip[1], tip[2])) / diag;
      const std::string what = std::string(sodt::toString(a)) + (flips ? " flips" : "");
      // The tip still moved (the sweeps did work around it) ...
      EXPECT_GT(vcg::Distance(out.vert[0].cP(), tip), 0.0) << what;
      // ... and the input tip is within the cover's limit of the output.
      EXPECT_LE(d, kCovered) << what << ": tip " << d / kBound << " bounds from the output";
    }
  }
}

/// On a jittered cube, basic slides the vertices next to the edges across
/// them in their tangent planes: the sampled distance both ways stays within
/// 1.5 times the bound (1.77 bounds without flips, 2.14 with, before the
/// cover), and every input vertex lies within the cover's limit of the output.
TEST(InputCover, SymmetricDistanceStaysNearTheBoundOnAJitteredCube) {
  for (bool flips : {false, true}) {
    sodt::MeshD input, out;
    sodt_test::makeCube(input, 12, 0.3, 3);
    vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(out, input);
    sodt::SodtParams p;
    p.flips = flips;
    p.maxDeviationRel = kBound;
    p.iterations = 20;
    sodt::SodtSmoother<sodt::MeshD>::Apply(out, p);
    const sodt::DistanceStats d = sodt::surfaceDistance(input, out);
    EXPECT_LE(d.maxRel, 1.5 * kBound) << (flips ? "flips" : "no flips");
    const double diag = diagonal(input);
    double worst = 0;
    for (const auto& v : input.vert)
      worst = std::max(worst, distanceToSurface(out, Vec3(v.cP()[0], v.cP()[1], v.cP()[2])) / diag);
    EXPECT_LE(worst, kCovered) << (flips ? "flips" : "no flips");
  }
}

/// On a half cylinder whose vertices are jittered along the arcs, sliding
/// along the border evens out the borders' chords: the new chords cut the
/// input's corners, each within the one-way bound, but the input's border
/// vertices between them end farther from the output.
TEST(InputCover, SlidingBorderKeepsTheInputBorderCovered) {
  for (unsigned seed : {3u, 7u, 11u}) {
    sodt::MeshD input, out;
    sodt_test::makeHalfCylinder(input, 24, 0.45, seed);
    vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(out, input);
    sodt::SodtParams p;
    p.slideBoundary = true;
    p.flips = true;
    p.maxDeviationRel = kBound;
    p.iterations = 20;
    const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(out, p);
    EXPECT_GT(s.movedBoundary, 0) << "seed " << seed;
    const double diag = diagonal(input);
    double worst = 0;
    for (const auto& v : input.vert)
      worst = std::max(worst, distanceToSurface(out, Vec3(v.cP()[0], v.cP()[1], v.cP()[2])) / diag);
    EXPECT_LE(worst, kCovered) << "seed " << seed << ": " << worst / kBound << " bounds";
  }
}

/// A flip that would lift the pair off an input point is refused; one that
/// keeps it near is taken, and the point moves to the nearer new face.
TEST(InputCover, FlipKeepsThePairsPointsCovered) {
  // A folded square: a-b is the crease edge, c and d its wings.
  std::vector<Vec3> pos = {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 0, 0.5), Vec3(0, 1, 0.5)};
  sodt::FaceList faces;
  faces.tri = {{0, 1, 2}, {1, 0, 3}};
  faces.live = {1, 1};
  faces.flippable = {1, 1};
  const sodt::RingTopology topo = sodt::buildRingTopology(faces, std::vector<char>(4, 0));
  sodt::InputCover cover;
  cover.prepare(faces, topo, pos, 0.01);
  EXPECT_GT(cover.points(), 4u);
  // The crease edge's midpoint lies 0.25 below the flipped pair.
  EXPECT_FALSE(cover.coveredAfterFlip(0, 1, {0, 3, 2}, {3, 1, 2}));
  // Flat, the flip changes nothing of the surface.
  pos[2][2] = pos[3][2] = 0;
  sodt::InputCover flat;
  flat.prepare(faces, topo, pos, 0.01);
  ASSERT_TRUE(flat.coveredAfterFlip(0, 1, {0, 3, 2}, {3, 1, 2}));
  faces.tri = {{0, 3, 2}, {3, 1, 2}};
  flat.commitFlip(0, 1);
  EXPECT_LE(flat.largestDistance(), 1e-12);
}

TEST(InputGrid, CandidatesHoldEveryTriangleWithinTheRadiusAndNotAllOthers) {
  // A soup of small triangles and needles in the unit cube: the candidates
  // of a ball (the repair's cover check measures them itself) hold every
  // triangle forEachNear finds within it, and a small ball leaves out most
  // of the soup.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> pos;
  sodt::FaceList faces;
  for (int k = 0; k < 400; ++k) {
    const Vec3 a(u(rng), u(rng), u(rng));
    const double size = k % 4 == 0 ? 0.3 : 0.03;  // every fourth a long needle
    const Vec3 b = a + Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * size;
    const Vec3 c = k % 4 == 0 ? (a + b) * 0.5 + Vec3(1e-4, 0, 0) : a + Vec3(u(rng), u(rng), u(rng)) * size;
    const int base = static_cast<int>(pos.size());
    pos.insert(pos.end(), {a, b, c});
    faces.tri.push_back({base, base + 1, base + 2});
    faces.live.push_back(1);
    faces.flippable.push_back(1);
  }
  const sodt::InputGrid grid(pos, faces);
  std::size_t found = 0, candidates = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 q(u(rng), u(rng), u(rng));
    const double r = 0.01 + 0.1 * u(rng);
    std::set<int> near, cand;
    ASSERT_TRUE(grid.forEachNear(q, r, [&near](int k) { near.insert(k); }));
    ASSERT_TRUE(grid.forEachCandidate(q, r, [&cand](int k) { cand.insert(k); }));
    for (int k : near) EXPECT_EQ(cand.count(k), 1u) << "query " << i << " misses triangle " << k;
    found += near.size();
    candidates += cand.size();
  }
  EXPECT_GT(found, 0u);
  // A candidate is a triangle whose box meets the ball: a few more than
  // those within it, far fewer than the soup (200 x 400).
  EXPECT_LT(candidates, 3 * found);
}

}  // namespace
