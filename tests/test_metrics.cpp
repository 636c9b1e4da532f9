// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the quality measures on shapes with known answers.
#include "test_mesh.h"

#include <sodt/metrics.h>

#include <gtest/gtest.h>

using Mesh = sodt::MeshD;

TEST(Metrics, AnglesOfKnownTriangles) {
  Mesh m;
  vcg::tri::Allocator<Mesh>::AddVertices(m, 4);
  m.vert[0].P() = vcg::Point3d(0, 0, 0);
  m.vert[1].P() = vcg::Point3d(1, 0, 0);
  m.vert[2].P() = vcg::Point3d(0, 1, 0);
  m.vert[3].P() = vcg::Point3d(0.5, -std::sqrt(3.0) / 2, 0);
  sodt_test::addFace(m, 0, 1, 2);  // 45, 45, 90
  sodt_test::addFace(m, 0, 3, 1);  // 60, 60, 60
  const sodt::AngleStats s = sodt::computeAngleStats(m);
  EXPECT_EQ(s.faces, 2);
  EXPECT_NEAR(s.minDeg, 45, 1e-9);
  EXPECT_NEAR(s.maxDeg, 90, 1e-9);
  EXPECT_EQ(s.histogram[45] + s.histogram[44], 2);
  EXPECT_EQ(s.histogram[60] + s.histogram[59], 3);
  long long total = 0;
  for (long long c : s.histogram) total += c;
  EXPECT_EQ(total, 6);
  EXPECT_DOUBLE_EQ(s.fracBelow30, 0.0);
  EXPECT_DOUBLE_EQ(s.fracAbove90, 0.0);
  EXPECT_NEAR(s.p1TriMinDeg, 45, 1e-9);
}

TEST(Metrics, VolumeOfCubeAndOpenMesh) {
  Mesh m;
  vcg::tri::Hexahedron(m);  // [-1,1]^3
  const sodt::VolumeResult v = sodt::enclosedVolume(m);
  ASSERT_TRUE(v.closed);
  EXPECT_NEAR(std::abs(v.volume), 8.0, 1e-12);
  Mesh s;
  sodt_test::makeSphere(s, 4);
  const sodt::VolumeResult vs = sodt::enclosedVolume(s);
  EXPECT_NEAR(vs.volume, 4.0 / 3.0 * sodt::kPi, 0.02);  // inscribed polyhedron, outward normals
  Mesh g;
  sodt_test::makeGrid(g, 4, 0.0, 1);
  EXPECT_FALSE(sodt::enclosedVolume(g).closed);
}

TEST(Metrics, HausdorffOfTranslatedCopy) {
  Mesh a;
  sodt_test::makeSphere(a, 3);
  Mesh b;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(b, a);
  EXPECT_NEAR(sodt::hausdorffRel(a, b), 0.0, 1e-12);
  const double d = 0.01;
  for (auto& v : b.vert) v.P()[0] += d;
  const double diag = sodt::bboxDiagonal(b);
  const double h = sodt::hausdorffRel(a, b);
  EXPECT_GT(h, 0.8 * d / diag);
  EXPECT_LT(h, 1.05 * d / diag);
  // the measure is symmetric
  EXPECT_NEAR(sodt::hausdorffRel(b, a) * sodt::bboxDiagonal(a), h * diag, 1e-6);
}

TEST(Metrics, InvertedFacesAgainstReference) {
  Mesh ref;
  sodt_test::makeGrid(ref, 4, 0.0, 1);
  Mesh m;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(m, ref);
  EXPECT_EQ(sodt::countInvertedFaces(m, ref), 0);
  // push interior vertex (1,1) across its neighbour (2,2): its incident faces fold
  m.vert[5].P() = vcg::Point3d(0.9, 0.9, 0);
  EXPECT_GT(sodt::countInvertedFaces(m, ref), 0);
  Mesh other;
  sodt_test::makeGrid(other, 5, 0.0, 1);
  EXPECT_EQ(sodt::countInvertedFaces(other, ref), -1);
}
