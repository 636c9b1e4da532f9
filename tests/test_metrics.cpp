// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the quality measures on shapes with known answers.
#include "test_mesh.h"

#include <sodt_io/corners.h>
#include <sodt_io/metrics.h>
#include <vcg/complex/append.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <cstring>
#include <utility>
#include <vector>

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

namespace {

/// The definition of isClosedOriented, on all directed edges at once: none
/// twice, each with its reverse.
bool closedOrientedByDefinition(const Mesh& m) {
  std::vector<std::pair<int, int>> half;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    for (int j = 0; j < 3; ++j)
      half.emplace_back(int(f.cV(j) - &m.vert[0]), int(f.cV((j + 1) % 3) - &m.vert[0]));
  }
  if (half.empty()) return false;
  std::sort(half.begin(), half.end());
  if (std::adjacent_find(half.begin(), half.end()) != half.end()) return false;
  for (const auto& h : half)
    if (!std::binary_search(half.begin(), half.end(), std::make_pair(h.second, h.first))) return false;
  return true;
}

}  // namespace

TEST(Metrics, ClosedOrientedAgreesWithItsDefinition) {
  // Spheres, whole and edited: a face removed, turned over, doubled, deleted,
  // a fin on an edge, two spheres.
  int closed = 0, open = 0;
  const auto check = [&](const Mesh& m, const char* what) {
    const bool want = closedOrientedByDefinition(m);
    EXPECT_EQ(sodt::isClosedOriented(m), want) << what;
    (want ? closed : open)++;
  };
  Mesh s;
  sodt_test::makeSphere(s, 3);
  check(s, "sphere");
  {
    Mesh e;
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(e, s);
    vcg::tri::Allocator<Mesh>::DeleteFace(e, e.face[7]);
    check(e, "a face deleted");
    e.face[7].ClearD();
    ++e.fn;
    check(e, "the face back");
    std::swap(e.face[3].V(0), e.face[3].V(1));
    check(e, "a face turned over");
  }
  {
    Mesh e;
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(e, s);
    sodt_test::addFace(e, int(e.face[5].V(0) - &e.vert[0]), int(e.face[5].V(1) - &e.vert[0]),
                       int(e.face[5].V(2) - &e.vert[0]));
    check(e, "a face doubled");
  }
  {
    Mesh e;
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(e, s);
    const int a = int(e.face[0].V(0) - &e.vert[0]), b = int(e.face[0].V(1) - &e.vert[0]);
    vcg::tri::Allocator<Mesh>::AddVertex(e, vcg::Point3d(0, 0, 3));
    const int c = int(e.vert.size()) - 1;
    sodt_test::addFace(e, b, a, c);  // a third face on edge (a, b)
    sodt_test::addFace(e, a, b, c);  // and its reverse: every edge paired, (a, b) four times
    check(e, "a fin on an edge");
  }
  {
    Mesh e;
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(e, s);
    vcg::tri::Append<Mesh, Mesh>::Mesh(e, s);
    check(e, "two spheres");
  }
  check(Mesh(), "empty");
  // Random small face sets over few vertices: repeated and degenerate faces,
  // pairs that close up by chance.
  std::mt19937 g(5);
  for (int trial = 0; trial < 3000; ++trial) {
    Mesh r;
    const int nv = 3 + int(g() % 5);
    vcg::tri::Allocator<Mesh>::AddVertices(r, nv);
    const int nf = 1 + int(g() % 8);
    for (int f = 0; f < nf; ++f) {
      const int a = int(g() % nv), b = int(g() % nv), c = int(g() % nv);
      sodt_test::addFace(r, a, b, c);
      if (g() % 2) sodt_test::addFace(r, a, c, b);  // its reverse: closes it up
    }
    check(r, "random faces");
  }
  EXPECT_GT(closed, 100);
  EXPECT_GT(open, 100);
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
  bool faceByFace = false;
  EXPECT_GT(sodt::countInvertedFaces(m, ref, 1, &faceByFace), 0);
  EXPECT_TRUE(faceByFace);
  // Other faces over the same square: each against the reference face under
  // it, which it faces as long as it is not turned over.
  Mesh other;
  sodt_test::makeGrid(other, 5, 0.0, 1);
  EXPECT_EQ(sodt::countInvertedFaces(other, ref, 1, &faceByFace), 0);
  EXPECT_FALSE(faceByFace);
  for (auto& f : other.face) std::swap(f.V(1), f.V(2));
  EXPECT_EQ(sodt::countInvertedFaces(other, ref), other.fn);
  // Once one face differs, each face against the face under it: the
  // turned-over face and the folded ones still count.
  Mesh flipped;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(flipped, m);
  std::swap(flipped.face[0].V(1), flipped.face[0].V(2));
  EXPECT_GT(sodt::countInvertedFaces(flipped, ref, 1, &faceByFace), sodt::countInvertedFaces(m, ref));
  EXPECT_FALSE(faceByFace);
}

namespace {

/// A flat patch (z = 0, facing +z) with a face along the edge A-B
/// folded against it: the face A, E, B faces -z while every face around
/// faces +z. Vertices A, B, C, D, E; E at (1, ey): a sliver of 0.57
/// degrees by default.
void makeFoldedSliverPatch(Mesh& m, double ey = 0.01) {
  const double p[5][2] = {{0, 0}, {2, 0}, {1, 1}, {1, -1}, {1, ey}};
  auto vi = vcg::tri::Allocator<Mesh>::AddVertices(m, 5);
  for (int i = 0; i < 5; ++i, ++vi) vi->P() = vcg::Point3d(p[i][0], p[i][1], 0);
  sodt_test::addFace(m, 0, 4, 2);  // above the sliver
  sodt_test::addFace(m, 4, 1, 2);
  sodt_test::addFace(m, 0, 3, 1);  // below A-B
  sodt_test::addFace(m, 0, 4, 1);  // the sliver, folded
}

}  // namespace

TEST(Metrics, AnyFaceFoldedInTheInputMayUnfold) {
  // Not only slivers: a face of 16.7 degrees folded over its neighbours
  // (as noise or a bad hole fill leaves them) has no side of its own
  // either. Unfolded, it faces like the surface around and counts
  // nowhere; a face beside it that turns over still counts.
  Mesh ref;
  makeFoldedSliverPatch(ref, 0.3);
  Mesh unfolded;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(unfolded, ref);
  unfolded.vert[4].P() = vcg::Point3d(1, -0.3, 0);
  bool faceByFace = false;
  EXPECT_EQ(sodt::countInvertedFaces(unfolded, ref, 1, &faceByFace), 0);
  EXPECT_TRUE(faceByFace);
  EXPECT_EQ(sodt::countFacesFacingAway(unfolded, ref), 0);
  Mesh turned;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(turned, ref);
  turned.vert[2].P() = vcg::Point3d(1, -2, 0);  // C below A-B: its two faces turn over
  EXPECT_EQ(sodt::countInvertedFaces(turned, ref), 2);
}

TEST(Metrics, AFoldedSliverMayUnfoldIntoTheSurface) {
  // A sliver of the input folded against the surface at its corners has no
  // side of its own: a face over it counts as turned over only when it
  // faces away from that surface too.
  Mesh ref;
  makeFoldedSliverPatch(ref);
  bool faceByFace = false;
  Mesh unfolded;  // E moved below A-B: the sliver faces +z like its neighbours
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(unfolded, ref);
  unfolded.vert[4].P() = vcg::Point3d(1, -0.3, 0);
  EXPECT_EQ(sodt::countInvertedFaces(unfolded, ref, 1, &faceByFace), 0);
  EXPECT_TRUE(faceByFace);
  Mesh kept;  // the input as it is: the fold was there, nothing turned
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(kept, ref);
  EXPECT_EQ(sodt::countInvertedFaces(kept, ref), 0);
  // Faces that do not correspond: the sliver turned to +z by its winding
  // is not counted, a face beside it turned to -z is.
  Mesh rewound;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(rewound, ref);
  std::swap(rewound.face[3].V(1), rewound.face[3].V(2));
  double turn = -1;
  EXPECT_EQ(sodt::countInvertedFaces(rewound, ref, 1, &faceByFace), 0);
  EXPECT_FALSE(faceByFace);
  EXPECT_EQ(sodt::countFacesFacingAway(rewound, ref, 1, &turn), 0);
  EXPECT_NEAR(turn, 0.0, 1e-9);
  std::swap(rewound.face[0].V(1), rewound.face[0].V(2));
  EXPECT_EQ(sodt::countInvertedFaces(rewound, ref), 1);
  // Face by face, a face over a good input face turned to -z counts.
  Mesh turned;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(turned, ref);
  turned.vert[2].P() = vcg::Point3d(1, -2, 0);  // C below A-B: its two faces turn over
  EXPECT_EQ(sodt::countInvertedFaces(turned, ref, 1, &faceByFace), 2);
  EXPECT_TRUE(faceByFace);
}

namespace {

/// One direction of the distance as surfaceDistance measured it before it
/// had its own sampler: vcglib's HausdorffSampler on MeshD copies.
std::pair<double, double> vcgOneSided(Mesh& from, Mesh& to, double bound) {
  using Sampler = vcg::tri::HausdorffSampler<Mesh>;
  Sampler hs(&to);
  hs.dist_upper_bound = bound;
  using SS = vcg::tri::SurfaceSampling<Mesh, Sampler>;
  SS::SamplingRandomGenerator().initialize(20130101u);
  SS::AllVertex(from, hs, false);
  SS::Montecarlo(from, hs, std::min(sodt::kMaxFaceSamples, std::max(10000, 2 * from.fn)));
  return {double(hs.getMaxDist()), double(hs.getMeanDist())};
}

/// Same bits (NaN equals NaN).
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST(Metrics, DistanceSamplerMatchesVcgHausdorffSampler) {
  Mesh a, b;
  sodt_test::makeSphere(a, 3);
  sodt_test::makeSphere(b, 4);
  sodt_test::jitterOnSphere(b, 0.02, 7);
  for (auto& v : b.vert) v.P() *= 1.01;
  Mesh A, B;
  sodt::detail::copyToDouble(a, A);
  sodt::detail::copyToDouble(b, B);
  sodt::SampleMesh As, Bs;
  sodt::detail::copyLive(a, As);
  sodt::detail::copyLive(b, Bs);
  const double bound = 10.0;
  const auto expected = vcgOneSided(A, B, bound);
  const auto expectedBa = vcgOneSided(B, A, bound);
  vcg::tri::UpdateBounding<Mesh>::Box(a);
  vcg::tri::UpdateBounding<Mesh>::Box(b);
  // More than 10000 samples each way: the lookups are split over the threads.
  // The faces in the grid (as for any ordinary mesh) or in the tree.
  for (const auto index : {sodt::FaceIndex::Auto, sodt::FaceIndex::Tree})
    for (int threads : {1, 2, 3}) {
      const auto ab = sodt::detail::oneSidedDistance(As, Bs, bound, threads, true, index);
      EXPECT_TRUE(sameBits(ab.first, expected.first)) << ab.first << " vs " << expected.first << ", " << threads;
      EXPECT_TRUE(sameBits(ab.second, expected.second)) << ab.second << " vs " << expected.second << ", " << threads;
      const auto ba = sodt::detail::oneSidedDistance(b, a, bound, threads, true, index);  // MeshD in place, no copy
      EXPECT_TRUE(sameBits(ba.first, expectedBa.first)) << ba.first << " vs " << expectedBa.first << ", " << threads;
      EXPECT_TRUE(sameBits(ba.second, expectedBa.second)) << ba.second << " vs " << expectedBa.second << ", " << threads;
    }
}

/// The distance measure's face grid is vcglib's GridStaticPtr::Set, cell for
/// cell: the same box, cell sizes and faces per cell, over the faces' own box
/// and over a larger one that covers the other mesh.
TEST(Metrics, FaceGridIsVcglibs) {
  Mesh m;
  sodt_test::makeSphere(m, 3);
  sodt_test::jitterOnSphere(m, 0.05, 3);
  sodt::SampleMesh s;
  sodt::detail::copyLive(m, s);
  using Grid = vcg::GridStaticPtr<sodt::SampleMesh::FaceType, double>;
  const auto sameGrid = [](Grid& a, Grid& b) {
    ASSERT_EQ(a.bbox.min, b.bbox.min);
    ASSERT_EQ(a.bbox.max, b.bbox.max);
    ASSERT_EQ(a.siz, b.siz);
    ASSERT_EQ(a.voxel, b.voxel);
    ASSERT_EQ(a.dim, b.dim);
    ASSERT_EQ(a.grid.size(), b.grid.size());
    ASSERT_EQ(a.links.size(), b.links.size());
    for (std::size_t c = 0; c + 1 < a.grid.size(); ++c) {
      std::vector<const void*> fa, fb;
      for (auto* l = a.grid[c]; l != a.grid[c + 1]; ++l) fa.push_back(l->Elem());
      for (auto* l = b.grid[c]; l != b.grid[c + 1]; ++l) fb.push_back(l->Elem());
      std::sort(fa.begin(), fa.end());
      std::sort(fb.begin(), fb.end());
      ASSERT_EQ(fa, fb) << "cell " << c;
    }
    EXPECT_EQ(a.grid.back()->Elem(), nullptr);  // the end marker
    EXPECT_EQ(b.grid.back()->Elem(), nullptr);
  };
  {
    Grid vcgGrid, ours;
    vcgGrid.Set(s.face.begin(), s.face.end());
    sodt::detail::setFaceGrid(ours, s.face.begin(), s.face.end(), vcg::Box3d());
    sameGrid(vcgGrid, ours);
  }
  {
    // A cover reaching beyond the faces' box: the grid spans both, inflated
    // by one n-th of the diagonal (n faces), with as many cells as faces.
    vcg::Box3d cover(vcg::Point3d(-3, -0.5, -0.5), vcg::Point3d(0.5, 2, 0.5));
    vcg::Box3d all = s.bbox;
    all.Add(cover);
    const double infl = all.Diag() / s.fn;
    all.min -= vcg::Point3d(infl, infl, infl);
    all.max += vcg::Point3d(infl, infl, infl);
    Grid vcgGrid, ours;
    vcgGrid.Set(s.face.begin(), s.face.end(), all, s.fn);
    sodt::detail::setFaceGrid(ours, s.face.begin(), s.face.end(), cover);
    sameGrid(vcgGrid, ours);
  }
}

/// Samples far from the other surface, in cells many cell widths away from
/// its nearest face: a sphere against an open, larger cap of a coarser
/// sphere. The search widens round by round there; the distances must still
/// be vcglib's, with the boxes tested four at a time or one at a time, on
/// one thread or more.
TEST(Metrics, DistanceSearchMatchesVcgFarFromTheOtherSurface) {
  Mesh a, sphere, b;
  sodt_test::makeSphere(a, 4);
  sodt_test::makeSphere(sphere, 3);
  for (auto& f : sphere.face)
    if ((f.cP(0)[2] + f.cP(1)[2] + f.cP(2)[2]) / 3 > -0.2) vcg::tri::Allocator<Mesh>::DeleteFace(sphere, f);
  sodt::detail::copyLive(sphere, b);  // the cap below z = -0.2, without the rest
  for (auto& v : b.vert) v.P() = v.P() * 1.3 + vcg::Point3d(0.05, 0, 0);
  vcg::tri::UpdateBounding<Mesh>::Box(a);
  vcg::tri::UpdateBounding<Mesh>::Box(b);
  ASSERT_GT(b.fn, 50);
  ASSERT_LT(b.fn, static_cast<int>(sphere.face.size()) / 2);
  const double bound = 10.0;
  Mesh A, B;
  sodt::detail::copyToDouble(a, A);
  sodt::detail::copyToDouble(b, B);
  const auto expected = vcgOneSided(A, B, bound);
  const auto expectedBa = vcgOneSided(B, A, bound);
  // The upper half of a is farther from the cap than the cap's grid cells
  // are wide: its samples need searches several cells wide.
  EXPECT_GT(expected.first, 1.0);
  for (int threads : {1, 2})
    for (bool simd : {true, false})
      for (const auto index : {sodt::FaceIndex::Auto, sodt::FaceIndex::Tree}) {
      sodt::SampleMesh As, Bs;
      sodt::detail::copyLive(a, As);
      sodt::detail::copyLive(b, Bs);
      const auto ab = sodt::detail::oneSidedDistance(As, Bs, bound, threads, simd, index);
      EXPECT_TRUE(sameBits(ab.first, expected.first)) << ab.first << " vs " << expected.first << ", " << threads;
      EXPECT_TRUE(sameBits(ab.second, expected.second)) << ab.second << " vs " << expected.second << ", " << threads;
      const auto ba = sodt::detail::oneSidedDistance(Bs, As, bound, threads, simd, index);
      EXPECT_TRUE(sameBits(ba.first, expectedBa.first)) << ba.first << " vs " << expectedBa.first << ", " << threads;
      EXPECT_TRUE(sameBits(ba.second, expectedBa.second)) << ba.second << " vs " << expectedBa.second << ", " << threads;
    }
}

/// A mesh with a spike against the same mesh without it (what smoothing
/// does to a spike): the samples on the spike lie millions of the smooth
/// mesh's grid cells away from it. Each used to cost a search round per cell
/// width (the CLI hung); the distance is the spike tip's.
TEST(Metrics, SamplesFarOutsideTheOtherMeshAreMeasured) {
  Mesh smooth, spiky;
  sodt_test::makeSphere(smooth, 3);
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(spiky, smooth);
  int tip = 0;
  for (std::size_t i = 0; i < spiky.vert.size(); ++i)
    if (spiky.vert[i].P()[0] > spiky.vert[tip].P()[0]) tip = static_cast<int>(i);
  const double length = 1e7;
  spiky.vert[tip].P()[0] = length;
  vcg::tri::UpdateBounding<Mesh>::Box(smooth);
  vcg::tri::UpdateBounding<Mesh>::Box(spiky);
  const sodt::DistanceStats d = sodt::surfaceDistance(smooth, spiky);  // relative to the spiky diagonal
  const double tipDistance = length - 1.0;  // the unit sphere's farthest point in x is at 1
  EXPECT_NEAR(d.maxRel * sodt::bboxDiagonal(spiky), tipDistance, 1e-6 * length);
  EXPECT_TRUE(std::isfinite(d.meanRel) && d.meanRel > 0 && d.meanRel < d.maxRel);
}

namespace {

/// Adds the triangle (a, b, c) to m with three vertices of its own.
void addTriangle(Mesh& m, const vcg::Point3d& a, const vcg::Point3d& b, const vcg::Point3d& c) {
  vcg::tri::Allocator<Mesh>::AddFace(m, a, b, c);
}

}  // namespace

/// A valley (z = |x - 0.5|) and the same valley with a needle whose long
/// edges span it from rim to rim: the needle's corners lie on the valley and
/// it has almost no area, so neither the vertices nor the area samples see
/// it, but the middle of its long edges is 0.5 / sqrt(2) from the valley.
/// maxEdgeRel finds it at the edges' midpoints; maxRel does not.
TEST(Metrics, PointsAlongTheEdgesFindWhatAreaSamplesMiss) {
  Mesh valley, needle;
  for (Mesh* m : {&valley, &needle}) {
    const vcg::Point3d a(0, 0, 0.5), b(0.5, 0, 0), c(1, 0, 0.5), d(0, 1, 0.5), e(0.5, 1, 0), f(1, 1, 0.5);
    addTriangle(*m, a, b, e);
    addTriangle(*m, a, e, d);
    addTriangle(*m, b, c, f);
    addTriangle(*m, b, f, e);
  }
  addTriangle(needle, vcg::Point3d(0, 0.5, 0.5), vcg::Point3d(1, 0.5, 0.5), vcg::Point3d(1, 0.5 + 1e-7, 0.5));
  for (Mesh* m : {&valley, &needle}) vcg::tri::UpdateBounding<Mesh>::Box(*m);
  const double diag = sodt::bboxDiagonal(valley);
  const sodt::DistanceStats d = sodt::surfaceDistance(needle, valley);
  EXPECT_LT(d.maxRel * diag, 1e-3);
  EXPECT_NEAR(d.maxEdgeRel * diag, 0.5 / std::sqrt(2.0), 1e-6);  // rounded to float, as maxRel is
  // Without the needle the edges add nothing.
  const sodt::DistanceStats same = sodt::surfaceDistance(valley, valley);
  EXPECT_EQ(same.maxEdgeRel, same.maxRel);
  EXPECT_LT(same.maxEdgeRel, 1e-12);
}

TEST(Metrics, SurfaceDistanceInPlaceEqualsCopying) {
  Mesh a, b;
  sodt_test::makeSphere(a, 4);
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(b, a);
  sodt_test::jitterOnSphere(b, 0.03, 11);
  for (auto& v : b.vert) v.P()[0] += 0.01;
  for (std::size_t i = 0; i < a.vert.size(); ++i) {
    a.vert[i].Q() = float(i);
    a.vert[i].C() = vcg::Color4b(1, 2, 3, 4);
  }
  a.vert[3].SetS();
  const std::vector<Mesh::VertexType> vertsBefore(a.vert.begin(), a.vert.end());
  const auto check = [](Mesh& x, auto& y, const char* what) {
    const sodt::DistanceStats copying = sodt::surfaceDistance(x, y);
    const sodt::DistanceStats inPlace = sodt::surfaceDistanceInPlace(x, y);
    EXPECT_TRUE(std::isfinite(copying.maxRel) && copying.maxRel > 0) << what;
    EXPECT_TRUE(sameBits(inPlace.maxRel, copying.maxRel)) << what << ": " << inPlace.maxRel << " vs " << copying.maxRel;
    EXPECT_TRUE(sameBits(inPlace.meanRel, copying.meanRel)) << what << ": " << inPlace.meanRel << " vs " << copying.meanRel;
    EXPECT_TRUE(sameBits(inPlace.maxEdgeRel, copying.maxEdgeRel)) << what;
  };
  check(a, b, "both sampled in place");
  // the sampled mesh keeps what a file would store
  for (std::size_t i = 0; i < a.vert.size(); ++i) {
    EXPECT_EQ(a.vert[i].cP(), vertsBefore[i].cP());
    EXPECT_EQ(a.vert[i].cQ(), vertsBefore[i].cQ());
    EXPECT_EQ(a.vert[i].cC(), vertsBefore[i].cC());
    EXPECT_EQ(a.vert[i].cFlags(), vertsBefore[i].cFlags());
  }
  sodt::SampleMesh bs;
  sodt::detail::copyLive(b, bs);
  check(a, bs, "reference as SampleMesh");
  // an unreferenced vertex and a deleted face: those meshes are copied
  Mesh c;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(c, b);
  vcg::tri::Allocator<Mesh>::AddVertices(c, 1);
  c.vert.back().P() = vcg::Point3d(5, 5, 5);
  EXPECT_FALSE(sodt::detail::samplesAsIs(c));
  check(a, c, "unreferenced vertex");
  check(c, a, "unreferenced vertex, other way");
  vcg::tri::Allocator<Mesh>::DeleteFace(c, c.face[0]);
  EXPECT_FALSE(sodt::detail::samplesAsIs(c));
  check(a, c, "deleted face");
  // far apart: the lower bound, NaN mean
  Mesh far;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(far, a);
  for (auto& v : far.vert) v.P()[1] += 100;
  const sodt::DistanceStats copying = sodt::surfaceDistance(far, b);
  const sodt::DistanceStats inPlace = sodt::surfaceDistanceInPlace(far, b);
  EXPECT_TRUE(std::isnan(inPlace.meanRel));
  EXPECT_TRUE(sameBits(inPlace.maxRel, copying.maxRel));
}

namespace {

/// Records the points a surface sampler is given, in order.
struct PointRecorder {
  std::vector<vcg::Point3d> points;
  template <class VertexType>
  void AddVert(const VertexType& v) {
    points.push_back(v.cP());
  }
  template <class FaceType>
  void AddFace(const FaceType& f, const vcg::Point3d& interp) {
    points.push_back(f.cP(0) * interp[0] + f.cP(1) * interp[1] + f.cP(2) * interp[2]);
  }
};

}  // namespace

/// The area-uniform samples of the distance measure are vcglib's Montecarlo
/// samples, the same points in the same order from the same random numbers,
/// on faces of very different areas, zero-area and deleted ones included.
TEST(Metrics, MontecarloSamplesAreVcglibs) {
  Mesh m;
  sodt_test::makeSphere(m, 4);
  sodt_test::jitterOnSphere(m, 0.2, 3);
  for (std::size_t i = 0; i < m.vert.size(); i += 7) m.vert[i].P() *= 1.5;  // uneven areas
  for (std::size_t f = 0; f < m.face.size(); f += 97) m.face[f].V(1) = m.face[f].V(0);  // zero area
  for (std::size_t f = 5; f < m.face.size(); f += 101) vcg::tri::Allocator<Mesh>::DeleteFace(m, m.face[f]);
  using SS = vcg::tri::SurfaceSampling<Mesh, PointRecorder>;
  for (int n : {1, 1000, 50000}) {
    PointRecorder vcgSamples, ours;
    SS::SamplingRandomGenerator().initialize(20130101u);
    SS::Montecarlo(m, vcgSamples, n);
    SS::SamplingRandomGenerator().initialize(20130101u);
    sodt::detail::montecarloSamples(m, ours, n);
    ASSERT_EQ(ours.points.size(), vcgSamples.points.size()) << n;
    int differ = 0;
    for (std::size_t i = 0; i < ours.points.size(); ++i)
      differ += std::memcmp(&ours.points[i], &vcgSamples.points[i], sizeof(vcg::Point3d)) != 0;
    EXPECT_EQ(differ, 0) << n;
    // And the generator is left where vcglib leaves it.
    const unsigned after = SS::SamplingRandomGenerator().generate(1u << 30);
    SS::SamplingRandomGenerator().initialize(20130101u);
    SS::Montecarlo(m, vcgSamples, n);
    EXPECT_EQ(after, SS::SamplingRandomGenerator().generate(1u << 30)) << n;
  }
}

/// The distance measure's shortcuts (curve order, faces passed over by
/// their bounding box) leave every distance as vcglib computes it, on a mesh
/// far from the origin too, where vcglib's point-face distance rounds at
/// the scale of the coordinates rather than of the distances.
TEST(Metrics, DistanceSamplerMatchesVcgFarFromTheOrigin) {
  for (double offset : {0.0, 1e4, -3e6}) {
    Mesh a, b;
    sodt_test::makeSphere(a, 4);
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(b, a);
    sodt_test::jitterOnSphere(b, 0.05, 5);
    for (auto& v : b.vert) v.P() *= 1.0 + 1e-6;  // distances far below the coordinates' rounding at 3e6
    for (Mesh* m : {&a, &b})
      for (auto& v : m->vert) v.P() += vcg::Point3d(offset, 0.5 * offset, -offset);
    vcg::tri::UpdateBounding<Mesh>::Box(a);
    vcg::tri::UpdateBounding<Mesh>::Box(b);
    Mesh A, B;
    sodt::detail::copyToDouble(a, A);
    sodt::detail::copyToDouble(b, B);
    const double bound = 10.0 + std::abs(offset);
    const auto expected = vcgOneSided(A, B, bound);
    for (int threads : {1, 2})
      for (const auto index : {sodt::FaceIndex::Auto, sodt::FaceIndex::Tree}) {
      Mesh a2, b2;
      sodt::detail::copyToDouble(a, a2);
      sodt::detail::copyToDouble(b, b2);
      vcg::tri::UpdateBounding<Mesh>::Box(a2);
      vcg::tri::UpdateBounding<Mesh>::Box(b2);
      const auto got = sodt::detail::oneSidedDistance(a2, b2, bound, threads, true, index);
      EXPECT_TRUE(sameBits(got.first, expected.first)) << got.first << " vs " << expected.first << ", offset " << offset;
      EXPECT_TRUE(sameBits(got.second, expected.second)) << got.second << " vs " << expected.second << ", offset " << offset;
    }
  }
}

TEST(Metrics, MeasuresAreTheSameOnAnyNumberOfThreads) {
  // Large enough for the measures to split their work between threads.
  Mesh s;
  sodt_test::makeSphere(s, 5);
  sodt_test::jitterOnSphere(s, 0.4, 21);
  ASSERT_GE(s.fn, 16384);
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  const auto check = [&](const Mesh& m, const char* what) {
    SCOPED_TRACE(what);
    const sodt::AngleStats a1 = sodt::computeAngleStats(m, 1);
    const sodt::VolumeResult v1 = sodt::enclosedVolume(m, 1);
    EXPECT_EQ(v1.closed, closedOrientedByDefinition(m));
    for (int t : {2, 3, 8}) {
      const sodt::AngleStats a = sodt::computeAngleStats(m, t);
      EXPECT_TRUE(same(a.minDeg, a1.minDeg) && same(a.maxDeg, a1.maxDeg) && same(a.fracBelow30, a1.fracBelow30) &&
                  same(a.fracAbove90, a1.fracAbove90) && same(a.p1TriMinDeg, a1.p1TriMinDeg))
          << t << " threads";
      EXPECT_EQ(a.faces, a1.faces);
      EXPECT_EQ(a.histogram, a1.histogram);
      const sodt::VolumeResult v = sodt::enclosedVolume(m, t);
      EXPECT_EQ(v.closed, v1.closed) << t << " threads";
      EXPECT_TRUE(same(v.volume, v1.volume)) << t << " threads";
      EXPECT_EQ(sodt::isClosedOriented(m, t), v1.closed);
    }
    return a1;
  };
  const sodt::AngleStats whole = check(s, "sphere");
  EXPECT_EQ(whole.faces, s.fn);
  {
    Mesh e;
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(e, s);
    vcg::tri::Allocator<Mesh>::DeleteFace(e, e.face[9000]);
    const sodt::AngleStats a = check(e, "a face deleted");
    EXPECT_EQ(a.faces, s.fn - 1);
    std::swap(e.face[12000].V(0), e.face[12000].V(1));
    check(e, "and one turned over");
  }
  {
    Mesh e;
    vcg::tri::Append<Mesh, Mesh>::MeshCopy(e, s);
    const auto& f = e.face[15000];
    sodt_test::addFace(e, int(f.cV(0) - &e.vert[0]), int(f.cV(1) - &e.vert[0]), int(f.cV(2) - &e.vert[0]));
    check(e, "a face doubled");
  }
  // Inverted faces: vertices pushed through the surface turn their faces over.
  Mesh moved;
  vcg::tri::Append<Mesh, Mesh>::MeshCopy(moved, s);
  for (int i = 0; i < moved.vn; i += 331) moved.vert[i].P() *= -0.2;
  const long long inv1 = sodt::countInvertedFaces(moved, s, 1);
  EXPECT_GT(inv1, 20);
  for (int t : {2, 3, 8}) EXPECT_EQ(sodt::countInvertedFaces(moved, s, t), inv1) << t << " threads";
  // Face lists that do not correspond, late in the list: each face against
  // the input face under it, the same count on any number of threads.
  std::swap(moved.face[19000].V(0), moved.face[19000].V(1));
  bool faceByFace = true;
  const long long inv2 = sodt::countInvertedFaces(moved, s, 1, &faceByFace);
  EXPECT_FALSE(faceByFace);
  EXPECT_GT(inv2, 20);
  for (int t : {2, 3}) EXPECT_EQ(sodt::countInvertedFaces(moved, s, t), inv2) << t << " threads";
}

/// A closed double fan of needles: in vcglib's grid each needle's box meets
/// a share of all cells, N^2 / 4 links for N rim vertices (the sampling of a
/// 100000-needle fan ran out of memory). The measure takes the tree of
/// oriented boxes for it and finds vcglib's distances, bit for bit, against
/// the same fan with its rim moved.
TEST(Metrics, NeedleFansAreMeasuredInTheTreeWithVcglibsDistances) {
  const int n = 3000;
  std::mt19937 g(17);
  std::vector<vcg::Point3d> ring, moved;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * sodt::kPi * k / n;
    ring.emplace_back(std::cos(t), std::sin(t), 0);
    const double s = 2 * sodt::kPi * (k + sodt_test::uniform(g, -0.3, 0.3)) / n;
    moved.emplace_back(std::cos(s), std::sin(s), sodt_test::uniform(g, -1e-3, 1e-3));
  }
  Mesh a, b;
  sodt_test::makeBipyramid(a, ring, vcg::Point3d(0, 0, 0.3));
  sodt_test::makeBipyramid(b, moved, vcg::Point3d(0, 0, 0.3));
  a.vert[1].P() = b.vert[1].P() = vcg::Point3d(0, 0, -0.3);
  vcg::tri::UpdateBounding<Mesh>::Box(a);
  vcg::tri::UpdateBounding<Mesh>::Box(b);
  Mesh A, B;
  sodt::detail::copyToDouble(a, A);
  sodt::detail::copyToDouble(b, B);
  const double bound = 10.0;
  const auto expected = vcgOneSided(A, B, bound);
  const auto expectedBa = vcgOneSided(B, A, bound);
  {
    sodt::detail::DistanceSampler<Mesh> auto_(b, bound, a.bbox), grid(b, bound, a.bbox, true, 1, sodt::FaceIndex::Grid);
    EXPECT_TRUE(auto_.usesTree());
    EXPECT_FALSE(grid.usesTree());
  }
  for (int threads : {1, 2}) {
    const auto ab = sodt::detail::oneSidedDistance(a, b, bound, threads);
    EXPECT_TRUE(sameBits(ab.first, expected.first)) << ab.first << " vs " << expected.first << ", " << threads;
    EXPECT_TRUE(sameBits(ab.second, expected.second)) << ab.second << " vs " << expected.second << ", " << threads;
    const auto ba = sodt::detail::oneSidedDistance(b, a, bound, threads);
    EXPECT_TRUE(sameBits(ba.first, expectedBa.first)) << ba.first << " vs " << expectedBa.first << ", " << threads;
    EXPECT_TRUE(sameBits(ba.second, expectedBa.second)) << ba.second << " vs " << expectedBa.second << ", " << threads;
  }
  EXPECT_GT(expected.first, 1e-4);  // the rims differ
}

/// A lone triangle with a 10-degree corner: its two border edges meet
/// there at less than the target, so no remesh that keeps the border can
/// do better; the corner is counted and its face left out of the rest.
TEST(Metrics, ABorderCornerSharperThanTheTargetIsProtected) {
  Mesh m;
  const double a = 10 * sodt::kPi / 180;
  addTriangle(m, vcg::Point3d(0, 0, 0), vcg::Point3d(1, 0, 0), vcg::Point3d(std::cos(a), std::sin(a), 0));
  const sodt::ProtectedAngles p = sodt::protectedAngles(m, 30.0, 25.0);
  EXPECT_EQ(p.corners, 1);
  EXPECT_NEAR(p.smallestDeg, 10.0, 1e-9);
  EXPECT_EQ(p.faces, 1);
  EXPECT_EQ(p.minAngleElsewhereDeg, 180.0);
  // Below a 5-degree target nothing is protected.
  const sodt::ProtectedAngles none = sodt::protectedAngles(m, 30.0, 5.0);
  EXPECT_EQ(none.corners, 0);
  EXPECT_EQ(none.faces, 0);
  EXPECT_NEAR(none.minAngleElsewhereDeg, 10.0, 1e-9);
}

/// A flat strip with a 1-degree sliver whose apex is lifted a little: its
/// normal turns 58 degrees from its neighbours', so a plain dihedral test
/// reads its edges as feature lines meeting at 1 degree. A sliver's normal
/// says nothing about features: it is not protected, and it is the mesh's
/// smallest angle. A real fin beside it (two faces at 90 degrees meeting
/// at 20 degrees) is.
TEST(Metrics, ASliverIsNotAFeatureCorner) {
  Mesh m;
  const vcg::Point3d A(0, 0, 0), B(1, 0, 0), C(0.5, 0.005, 0.008), D(0.5, -1, 0), E(0.5, 1, 0);
  addTriangle(m, A, D, B);
  addTriangle(m, A, B, C);
  addTriangle(m, A, C, E);
  addTriangle(m, C, B, E);
  vcg::tri::Clean<Mesh>::RemoveDuplicateVertex(m);
  const double sliver = std::atan(std::sqrt(0.005 * 0.005 + 0.008 * 0.008) / 0.5) * 180 / sodt::kPi;
  sodt::ProtectedAngles p = sodt::protectedAngles(m, 30.0, 25.0);
  EXPECT_EQ(p.corners, 0);
  EXPECT_EQ(p.faces, 0);
  EXPECT_NEAR(p.minAngleElsewhereDeg, sliver, 1e-6);
  // The fin: faces (P, Q, R) in z = 0 and (P, Q, S) in y = 0 along the
  // edge PQ; its corner at P is 20 degrees on both sides, between PQ (a
  // feature, 90 degrees) and the borders PR and PS.
  Mesh fin;
  const double t = std::tan(20 * sodt::kPi / 180);
  addTriangle(fin, vcg::Point3d(10, 0, 0), vcg::Point3d(11, 0, 0), vcg::Point3d(11, t, 0));
  addTriangle(fin, vcg::Point3d(11, 0, 0), vcg::Point3d(10, 0, 0), vcg::Point3d(11, 0, t));
  vcg::tri::Clean<Mesh>::RemoveDuplicateVertex(fin);
  p = sodt::protectedAngles(fin, 30.0, 25.0);
  EXPECT_EQ(p.corners, 2);
  EXPECT_NEAR(p.smallestDeg, 20.0, 1e-9);
  EXPECT_EQ(p.faces, 2);
}
