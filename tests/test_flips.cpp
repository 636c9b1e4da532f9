// SPDX-License-Identifier: GPL-3.0-or-later
// Edge flips between sweeps, best-state return and the tolerance stop:
// manifoldness, creases never flipped, returned quality never below the input's.
#include "test_mesh.h"

#include <sodt/flips.h>
#include <sodt/io.h>
#include <sodt/metrics.h>
#include <sodt/prebuilt.h>
#include <sodt/topology.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <set>

namespace {

std::set<std::pair<int, int>> edgeSet(const sodt::MeshD& m) {
  std::set<std::pair<int, int>> e;
  for (const auto& f : m.face)
    for (int j = 0; j < 3; ++j) {
      const int a = int(f.cV(j) - &m.vert[0]), b = int(f.cV((j + 1) % 3) - &m.vert[0]);
      e.insert({std::min(a, b), std::max(a, b)});
    }
  return e;
}

/// Edges whose two faces' normals differ by more than minDeg.
std::set<std::pair<int, int>> sharpEdges(const sodt::MeshD& m, double minDeg) {
  std::set<std::pair<int, int>> out;
  for (const auto& kv : sodt_test::dihedralAngles(m))
    if (kv.second > minDeg) out.insert(kv.first);
  return out;
}

sodt::SodtStats smooth(sodt::MeshD& m, sodt::Algorithm a, bool flips, sodt::Guard g = sodt::Guard::Quality,
                       bool keepBest = false, double tol = 0, int iterations = 20) {
  sodt::SodtParams p;
  p.algorithm = a;
  p.flips = flips;
  p.guard = g;
  p.keepBest = keepBest;
  p.toleranceDeg = tol;
  p.iterations = iterations;
  return sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
}

}  // namespace

TEST(Flips, FlipPassImprovesAPlanarPairAndRefusesAFold) {
  // Quad a(0,0) b(1,0.05) c(0.5,0.1) d(0.5,-2): the pair (a,b,c),(b,a,d) has a sliver.
  std::vector<sodt::Vec3> pos{{0, 0, 0}, {1, 0, 0}, {0.5, 0.05, 0}, {0.5, -1, 0}};
  sodt::FaceList fl;
  fl.tri = {{{0, 1, 2}}, {{1, 0, 3}}};
  fl.live = {1, 1};
  fl.flippable = {1, 1};
  EXPECT_EQ(sodt::flipPass(fl, pos, sodt::FlipRules{}), 1);
  EXPECT_EQ(fl.tri[0], (std::array<int, 3>{{0, 3, 2}}));
  EXPECT_EQ(fl.tri[1], (std::array<int, 3>{{3, 1, 2}}));
  // A non-convex quad: flipping would fold, so nothing happens.
  std::vector<sodt::Vec3> dart{{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {1.5, -0.05, 0}};
  fl.tri = {{{0, 1, 2}}, {{1, 0, 3}}};
  EXPECT_EQ(sodt::flipPass(fl, dart, sodt::FlipRules{}), 0);
  // Not flippable (selection) or too sharp a dihedral: nothing happens.
  fl.tri = {{{0, 1, 2}}, {{1, 0, 3}}};
  fl.flippable = {1, 0};
  EXPECT_EQ(sodt::flipPass(fl, pos, sodt::FlipRules{}), 0);
  fl.flippable = {1, 1};
  std::vector<sodt::Vec3> bent = pos;
  bent[3][2] = 1.0;  // 45 degrees out of the plane
  EXPECT_EQ(sodt::flipPass(fl, bent, sodt::FlipRules{}), 0);
}

TEST(Flips, KeepVertexCountManifoldnessAndOrientation) {
  sodt::MeshD m;
  sodt_test::makeSphere(m, 3);
  sodt_test::jitterOnSphere(m, 0.45, 77);
  const int nv = m.vn, nf = m.fn;
  const double vol0 = sodt::enclosedVolume(m).volume;
  const auto before = sodt::computeAngleStats(m);
  const sodt::SodtStats s = smooth(m, sodt::Algorithm::Basic, true);
  EXPECT_GT(s.flips, 0);
  EXPECT_EQ(m.vn, nv);
  EXPECT_EQ(m.fn, nf);
  EXPECT_TRUE(sodt::isClosedOriented(m));
  const sodt::RingTopology t = sodt::buildRingTopology(m);
  for (int i = 0; i < m.vn; ++i) EXPECT_EQ(t.kind[i], sodt::VertexKind::Interior) << i;
  EXPECT_GT(sodt::computeAngleStats(m).minDeg, before.minDeg);
  EXPECT_LT(std::abs(sodt::enclosedVolume(m).volume - vol0) / vol0, 1e-2);
}

TEST(Flips, PerFaceDataStaysWithItsTriangle) {
  // The sweeps keep faces in an order of their own; after flips each
  // triangle must be written back to its own mesh face, so that per-face
  // data stays with it: a face that no flip touched keeps its slot (a
  // triangle that a flip and a flip back recreate may come back in the
  // slot of its neighbour). And each face's normal must be its own.
  sodt::MeshD m;
  sodt_test::makeSphere(m, 3);
  sodt_test::jitterOnSphere(m, 0.45, 78);
  std::mt19937 g(4);
  std::shuffle(m.face.begin(), m.face.end(), g);  // faces stored in no particular order
  const auto triple = [&m](const sodt::MeshD::FaceType& f) {
    std::array<int, 3> t;
    for (int j = 0; j < 3; ++j) t[j] = int(f.cV(j) - &m.vert[0]);
    std::sort(t.begin(), t.end());
    return t;
  };
  std::vector<std::array<int, 3>> before;
  for (const auto& f : m.face) before.push_back(triple(f));
  const std::set<std::array<int, 3>> input(before.begin(), before.end());
  const sodt::SodtStats s = smooth(m, sodt::Algorithm::Basic, true);
  EXPECT_GT(s.flips, 0);
  int unchanged = 0, sameSlot = 0;
  for (std::size_t f = 0; f < m.face.size(); ++f) {
    const std::array<int, 3> t = triple(m.face[f]);
    unchanged += input.count(t) > 0;
    sameSlot += t == before[f];
    const vcg::Point3d a = vcg::TriangleNormal(m.face[f]).Normalize();
    EXPECT_LT((m.face[f].cN() - a).Norm(), 1e-12) << f;
  }
  EXPECT_GT(unchanged, m.fn / 2);
  EXPECT_GE(sameSlot, unchanged - 2 * s.flips);  // each flip touches two faces
}

TEST(Flips, CubeEdgesAreNeverFlipped) {
  for (sodt::Algorithm a : {sodt::Algorithm::Basic, sodt::Algorithm::Feature}) {
    sodt::MeshD m;
    sodt_test::makeCube(m, 8, 0.3, 5);
    const auto sharp = sharpEdges(m, 30);
    ASSERT_EQ(sharp.size(), 12u * 8u);  // 12 cube edges of 8 segments each
    const sodt::SodtStats s = smooth(m, a, true);
    EXPECT_GT(s.flips, 0);
    const auto edges = edgeSet(m);
    for (const auto& e : sharp) EXPECT_TRUE(edges.count(e)) << e.first << "-" << e.second;
  }
}

TEST(Flips, OnlySelectedFacesAreFlipped) {
  sodt::MeshD m;
  sodt_test::makeGrid(m, 15, 0.4, 3);
  for (auto& v : m.vert) (v.P()[0] < 0.5) ? v.SetS() : v.ClearS();
  const auto e0 = edgeSet(m);
  sodt::SodtParams p;
  p.flips = true;
  p.selectedOnly = true;
  const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
  EXPECT_GT(s.flips, 0);
  // every new edge joins two selected vertices
  for (const auto& e : edgeSet(m))
    if (!e0.count(e)) EXPECT_TRUE(m.vert[e.first].IsS() && m.vert[e.second].IsS());
}

TEST(KeepBest, ReturnedQualityIsNeverBelowTheInput) {
  // The literal update (guard none) wrecks the bundled marching-cubes mesh
  // within 50 sweeps; keepBest must hand back a state at least as good as the input.
  const std::string path = std::string(SODT_MESH_DIR) + "/blobs_mc.ply";
  ASSERT_TRUE(sodt_test::fileExists(path)) << path;
  sodt::MeshD m;
  sodt::loadMesh(path, m);
  sodt::MeshD literal;
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(literal, m);
  const double input = sodt::computeAngleStats(m).minDeg;
  smooth(literal, sodt::Algorithm::Basic, false, sodt::Guard::None, false, 0, 50);
  ASSERT_LT(sodt::computeAngleStats(literal).minDeg, input) << "fixture should degrade without keepBest";
  for (bool flips : {false, true}) {
    sodt::MeshD w;
    vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(w, m);
    const sodt::SodtStats s = smooth(w, sodt::Algorithm::Basic, flips, sodt::Guard::None, true, 0, 50);
    EXPECT_GE(sodt::computeAngleStats(w).minDeg, input);
    EXPECT_LE(s.returnedSweep, s.iterations);
    EXPECT_TRUE(sodt::isClosedOriented(w));
  }
}

TEST(KeepBest, ToleranceStopsWhenSweepsStopHelping) {
  sodt::MeshD m;
  sodt_test::makeSphere(m, 3);
  sodt_test::jitterOnSphere(m, 0.3, 6);
  const sodt::SodtStats s = smooth(m, sodt::Algorithm::Basic, false, sodt::Guard::Quality, false, 0.5, 50);
  EXPECT_TRUE(s.stoppedEarly);
  EXPECT_LT(s.iterations, 50);
  EXPECT_GE(s.iterations, 2);
  sodt::MeshD full;
  sodt_test::makeSphere(full, 3);
  sodt_test::jitterOnSphere(full, 0.3, 6);
  const sodt::SodtStats f = smooth(full, sodt::Algorithm::Basic, false, sodt::Guard::Quality, false, 0, 50);
  EXPECT_FALSE(f.stoppedEarly);
  EXPECT_EQ(f.iterations, 50);
}
