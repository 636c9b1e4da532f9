// SPDX-License-Identifier: GPL-3.0-or-later
// The deviation guard: its face test must give the answer of the exact
// point-triangle distance everywhere, and the margins it keeps between visits
// must not change any result.
#include <sodt/guards/deviation.h>
#include <sodt_io/io.h>
#include <sodt_io/mesh.h>
#include <sodt_io/prebuilt.h>

#include <vcg/complex/append.h>

#include "full_fixture.h"
#include "test_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace {

using sodt::Vec3;

/// One InputSurface over loose triangles (no topology needed by nearFace).
struct Triangles {
  std::vector<Vec3> pos;
  sodt::FaceList faces;
  sodt::RingTopology topo;
  sodt::InputSurface in;

  void add(const Vec3& a, const Vec3& b, const Vec3& c) {
    const int i = static_cast<int>(pos.size());
    pos.insert(pos.end(), {a, b, c});
    faces.tri.push_back({i, i + 1, i + 2});
    faces.live.push_back(1);
    faces.flippable.push_back(0);
  }
  void prepare(double limit) {
    in.faces = &faces;
    in.topo = &topo;
    in.pos = &pos;
    in.prepare(limit);
  }
  bool exact(int f, const Vec3& q) const {
    const auto& t = faces.tri[f];
    return sodt::pointTriangleDistance2(q, pos[t[0]], pos[t[1]], pos[t[2]]) <= in.limit2;
  }
};

/// A point at signed height h over the barycentric point (u, v) of face f
/// (u, v may lie outside the face), plus a little noise.
Vec3 probe(const Triangles& T, int f, double u, double v, double h) {
  const auto& t = T.faces.tri[f];
  const Vec3 &a = T.pos[t[0]], &b = T.pos[t[1]], &c = T.pos[t[2]];
  Vec3 n = (b - a) ^ (c - a);
  const double len = n.Norm();
  if (len > 0) n /= len;
  return a + (b - a) * u + (c - a) * v + n * h;
}

TEST(DeviationGuard, FaceTestAgreesWithTheExactDistance) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  Triangles T;
  const double offsets[] = {0.0, 1e3, -4e5};  // far from the origin too
  for (double off : offsets) {
    for (int k = 0; k < 40; ++k) {
      const Vec3 o(off + U(rng), off * 0.5 + U(rng), U(rng));
      const Vec3 a = o + Vec3(U(rng), U(rng), U(rng)), b = o + Vec3(U(rng), U(rng), U(rng));
      Vec3 c = o + Vec3(U(rng), U(rng), U(rng));
      if (k % 10 == 0) c = a + (b - a) * 0.3;  // collinear: no plane
      if (k % 10 == 1) c = a + (b - a) * 0.5 + Vec3(1e-9, 0, 0);  // a sliver
      T.add(a, b, c);
    }
  }
  const double limit = 0.05;
  T.prepare(limit);
  long long tested = 0, near = 0, borderline = 0;
  std::uniform_real_distribution<double> bary(-0.3, 1.3);
  for (int f = 0; f < static_cast<int>(T.faces.tri.size()); ++f) {
    for (int s = 0; s < 3000; ++s) {
      // Heights clustered at the bound and barycentrics at the edges, where
      // the fast path must hand over to the exact distance.
      double h = limit * (s % 3 == 0 ? U(rng) * 3 : (1 + 1e-7 * U(rng)) * (U(rng) < 0 ? -1 : 1));
      double u = bary(rng), v = bary(rng);
      if (s % 4 == 1) u = 1e-9 * U(rng);
      if (s % 4 == 2) v = 1 - u + 1e-9 * U(rng);
      const Vec3 q = probe(T, f, u, v, h);
      const bool want = T.exact(f, q);
      const auto& t = T.faces.tri[f];
      const double exact = std::sqrt(sodt::pointTriangleDistance2(q, T.pos[t[0]], T.pos[t[1]], T.pos[t[2]]));
      // The reference itself rounds at the scale of the coordinates (far
      // from the origin, 1e-11 here): closer to the bound than that, either
      // answer is right.
      const Vec3& a = T.pos[t[0]];
      const double band = 1e-13 * (std::abs(a[0]) + std::abs(a[1]) + std::abs(a[2]) + T.in.reach[f] + limit);
      double dist = -1;
      const bool got = T.in.nearFace(f, q, &dist);
      if (std::abs(exact - limit) > band) { ASSERT_EQ(got, want) << "face " << f << " sample " << s; }
      if (got) {
        // The distance it reports bounds the exact one from above, closely.
        ASSERT_GE(dist, exact - band) << "face " << f << " sample " << s;
        ASSERT_LE(dist, exact + 1e-8 * (T.in.reach[f] + limit)) << "face " << f << " sample " << s;
      }
      ++tested;
      near += want;
      borderline += std::abs(std::abs(h) - limit) < 1e-6 * limit;
    }
  }
  // Both answers occur often, and many samples sit at the bound.
  EXPECT_GT(near, tested / 5);
  EXPECT_LT(near, tested * 4 / 5);
  EXPECT_GT(borderline, tested / 2);
}

}  // namespace

/// The margins the guard reuses between visits only save distance queries:
/// runs with and without them end bit for bit alike, with the same counters,
/// while a good share of the checked points needs no query (most of them
/// at the default bound). A tight bound (0.02%) makes the guard decide
/// often; the noisy cube has creases and a corner. After flips the stars a
/// flip did not change keep their margins: the shares asked of the last two
/// flip cases are above what they reach when flips drop every margin (0.48
/// and 0.31). Those shares are of the full fixture's 15 sweeps; the small
/// fixture's 5 leave the margins less time to pay off (3% to 46% of the
/// points), so it asks only that they answer 2%.
SODT_FULL_FIXTURE_TEST(DeviationGuard, ReusedMarginsChangeNoResult) {
  struct Case {
    const char* mesh;
    sodt::Algorithm algorithm;
    sodt::Guard guard;
    bool flips;
    double bound;
    double reusedShare;  ///< at least this share of the checked points (full fixture)
  };
  const Case cases[] = {
      {"blobs_mc.ply", sodt::Algorithm::Basic, sodt::Guard::Fold, false, 0.001, 0.4},
      {"blobs_mc.ply", sodt::Algorithm::Basic, sodt::Guard::Quality, false, 0.0002, 0.05},
      {"blobs_mc.ply", sodt::Algorithm::Basic, sodt::Guard::Fold, true, 0.0002, 0.02},
      {"blobs_mc.ply", sodt::Algorithm::Basic, sodt::Guard::Quality, true, 0.001, 0.55},
      {"cube_noisy.ply", sodt::Algorithm::Feature, sodt::Guard::Quality, true, 0.001, 0.45},
      {"cube_noisy.ply", sodt::Algorithm::Feature, sodt::Guard::Quality, false, 0.0002, 0.05},
      {"sphere_jitter.ply", sodt::Algorithm::Odt, sodt::Guard::Fold, false, 0.0002, 0.05},
  };
  for (const Case& c : cases) {
    const std::string what = std::string(c.mesh) + " " + sodt::toString(c.guard) + (c.flips ? " flips" : "");
    sodt::MeshD input;
    sodt::loadMesh(std::string(SODT_MESH_DIR) + "/" + c.mesh, input);
    sodt::MeshD with, without;
    vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(with, input);
    vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(without, input);
    sodt::SodtParams p;
    p.algorithm = c.algorithm;
    p.guard = c.guard;
    p.flips = c.flips;
    p.maxDeviationRel = c.bound;
    p.iterations = sodt_test::fullFixture() ? 15 : 5;
    p.threads = 2;
    const sodt::SodtStats a = sodt::SodtSmoother<sodt::MeshD>::Apply(with, p);
    sodt::SweepTuning noMargins;
    noMargins.reuseDeviationMargins = false;
    const sodt::SodtStats b = sodt::SodtSmoother<sodt::MeshD>::Apply(without, p, nullptr, nullptr, noMargins);
    EXPECT_TRUE(sodt_test::positions(with) == sodt_test::positions(without)) << what;
    EXPECT_TRUE(sodt_test::faceIndices(with) == sodt_test::faceIndices(without)) << what;
    EXPECT_EQ(a.moved, b.moved) << what;
    EXPECT_EQ(a.backtracked, b.backtracked) << what;
    EXPECT_EQ(a.fallbackMoves, b.fallbackMoves) << what;
    EXPECT_EQ(a.rejected, b.rejected) << what;
    EXPECT_EQ(a.flips, b.flips) << what;
    EXPECT_EQ(b.deviationReused, 0) << what;
    EXPECT_GT(a.moved + a.backtracked + a.fallbackMoves, 0) << what;
    // The margins do get used, and only instead of queries.
    EXPECT_GT(a.deviationReused, (sodt_test::fullFixture() ? c.reusedShare : 0.02) * b.deviationQueries) << what;
    EXPECT_EQ(a.deviationReused + a.deviationQueries, b.deviationQueries) << what;
    std::printf("%s: %lld of %lld checked points answered from margins\n", what.c_str(), a.deviationReused,
                b.deviationQueries);
  }
}

/// Stored margins and odometers stay lower bounds of what they round,
/// whatever the magnitude (beyond float's range too).
TEST(DeviationGuard, FloatBelowIsALowerBound) {
  const double values[] = {0.0, 1e-300, 1e-30, 0.1, 1.0 / 3.0, 12345.678, 3e38, 3.5e38, 1e100, 1e300,
                           -1e-300, -0.1, -1.0 / 3.0, -3e38, -3.5e38, -1e100};
  for (double x : values) {
    const float f = sodt::InputSurface::floatBelow(x);
    EXPECT_LE(static_cast<double>(f), x) << x;
    if (std::abs(x) < 1e30 && std::abs(x) > 1e-30) { EXPECT_GT(static_cast<double>(f), x - 1e-5 * std::abs(x)) << x; }
  }
  EXPECT_TRUE(std::isnan(sodt::InputSurface::floatBelow(std::nan(""))));
}

/// The first sweep starts from the input, whose vertices, centroids and edge
/// midpoints lie on the input: it checks them from the margin that leaves
/// instead of querying. The result is the same as querying every point, on
/// a mesh far from the origin too (where rounding eats into that margin).
/// Against these coarse meshes' first steps the loose bounds leave the
/// margin to answer most points, the tight ones leave the queries to decide.
TEST(DeviationGuard, FirstSweepStartsFromTheInputMargin) {
  struct Case {
    const char* mesh;
    double bound;
    double offset;    ///< added to every coordinate
    double minShare;  ///< of the checked points, answered from the margin
  };
  const Case cases[] = {{"blobs_mc.ply", 0.01, 0.0, 0.9},     {"sphere_jitter.ply", 0.005, 0.0, 0.3},
                        {"blobs_mc.ply", 0.01, 3e3, 0.9},     {"blobs_mc.ply", 0.0002, 0.0, 0.001},
                        {"cube_noisy.ply", 0.001, 0.0, 0.05}, {"cube_noisy.ply", 0.003, 0.0, 0.15},
                        {"cube_jitter.ply", 0.003, 0.0, 0.03}};
  for (const Case& c : cases) {
    const std::string what = std::string(c.mesh) + " bound " + std::to_string(c.bound) + " offset " +
                             std::to_string(c.offset);
    sodt::MeshD input;
    sodt::loadMesh(std::string(SODT_MESH_DIR) + "/" + c.mesh, input);
    for (auto& v : input.vert) v.P() += vcg::Point3d(c.offset, -c.offset, c.offset);
    sodt::MeshD with, without;
    vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(with, input);
    vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(without, input);
    sodt::SodtParams p;
    p.guard = sodt::Guard::Fold;
    p.maxDeviationRel = c.bound;
    p.iterations = 1;
    const sodt::SodtStats a = sodt::SodtSmoother<sodt::MeshD>::Apply(with, p);
    sodt::SweepTuning noMargins;
    noMargins.reuseDeviationMargins = false;
    const sodt::SodtStats b = sodt::SodtSmoother<sodt::MeshD>::Apply(without, p, nullptr, nullptr, noMargins);
    EXPECT_TRUE(sodt_test::positions(with) == sodt_test::positions(without)) << what;
    EXPECT_EQ(a.moved, b.moved) << what;
    EXPECT_EQ(a.backtracked, b.backtracked) << what;
    EXPECT_EQ(a.rejected, b.rejected) << what;
    EXPECT_EQ(a.deviationReused + a.deviationQueries, b.deviationQueries) << what;
    EXPECT_GT(a.deviationReused, c.minShare * b.deviationQueries) << what;
    std::printf("%s: first sweep, %lld of %lld checked points answered from margins\n", what.c_str(),
                a.deviationReused, b.deviationQueries);
  }
}

namespace {

/// The faces of v's patch, sorted, each once.
std::vector<int> patchOf(const sodt::InputSurface& in, int v) {
  std::vector<int> faces;
  in.forEachPatchFace(v, [&](int f, int) {
    faces.push_back(f);
    return false;
  });
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

/// The faces of v's one-ring and of its interior neighbours' one-rings.
std::vector<int> twoRingOf(const sodt::RingTopology& T, int v) {
  std::vector<int> faces;
  for (int k = T.ringBegin[v]; k < T.ringBegin[v + 1]; ++k) {
    faces.push_back(T.ringFace[k]);
    const int u = T.ringIdx[k];
    if (T.kind[u] != sodt::VertexKind::Interior) continue;
    for (int j = T.ringBegin[u]; j < T.ringBegin[u + 1]; ++j) faces.push_back(T.ringFace[j]);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

/// The input surface of a whole mesh, as the smoother builds it.
struct MeshSurface {
  sodt::FaceList faces;
  sodt::RingTopology topo;
  std::vector<Vec3> pos;
  sodt::InputSurface in;

  MeshSurface(const sodt::MeshD& m, double limit) : faces(sodt::makeFaceList(m)), topo(sodt::buildRingTopology(m)) {
    for (const auto& v : m.vert) pos.push_back(v.cP());
    in.faces = &faces;
    in.topo = &topo;
    in.pos = &pos;
    in.prepare(limit);
  }
  MeshSurface(const MeshSurface&) = delete;  // in points into this object
  MeshSurface& operator=(const MeshSurface&) = delete;
};

}  // namespace

/// Where no star has more than kPatchWindow faces, a vertex's patch is its
/// input two-ring, as it always was.
TEST(DeviationGuard, PatchIsTheTwoRingAroundOrdinaryStars) {
  for (const char* name : {"blobs_mc.ply", "torus.off", "cube_jitter.ply"}) {
    sodt::MeshD m;
    sodt::loadMesh(std::string(SODT_MESH_DIR) + "/" + name, m);
    const MeshSurface S(m, 0.01);
    const sodt::RingTopology& topo = S.topo;
    const sodt::InputSurface& in = S.in;
    int interior = 0;
    for (int v = 0; v < static_cast<int>(m.vert.size()); ++v) {
      ASSERT_LE(topo.ringSize(v), int{sodt::InputSurface::kPatchWindow}) << name;
      if (topo.kind[v] != sodt::VertexKind::Interior) continue;
      ++interior;
      ASSERT_EQ(patchOf(in, v), twoRingOf(topo, v)) << name << " vertex " << v;
    }
    EXPECT_GT(interior, 100) << name;
  }
}

/// Next to a vertex of valence N the patch takes kPatchWindow faces of its
/// star, those on either side of the edge, so that a sweep costs time linear
/// in the faces: a rim vertex of a closed double fan searches
/// 2 kPatchWindow faces, not 2 N + 2. The apexes' patches are their own
/// stars and the rim faces next to them.
TEST(DeviationGuard, PatchNextToAHighValenceVertexIsAWindow) {
  const int n = 1000;
  std::vector<vcg::Point3d> ring;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * sodt::kPi * k / n;
    ring.emplace_back(std::cos(t), std::sin(t), 0);
  }
  sodt::MeshD m;
  sodt_test::makeBipyramid(m, ring, vcg::Point3d(0, 0, 1));
  const MeshSurface S(m, 0.01);
  const sodt::FaceList& faces = S.faces;
  const sodt::RingTopology& topo = S.topo;
  const std::vector<Vec3>& pos = S.pos;
  const sodt::InputSurface& in = S.in;
  const int w = sodt::InputSurface::kPatchWindow;
  for (int v = 2; v < n + 2; ++v) {
    ASSERT_EQ(topo.kind[v], sodt::VertexKind::Interior);
    const std::vector<int> patch = patchOf(in, v);
    ASSERT_EQ(static_cast<int>(patch.size()), 2 * w) << "rim vertex " << v;
    // The window is centred on v: faces of the top apex's star within w / 2
    // rim steps of v, and v's own faces.
    for (int f : patch) {
      const auto& t = faces.tri[f];
      int apex = -1, lo = -1;  // the apex and the first rim corner in ring order
      for (int j = 0; j < 3; ++j)
        if (t[j] < 2) apex = t[j];
      ASSERT_GE(apex, 0);
      for (int j = 0; j < 3; ++j)
        if (t[j] >= 2 && (t[(j + 1) % 3] >= 2) && apex == 0) lo = t[j] - 2;
      if (apex == 0) {
        const int steps = ((lo - (v - 2)) % n + n) % n;
        EXPECT_TRUE(steps < w / 2 || steps >= n - w / 2) << "rim vertex " << v << ", face " << f;
      }
    }
  }
  for (int apex : {0, 1}) EXPECT_EQ(static_cast<int>(patchOf(in, apex).size()), 2 * n) << "apex " << apex;
  // A point over the far side of the top cone is near the input surface but
  // not near a rim vertex's patch; it is near the apex's.
  const Vec3 far = (pos[0] + pos[2 + n / 2] + pos[2 + n / 2 + 1]) / 3.0;
  EXPECT_LT(in.nearFaceOf(2, far, -1), 0);
  EXPECT_GE(in.nearFaceOf(0, far, -1), 0);
}
