// SPDX-License-Identifier: GPL-3.0-or-later
// The defect zoo through the core: every zoo mesh, every algorithm (basic,
// feature, denoise), every guard, with and without flips, on a double and a
// float mesh. Asserts the documented outcome: which vertices stay bitwise
// fixed and how they are counted, no exception except InvalidInput for
// non-finite input (mesh untouched), no-op without faces, finite output, no
// face turned against its input orientation, the smallest angle of the
// non-degenerate faces never lowered by the quality guard, scale invariance.
#include "defect_zoo.h"
#include "zoo_checks.h"

#include <gtest/gtest.h>

#include <sodt_io/io.h>
#include <sodt_io/metrics.h>
#include <sodt_io/prebuilt.h>
#include <sodt/maths/topology.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using sodt::Algorithm;
using sodt::Guard;
using sodt::MeshD;
using sodt::MeshF;
using sodt_zoo::CoreOutcome;
using sodt_zoo::Kind;
using sodt_zoo::ZooMesh;

const char* meshTypeName(const MeshD*) { return "double"; }
const char* meshTypeName(const MeshF*) { return "float"; }

/// Vertices and faces of m are exactly those of ref (bitwise coordinates).
template <class M>
void expectUntouched(const M& m, const M& ref) {
  ASSERT_EQ(m.vert.size(), ref.vert.size());
  ASSERT_EQ(m.face.size(), ref.face.size());
  for (std::size_t i = 0; i < m.vert.size(); ++i)
    EXPECT_TRUE(sodt_zoo::sameBits<M>(m.vert[i].cP(), ref.vert[i].cP())) << "vertex " << i << " changed";
  for (std::size_t f = 0; f < m.face.size(); ++f)
    for (int j = 0; j < 3; ++j)
      EXPECT_EQ(m.face[f].cV(j) - &m.vert[0], ref.face[f].cV(j) - &ref.vert[0]) << "face " << f << " changed";
}

/// One run of the smoother on zoo mesh z with the documented expectations.
template <class M>
void checkRun(const ZooMesh& z, Algorithm a, Guard g, bool flips) {
  SCOPED_TRACE(std::string(meshTypeName(static_cast<M*>(nullptr))) + " mesh, algorithm " + sodt::toString(a) +
               ", guard " + sodt::toString(g) + ", flips " + (flips ? "on" : "off"));
  M m, ref;
  sodt_zoo::toMesh(z.soup, m);
  sodt_zoo::toMesh(z.soup, ref);
  sodt::SodtParams p;
  p.algorithm = a;
  p.guard = g;
  p.flips = flips;
  sodt::Classification cls;

  if (z.core == CoreOutcome::InvalidInput) {
    try {
      sodt::SodtSmoother<M>::Apply(m, p, nullptr, &cls);
      ADD_FAILURE() << "no exception for a mesh with non-finite coordinates";
    } catch (const sodt::InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(z.coreError), std::string::npos)
          << "message '" << e.what() << "' does not contain '" << z.coreError << "'";
    } catch (const std::exception& e) {
      ADD_FAILURE() << "unexpected exception type: " << e.what();
    }
    expectUntouched(m, ref);
    return;
  }

  sodt::SodtStats st;
  try {
    st = sodt::SodtSmoother<M>::Apply(m, p, nullptr, &cls);
  } catch (const std::exception& e) {
    FAIL() << "unexpected exception: " << e.what();
  }
  // With Guard::None the flattened sphere diverges; positions the mesh's
  // scalar cannot hold are never written, so the output stays finite.
  EXPECT_TRUE(sodt_zoo::allFinite(m)) << "non-finite output coordinate";

  if (z.core == CoreOutcome::NoOp) {
    expectUntouched(m, ref);
    EXPECT_EQ(st.activeVertices, 0);
    EXPECT_EQ(st.fixedBoundary, 0);
    EXPECT_EQ(st.fixedNonManifold, 0);
    EXPECT_EQ(st.iterations, 0);
    EXPECT_EQ(st.flips, 0);
    return;
  }

  // Counters: every fixed vertex counted once, every visit counted once.
  EXPECT_EQ(st.fixedBoundary, z.count(Kind::Boundary));
  EXPECT_EQ(st.fixedNonManifold, z.count(Kind::NonManifold));
  EXPECT_EQ(st.activeVertices, z.count(Kind::Interior) - st.cornerVertices);
  if (a == Algorithm::Basic) {
    EXPECT_EQ(st.cornerVertices, 0);
  }
  EXPECT_EQ(st.moved + st.backtracked + st.rejected + st.failedSolves + st.unchanged + st.fallbackMoves,
            static_cast<long long>(st.iterations) * st.activeVertices);

  // Fixed vertices keep their bits; interior ones are classified and may move.
  int movedInterior = 0;
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    const Kind k = z.kind[i];
    const bool same = sodt_zoo::sameBits<M>(m.vert[i].cP(), ref.vert[i].cP());
    if (k != Kind::Interior) {
      EXPECT_TRUE(same) << sodt_zoo::toString(k) << " vertex " << i << " moved";
      if (k != Kind::Deleted) {
        EXPECT_EQ(cls.cls[i], sodt::VertexClass::Fixed) << "vertex " << i;
      }
    } else {
      EXPECT_NE(cls.cls[i], sodt::VertexClass::Fixed) << "interior vertex " << i << " classified fixed";
      movedInterior += same ? 0 : 1;
    }
  }
  if (z.count(Kind::Interior) > 0 && z.name != "collapsed_to_point") {
    EXPECT_GT(movedInterior, 0) << "nothing was smoothed";
  }

  // Flips and turning faces over to one winding change the face list.
  const bool facesChanged = st.flips > 0 || st.reorientedFaces > 0;
  if (g != Guard::None) {
    if (!facesChanged) {
      EXPECT_EQ(sodt::countInvertedFaces(m, ref), 0) << "faces turned by more than 90 degrees";
    } else {
      const sodt_zoo::EdgeReport before = sodt_zoo::edgeReport(ref), after = sodt_zoo::edgeReport(m);
      EXPECT_TRUE(after.notWorseThan(before))
          << "flips made the edges worse: border " << before.border << " -> " << after.border
          << ", non-manifold " << before.nonManifold << " -> " << after.nonManifold << ", misoriented "
          << before.misoriented << " -> " << after.misoriented;
    }
  }
  if (g == Guard::Quality) {
    const std::vector<char> degenerate = sodt_zoo::degenerateFaces(z.soup);
    std::vector<char> regular(degenerate.size());
    bool anyDegenerate = false;
    for (std::size_t f = 0; f < degenerate.size(); ++f) {
      regular[f] = !degenerate[f];
      anyDegenerate = anyDegenerate || degenerate[f];
    }
    constexpr double kTolDeg = 1e-7;  // atan2 angles vs the guard's squared cosines
    if (!facesChanged) {
      const double before = sodt_zoo::minAngleDeg(ref, regular), after = sodt_zoo::minAngleDeg(m, regular);
      // Note: the quality guard does not limit a vertex whose star holds an
      // exactly zero-area face (that star's smallest angle is already 0), so
      // nothing in the core guarantees this for the zero-area zoo meshes; it
      // holds because the S-ODT and Laplacian steps improve those stars.
      EXPECT_GE(after, before - kTolDeg) << "smallest angle of the non-degenerate faces went down";
    } else if (!anyDegenerate) {
      EXPECT_GE(sodt_zoo::minAngleDeg(m, {}), sodt_zoo::minAngleDeg(ref, {}) - kTolDeg)
          << "smallest angle went down with flips";
    }
  }
}

std::string paramName(const testing::TestParamInfo<std::string>& info) { return info.param; }

// ---------------------------------------------------------------------------

class Zoo : public testing::TestWithParam<std::string> {};

class ZooTopology : public testing::TestWithParam<std::string> {};

/// The generator's expectation agrees with the core's one-ring topology.
TEST_P(ZooTopology, KindsMatchConstruction) {
  const ZooMesh z = sodt_zoo::zooMesh(GetParam());
  MeshD m;
  sodt_zoo::toMesh(z.soup, m);
  const sodt::RingTopology topo = sodt::buildRingTopology(m);
  const std::vector<Kind>& want = z.topologyKind.empty() ? z.kind : z.topologyKind;
  ASSERT_EQ(topo.kind.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i)
    EXPECT_EQ(static_cast<int>(topo.kind[i]), static_cast<int>(want[i]))
        << "vertex " << i << ": expected " << sodt_zoo::toString(want[i]);
}

TEST_P(Zoo, DoubleMeshAllSettings) {
  const ZooMesh z = sodt_zoo::zooMesh(GetParam());
  for (Algorithm a : {Algorithm::Basic, Algorithm::Feature, Algorithm::Denoise})
    for (Guard g : {Guard::Quality, Guard::Fold, Guard::None})
      for (bool flips : {false, true}) checkRun<MeshD>(z, a, g, flips);
}

TEST_P(Zoo, FloatMeshAllSettings) {
  const ZooMesh z = sodt_zoo::zooMesh(GetParam());
  for (Algorithm a : {Algorithm::Basic, Algorithm::Feature, Algorithm::Denoise})
    for (Guard g : {Guard::Quality, Guard::Fold, Guard::None})
      for (bool flips : {false, true}) checkRun<MeshF>(z, a, g, flips);
}

INSTANTIATE_TEST_SUITE_P(Core, Zoo, testing::ValuesIn(sodt_zoo::zooNames()), paramName);

/// Zoo meshes the core smooths (the others have no topology to compare).
std::vector<std::string> smoothedNames() {
  std::vector<std::string> n;
  for (const std::string& name : sodt_zoo::zooNames())
    if (sodt_zoo::zooMesh(name).core == CoreOutcome::Smooths) n.push_back(name);
  return n;
}

INSTANTIATE_TEST_SUITE_P(Core, ZooTopology, testing::ValuesIn(smoothedNames()), paramName);

// ---------------------------------------------------------------------------

/// Runs `a` with default parameters on a copy of soup; returns the output.
template <class M>
sodt_zoo::Soup smoothed(const sodt_zoo::Soup& soup, Algorithm a) {
  M m;
  sodt_zoo::toMesh(soup, m);
  sodt::SodtParams p;
  p.algorithm = a;
  sodt::SodtSmoother<M>::Apply(m, p);
  return sodt_zoo::fromMesh(m);
}

template <class M>
double minAngleOf(const sodt_zoo::Soup& s) {
  M m;
  sodt_zoo::toMesh(s, m);
  return sodt_zoo::minAngleDeg(m, {});
}

/// The same mesh scaled by 2^-20 and 2^20 (exact in floating point): every
/// output coordinate is the reference output scaled by the same factor, bit
/// for bit. The core has no absolute length anywhere.
template <class M>
void checkPowerOfTwoScaling() {
  const sodt_zoo::Soup unitSoup = sodt_zoo::scaledToDiagonal(sodt_zoo::jitteredSphere(2, 0.35, 1), 1.0);
  for (Algorithm a : {Algorithm::Basic, Algorithm::Feature, Algorithm::Denoise}) {
    const sodt_zoo::Soup r = smoothed<M>(unitSoup, a);
    for (int e : {-20, 20}) {
      SCOPED_TRACE(std::string(sodt::toString(a)) + " scaled by 2^" + std::to_string(e));
      sodt_zoo::Soup in = unitSoup;
      for (auto& p : in.pos)
        for (double& c : p) c = std::ldexp(c, e);
      const sodt_zoo::Soup s = smoothed<M>(in, a);
      int differ = 0;
      for (std::size_t i = 0; i < s.pos.size(); ++i)
        for (int k = 0; k < 3; ++k) differ += !sodt_zoo::sameBits(std::ldexp(s.pos[i][k], -e), r.pos[i][k]);
      EXPECT_EQ(differ, 0) << "coordinates that are not the reference scaled exactly";
    }
  }
}

TEST(ZooScale, PowerOfTwoScalingIsExactDouble) { checkPowerOfTwoScaling<MeshD>(); }
TEST(ZooScale, PowerOfTwoScalingIsExactFloat) { checkPowerOfTwoScaling<MeshF>(); }

/// The zoo's tiny_scale and huge_scale meshes (diagonals 1e-6 and 1e6, not
/// exact factors) reach the smallest angle of the same mesh at diagonal 1
/// within kAngleTolDeg. Positions are not compared: rounding differences of
/// one ulp already change some accept/reject decisions of the guard, and the
/// Gauss-Seidel sweeps carry them on (about 0.1% of the diagonal after 20
/// sweeps, the same as for the mesh scaled by 1 + 1e-15).
template <class M>
void checkDecimalScaling(double kAngleTolDeg) {
  const sodt_zoo::Soup unitSoup = sodt_zoo::scaledToDiagonal(sodt_zoo::zooMesh("clean_sphere").soup, 1.0);
  for (Algorithm a : {Algorithm::Basic, Algorithm::Feature, Algorithm::Denoise}) {
    const double refAngle = minAngleOf<M>(smoothed<M>(unitSoup, a));
    EXPECT_GT(refAngle, minAngleOf<M>(unitSoup) + 1.0) << sodt::toString(a) << " did not smooth";
    for (const char* name : {"tiny_scale", "huge_scale"}) {
      SCOPED_TRACE(std::string(sodt::toString(a)) + " on " + name);
      EXPECT_NEAR(minAngleOf<M>(smoothed<M>(sodt_zoo::zooMesh(name).soup, a)), refAngle, kAngleTolDeg);
    }
  }
}

TEST(ZooScale, DecimalScalingKeepsTheMinAngleDouble) { checkDecimalScaling<MeshD>(1e-6); }
TEST(ZooScale, DecimalScalingKeepsTheMinAngleFloat) { checkDecimalScaling<MeshF>(1e-4); }

/// Far outside any real unit (double only): no exception, finite output, no
/// fold. (Measured: from 1e-60 to 1e60 the result equals the one at diagonal
/// 1; at 1e+-100 the quartic coefficients of the local solve underflow or
/// overflow, every solve fails and nothing moves.)
TEST(ZooScale, ExtremeScalesDoNotBreak) {
  const sodt_zoo::Soup unitSoup = sodt_zoo::scaledToDiagonal(sodt_zoo::jitteredSphere(2, 0.35, 1), 1.0);
  // Beyond the sizes it is verified at, the smoother refuses, mesh untouched.
  for (double diag : {1e-100, 1e100}) {
    MeshD m;
    sodt_zoo::toMesh(sodt_zoo::scaledToDiagonal(unitSoup, diag), m);
    const double x0 = m.vert[5].P()[0];
    EXPECT_THROW(sodt::SodtSmoother<MeshD>::Apply(m, sodt::SodtParams()), sodt::InvalidInput);
    EXPECT_EQ(m.vert[5].P()[0], x0);
  }
  for (double diag : {sodt::kMinMeshSize * 1.001, 1e-20, 1e30, sodt::kMaxMeshSize * 0.999})
    for (Algorithm a : {Algorithm::Basic, Algorithm::Feature, Algorithm::Denoise}) {
      SCOPED_TRACE(std::string(sodt::toString(a)) + " at diagonal " + std::to_string(diag));
      MeshD m, ref;
      sodt_zoo::toMesh(sodt_zoo::scaledToDiagonal(unitSoup, diag), m);
      sodt_zoo::toMesh(sodt_zoo::scaledToDiagonal(unitSoup, diag), ref);
      sodt::SodtParams p;
      p.algorithm = a;
      EXPECT_NO_THROW(sodt::SodtSmoother<MeshD>::Apply(m, p));
      EXPECT_TRUE(sodt_zoo::allFinite(m));
      EXPECT_EQ(sodt::countInvertedFaces(m, ref), 0);
      EXPECT_GE(sodt_zoo::minAngleDeg(m, {}), sodt_zoo::minAngleDeg(ref, {}) - 1e-7);
    }
}

// ---------------------------------------------------------------------------

/// The non-finite message names the count and the first offending vertex.
TEST(ZooNonFinite, MessageNamesCountAndFirstVertex) {
  const ZooMesh z = sodt_zoo::zooMesh("inf_coordinates");
  MeshD m;
  sodt_zoo::toMesh(z.soup, m);
  try {
    sodt::SodtSmoother<MeshD>::Apply(m, sodt::SodtParams());
    FAIL() << "no exception";
  } catch (const sodt::InvalidInput& e) {
    EXPECT_STREQ(e.what(),
                 "3 vertices have a non-finite coordinate (NaN or infinite; first: vertex 3); the mesh was not "
                 "changed");
  }
}

/// Bad parameters throw InvalidInput before the mesh is touched.
TEST(ZooParams, BadParametersThrowAndLeaveTheMesh) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::vector<std::pair<std::string, std::function<void(sodt::SodtParams&)>>> cases = {
      {"iterations", [](sodt::SodtParams& p) { p.iterations = -1; }},
      {"iterations", [](sodt::SodtParams& p) { p.iterations = 100001; }},
      {"maxBacktracks", [](sodt::SodtParams& p) { p.maxBacktracks = 61; }},
      {"guard", [](sodt::SodtParams& p) { p.guard = static_cast<Guard>(7); }},
      {"algorithm", [](sodt::SodtParams& p) { p.algorithm = static_cast<Algorithm>(-1); }},
      {"epsilon", [nan](sodt::SodtParams& p) { p.epsilon = nan; }},
      {"epsilon", [](sodt::SodtParams& p) { p.epsilon = 0; }},
      {"eta", [inf](sodt::SodtParams& p) { p.eta = inf; }},
      {"maxDeviationRel", [nan](sodt::SodtParams& p) { p.maxDeviationRel = nan; }},
      {"maxDeviationRel", [](sodt::SodtParams& p) { p.maxDeviationRel = -1e-9; }},
      {"flipMaxDihedralDeg", [](sodt::SodtParams& p) { p.flipMaxDihedralDeg = 90.5; }},
      {"toleranceDeg", [nan](sodt::SodtParams& p) { p.toleranceDeg = nan; }},
      {"maxNormalStepRel", [inf](sodt::SodtParams& p) { p.maxNormalStepRel = inf; }},
  };
  const ZooMesh z = sodt_zoo::zooMesh("combination");
  for (const auto& c : cases) {
    SCOPED_TRACE(c.first);
    MeshD m, ref;
    sodt_zoo::toMesh(z.soup, m);
    sodt_zoo::toMesh(z.soup, ref);
    sodt::SodtParams p;
    c.second(p);
    try {
      sodt::SodtSmoother<MeshD>::Apply(m, p);
      ADD_FAILURE() << "no exception";
    } catch (const sodt::InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(c.first), std::string::npos) << e.what();
    }
    expectUntouched(m, ref);
  }
}

// ---------------------------------------------------------------------------

/// The project's OFF loader fan-triangulates the zoo's polygon file into
/// exactly the zoo's triangles, with the coordinates bit for bit.
TEST(ZooLoader, PolygonsAreFanTriangulated) {
  const ZooMesh z = sodt_zoo::zooMesh("polygons");
  ASSERT_FALSE(z.offText.empty());
  char dir[] = "/tmp/sodt_zoo_loader_XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  const std::string path = std::string(dir) + "/polygons.off";
  sodt_zoo::writeText(path, z.offText);
  MeshD m;
  sodt::LoadInfo info;
  sodt::loadMesh(path, m, &info);
  ::unlink(path.c_str());
  ::rmdir(dir);
  EXPECT_TRUE(info.polygons);
  const sodt_zoo::Soup s = sodt_zoo::fromMesh(m);
  ASSERT_EQ(s.pos.size(), z.soup.pos.size());
  ASSERT_EQ(s.tri.size(), z.soup.tri.size());
  for (std::size_t i = 0; i < s.pos.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(sodt_zoo::sameBits(s.pos[i][k], z.soup.pos[i][k])) << "vertex " << i;
  for (std::size_t f = 0; f < s.tri.size(); ++f) EXPECT_EQ(s.tri[f], z.soup.tri[f]) << "face " << f;
}

/// A binary little-endian PLY of a rows x cols grid of quads split in
/// triangles, with an element of fixed-size rows after the faces. The
/// body is several times the loader's 64 KB read buffer, so values straddle
/// its edges. badFace: a face whose last index is made out of range (-1: none).
std::string gridPly(int rows, int cols, long long badFace = -1) {
  std::string body;
  auto put = [&body](const void* p, std::size_t n) { body.append(static_cast<const char*>(p), n); };
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c <= cols; ++c) {
      const float z = 0.25f * static_cast<float>((r * 7 + c * 3) % 5);
      const float xyz[3] = {static_cast<float>(c), static_cast<float>(r), z};
      put(xyz, sizeof xyz);
    }
  long long face = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int a = r * (cols + 1) + c, b = a + 1, d = a + cols + 1, e = d + 1;
      for (const std::array<int, 3>& t : {std::array<int, 3>{a, b, e}, std::array<int, 3>{a, e, d}}) {
        const unsigned char n = 3;
        put(&n, 1);
        std::array<int, 3> u = t;
        if (face++ == badFace) u[2] = (rows + 1) * (cols + 1);
        put(u.data(), sizeof u);
      }
    }
  for (int k = 0; k < 5000; ++k) {
    const float v = static_cast<float>(k);
    put(&v, sizeof v);
  }
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string((rows + 1) * (cols + 1)) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
         std::to_string(2LL * rows * cols) +
         "\nproperty list uchar int vertex_indices\nelement extra 5000\nproperty float value\nend_header\n" + body;
}

/// The loader walks a binary body through a buffer of its own: files many
/// buffers long load, and a bad index or a cut anywhere, at the buffer's
/// edges too, is found and named.
TEST(ZooLoader, LongBinaryFilesAreCheckedAcrossTheReadBuffer) {
  char dir[] = "/tmp/sodt_zoo_buffer_XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  const std::string path = std::string(dir) + "/grid.ply";
  const int rows = 120, cols = 150;  // 18271 vertices, 36000 faces of 13 bytes: 468 KB of faces
  const std::string good = gridPly(rows, cols);
  const std::size_t bodyStart = good.find("end_header\n") + 11;
  const std::size_t facesStart = bodyStart + 12 * std::size_t(rows + 1) * (cols + 1);
  const std::size_t extraStart = facesStart + 13 * 2 * std::size_t(rows) * cols;
  ASSERT_EQ(extraStart + 4 * 5000, good.size());
  auto loadError = [&](const std::string& bytes) -> std::string {
    sodt_zoo::writeText(path, bytes);
    MeshD m;
    try {
      sodt::loadMesh(path, m);
    } catch (const sodt::InvalidInput& e) {
      return e.what();
    }
    EXPECT_EQ(m.vn, (rows + 1) * (cols + 1));
    EXPECT_EQ(m.fn, 2 * rows * cols);
    return "";
  };
  EXPECT_EQ(loadError(good), "");
  // A bad index in the face that straddles each of the first buffer edges
  // in the face block, and in the first and the last face.
  const std::size_t kBuffer = 1 << 16;
  std::vector<long long> badFaces = {0, 2LL * rows * cols - 1};
  for (std::size_t edge = kBuffer; edge < extraStart - bodyStart; edge += kBuffer)
    if (bodyStart + edge > facesStart) badFaces.push_back(static_cast<long long>((bodyStart + edge - facesStart) / 13));
  ASSERT_GE(badFaces.size(), 8u);
  for (long long f : badFaces)
    EXPECT_NE(loadError(gridPly(rows, cols, f)).find("vertex index out of range"), std::string::npos) << "face " << f;
  // Cuts: inside the faces (at and around buffer edges) and inside the element after them.
  for (std::size_t edge = kBuffer; edge < extraStart - bodyStart; edge += kBuffer)
    for (std::size_t cut : {bodyStart + edge - 1, bodyStart + edge, bodyStart + edge + 1}) {
      if (cut <= facesStart + 13) continue;
      EXPECT_NE(loadError(good.substr(0, cut)).find("the data ends inside element 'face'"), std::string::npos)
          << "cut at " << cut;
    }
  EXPECT_NE(loadError(good.substr(0, good.size() - 3)).find("the data ends inside element 'extra'"), std::string::npos);
  ::unlink(path.c_str());
  ::rmdir(dir);
}


/// A rows x cols grid as text: OFF (coordinates with 17 significant digits,
/// comments, tabs and CRLF line ends mixed in) or ASCII PLY (float-exact
/// coordinates, a float quality per vertex). pad: spaces before the first
/// vertex, which move every token against the scanner's block edges.
/// xyz gets the coordinates the text holds.
std::string gridText(bool off, int rows, int cols, int pad, std::vector<std::array<double, 3>>& xyz) {
  const int nv = (rows + 1) * (cols + 1), nf = 2 * rows * cols;
  std::string t = off ? "OFF\n# a grid\n" + std::to_string(nv) + " " + std::to_string(nf) + " 0\n"
                      : "ply\nformat ascii 1.0\nelement vertex " + std::to_string(nv) +
                            "\nproperty float x\nproperty float y\nproperty float z\nproperty float quality\n"
                            "element face " + std::to_string(nf) +
                            "\nproperty list uchar int vertex_indices\nend_header\n";
  t.append(static_cast<std::size_t>(pad), ' ');
  xyz.clear();
  char buf[64];
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c <= cols; ++c) {
      const int i = r * (cols + 1) + c;
      // OFF: values with all their digits; PLY: eighths, which a float holds.
      const double z = off ? std::sin(0.37 * i) / 3.0 : 0.125 * ((r * 7 + c * 3) % 11);
      xyz.push_back({static_cast<double>(c), static_cast<double>(r), z});
      std::snprintf(buf, sizeof buf, off ? "%d\t%d %.17g" : "%d %d %.9g", c, r, z);
      t += buf;
      if (off)
        t += i % 3 == 0 ? "\r\n" : i % 3 == 1 ? "  # note\n" : "          \n";
      else
        t += i % 2 ? " 0.5                       \n" : " 0.5\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\r\n";
    }
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int a = r * (cols + 1) + c, b = a + 1, d = a + cols + 1, e = d + 1;
      t += "3 " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(e) + "\n";
      t += "3 " + std::to_string(a) + " " + std::to_string(e) + "\t" + std::to_string(d) + "\n";
    }
  return t;
}

/// Text files are read in blocks of 1 MB: files several blocks long load
/// with every value as written, whichever tokens straddle the blocks'
/// edges, a token longer than a block is read whole, and a bad value or a
/// cut past the first block is found and named, with its line in OFF.
TEST(ZooLoader, LongTextFilesAreReadAcrossTheScannerBlocks) {
  char dir[] = "/tmp/sodt_zoo_text_XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  const int rows = 180, cols = 180;  // 32761 vertices and 64800 faces: the faces start past the first block
  auto load = [&](const std::string& name, const std::string& text, MeshD& m) -> std::string {
    const std::string path = std::string(dir) + "/" + name;
    sodt_zoo::writeText(path, text);
    std::string error;
    try {
      sodt::loadMesh(path, m);
    } catch (const sodt::InvalidInput& e) {
      error = e.what();
    }
    ::unlink(path.c_str());
    return error;
  };
  for (const bool off : {true, false}) {
    const std::string name = off ? "grid.off" : "grid.ply";
    for (const int pad : {0, 1, 2, 3, 5, 8}) {
      SCOPED_TRACE(name + ", pad " + std::to_string(pad));
      std::vector<std::array<double, 3>> xyz;
      const std::string text = gridText(off, rows, cols, pad, xyz);
      ASSERT_GT(text.size(), std::size_t(1) << 20);
      MeshD m;
      ASSERT_EQ(load(name, text, m), "");
      ASSERT_EQ(m.vn, static_cast<int>(xyz.size()));
      ASSERT_EQ(m.fn, 2 * rows * cols);
      int wrong = 0;
      for (std::size_t i = 0; i < xyz.size(); ++i)
        for (int k = 0; k < 3; ++k) wrong += !sodt_zoo::sameBits(m.vert[i].P()[k], xyz[i][k]);
      EXPECT_EQ(wrong, 0);
      // The last face is (a, e, d) of the last quad.
      const int a = (rows - 1) * (cols + 1) + cols - 1;
      const MeshD::FaceType& f = m.face.back();
      EXPECT_EQ(f.cV(0) - &m.vert[0], a);
      EXPECT_EQ(f.cV(1) - &m.vert[0], a + cols + 2);
      EXPECT_EQ(f.cV(2) - &m.vert[0], a + cols + 1);
    }
    std::vector<std::array<double, 3>> xyz;
    const std::string text = gridText(off, rows, cols, 0, xyz);
    const std::size_t faces = text.find("\n3 0 1 " + std::to_string(cols + 2) + "\n") + 1;
    ASSERT_GT(faces, std::size_t(1) << 20);  // the faces start in the second block
    MeshD m;
    // A cut in the faces, past the first block.
    const std::string cut = load(name, text.substr(0, text.size() - 10), m);
    EXPECT_NE(cut.find(off ? "unexpected end of file in face" : "the data ends inside element 'face'"),
              std::string::npos) << cut;
    // A bad index in the faces.
    std::string bad = text;
    bad.insert(faces + 2, "1x");
    const std::string named = load(name, bad, m);
    if (off) {
      const long line = static_cast<long>(std::count(text.begin(), text.begin() + faces, '\n')) + 1;
      EXPECT_NE(named.find("at line " + std::to_string(line) + ": face 0: expected a vertex index, got '1x0'"),
                std::string::npos) << named;
    } else {
      EXPECT_NE(named.find("malformed integer '1x0'"), std::string::npos) << named;
    }
    // A token of 4096 bytes, the longest read (zeros before a value), and
    // one longer, refused: binary data read as text must not grow a token
    // without bound.
    std::string longToken = text;
    longToken.insert(faces + 2, std::string(4095, '0'));
    ASSERT_EQ(load(name, longToken, m), "");
    EXPECT_EQ(m.face[0].cV(0) - &m.vert[0], 0);
    EXPECT_EQ(m.face[0].cV(1) - &m.vert[0], 1);
    longToken.insert(faces + 2, "0");
    const std::string refused = load(name, longToken, m);
    const long line = static_cast<long>(std::count(text.begin(), text.begin() + faces, '\n')) + 1;
    EXPECT_NE(refused.find(off ? "line " + std::to_string(line) + ": more than 4096 bytes without a space"
                               : std::string("more than 4096 bytes without a space")),
              std::string::npos) << refused;
  }
  ::rmdir(dir);
}

}  // namespace
