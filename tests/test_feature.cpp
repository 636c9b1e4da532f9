// SPDX-License-Identifier: GPL-3.0-or-later
// Feature-preserving (Algorithm 2) and denoising (Algorithm 3) sweeps on
// shapes with known features: cubes keep corners and edges, noise goes down.
#include "test_mesh.h"

#include <sodt_io/metrics.h>
#include <sodt_io/prebuilt.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

using sodt::Algorithm;
using sodt::VertexClass;

namespace {

template <class M>
sodt::SodtStats run(M& m, Algorithm a, int iterations, sodt::Classification* c = nullptr,
                    sodt::Guard guard = sodt::Guard::Quality) {
  sodt::SodtParams p;
  p.algorithm = a;
  p.iterations = iterations;
  p.guard = guard;
  return sodt::SodtSmoother<M>::Apply(m, p, nullptr, c);
}

template <class P>
int coordsAtOne(const P& p, double tol) {
  int c = 0;
  for (int k = 0; k < 3; ++k) c += std::abs(std::abs(double(p[k])) - 1.0) <= tol;
  return c;
}

/// Distance from p to the surface of the cube [-1,1]^3.
template <class P>
double cubeDistance(const P& p) {
  double outside = 0, inside = 1e9;
  for (int k = 0; k < 3; ++k) {
    const double d = std::abs(double(p[k])) - 1.0;
    outside += d > 0 ? d * d : 0;
    inside = std::min(inside, -d);
  }
  return outside > 0 ? std::sqrt(outside) : inside;
}

}  // namespace

template <class M>
class FeatureTest : public ::testing::Test {};
using MeshTypes = ::testing::Types<sodt::MeshF, sodt::MeshD>;
TYPED_TEST_SUITE(FeatureTest, MeshTypes);

TYPED_TEST(FeatureTest, CubeKeepsCornersEdgesAndFacesUnderAlgorithm2) {
  TypeParam m;
  sodt_test::makeCube(m, 8, 0.3, 21);
  TypeParam ref;
  vcg::tri::Append<TypeParam, TypeParam>::MeshCopy(ref, m);
  const auto before = sodt::computeAngleStats(m);
  sodt::Classification c;
  const sodt::SodtStats s = run(m, Algorithm::Feature, 20, &c);
  EXPECT_EQ(s.cornerVertices, 8);
  EXPECT_GT(s.moved + s.backtracked, 0);
  const double tol = std::is_same<TypeParam, sodt::MeshF>::value ? 1e-6 : 1e-12;
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    const int want = coordsAtOne(ref.vert[i].cP(), 0);
    if (c.cls[i] == VertexClass::Corner) {
      EXPECT_EQ(m.vert[i].cP(), ref.vert[i].cP()) << "corner " << i << " moved";
    }
    // edge vertices stay on their edge line, face vertices on their face plane
    EXPECT_EQ(coordsAtOne(m.vert[i].cP(), tol), want) << "vertex " << i;
  }
  const auto after = sodt::computeAngleStats(m);
  EXPECT_GT(after.minDeg, before.minDeg + 5);
  EXPECT_EQ(sodt::countInvertedFaces(m, ref), 0);
}

TYPED_TEST(FeatureTest, DenoisingKeepsCornersBitIdentical) {
  TypeParam m;
  sodt_test::makeCube(m, 8, 0.3, 22);
  std::mt19937 g(3);
  for (auto& v : m.vert)  // noise along the outward direction, corners included
    if (coordsAtOne(v.cP(), 0) < 3) v.P() = v.P() * typename TypeParam::ScalarType(1 + sodt_test::uniform(g, -0.02, 0.02));
  TypeParam ref;
  vcg::tri::Append<TypeParam, TypeParam>::MeshCopy(ref, m);
  sodt::Classification c;
  run(m, Algorithm::Denoise, 20, &c);
  EXPECT_EQ(c.corner(), 8);
  for (std::size_t i = 0; i < m.vert.size(); ++i)
    if (c.cls[i] == VertexClass::Corner) { EXPECT_EQ(m.vert[i].cP(), ref.vert[i].cP()) << i; }
  EXPECT_EQ(sodt::countInvertedFaces(m, ref), 0);
}

TEST(Feature, DenoisingBringsANoisyCubeCloserToTheCube) {
  sodt::MeshD m;
  sodt_test::makeCube(m, 10, 0.0, 1);
  std::mt19937 g(77);
  const double h = 0.2;  // cell size
  for (auto& v : m.vert) {
    if (coordsAtOne(v.cP(), 0) != 1) continue;  // face-interior vertices: noise along the face normal
    for (int k = 0; k < 3; ++k)
      if (std::abs(std::abs(v.P()[k]) - 1.0) == 0) v.P()[k] += sodt_test::uniform(g, -0.15, 0.15) * h;
  }
  auto meanDistance = [](const sodt::MeshD& mm) {
    double s = 0;
    for (const auto& v : mm.vert) s += cubeDistance(v.cP());
    return s / mm.vn;
  };
  const double d0 = meanDistance(m);
  sodt::Classification c;
  run(m, Algorithm::Denoise, 20, &c);
  std::printf("noisy cube: mean distance %.5f -> %.5f\n", d0, meanDistance(m));
  EXPECT_EQ(c.corner(), 8);
  EXPECT_LT(meanDistance(m), 0.6 * d0);
}

TEST(Feature, DenoisingBringsANoisySphereCloserToTheSphere) {
  sodt::MeshD m;
  sodt_test::makeSphere(m, 4);
  std::mt19937 g(2013);
  double meanEdge = 0;
  for (const auto& f : m.face) meanEdge += vcg::Distance(f.cP(0), f.cP(1));
  meanEdge /= m.fn;
  for (auto& v : m.vert) v.P() *= 1 + sodt_test::uniform(g, -0.3, 0.3) * meanEdge;
  auto rms = [](const sodt::MeshD& mm) {
    double s = 0;
    for (const auto& v : mm.vert) s += (v.cP().Norm() - 1) * (v.cP().Norm() - 1);
    return std::sqrt(s / mm.vn);
  };
  const double r0 = rms(m);
  sodt::MeshD basic;
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(basic, m);
  sodt::Classification c;
  run(m, Algorithm::Denoise, 20, &c);
  EXPECT_EQ(c.corner(), 0);
  std::printf("noisy sphere: rms distance %.5f -> %.5f\n", r0, rms(m));
  EXPECT_LT(rms(m), 0.75 * r0);
  // Algorithm 1 moves in tangent planes and cannot remove noise
  run(basic, Algorithm::Basic, 20);
  EXPECT_GT(rms(basic), 0.8 * r0);
}

TEST(Feature, DeviationGuardBoundsTheDistanceToTheInput) {
  // A coarse cylinder-like shape: without the guard, tangent-plane moves cut
  // across its edges; with it, every vertex stays near the input surface.
  sodt::MeshD m;
  sodt_test::makeCube(m, 6, 0.3, 8);
  for (auto& v : m.vert) v.P()[0] *= 1.0 + 0.3 * v.P()[1] * v.P()[1];  // bend the faces
  sodt::MeshD ref;
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(ref, m);
  sodt::SodtParams p;
  p.maxDeviationRel = 0.001;
  sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
  vcg::tri::UpdateBounding<sodt::MeshD>::Box(ref);
  const double diag = ref.bbox.Diag();
  // The guard checks the vertices and the edge midpoints of the output
  // against the input: the sampled distance from the output to the input
  // stays of the order of the bound (face interiors are not checked, and on
  // these bent faces they end up to about twice as far).
  const double toInput = sodt::detail::oneSidedDistance(m, ref, diag).first / diag;
  const double guarded = sodt::hausdorffRel(m, ref);
  sodt::MeshD free;
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(free, ref);
  p.maxDeviationRel = 0;
  sodt::SodtSmoother<sodt::MeshD>::Apply(free, p);
  const double unguarded = sodt::hausdorffRel(free, ref);
  std::printf("bent cube: output->input %.5f, Hausdorff %.5f guarded, %.5f unguarded (of the diagonal)\n", toInput,
              guarded, unguarded);
  EXPECT_LT(toInput, 0.0025);
  // The other direction (input points the output no longer covers, on chords
  // of the bent faces) is not bounded by the guard, but stays small.
  EXPECT_LT(guarded, 0.0025);
  // Without the bound the faces cut across the bent cube's creases; only the
  // reach box (the input's bounding box) still holds them.
  EXPECT_GT(unguarded, 5 * guarded);
}
