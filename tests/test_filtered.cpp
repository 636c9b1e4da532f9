// SPDX-License-Identifier: GPL-3.0-or-later
// Algorithm::Filtered: filtered face normals, vertices that follow them,
// then S-ODT sweeps. On noise along the normals of a cube and a sphere
// (Gaussian, fixed seeds) the result must come much closer to the clean
// surface, keep the cube's edges sharp, and have good triangles.

#include "test_mesh.h"

#include <sodt/denoise/noise_estimate.h>
#include <sodt/denoise/filter_select.h>
#include <sodt/denoise/normal_filter.h>
#include <sodt/denoise/surface_restore.h>
#include <sodt_io/io.h>
#include <sodt_io/metrics.h>
#include <sodt_io/prebuilt.h>

#include <vcg/complex/algorithms/smooth.h>
#include <vcg/complex/algorithms/update/flag.h>
#include <vcg/complex/algorithms/update/normal.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace {

using sodt::Algorithm;

/// A standard normal draw from two uniform ones (Box-Muller), the same on
/// every platform.
double gaussian(std::mt19937& g) {
  const double u = 1.0 - sodt_test::uniform01(g), v = sodt_test::uniform01(g);
  return std::sqrt(-2.0 * std::log(u)) * std::cos(2 * M_PI * v);
}

double meanEdge(const sodt::MeshD& m) {
  double s = 0;
  for (const auto& f : m.face)
    for (int j = 0; j < 3; ++j) s += vcg::Distance(f.cP(j), f.cP((j + 1) % 3));
  return s / (3.0 * m.fn);
}

/// Moves every vertex along its area-weighted normal by sigma mean edge
/// lengths times a standard normal draw.
void addNormalNoise(sodt::MeshD& m, double sigma, unsigned seed) {
  vcg::tri::UpdateNormal<sodt::MeshD>::PerVertexNormalizedPerFace(m);
  const double h = meanEdge(m);
  std::mt19937 g(seed);
  for (auto& v : m.vert) v.P() += v.cN() * (sigma * h * gaussian(g));
}

double cubeDistance(const vcg::Point3d& p) {
  double outside = 0, inside = 1e9;
  for (int k = 0; k < 3; ++k) {
    const double d = std::abs(p[k]) - 1.0;
    outside += d > 0 ? d * d : 0;
    inside = std::min(inside, -d);
  }
  return outside > 0 ? std::sqrt(outside) : inside;
}

/// Mean distance of the vertices and face centroids to the cube [-1,1]^3.
double meanCubeDistance(const sodt::MeshD& m) {
  double s = 0;
  for (const auto& v : m.vert) s += cubeDistance(v.cP());
  for (const auto& f : m.face) s += cubeDistance((f.cP(0) + f.cP(1) + f.cP(2)) / 3.0);
  return s / (m.vn + m.fn);
}

/// Mean absolute difference, in degrees, between the dihedral angles of m
/// and those of the clean mesh on the clean mesh's edges sharper than 60.
double sharpDihedralError(const sodt::MeshD& m, const sodt::MeshD& clean) {
  const auto a = sodt_test::dihedralAngles(m), c = sodt_test::dihedralAngles(clean);
  double s = 0;
  int n = 0;
  for (const auto& kv : c)
    if (kv.second > 60) {
      s += std::abs(a.at(kv.first) - kv.second);
      ++n;
    }
  return n ? s / n : 0;
}

sodt::SodtStats runFiltered(sodt::MeshD& m) {
  sodt::SodtParams p;
  p.algorithm = Algorithm::Filtered;
  p.threads = 1;
  return sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
}

}  // namespace

TEST(Filtered, NoisyCubeComesCloseToTheCubeWithSharpEdgesAndGoodTriangles) {
  sodt::MeshD clean, m;
  sodt_test::makeCube(clean, 10);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(m, clean);
  addNormalNoise(m, 0.3, 30);
  sodt::MeshD noisy;
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(noisy, m);
  const double d0 = meanCubeDistance(m), e0 = sharpDihedralError(m, clean);

  runFiltered(m);
  const double d1 = meanCubeDistance(m), e1 = sharpDihedralError(m, clean);
  const sodt::AngleStats angles = sodt::computeAngleStats(m);
  std::printf("noisy cube (sigma 0.3 edges): mean distance %.5f -> %.5f, sharp dihedral error %.1f -> %.1f deg, "
              "min angle %.1f deg\n", d0, d1, e0, e1, angles.minDeg);
  EXPECT_LT(d1, 0.35 * d0);
  EXPECT_LT(e1, 6.0);  // the edges stay near 90 degrees (the noise leaves 27.5 degrees)
  EXPECT_EQ(sodt::countInvertedFaces(m, clean), 0);
  EXPECT_GT(angles.minDeg, 25.0);

  // The paper's Algorithm 3 stays as it was: it removes far less of this noise.
  sodt::SodtParams p;
  p.algorithm = Algorithm::Denoise;
  p.threads = 1;
  sodt::SodtSmoother<sodt::MeshD>::Apply(noisy, p);
  EXPECT_GT(meanCubeDistance(noisy), 1.5 * d1);
}

TEST(Filtered, CornersKeepWhereTheFilterTookThem) {
  // The sweeps hold the vertices classified as corners still; those the
  // filter moved must be returned where it moved them, not where the noise
  // had put them.
  sodt::MeshD clean, m;
  sodt_test::makeCube(clean, 12);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(m, clean);
  addNormalNoise(m, 0.5, 5);
  const std::vector<vcg::Point3d> noisy = [&] {
    std::vector<vcg::Point3d> p;
    for (const auto& v : m.vert) p.push_back(v.cP());
    return p;
  }();
  sodt::SodtParams p;
  p.algorithm = Algorithm::Filtered;
  p.threads = 1;
  sodt::Classification cls;
  const sodt::SodtStats st = sodt::SodtSmoother<sodt::MeshD>::Apply(m, p, nullptr, &cls);
  ASSERT_EQ(st.filter.kind, sodt::FilterKind::Normals);
  ASSERT_GT(cls.corner(), 0);
  double before = 0, after = 0;
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    if (cls.cls[i] != sodt::VertexClass::Corner) continue;
    EXPECT_NE(m.vert[i].cP(), noisy[i]) << "corner vertex " << i << " kept its noisy position";
    before += std::abs(cubeDistance(noisy[i]));
    after += std::abs(cubeDistance(m.vert[i].cP()));
  }
  std::printf("%d corner vertices: summed distance to the cube %.4f -> %.4f\n", cls.corner(), before, after);
  EXPECT_LT(after, 0.5 * before);
}

TEST(Filtered, NoisySphereComesCloseToTheSphere) {
  sodt::MeshD m;
  sodt_test::makeSphere(m, 4);
  addNormalNoise(m, 0.3, 2011);
  auto meanRadiusError = [](const sodt::MeshD& mm) {
    double s = 0;
    for (const auto& v : mm.vert) s += std::abs(v.cP().Norm() - 1);
    return s / mm.vn;
  };
  const double r0 = meanRadiusError(m);
  runFiltered(m);
  const sodt::AngleStats angles = sodt::computeAngleStats(m);
  std::printf("noisy sphere (sigma 0.3 edges): mean radius error %.5f -> %.5f, min angle %.1f deg\n", r0,
              meanRadiusError(m), angles.minDeg);
  EXPECT_LT(meanRadiusError(m), 0.3 * r0);
  EXPECT_GT(angles.minDeg, 30.0);
}

TEST(Filtered, BorderVerticesStayAndAFlatGridStaysFlat) {
  // An open, bumpy grid: interior vertices go back to the plane, border
  // vertices stay where they are.
  sodt::MeshD m;
  sodt_test::makeGrid(m, 21, 0.2, 5);
  std::mt19937 g(9);
  for (auto& v : m.vert) v.P()[2] = 0.01 * gaussian(g);
  sodt::MeshD ref;
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(ref, m);
  auto rmsHeight = [](const sodt::MeshD& mm) {
    double s = 0;
    for (const auto& v : mm.vert) s += v.cP()[2] * v.cP()[2];
    return std::sqrt(s / mm.vn);
  };
  const sodt::SodtStats st = runFiltered(m);
  EXPECT_EQ(st.fixedBoundary, 80);
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    const auto& p = ref.vert[i].cP();
    const bool border = p[0] == 0 || p[1] == 0 || p[0] == 1 || p[1] == 1;
    if (border) {
      EXPECT_EQ(m.vert[i].cP(), p) << i;
    }
  }
  std::printf("bumpy grid: rms height %.5f -> %.5f\n", rmsHeight(ref), rmsHeight(m));
  EXPECT_LT(rmsHeight(m), 0.6 * rmsHeight(ref));  // the border keeps its noise
}

TEST(Filtered, ABoxTooSmallToEstimateItsNoiseKeepsItsShape) {
  // A 12-triangle box: its noise cannot be estimated, so no filter runs,
  // and the sweeps find every vertex a corner (a fixed filter took 99% of
  // its volume and made them all smooth).
  sodt::MeshD box;
  sodt_test::makeCube(box, 1);
  const auto before = sodt_test::positions(box);
  const sodt::SodtStats st = runFiltered(box);
  EXPECT_EQ(st.filter.kind, sodt::FilterKind::None);
  EXPECT_EQ(st.cornerVertices, 8);
  EXPECT_EQ(sodt_test::positions(box), before);
}

TEST(Filtered, RangeSigmaFollowsTheFeatureAngle) {
  // The normal filter's sigmas come from the mesh and the feature angle alone.
  sodt::MeshD m;
  sodt_test::makeCube(m, 4);
  sodt::FaceList faces = sodt::makeFaceList(m);
  std::vector<sodt::Vec3> pos;
  for (const auto& v : m.vert) pos.push_back(sodt::Vec3::Construct(v.cP()));
  std::vector<char> movable(pos.size(), 1);
  const sodt::NormalFilterRounds r30(faces, movable, 30.0, pos, 1), r60(faces, movable, 60.0, pos, 1);
  const sodt::NormalFilterSettings &s30 = r30.settings(), &s60 = r60.settings();
  EXPECT_NEAR(s30.sigmaRange, 2 * std::sin(7.5 * M_PI / 180), 1e-12);
  EXPECT_NEAR(s60.sigmaRange, 2 * std::sin(15 * M_PI / 180), 1e-12);
  EXPECT_EQ(s30.sigmaSpatial, s60.sigmaSpatial);
  EXPECT_GT(s30.sigmaSpatial, 0.2);  // cells of 0.5: centroids of faces across an edge lie 0.24-0.33 apart
  EXPECT_LT(s30.sigmaSpatial, 0.35);
  // The clean cube stays the cube: vertices move within its faces, and the
  // faces of two sides, 90 degrees apart, mix with weight exp(-|n1 - n2|^2 /
  // 2 sigma_r^2) = exp(-14.7) only.
  std::vector<sodt::Vec3> a = pos;
  for (int k = 0; k < 4; ++k) r30.round(a);
  for (std::size_t i = 0; i < pos.size(); ++i) EXPECT_LT(std::abs(cubeDistance(a[i])), 1e-5) << i;
}

TEST(Filtered, VertexUpdatesSqueezeNoFaceBelowTheAngleFloor) {
  // Every face keeps its smallest angle at or above the smaller of where it
  // started and kFilterAngleFloorDeg, however many rounds run: on a cube
  // this noisy the updates would otherwise squeeze faces at the corners
  // into slivers the sweeps cannot unfold.
  sodt::MeshD m;
  sodt_test::makeCube(m, 12);
  addNormalNoise(m, 0.5, 10);  // a seed that squeezed a face to 0.1 degrees
  const sodt::FaceList faces = sodt::makeFaceList(m);
  std::vector<sodt::Vec3> pos;
  for (const auto& v : m.vert) pos.push_back(sodt::Vec3::Construct(v.cP()));
  const std::vector<sodt::Vec3> start = pos;
  const std::vector<char> movable(pos.size(), 1);
  const sodt::NormalFilterRounds rounds(faces, movable, 30.0, pos, 1);
  const double floorRad = sodt::kFilterAngleFloorDeg * M_PI / 180;
  auto angle = [&](const std::vector<sodt::Vec3>& p, const std::array<int, 3>& t) {
    return sodt::triangleMinAngle(p[t[0]], p[t[1]], p[t[2]]);
  };
  double lowest = M_PI;
  for (int r = 0; r < sodt::kMaxNormalRounds; ++r) rounds.round(pos);
  for (const std::array<int, 3>& t : faces.tri) {
    EXPECT_GE(angle(pos, t), std::min(angle(start, t), floorRad) - 1e-12);
    lowest = std::min(lowest, angle(pos, t));
  }
  std::printf("noisy cube after %d rounds: smallest angle %.1f deg\n", sodt::kMaxNormalRounds, lowest * 180 / M_PI);
}

TEST(Filtered, SweepsTurnFacesUpToTheirOwnBoundWhateverTheFaceTurnParameter) {
  // The filtered sweeps straighten the crumpled triangles the filter
  // leaves at high noise, which needs faces to turn further than the other
  // algorithms' default face-turn bound allows: they use
  // kFilteredFaceTurnDeg, and the parameter does not change the result.
  // It needs them to leave the denoised surface by more than the default
  // deviation bound too (with it, this cube's smallest angle stays at 10
  // degrees): the bound is off here.
  sodt::MeshD clean, noisy;
  sodt_test::makeCube(clean, 10);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(noisy, clean);
  addNormalNoise(noisy, 0.5, 50);
  sodt::MeshD a, b;
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(a, noisy);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(b, noisy);
  sodt::SodtParams p;
  p.algorithm = Algorithm::Filtered;
  p.threads = 1;
  p.maxDeviationRel = 0;
  p.maxFaceTurnDeg = 10;
  const sodt::SodtStats sa = sodt::SodtSmoother<sodt::MeshD>::Apply(a, p);
  p.maxFaceTurnDeg = 90;
  sodt::SodtSmoother<sodt::MeshD>::Apply(b, p);
  for (int i = 0; i < a.vn; ++i) ASSERT_EQ(a.vert[i].cP(), b.vert[i].cP()) << "vertex " << i;
  EXPECT_LE(sa.maxFaceTurnDeg, sodt::kFilteredFaceTurnDeg + 1e-9);

  const sodt::AngleStats angles = sodt::computeAngleStats(a);
  std::printf("noisy cube (sigma 0.5 edges): min angle %.1f -> %.1f deg, sharp dihedral error %.1f -> %.1f deg, "
              "largest face turn %.1f deg\n", sodt::computeAngleStats(noisy).minDeg, angles.minDeg,
              sharpDihedralError(noisy, clean), sharpDihedralError(a, clean), sa.maxFaceTurnDeg);
  EXPECT_GE(angles.minDeg, 20.0);
  EXPECT_EQ(sodt::countInvertedFaces(a, clean), 0);
  EXPECT_LT(meanCubeDistance(a), 0.5 * meanCubeDistance(noisy));
}

TEST(NoiseEstimate, ReadsTheNoiseNotTheCurvature) {
  // Clean: flat sides read 0; a coarse torus (16 segments around its tube)
  // and a sphere read little, though their faces turn 22 and 12 degrees
  // from one ring to the next.
  sodt::MeshD cube, sphere, torus;
  sodt_test::makeCube(cube, 10);
  sodt_test::makeSphere(sphere, 4);
  sodt::loadMesh(std::string(SODT_MESH_DIR) + "/torus.off", torus);
  for (const sodt::MeshD* m : {&cube, &sphere, &torus}) {
    const sodt::NoiseEstimate e = sodt::estimateNoiseOf(*m);
    EXPECT_GE(e.samples, 400);
    EXPECT_LT(e.sigmaEdges, sodt::kLittleNoiseEdges) << m->vn << " vertices";
  }
  // Normal noise of sigma edges reads about sigma on smooth shapes. On the
  // small cube most vertices lie within two rings of an edge, where no
  // quadric fits, and it reads up to half as much again.
  for (double sigma : {0.1, 0.3}) {
    for (sodt::MeshD* clean : {&cube, &sphere, &torus}) {
      sodt::MeshD m;
      vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(m, *clean);
      addNormalNoise(m, sigma, 7);
      const double e = sodt::estimateNoiseOf(m).sigmaEdges;
      std::printf("%d vertices, noise %.2f edges: estimated %.3f\n", m.vn, sigma, e);
      EXPECT_GT(e, 0.8 * sigma);
      EXPECT_LT(e, (clean == &cube ? 1.6 : 1.3) * sigma);
    }
  }
}

namespace {

/// A closed cylinder of radius 1 and height h as CAD exports write one:
/// `segments` flat strips around it, each split into two triangles, and
/// each end a fan from its centre.
void makeCadCylinder(sodt::MeshD& m, int segments, double h) {
  m.Clear();
  vcg::tri::Allocator<sodt::MeshD>::AddVertices(m, 2 * segments + 2);
  for (int k = 0; k < segments; ++k) {
    const double a = 2 * M_PI * k / segments;
    m.vert[k].P() = vcg::Point3d(std::cos(a), std::sin(a), 0);
    m.vert[segments + k].P() = vcg::Point3d(std::cos(a), std::sin(a), h);
  }
  const int bottom = 2 * segments, top = bottom + 1;
  m.vert[bottom].P() = vcg::Point3d(0, 0, 0);
  m.vert[top].P() = vcg::Point3d(0, 0, h);
  for (int k = 0; k < segments; ++k) {
    const int a = k, b = (k + 1) % segments;
    sodt_test::addFace(m, a, b, segments + b);
    sodt_test::addFace(m, a, segments + b, segments + a);
    sodt_test::addFace(m, bottom, b, a);
    sodt_test::addFace(m, top, segments + a, segments + b);
  }
}

}  // namespace

TEST(NoiseEstimate, CleanCadPartsReadClean) {
  // On a coarse CAD part most vertices lie on a sharp edge, where no
  // quadric fits (a cube of 4 x 4 cells a side read 0.15 mean edges, a
  // 12-strip cylinder 0.72); but their faces lie flat on the sides, which
  // noise would tilt apart.
  sodt::MeshD cube, cylinder;
  sodt_test::makeCube(cube, 4);
  makeCadCylinder(cylinder, 12, 0.5);
  for (const sodt::MeshD* m : {&cube, &cylinder}) {
    const sodt::NoiseEstimate e = sodt::estimateNoiseOf(*m);
    EXPECT_GE(e.samples, 20);
    EXPECT_LT(e.sigmaEdges, sodt::kLittleNoiseEdges) << m->vn << " vertices";
  }
  // Noise tilts them apart even when it is small: a cube and a sphere with
  // noise of 0.05 mean edges read it (the cube up to 1.6 times, see above).
  sodt::MeshD sphere;
  sodt_test::makeSphere(sphere, 4);
  sodt_test::makeCube(cube, 10);
  for (sodt::MeshD* clean : {&cube, &sphere})
    for (unsigned seed : {1u, 2u}) {
      sodt::MeshD m;
      vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(m, *clean);
      addNormalNoise(m, 0.05, seed);
      const double e = sodt::estimateNoiseOf(m).sigmaEdges;
      EXPECT_GT(e, 0.8 * 0.05) << m.vn << " vertices, seed " << seed;
      EXPECT_LT(e, 1.7 * 0.05) << m.vn << " vertices, seed " << seed;
    }
}

TEST(NoiseEstimate, PerComponentASmallNoisyPartBesideALargeCleanOne) {
  // The median over the whole mesh reads the large clean sphere; each part
  // on its own reads its own noise.
  sodt::MeshD large, small, both;
  sodt_test::makeSphere(large, 5);
  sodt_test::makeSphere(small, 2);
  addNormalNoise(small, 0.3, 3);
  for (auto& v : small.vert) v.P() = v.P() * 0.2 + vcg::Point3d(3, 0, 0);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::Mesh(both, small);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::Mesh(both, large);
  EXPECT_LT(sodt::estimateNoiseOf(both).sigmaEdges, sodt::kLittleNoiseEdges);
  int count = 0;
  const std::vector<sodt::ComponentNoise> parts = sodt::estimateNoiseByComponentOf(both, 10, &count);
  EXPECT_EQ(count, 2);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].faces, large.fn);  // the most faces first
  EXPECT_EQ(parts[0].vertices, large.vn);
  EXPECT_LT(parts[0].noise.sigmaEdges, sodt::kLittleNoiseEdges);
  EXPECT_EQ(parts[0].noise.samples, sodt::kComponentNoiseSamples);
  EXPECT_EQ(parts[1].faces, small.fn);
  EXPECT_EQ(parts[1].noise.samples, small.vn);
  EXPECT_GT(parts[1].noise.sigmaEdges, 0.8 * 0.3);
  EXPECT_LT(parts[1].noise.sigmaEdges, 1.3 * 0.3);
  // At most maxComponents are estimated; the count is of all of them.
  const std::vector<sodt::ComponentNoise> first = sodt::estimateNoiseByComponentOf(both, 1, &count);
  EXPECT_EQ(count, 2);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].noise.sigmaEdges, parts[0].noise.sigmaEdges);
}

TEST(NoiseEstimate, TooSmallAMeshGivesNoEstimate) {
  sodt::MeshD m;
  // 8 vertices: none has 9 two-ring neighbours to fit; the two whose faces
  // lie flat in pairs read as clean, but two are too few to tell.
  sodt_test::makeCube(m, 1);
  const sodt::NoiseEstimate e = sodt::estimateNoiseOf(m);
  EXPECT_LT(e.samples, 10);
  EXPECT_TRUE(std::isnan(e.sigmaEdges));
}

TEST(NoiseEstimate, PassesOverBorderVertices) {
  // A flat open grid: only vertices with a closed fan are predicted (a
  // border vertex would be extrapolated), and the flat grid reads 0.
  sodt::MeshD m;
  sodt_test::makeGrid(m, 20, 0.0, 1);
  const sodt::NoiseEstimate e = sodt::estimateNoiseOf(m);
  EXPECT_EQ(e.samples, (20 - 2) * (20 - 2));
  EXPECT_LT(e.sigmaEdges, 1e-9);
}

namespace {

std::vector<sodt::Vec3> positions(const sodt::MeshD& m) {
  std::vector<sodt::Vec3> pos;
  for (const auto& v : m.vert) pos.push_back(sodt::Vec3::Construct(v.cP()));
  return pos;
}

/// Runs filtered's first stage alone on m (every vertex movable).
sodt::FilterChoice firstStage(sodt::MeshD& m, double noiseLevel = 0, int threads = 1) {
  const sodt::FaceList faces = sodt::makeFaceList(m);
  std::vector<sodt::Vec3> pos = positions(m);
  const std::vector<char> movable(pos.size(), 1);
  const sodt::FilterChoice c = sodt::filteredDenoise(faces, movable, 30.0, noiseLevel, threads, pos);
  for (std::size_t i = 0; i < pos.size(); ++i) m.vert[i].P() = vcg::Point3d(pos[i][0], pos[i][1], pos[i][2]);
  return c;
}

/// Mean squared difference of a and the clean positions along unit normals n.
double errorAlong(const std::vector<sodt::Vec3>& a, const std::vector<sodt::Vec3>& clean,
                  const std::vector<sodt::Vec3>& n) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = n[i] * (a[i] - clean[i]);
    s += d * d;
  }
  return s / double(a.size());
}

}  // namespace

TEST(FilterSelect, UmbrellaStepsAreTaubinSmoothing) {
  // A pair of umbrella steps is vcglib's Taubin step (MeshLab's Taubin
  // smoothing) with the same lambda and mu.
  sodt::MeshD m, ref;
  sodt_test::makeSphere(m, 3);
  addNormalNoise(m, 0.3, 5);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(ref, m);
  vcg::tri::UpdateFlags<sodt::MeshD>::FaceBorderFromNone(ref);
  vcg::tri::Smooth<sodt::MeshD>::VertexCoordTaubin(ref, 7, float(sodt::kTaubinLambda), float(sodt::kTaubinMu));
  const sodt::FaceList faces = sodt::makeFaceList(m);
  std::vector<sodt::Vec3> pos = positions(m);
  const std::vector<char> movable(pos.size(), 1);
  const sodt::UmbrellaSmoother u(faces, movable, m.vn, 2);
  for (int k = 0; k < 7; ++k) u.pair(pos);
  double moved = 0;
  for (int i = 0; i < m.vn; ++i) {
    moved = std::max(moved, (pos[i] - sodt::Vec3::Construct(m.vert[i].cP())).Norm());
    // vcglib takes lambda and mu as floats.
    EXPECT_LT((pos[i] - sodt::Vec3::Construct(ref.vert[i].cP())).Norm(), 1e-6) << i;
  }
  EXPECT_GT(moved, 0.01);
}

TEST(FilterSelect, RiskEstimatesTheErrorToTheCleanSurface) {
  // Stein's unbiased risk estimate of Taubin smoothing (a linear filter)
  // against the true mean squared error along the normals, for noise
  // along the normals of a sphere, at lengths from too short to too long.
  sodt::MeshD clean, m;
  sodt_test::makeSphere(clean, 5);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(m, clean);
  addNormalNoise(m, 0.3, 77);
  const std::vector<sodt::Vec3> y = positions(m), c = positions(clean);
  std::vector<sodt::Vec3> n;
  for (const sodt::Vec3& p : c) n.push_back(p / p.Norm());
  // The noise as drawn (a few percent off the 0.3 edges asked for).
  const double sigma = std::sqrt(errorAlong(y, c, n));
  const sodt::FaceList faces = sodt::makeFaceList(m);
  const std::vector<char> movable(y.size(), 1);
  const sodt::UmbrellaSmoother u(faces, movable, m.vn, 1);
  const sodt::detail::RiskProbe probe(y, n, movable, sigma);
  std::vector<sodt::Vec3> f = y, fp = probe.probed();
  const double input = errorAlong(y, c, n);
  double best = 1e9;
  int bestAt = 0;
  for (int k = 1; k <= 60; ++k) {
    u.pair(f);
    u.pair(fp);
    if (k % 5 && k != 1) continue;
    const double risk = probe.risk(f, fp), truth = errorAlong(f, c, n);
    std::printf("%2d pairs: risk %.3e, true error %.3e (input %.3e)\n", k, risk, truth, input);
    // It is unbiased, but for one draw of the noise and of the probe it
    // strayed by up to 0.3 of the error at 60 pairs, 0.02 of the input's
    // (six draws).
    EXPECT_NEAR(risk, truth, 0.2 * truth + 0.02 * input) << k << " pairs";
    if (truth < best) best = truth, bestAt = k;
  }
  EXPECT_GT(bestAt, 1);  // the lengths span the optimum
  EXPECT_LT(bestAt, 60);
  EXPECT_NEAR(probe.riskOfNone(), input, 1e-12 * input);
}

TEST(FilterSelect, PicksTaubinOnACoarseTorusAndTheNormalFilterOnANoisyCube) {
  // The coarse torus turns its faces 22 degrees per ring: the normal filter
  // flattens that, Taubin smoothing keeps it. The cube's flat sides and
  // sharp edges are the normal filter's. The pick must also be the better
  // of the two on the clean mesh's terms.
  sodt::MeshD torus, cube;
  sodt::loadMesh(std::string(SODT_MESH_DIR) + "/torus.off", torus);
  sodt_test::makeCube(cube, 10);
  for (sodt::MeshD* clean : {&torus, &cube}) {
    sodt::MeshD m;
    vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(m, *clean);
    addNormalNoise(m, 0.3, 123);
    const std::vector<sodt::Vec3> y = positions(m), c = positions(*clean);
    const sodt::FilterChoice choice = firstStage(m);
    const double err = sodt::surfaceDistance(m, *clean).meanRel;
    // The other family at its own best length, measured on the clean mesh.
    const sodt::FaceList faces = sodt::makeFaceList(m);
    const std::vector<char> movable(y.size(), 1);
    double other = 1e9;
    std::vector<sodt::Vec3> p = y;
    const sodt::NormalFilterRounds normals(faces, movable, 30.0, y, 1);
    const sodt::UmbrellaSmoother umbrella(faces, movable, m.vn, 1);
    sodt::MeshD probe;
    vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(probe, m);
    for (int k = 1; k <= 12; ++k) {
      if (choice.kind == sodt::FilterKind::Normals) {
        for (int j = 0; j < sodt::kUmbrellaCheck; ++j) umbrella.pair(p);
      } else {
        normals.round(p);
      }
      for (int i = 0; i < probe.vn; ++i) probe.vert[i].P() = vcg::Point3d(p[i][0], p[i][1], p[i][2]);
      other = std::min(other, sodt::surfaceDistance(probe, *clean).meanRel);
    }
    std::printf("%d vertices: %s, mean distance %.3e; the other filter at best %.3e\n", m.vn,
                sodt::describe(choice).c_str(), err, other);
    EXPECT_EQ(choice.kind, clean == &torus ? sodt::FilterKind::Taubin : sodt::FilterKind::Normals);
    EXPECT_LT(err, other);
    EXPECT_TRUE(choice.noiseEstimated);
    EXPECT_NEAR(choice.noiseEdges, 0.3, 0.1);
    EXPECT_LT(choice.risk, 0.5 * choice.riskNone);
  }
}

TEST(FilterSelect, LeavesACleanMeshOrOneWithLittleNoiseGivenAsItIs) {
  sodt::MeshD sphere;
  sodt_test::makeSphere(sphere, 4);
  const std::vector<sodt::Vec3> before = positions(sphere);
  const sodt::FilterChoice clean = firstStage(sphere);
  EXPECT_EQ(clean.kind, sodt::FilterKind::None) << sodt::describe(clean);
  EXPECT_EQ(positions(sphere), before);
  // Noisy, but the user says the noise is a thousandth of an edge: no
  // filter removes that little without moving the surface more.
  addNormalNoise(sphere, 0.3, 4);
  const std::vector<sodt::Vec3> noisy = positions(sphere);
  const sodt::FilterChoice given = firstStage(sphere, 0.001);
  EXPECT_EQ(given.kind, sodt::FilterKind::None) << sodt::describe(given);
  EXPECT_FALSE(given.noiseEstimated);
  EXPECT_EQ(given.noiseEdges, 0.001);
  EXPECT_EQ(positions(sphere), noisy);
  // Told the true level, it filters.
  EXPECT_NE(firstStage(sphere, 0.3).kind, sodt::FilterKind::None);
}

TEST(FilterSelect, NoFilterWhenTheNoiseLevelIsUnknown) {
  // A 12-triangle box has too few vertices to estimate its noise from: a
  // filter would only guess, and the normal filter rounds it once ran
  // then took 99% of its volume.
  sodt::MeshD box;
  sodt_test::makeCube(box, 1);
  const std::vector<sodt::Vec3> before = positions(box);
  const sodt::FilterChoice c = firstStage(box);
  EXPECT_EQ(c.kind, sodt::FilterKind::None) << sodt::describe(c);
  EXPECT_TRUE(std::isnan(c.noiseEdges));
  EXPECT_TRUE(std::isnan(c.risk));
  EXPECT_EQ(positions(box), before);
  EXPECT_NE(sodt::describe(c).find("could not be estimated"), std::string::npos) << sodt::describe(c);
}

TEST(FilterSelect, AFilterThatBarelyBeatsNoneIsNotApplied) {
  // Told a noise level of 0.2 edges where it is 0.3, the best filter (five
  // Taubin step pairs) scores 0.74 of no filter: too little to trust an
  // estimate with, so the input stays, and the report names the filter.
  sodt::MeshD sphere;
  sodt_test::makeSphere(sphere, 4);
  addNormalNoise(sphere, 0.3, 4);
  const std::vector<sodt::Vec3> noisy = positions(sphere);
  const sodt::FilterChoice c = firstStage(sphere, 0.2);
  EXPECT_EQ(c.kind, sodt::FilterKind::None) << sodt::describe(c);
  EXPECT_NE(c.passedOver, sodt::FilterKind::None);
  EXPECT_GT(c.passedOverSteps, 0);
  EXPECT_GT(c.risk, sodt::kSureMargin * c.riskNone);
  EXPECT_LT(c.risk, c.riskNone);
  EXPECT_EQ(positions(sphere), noisy);
  EXPECT_NE(sodt::describe(c).find("not below"), std::string::npos) << sodt::describe(c);
}

TEST(FilterSelect, SameChoiceAndResultForEveryThreadCount) {
  sodt::MeshD a, b;
  sodt_test::makeSphere(a, 4);
  addNormalNoise(a, 0.3, 8);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(b, a);
  const sodt::FilterChoice ca = firstStage(a, 0, 1), cb = firstStage(b, 0, 2);
  EXPECT_EQ(ca.kind, cb.kind);
  EXPECT_EQ(ca.steps, cb.steps);
  EXPECT_EQ(ca.risk, cb.risk);
  EXPECT_EQ(positions(a), positions(b));
}

namespace {

/// Distance of p to the bundled torus (tube radius 0.4 around a circle of
/// radius 1 in the z = 0 plane).
double torusDistance(const vcg::Point3d& p) {
  const double ring = std::hypot(p[0], p[1]) - 1.0;
  return std::abs(std::hypot(ring, p[2]) - 0.4);
}

double meanTorusDistance(const sodt::MeshD& m) {
  double s = 0;
  for (const auto& v : m.vert) s += torusDistance(v.cP());
  return s / m.vn;
}

/// The quadrics of every vertex of m where its surface is smooth within
/// 15 degrees (half the default feature angle).
sodt::SurfaceQuadrics quadricsOf(const sodt::MeshD& m) {
  const std::vector<sodt::Vec3> pos = positions(m);
  std::vector<int> all(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i) all[i] = static_cast<int>(i);
  sodt::SurfaceQuadrics q;
  q.fit(sodt::buildRingTopology(m), pos, all, std::cos(15.0 * M_PI / 180), 1);
  return q;
}

}  // namespace

TEST(SurfaceRestore, PutsTangentialMovesBackOnACurvedSurface) {
  // Every vertex of a unit sphere moved by a third of an edge in its
  // tangent plane ends off the sphere by about kappa d^2 / 2; put back on
  // its quadric, by much less.
  sodt::MeshD sphere;
  sodt_test::makeSphere(sphere, 3);
  const std::vector<sodt::Vec3> pos = positions(sphere);
  const sodt::SurfaceQuadrics q = quadricsOf(sphere);
  const double step = meanEdge(sphere) / 3;
  std::mt19937 g(5);
  double offPlane = 0, offQuadric = 0;
  for (std::size_t i = 0; i < pos.size(); ++i) {
    ASSERT_TRUE(q.has(static_cast<int>(i)));
    const sodt::Vec3 n = pos[i] / pos[i].Norm();
    const sodt::Vec3 a = std::abs(n[0]) < 0.9 ? sodt::Vec3(1, 0, 0) : sodt::Vec3(0, 1, 0);
    const sodt::Vec3 u = (a - n * (a * n)).Normalize(), v = n ^ u;
    const double t = 2 * M_PI * sodt_test::uniform01(g);
    const sodt::Vec3 x = pos[i] + (u * std::cos(t) + v * std::sin(t)) * step;
    sodt::Vec3 y;
    ASSERT_TRUE(q.onQuadric(static_cast<int>(i), x, 1.5 * step, y));
    offPlane += std::abs(x.Norm() - 1);
    offQuadric += std::abs(y.Norm() - 1);
    // Too far from the vertex for its quadric.
    EXPECT_FALSE(q.onQuadric(static_cast<int>(i), pos[i] + u * (3 * step), 1.5 * step, y));
  }
  std::printf("off the sphere: %.3e in the tangent planes, %.3e on the quadrics\n", offPlane / pos.size(),
              offQuadric / pos.size());
  EXPECT_LT(offQuadric, 0.1 * offPlane);

  // No quadric across or beside a sharp edge: on a cube only the vertices
  // two rings or more from an edge have one, and it is flat.
  sodt::MeshD cube;
  sodt_test::makeCube(cube, 6);
  const std::vector<sodt::Vec3> cp = positions(cube);
  const sodt::SurfaceQuadrics cq = quadricsOf(cube);
  int with = 0;
  for (std::size_t i = 0; i < cp.size(); ++i) {
    // Coordinates strictly inside the side, more than a ring from its edges
    // (edges a third long): the other one is the side's.
    int inside = 0, side = -1;
    for (int k = 0; k < 3; ++k) {
      if (std::abs(cp[i][k]) < 0.5)
        ++inside;
      else
        side = k;
    }
    EXPECT_EQ(cq.has(static_cast<int>(i)), inside == 2) << cp[i][0] << " " << cp[i][1] << " " << cp[i][2];
    if (!cq.has(static_cast<int>(i))) continue;
    ++with;
    sodt::Vec3 x = cp[i] + sodt::Vec3(0.1, 0.1, 0.1), y;
    x[side] = cp[i][side];  // a move within the side
    ASSERT_TRUE(cq.onQuadric(static_cast<int>(i), x, 1.0, y));
    EXPECT_LT((y - x).Norm(), 1e-12);
  }
  EXPECT_GT(with, 0);
}

TEST(Filtered, SweepsKeepTheDenoisedSurfaceOfACoarseTorus) {
  // The sweeps' moves lie in tangent planes; on the coarse torus (faces
  // turn 22 degrees per ring) that alone took the result further from the
  // clean torus than the denoised surface was. Set back on the denoised
  // surface's quadrics, the result is as close as the denoised surface.
  sodt::MeshD clean;
  sodt::loadMesh(std::string(SODT_MESH_DIR) + "/torus.off", clean);
  sodt::MeshD m, denoised;
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(m, clean);
  addNormalNoise(m, 0.2, 11);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(denoised, m);
  const double noisy = meanTorusDistance(m);
  firstStage(denoised);
  const sodt::SodtStats st = runFiltered(m);
  const double first = meanTorusDistance(denoised), result = meanTorusDistance(m);
  std::printf("mean distance to the torus: noisy %.4e, denoised %.4e, result %.4e; %d vertices restored\n", noisy,
              first, result, st.restoredVertices);
  EXPECT_GT(st.restoredVertices, m.vn / 2);
  EXPECT_LT(first, 0.6 * noisy);
  EXPECT_LE(result, first);
}

TEST(Filtered, SweepsStayWithinTheBoundOfTheFilteredSurface) {
  // The sweeps have the deviation bound, against the surface the filter
  // made: the result is never farther from the input than the filter
  // moved it, plus the bound. Clean coarse cylinders get no filter and so
  // stay within the bound of their input (as with feature); a noisy cube
  // stays within it of its denoised surface, the bound raised to half the
  // noise's standard deviation. (The sampled Hausdorff distance may pass
  // the bound between the checked points: 1.5 times.)
  const double bound = sodt::SodtParams().maxDeviationRel;
  sodt::MeshD cylinder, input;
  makeCadCylinder(cylinder, 24, 0.5);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(input, cylinder);
  const sodt::SodtStats sc = runFiltered(cylinder);
  EXPECT_EQ(sc.filter.kind, sodt::FilterKind::None) << sodt::describe(sc.filter);
  EXPECT_EQ(sc.filteredSweepBoundRel, bound);
  const double dc = sodt::surfaceDistance(cylinder, input).maxRel;
  EXPECT_LE(dc, 1.5 * bound);
  // A coarse half cylinder (8 segments) of uneven chords: its vertices
  // slide around it, and without the bound that cuts its arcs.
  sodt::MeshD arc, arcInput, unbounded;
  sodt_test::makeHalfCylinder(arc, 8, 0.3, 5);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(arcInput, arc);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(unbounded, arc);
  const sodt::SodtStats sa = runFiltered(arc);
  const double da = sodt::surfaceDistance(arc, arcInput).maxRel;
  EXPECT_EQ(sa.filter.kind, sodt::FilterKind::None) << sodt::describe(sa.filter);
  EXPECT_GT(sa.moved + sa.backtracked + sa.fallbackMoves, 0);
  EXPECT_LE(da, 1.5 * bound);
  sodt::SodtParams off;
  off.algorithm = Algorithm::Filtered;
  off.threads = 1;
  off.maxDeviationRel = 0;
  sodt::SodtSmoother<sodt::MeshD>::Apply(unbounded, off);
  const double du = sodt::surfaceDistance(unbounded, arcInput).maxRel;
  EXPECT_GT(du, 3 * bound);

  sodt::MeshD cube, denoised;
  sodt_test::makeCube(cube, 10);
  addNormalNoise(cube, 0.3, 31);
  vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(denoised, cube);
  const sodt::FilterChoice c = firstStage(denoised);
  const sodt::SodtStats sn = runFiltered(cube);
  EXPECT_EQ(sn.filter.kind, c.kind);
  EXPECT_NE(sn.filter.kind, sodt::FilterKind::None);
  const double dn = sodt::surfaceDistance(cube, denoised).maxRel;
  // Half the noise level, in diagonals: the noisy input's mean edge, the
  // cube's diagonal 2 sqrt(3) (the noise changes it by a few percent).
  sodt::MeshD cube2;
  sodt_test::makeCube(cube2, 10);
  addNormalNoise(cube2, 0.3, 31);
  const double half = 0.5 * sn.filter.noiseEdges * sodt::meanEdgeLength(cube2) / (2 * std::sqrt(3.0));
  EXPECT_GT(half, 2 * bound);
  EXPECT_NEAR(sn.filteredSweepBoundRel, half, 0.05 * half);
  std::printf("Hausdorff distance, in diagonals: clean cylinder to its input %.2e, half cylinder %.2e (%.2e "
              "without the bound), noisy cube to its denoised surface %.2e (bound %.2e, half the noise %.2e)\n",
              dc, da, du, dn, bound, sn.filteredSweepBoundRel);
  EXPECT_LE(dn, 1.5 * sn.filteredSweepBoundRel);
  // A bound given above half the noise is kept as given.
  sodt::SodtParams wide;
  wide.algorithm = Algorithm::Filtered;
  wide.threads = 1;
  wide.maxDeviationRel = 3 * half;
  EXPECT_EQ(sodt::SodtSmoother<sodt::MeshD>::Apply(cube2, wide).filteredSweepBoundRel, wide.maxDeviationRel);
}
