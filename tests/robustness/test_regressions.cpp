// SPDX-License-Identifier: GPL-3.0-or-later
// Regression tests of the bugs the robustness zoo found (all fixed): each
// asserts the behaviour that is right. ctest labels: robustness;regression.
#include "cli_runner.h"
#include "defect_zoo.h"
#include "zoo_checks.h"

#include <gtest/gtest.h>

#include <sodt_io/io.h>
#include <sodt_io/prebuilt.h>
#include <sodt/maths/topology.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace {

using sodt_zoo::RunResult;
using sodt_zoo::TempDir;

/// Exit 0 with a finite output, or exit 1 with one "sodt: error:" line and no
/// output; never a crash or a hang.
void expectZeroOrCleanFailure(const RunResult& r, const std::string& out) {
  ASSERT_FALSE(r.crashed()) << r.describe();
  if (r.exitCode == 0) {
    sodt::MeshD m;
    ASSERT_NO_THROW(sodt::loadMesh(out, m));
    EXPECT_TRUE(sodt_zoo::allFinite(m));
    return;
  }
  EXPECT_EQ(r.exitCode, 1) << r.describe();
  const std::vector<std::string> lines = r.errLines();
  ASSERT_EQ(lines.size(), 1u) << r.describe();
  EXPECT_EQ(lines[0].rfind("sodt: error: ", 0), 0u) << lines[0];
  EXPECT_FALSE(sodt_zoo::fileExists(out));
}

// ---------------------------------------------------------------------------
// Core

/// BUG: vcg_core/sodt/smoother.h, SodtSmoother::visitVertex() with
/// Guard::None commits representable(pr.target) without a finiteness check.
/// On a float mesh (MeshF, MeshLab's CMeshO) a target beyond FLT_MAX (the
/// literal paper update diverges on the flattened sphere: |x| ~ 1e28 after 10
/// sweeps) rounds to +-inf, and later sweeps make NaN: after 20 sweeps every
/// coordinate of the mesh is non-finite, and Apply() returns normally. (In
/// double the same run saturates near 1e64, finite.) The plugin exposes this
/// guard as "None (paper, literal)". Right: never commit a non-finite
/// position (count the visit as failed), so the output stays finite.
TEST(RegressionCore, GuardNoneNeverWritesNonFiniteCoordinatesOnFloatMesh) {
  const sodt_zoo::ZooMesh z = sodt_zoo::zooMesh("flattened");
  for (sodt::Algorithm a : {sodt::Algorithm::Basic, sodt::Algorithm::Feature}) {
    SCOPED_TRACE(sodt::toString(a));
    sodt::MeshF m;
    sodt_zoo::toMesh(z.soup, m);
    sodt::SodtParams p;
    p.algorithm = a;
    p.guard = sodt::Guard::None;
    ASSERT_NO_THROW(sodt::SodtSmoother<sodt::MeshF>::Apply(m, p));
    int bad = 0;
    for (const auto& v : m.vert)
      for (int k = 0; k < 3; ++k) bad += !std::isfinite(v.cP()[k]);
    EXPECT_EQ(bad, 0) << "non-finite coordinates written into the mesh";
  }
}

/// MINOR BUG: vcg_core/sodt/maths/topology.h, buildRingTopology(): a vertex that
/// only faces with a repeated index use is classified Isolated (the
/// `b == e` test comes before the `badFace` test), although the contract says
/// "the vertices of a face with a repeated vertex are marked NonManifold".
/// It still never moves, but SodtStats::fixedNonManifold, the CLI report and
/// the plugin log do not count it. (Some exporters write polylines as
/// triangles (a, b, b).) Right: NonManifold, counted.
TEST(RegressionCore, VerticesOnlyInRepeatedIndexFacesAreNonManifold) {
  sodt_zoo::Soup s = sodt_zoo::jitteredSphere(2, 0.35, 1);
  const int x = static_cast<int>(s.pos.size());
  s.pos.push_back({2, 0, 0});
  s.pos.push_back({3, 0, 0});
  s.tri.push_back({x, x + 1, x + 1});
  sodt::MeshD m;
  sodt_zoo::toMesh(s, m);
  const sodt::SodtStats st = sodt::SodtSmoother<sodt::MeshD>::Apply(m, sodt::SodtParams());
  EXPECT_EQ(st.fixedNonManifold, 2);
  const sodt::RingTopology topo = sodt::buildRingTopology(m);
  EXPECT_EQ(topo.kind[x], sodt::VertexKind::NonManifold);
  EXPECT_EQ(topo.kind[x + 1], sodt::VertexKind::NonManifold);
}

// ---------------------------------------------------------------------------
// CLI

/// BUG: vcg_core/sodt_io/metrics.h, sodt::surfaceDistance() ->
/// detail::oneSidedDistance() -> vcg SurfaceSampling::Montecarlo segfaults
/// (SIGSEGV, exit 139) when every face has zero area but the bounding box is
/// not flat: `sodt smooth` (distanceTo) and `sodt stats --reference` crash.
/// Repro: printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 1 3\n' > a.off;
/// sodt smooth a.off b.ply. Right: exit 0 (nothing to smooth; the distance
/// reported as 0 or null), or a clean exit 1.
TEST(RegressionCli, ZeroAreaFacesOnlyDoNotCrashSmooth) {
  const sodt_zoo::ZooMesh z = sodt_zoo::zooMesh("zero_area_faces_only");
  TempDir dir;
  const std::string in = dir / "in.ply", out = dir / "out.ply";
  sodt_zoo::writePly(in, z.soup, sodt_zoo::PlyEncoding::BinaryLE, true);
  const RunResult r = sodt_zoo::runSodt({"smooth", in, out, "--quiet"}, 30);
  ASSERT_FALSE(r.crashed()) << r.describe();
  EXPECT_EQ(r.exitCode, 0) << r.describe();
  expectZeroOrCleanFailure(r, out);
}

TEST(RegressionCli, ZeroAreaFacesOnlyDoNotCrashStatsReference) {
  TempDir dir;
  const std::string in = dir / "a.off";
  sodt_zoo::writeText(in, "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 1 3\n");
  const RunResult r = sodt_zoo::runSodt({"stats", in, "--reference", in}, 30);
  ASSERT_FALSE(r.crashed()) << r.describe();
  EXPECT_EQ(r.exitCode, 0) << r.describe();
}

std::string plyHeader(const std::string& listTypes, int nv, int nf, const std::string& format = "binary_little_endian") {
  return "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(nv) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(nf) +
         "\nproperty list " + listTypes + " vertex_indices\nend_header\n";
}

/// A binary PLY: n vertices on a circle and one face listing them all, with
/// an int corner count.
std::string bigPolygon(int n) {
  std::string s = plyHeader("int int", n, 1);
  for (int i = 0; i < n; ++i) {
    const float v[3] = {static_cast<float>(std::cos(2 * M_PI * i / n)), static_cast<float>(std::sin(2 * M_PI * i / n)),
                        0.0f};
    s.append(reinterpret_cast<const char*>(v), sizeof v);
  }
  const std::int32_t count = n;
  s.append(reinterpret_cast<const char*>(&count), 4);
  for (std::int32_t i = 0; i < n; ++i) s.append(reinterpret_cast<const char*>(&i), 4);
  return s;
}

/// BUG: vcg_core/sodt_io/io.cpp, loadPly(): vcglib 2020.09's PLY reader keeps a
/// face's corners in `int v[512]` (import_ply.h LoadPly_FaceAux) and its count
/// in an unsigned char, and plylib.cpp ReadBin() writes as many corners as
/// the file's count says. checkPlyHeader() bounds the element counts only.
/// - a polygon with more than ~600 corners (int count) overruns the stack
///   buffer: the CLI dies with SIGSEGV (exit 139) on a 60 KB file;
/// - a polygon with 256..600 corners is silently cut to (count mod 256)
///   corners: a 300-gon loads as a 44-gon, the mesh is wrong.
/// Right: load the polygon (fan, count - 2 triangles) or reject the file
/// cleanly; never crash, never truncate.
TEST(RegressionCli, PlyPolygonsWithManyCornersLoadOrFailCleanly) {
  for (int n : {300, 5000}) {
    SCOPED_TRACE(std::to_string(n) + "-gon");
    TempDir dir;
    const std::string in = dir / "poly.ply", out = dir / "out.ply";
    sodt_zoo::writeText(in, bigPolygon(n));
    const RunResult r = sodt_zoo::runSodt({"smooth", in, out, "--quiet"}, 30);
    expectZeroOrCleanFailure(r, out);
    if (!r.crashed() && r.exitCode == 0) {
      sodt::MeshD m;
      sodt::loadMesh(out, m);
      EXPECT_EQ(m.fn, n - 2) << "the polygon was not triangulated whole";
    }
  }
}

/// BUG: vcg_core/sodt_io/io.cpp, loadPly(): a PLY face with 0, 1 or 2 corners
/// is accepted and becomes a fabricated triangle: vcglib reads v[0..2] of its
/// face buffer, which hold the previous face's corners or, for the first
/// face, uninitialised stack memory (undefined behaviour; observed (0, 0, 0)
/// and (0, 1, 0)). `sodt smooth` exits 0 and OUT contains triangles that IN
/// does not have. The OFF parser rejects the same faces ("face f has 2
/// corners"). Right: exit 1 naming the face.
TEST(RegressionCli, PlyFacesWithFewerThanThreeCornersAreRejected) {
  for (const char* face : {"2 0 1", "1 0", "0"}) {
    SCOPED_TRACE(face);
    TempDir dir;
    const std::string in = dir / "few.ply", out = dir / "out.ply";
    sodt_zoo::writeText(in, plyHeader("uchar int", 4, 2, "ascii") + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + face +
                                "\n3 0 1 2\n");
    const RunResult r = sodt_zoo::runSodt({"smooth", in, out, "--quiet"}, 30);
    ASSERT_FALSE(r.crashed()) << r.describe();
    EXPECT_EQ(r.exitCode, 1) << "accepted; " << r.describe();
    expectZeroOrCleanFailure(r, out);
  }
}

/// BUG: same place: a binary face list whose count is 0xFFFFFFFF (uint)
/// reads as -1, stores 255 as the corner count and fan-triangulates 255
/// corners of the (uninitialised) face buffer; what follows depends on the
/// stack (observed: one (0, 0, 0) face, then the zero-area crash above, here
/// a hang in the distance sampling, killed here after 3 s). Right: exit 1,
/// "bad corner count".
TEST(RegressionCli, PlyCornerCountOverflowIsRejected) {
  std::string s = plyHeader("uint int", 4, 1);
  const float v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  s.append(reinterpret_cast<const char*>(v), sizeof v);
  const std::uint32_t count = 0xFFFFFFFFu;
  s.append(reinterpret_cast<const char*>(&count), 4);
  for (std::int32_t i : {0, 1, 2}) s.append(reinterpret_cast<const char*>(&i), 4);
  TempDir dir;
  const std::string in = dir / "overflow.ply", out = dir / "out.ply";
  sodt_zoo::writeText(in, s);
  const RunResult r = sodt_zoo::runSodt({"smooth", in, out, "--quiet"}, 3);
  ASSERT_FALSE(r.crashed()) << r.describe();
  EXPECT_EQ(r.exitCode, 1) << r.describe();
  expectZeroOrCleanFailure(r, out);
}

}  // namespace
