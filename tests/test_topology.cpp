// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the ring topology: closed fans, borders, pinched vertices,
// non-manifold edges, deleted and degenerate faces.
#include "test_mesh.h"

#include <sodt/maths/topology.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using sodt::VertexKind;
using Mesh = sodt::MeshD;

TEST(Topology, ClosedSphereHasOnlyInteriorVerticesWithOrderedRings) {
  Mesh m;
  sodt_test::makeSphere(m, 2);
  const sodt::RingTopology t = sodt::buildRingTopology(m);
  for (int i = 0; i < m.vn; ++i) {
    ASSERT_EQ(t.kind[i], VertexKind::Interior) << i;
    const int n = t.ringSize(i);
    EXPECT_TRUE(n == 5 || n == 6);
    // consecutive ring vertices together with i form a face of the mesh, same orientation
    for (int k = 0; k < n; ++k) {
      const int a = t.ringIdx[t.ringBegin[i] + k], b = t.ringIdx[t.ringBegin[i] + (k + 1) % n];
      bool found = false;
      for (const auto& f : m.face)
        for (int j = 0; j < 3; ++j)
          if (f.cV(j) == &m.vert[i] && f.cV((j + 1) % 3) == &m.vert[a] && f.cV((j + 2) % 3) == &m.vert[b])
            found = true;
      EXPECT_TRUE(found) << i << " " << a << " " << b;
    }
  }
}

TEST(Topology, GridBorderIsBoundary) {
  Mesh m;
  sodt_test::makeGrid(m, 5, 0.0, 1);
  const sodt::RingTopology t = sodt::buildRingTopology(m);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) {
      const bool border = x == 0 || y == 0 || x == 4 || y == 4;
      EXPECT_EQ(t.kind[y * 5 + x], border ? VertexKind::Boundary : VertexKind::Interior) << x << "," << y;
    }
}

TEST(Topology, PinchedVertexAndNonManifoldEdgeAreDetected) {
  // Two closed octahedra sharing one vertex: that vertex has two closed fans.
  Mesh m;
  vcg::tri::Octahedron(m);
  Mesh second;
  vcg::tri::Octahedron(second);
  const int n0 = m.vn;
  vcg::tri::Allocator<Mesh>::AddVertices(m, second.vn - 1);
  // second's vertex 0 is glued to m's vertex 0; the others are shifted copies
  std::vector<int> map(second.vn);
  map[0] = 0;
  for (int i = 1; i < second.vn; ++i) {
    map[i] = n0 + i - 1;
    m.vert[map[i]].P() = second.vert[i].P() + second.vert[0].P() * -1.0 + m.vert[0].P() + vcg::Point3d(2, 0, 0);
  }
  for (const auto& f : second.face)
    sodt_test::addFace(m, map[f.cV(0) - &second.vert[0]], map[f.cV(1) - &second.vert[0]],
                       map[f.cV(2) - &second.vert[0]]);
  sodt::RingTopology t = sodt::buildRingTopology(m);
  EXPECT_EQ(t.kind[0], VertexKind::NonManifold);
  for (int i = 1; i < m.vn; ++i) EXPECT_EQ(t.kind[i], VertexKind::Interior) << i;

  // A third face on an edge of a single octahedron: both ends of that edge are non-manifold.
  Mesh o;
  vcg::tri::Octahedron(o);
  const auto& f0 = o.face[0];
  const int a = f0.cV(0) - &o.vert[0], b = f0.cV(1) - &o.vert[0];
  vcg::tri::Allocator<Mesh>::AddVertices(o, 1);
  o.vert.back().P() = vcg::Point3d(5, 5, 5);
  sodt_test::addFace(o, a, b, o.vn - 1);
  t = sodt::buildRingTopology(o);
  EXPECT_EQ(t.kind[a], VertexKind::NonManifold);
  EXPECT_EQ(t.kind[b], VertexKind::NonManifold);
}

TEST(Topology, DeletedIsolatedAndDegenerateFaceVertices) {
  Mesh m;
  sodt_test::makeSphere(m, 1);
  vcg::tri::Allocator<Mesh>::AddVertices(m, 1);  // isolated
  const int iso = m.vn - 1;
  vcg::tri::Allocator<Mesh>::DeleteVertex(m, m.vert[iso]);
  vcg::tri::Allocator<Mesh>::AddVertices(m, 1);
  const int lonely = static_cast<int>(m.vert.size()) - 1;
  // a face with a repeated vertex marks its vertices as non-manifold
  sodt_test::addFace(m, 3, 3, 4);
  const sodt::RingTopology t = sodt::buildRingTopology(m);
  EXPECT_EQ(t.kind[iso], VertexKind::Deleted);
  EXPECT_EQ(t.kind[lonely], VertexKind::Isolated);
  EXPECT_EQ(t.kind[3], VertexKind::NonManifold);
  EXPECT_EQ(t.kind[4], VertexKind::NonManifold);
  EXPECT_EQ(t.kind[5], VertexKind::Interior);
}

TEST(Topology, SmallAndLargeFanChecksAgree) {
  // Fans up to detail::kSmallFan edges are checked pairwise, larger ones by
  // sorting: on random fans (closed rings, open ones, several rings, repeated
  // starts or ends) both must give the same kind and the same ring.
  using sodt::detail::FanEdge;
  std::mt19937 g(77);
  int kinds[5] = {0, 0, 0, 0, 0};
  for (int trial = 0; trial < 20000; ++trial) {
    const int n = 1 + static_cast<int>(g() % sodt::detail::kSmallFan);
    std::vector<int> labels(2 * n);
    for (int& l : labels) l = static_cast<int>(g() % 1000);
    std::vector<FanEdge> fan;
    switch (g() % 4) {
      case 0:  // one closed ring
      case 1:  // a ring, then one edge broken, reversed or duplicated
        for (int k = 0; k < n; ++k) fan.push_back({labels[k], labels[(k + 1) % n], 100 + k});
        break;
      case 2: {  // two rings
        const int h = std::max(1, n / 2);
        for (int k = 0; k < h; ++k) fan.push_back({labels[k], labels[(k + 1) % h], 100 + k});
        for (int k = h; k < n; ++k) fan.push_back({labels[k], labels[k + 1 < n ? k + 1 : h], 100 + k});
        break;
      }
      default:  // random edges
        for (int k = 0; k < n; ++k) fan.push_back({labels[g() % (2 * n)], labels[g() % (2 * n)], 100 + k});
        break;
    }
    if (fan.size() > 1 && g() % 2) {
      FanEdge& e = fan[g() % fan.size()];
      switch (g() % 3) {
        case 0: e.b = labels[n + g() % n]; break;
        case 1: std::swap(e.a, e.b); break;
        default: e = fan[g() % fan.size()]; break;
      }
    }
    std::shuffle(fan.begin(), fan.end(), g);  // the mesh's face order
    sodt::RingTopology a, b;
    std::vector<FanEdge> edges;
    std::vector<int> ends;
    const VertexKind ka = sodt::detail::closeSmallFan(fan.data(), static_cast<int>(fan.size()), a);
    const VertexKind kb = sodt::detail::closeFan(fan.data(), static_cast<int>(fan.size()), edges, ends, b);
    ASSERT_EQ(ka, kb) << "trial " << trial;
    EXPECT_EQ(a.ringIdx, b.ringIdx) << "trial " << trial;
    EXPECT_EQ(a.ringFace, b.ringFace) << "trial " << trial;
    if (ka == VertexKind::Interior) {
      EXPECT_EQ(a.ringIdx.size(), fan.size());
    } else {
      EXPECT_TRUE(a.ringIdx.empty());
    }
    ++kinds[static_cast<int>(ka)];
  }
  EXPECT_GT(kinds[static_cast<int>(VertexKind::Interior)], 2000);
  EXPECT_GT(kinds[static_cast<int>(VertexKind::Boundary)], 1000);
  EXPECT_GT(kinds[static_cast<int>(VertexKind::NonManifold)], 2000);
}

TEST(Topology, FacesSortedByVertexKeepTheRings) {
  // sortFacesByVertex: a stable reordering by smallest vertex, dead faces
  // last, that changes nothing but the face numbers the rings refer to.
  Mesh m;
  sodt_test::makeSphere(m, 2);
  sodt_test::addFace(m, 3, 3, 4);  // repeated vertex
  sodt_test::addFace(m, 7, 8, 9);  // non-manifold edges
  vcg::tri::Allocator<Mesh>::DeleteFace(m, m.face[11]);
  sodt::FaceList input = sodt::makeFaceList(m);
  std::mt19937 g(5);
  std::vector<int> shuffled(input.tri.size());
  for (std::size_t f = 0; f < shuffled.size(); ++f) shuffled[f] = static_cast<int>(f);
  std::shuffle(shuffled.begin(), shuffled.end(), g);
  sodt::FaceList a;  // the input faces in a scattered order
  for (int f : shuffled) {
    a.tri.push_back(input.tri[f]);
    a.live.push_back(input.live[f]);
    a.flippable.push_back(f % 3 != 0);
  }
  sodt::FaceList b = a;
  const std::vector<int> previous = sodt::sortFacesByVertex(b, m.vn);
  ASSERT_EQ(previous.size(), a.tri.size());
  std::vector<int> seen(a.tri.size(), 0);
  const auto key = [&](std::size_t f) {
    return b.live[f] ? std::min({b.tri[f][0], b.tri[f][1], b.tri[f][2]}) : m.vn;
  };
  for (std::size_t f = 0; f < b.tri.size(); ++f) {
    ASSERT_GE(previous[f], 0);
    ASSERT_EQ(seen[previous[f]]++, 0);
    EXPECT_EQ(b.tri[f], a.tri[previous[f]]);
    EXPECT_EQ(b.live[f], a.live[previous[f]]);
    EXPECT_EQ(b.flippable[f], a.flippable[previous[f]]);
    if (f > 0) {
      ASSERT_LE(key(f - 1), key(f)) << f;
      if (key(f - 1) == key(f)) { EXPECT_LT(previous[f - 1], previous[f]) << f; }
    }
  }
  EXPECT_FALSE(b.live.back());
  std::vector<char> deleted(m.vert.size(), 0);
  const sodt::RingTopology ta = sodt::buildRingTopology(a, deleted), tb = sodt::buildRingTopology(b, deleted);
  EXPECT_EQ(ta.kind, tb.kind);
  EXPECT_EQ(ta.ringBegin, tb.ringBegin);
  EXPECT_EQ(ta.ringIdx, tb.ringIdx);
  ASSERT_EQ(ta.ringFace.size(), tb.ringFace.size());
  for (std::size_t k = 0; k < tb.ringFace.size(); ++k) EXPECT_EQ(previous[tb.ringFace[k]], ta.ringFace[k]) << k;
  int nonManifold = 0;
  for (VertexKind k : tb.kind) nonManifold += k == VertexKind::NonManifold;
  EXPECT_GE(nonManifold, 3);
}
