// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the normal-tensor classification (paper Eq. 9-10) on shapes whose
// classes are known: cubes, planes, spheres.
#include "test_mesh.h"

#include <sodt/maths/classify.h>
#include <sodt/mesh/output.h>

#include <gtest/gtest.h>

#include <cmath>

using sodt::VertexClass;

namespace {

/// Number of coordinates at +-1 (on a face: 1, on an edge: 2, a corner: 3).
template <class P>
int boundaryCoords(const P& p) {
  int c = 0;
  for (int k = 0; k < 3; ++k) c += std::abs(std::abs(double(p[k])) - 1.0) < 1e-9;
  return c;
}

}  // namespace

TEST(Classify, EigenvalueRule) {
  EXPECT_EQ(sodt::classifyEigenvalues(1, 0, 0, 2, 2), VertexClass::Smooth);
  EXPECT_EQ(sodt::classifyEigenvalues(1, 1, 0, 2, 2), VertexClass::Crease);
  EXPECT_EQ(sodt::classifyEigenvalues(1, 1, 1, 2, 2), VertexClass::Corner);
  // two planes whose normals differ by theta: crease iff cos(theta) < eps / (eps + 2)
  for (double deg : {50.0, 70.0}) {
    const double c = std::cos(deg * sodt::kPi / 180);
    const VertexClass got = sodt::classifyEigenvalues(1 + c, 1 - c, 0, 2, 2);
    EXPECT_EQ(got, deg > 60 ? VertexClass::Crease : VertexClass::Smooth) << deg;
  }
}

template <class M>
class ClassifyTest : public ::testing::Test {};
using MeshTypes = ::testing::Types<sodt::MeshF, sodt::MeshD>;
TYPED_TEST_SUITE(ClassifyTest, MeshTypes);

TYPED_TEST(ClassifyTest, CubeHasEightCornersAndCreaseEdges) {
  for (double jitter : {0.0, 0.3}) {
    TypeParam m;
    sodt_test::makeCube(m, 8, jitter, 11);
    const sodt::Classification c = sodt::classifyVertices(m, 2.0, 2.0);
    EXPECT_EQ(c.corner(), 8) << "jitter " << jitter;
    for (std::size_t i = 0; i < m.vert.size(); ++i) {
      const int b = boundaryCoords(m.vert[i].cP());
      const VertexClass want = b == 3 ? VertexClass::Corner : b == 2 ? VertexClass::Crease : VertexClass::Smooth;
      EXPECT_EQ(c.cls[i], want) << "vertex " << i << " jitter " << jitter;
      if (want == VertexClass::Crease) {
        // e3 runs along the edge: the axis whose coordinate is not +-1
        int axis = 0;
        for (int k = 0; k < 3; ++k)
          if (std::abs(std::abs(double(m.vert[i].cP()[k])) - 1.0) > 1e-9) axis = k;
        EXPECT_NEAR(std::abs(c.creaseDir[i][axis]), 1.0, 1e-9);
      }
    }
  }
}

TYPED_TEST(ClassifyTest, PlaneAndSphereAreSmooth) {
  TypeParam g;
  sodt_test::makeGrid(g, 12, 0.3, 5);
  sodt::Classification c = sodt::classifyVertices(g, 2.0, 2.0);
  EXPECT_EQ(c.crease() + c.corner(), 0);
  EXPECT_EQ(c.fixed(), 4 * 11);  // the border
  EXPECT_EQ(c.smooth(), 10 * 10);
  TypeParam s;
  sodt_test::makeSphere(s, 3);
  sodt_test::jitterOnSphere(s, 0.3, 9);
  c = sodt::classifyVertices(s, 2.0, 2.0);
  EXPECT_EQ(c.smooth(), s.vn);
}

TEST(Classify, LargerEpsilonFindsShallowerCreases) {
  // A roof: two planes meeting at a ridge with normals 50 degrees apart.
  sodt::MeshD m;
  sodt_test::makeGrid(m, 11, 0.0, 1);
  const double slope = std::tan(25.0 * sodt::kPi / 180);
  for (auto& v : m.vert) v.P()[2] = -slope * std::abs(v.P()[0] - 0.5);
  const sodt::Classification strict = sodt::classifyVertices(m, 2.0, 2.0);
  EXPECT_EQ(strict.crease(), 0);
  const sodt::Classification loose = sodt::classifyVertices(m, 8.0, 2.0);
  EXPECT_EQ(loose.crease(), 9);  // the interior ridge vertices
}

TEST(Classify, OutputWritesCodesPaletteAndSelection) {
  sodt::MeshF m;
  sodt_test::makeCube(m, 4);
  const sodt::Classification c = sodt::classifyVertices(m, 2.0, 2.0);
  sodt::writeClassToQuality(m, c);
  sodt::colorizeByClass(m, c);
  const int selected = sodt::selectFeatureVertices(m, c);
  EXPECT_EQ(selected, c.crease() + c.corner());
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    EXPECT_EQ(m.vert[i].Q(), float(static_cast<int>(c.cls[i])));
    EXPECT_EQ(m.vert[i].C(), sodt::classColor(c.cls[i]));
    EXPECT_EQ(m.vert[i].IsS(), c.cls[i] != VertexClass::Smooth);
  }
  // the palette distinguishes every class
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      EXPECT_NE(sodt::classColor(VertexClass(a)), sodt::classColor(VertexClass(b)));
}
