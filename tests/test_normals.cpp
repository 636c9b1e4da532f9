// SPDX-License-Identifier: GPL-3.0-or-later
// The normals Apply writes, against vcglib's normal update.
#include "test_mesh.h"

#include <sodt_io/mesh.h>
#include <sodt_io/prebuilt.h>

#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/append.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

/// A jittered sphere with a hole, a pinched vertex, deleted faces and
/// vertices, an unreferenced vertex and a zero-area face.
template <class M>
void makeAwkwardMesh(M& m) {
  using N = typename M::VertexType::NormalType;
  sodt_test::makeSphere(m, 3);
  sodt_test::jitterOnSphere(m, 0.3, 5);
  for (auto& v : m.vert) v.N() = N(0.3f, -2.0f, 0.5f);  // stale normals
  vcg::tri::Allocator<M>::DeleteFace(m, m.face[7]);   // a hole: border vertices
  vcg::tri::Allocator<M>::DeleteFace(m, m.face[100]);
  m.face[30].V(1)->P() = m.face[30].V(0)->P();  // zero area
  // A second sphere touching the first at one vertex: a pinch.
  M other;
  sodt_test::makeSphere(other, 1);
  const int base = static_cast<int>(m.vert.size());
  vcg::tri::Append<M, M>::Mesh(m, other);
  for (int i = base; i < static_cast<int>(m.vert.size()); ++i) m.vert[i].P() += typename M::CoordType(0, 0, 2);
  for (auto& f : m.face)
    for (int j = 0; j < 3; ++j)
      if (f.V(j) == &m.vert[base]) f.V(j) = &m.vert[0];
  vcg::tri::Allocator<M>::DeleteVertex(m, m.vert[base]);
  vcg::tri::Allocator<M>::AddVertex(m, typename M::CoordType(5, 5, 5));  // unreferenced
  m.vert.back().N() = N(0, 3, 4);
}

template <class M>
double angle(const typename M::VertexType::NormalType& a, const typename M::VertexType::NormalType& b) {
  return std::atan2((a ^ b).Norm(), a * b);
}

template <class M>
void expectAgreement(int threads, double tolerance) {
  M ours, ref;
  makeAwkwardMesh(ours);
  makeAwkwardMesh(ref);
  sodt::SodtParams p;
  p.iterations = 0;  // nothing moves: the normals of the input
  p.threads = threads;
  sodt::SodtSmoother<M>::Apply(ours, p);
  vcg::tri::UpdateNormal<M>::PerVertexNormalizedPerFaceNormalized(ref);
  int checked = 0;
  for (std::size_t i = 0; i + 1 < ours.vert.size(); ++i) {
    if (ref.vert[i].IsD()) continue;
    if (ref.vert[i].cN().Norm() == 0) {
      EXPECT_EQ(ours.vert[i].cN().Norm(), 0) << i;
      continue;
    }
    EXPECT_NEAR(ours.vert[i].cN().Norm(), 1.0, 1e-6) << i;
    EXPECT_LT(angle<M>(ours.vert[i].cN(), ref.vert[i].cN()), tolerance) << "vertex " << i;
    ++checked;
  }
  EXPECT_GT(checked, 600);
  for (std::size_t f = 0; f < ours.face.size(); ++f) {
    if (ref.face[f].IsD()) continue;
    if (ref.face[f].cN().Norm() == 0) {
      EXPECT_EQ(ours.face[f].cN().Norm(), 0) << f;
      continue;
    }
    EXPECT_LT(angle<M>(ours.face[f].cN(), ref.face[f].cN()), tolerance) << "face " << f;
  }
  // Left alone: the unreferenced vertex.
  EXPECT_EQ(ours.vert.back().cN(), typename M::VertexType::NormalType(0, 3, 4));
}

}  // namespace

TEST(Normals, AgreeWithVcglibOnBordersPinchesAndDegenerateFaces) {
  expectAgreement<sodt::MeshF>(1, 1e-5);
  expectAgreement<sodt::MeshF>(2, 1e-5);
  expectAgreement<sodt::MeshD>(2, 1e-12);
}

TEST(Normals, FollowTheSmoothedSurface) {
  // After smoothing, the normals are those of the new positions.
  sodt::MeshD m, ref;
  sodt_test::makeSphere(m, 3);
  sodt_test::jitterOnSphere(m, 0.4, 9);
  sodt::SodtParams p;
  p.iterations = 5;
  sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(ref, m);
  vcg::tri::UpdateNormal<sodt::MeshD>::PerVertexNormalizedPerFaceNormalized(ref);
  for (std::size_t i = 0; i < m.vert.size(); ++i)
    ASSERT_LT(angle<sodt::MeshD>(m.vert[i].cN(), ref.vert[i].cN()), 1e-12) << i;
  for (std::size_t f = 0; f < m.face.size(); ++f)
    ASSERT_LT(angle<sodt::MeshD>(m.face[f].cN(), ref.face[f].cN()), 1e-12) << f;
}
