// SPDX-License-Identifier: GPL-3.0-or-later
// Comparison tests (ctest label "comparison"): S-ODT against MeshLab 2020.09's
// built-in smoothers, run by meshlabserver on the bundled meshes through the
// same code as sodt_compare (bench/compare, sodt_compare_lib).
//
// * On every bundled mesh, S-ODT's smallest angle beats every vertex-moving
//   MeshLab smoother whose Hausdorff distance to the input is no larger
//   (a smoother that moves the surface further may win; it is not held
//   against S-ODT), and S-ODT inverts no face.
// * TwoStep Smooth inverts faces on blobs_mc.ply and sphere_jitter.ply; S-ODT
//   inverts none there.
// * The .mlx scripts written for the built-in filters list exactly the
//   filters' parameters (checked by sodt_plugin_script_tool against the
//   installed MeshLab plugins, with MeshLab's own script parser).
// * The rows of S-ODT with flips and with flips and local repair run the
//   mesh's headline variant; the repair row's vertex counts are the
//   smoother's (added and removed), and its minimum angle is no smaller than
//   that of the same run without the repair. The verdict "repair beats
//   remeshing" needs a larger minimum angle, no larger Hausdorff distance and
//   fewer vertices changed, each checked on its own.
// * sodt_compare writes RESULTS.md and the SVG figures.

#include "compare.h"
#include "process.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#ifndef SODT_MESH_DIR
#error "SODT_MESH_DIR must name the bundled meshes"
#endif
#ifndef SODT_COMPARE_EXE
#define SODT_COMPARE_EXE ""
#endif
#ifndef SODT_SCRIPT_TOOL
#define SODT_SCRIPT_TOOL ""
#endif
#ifndef SODT_HAVE_PLUGIN
#define SODT_HAVE_PLUGIN 0
#endif
#ifndef SODT_SHARED_MESH_DIR
#define SODT_SHARED_MESH_DIR ""
#endif

namespace {

using namespace sodtcmp;

/// A fresh folder under TMPDIR, removed at the end unless SODT_TEST_KEEP is set.
class TempDir {
 public:
  TempDir() {
    const char* t = std::getenv("TMPDIR");
    std::string tmpl = std::string(t && *t ? t : "/tmp") + "/sodt-comparison.XXXXXX";
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    if (mkdtemp(buf.data())) path_ = buf.data();
  }
  ~TempDir() {
    if (path_.empty()) return;
    if (std::getenv("SODT_TEST_KEEP"))
      std::printf("work folder kept: %s\n", path_.c_str());
    else
      proc::removeTree(path_);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// The vertex-moving built-in MeshLab smoothers (same connectivity).
std::vector<std::string> builtinSmoothers() {
  std::vector<std::string> ids;
  for (const Method& m : allMethods())
    if (m.kind == Kind::Builtin && m.smoother) ids.push_back(m.id);
  return ids;
}

/// Runs S-ODT (basic and `variant`) and the given MeshLab methods on a bundled mesh.
MeshReport runOn(const std::string& mesh, sodt::Algorithm variant, std::vector<std::string> meshlabIds,
                 const TempDir& dir) {
  Options opt;
  opt.iterations = 20;
  opt.workDir = dir.path() + "/work";
  opt.curves = false;
  opt.quiet = true;
  opt.timingRuns = 1;
  opt.methods = {"sodt_basic"};
  if (variant == sodt::Algorithm::Feature) opt.methods.push_back("sodt_feature");
  if (variant == sodt::Algorithm::Denoise) opt.methods.push_back("sodt_denoise");
  opt.methods.insert(opt.methods.end(), meshlabIds.begin(), meshlabIds.end());
  MeshLabServer server;
  std::string err;
  const bool started = server.start(defaultMeshLabConfig(), opt.workDir, err);
  EXPECT_TRUE(started) << "meshlabserver is needed for the comparison tests: " << err;
  MeshJob job;
  job.path = std::string(SODT_MESH_DIR) + "/" + mesh;
  job.name = baseName(mesh);
  job.variant = variant;
  MeshReport rep = compareMesh(job, opt, started ? &server : nullptr);
  // The table, for the test log.
  std::printf("%-48s %8s %8s %12s %9s %8s\n", "method", "min deg", "max deg", "Hausdorff %", "inverted", "time s");
  std::printf("%-48s %8.2f %8.2f\n", "input", rep.input.minDeg, rep.input.maxDeg);
  for (const Row& r : rep.rows) {
    if (r.m.ok)
      std::printf("%-48s %8.2f %8.2f %12.4g %9lld %8.2f\n", r.method.label.c_str(), r.m.minDeg, r.m.maxDeg,
                  100 * r.m.hausInput, r.m.inverted, r.m.seconds);
    else
      std::printf("%-48s failed: %s\n", r.method.label.c_str(), r.m.error.c_str());
  }
  return rep;
}

/// S-ODT row `id` beats every smoother no further from the input than it,
/// holds against at least one smoother, and inverts nothing.
void expectBeatsCloserSmoothers(const MeshReport& rep, const std::string& id) {
  const Row* s = rep.row(id);
  ASSERT_TRUE(s != nullptr && s->m.ok) << id << " did not run";
  EXPECT_EQ(s->m.inverted, 0) << id << " inverted faces";
  EXPECT_GT(s->m.minDeg, rep.input.minDeg) << id << " did not improve the smallest angle";
  int heldAgainst = 0;
  for (const std::string& b : builtinSmoothers()) {
    const Row* r = rep.row(b);
    ASSERT_TRUE(r != nullptr) << b << " was not run";
    ASSERT_TRUE(r->m.ok) << r->method.label << " failed: " << r->m.error;
    if (r->m.hausInput > s->m.hausInput + 1e-6) continue;  // moves the surface further: not held against S-ODT
    ++heldAgainst;
    EXPECT_GT(s->m.minDeg, r->m.minDeg)
        << id << " (min " << s->m.minDeg << " deg, Hausdorff " << 100 * s->m.hausInput << " %) does not beat "
        << r->method.label << " (min " << r->m.minDeg << " deg, Hausdorff " << 100 * r->m.hausInput << " %)";
  }
  EXPECT_GE(heldAgainst, 1) << "no MeshLab smoother stayed as close to the input as " << id
                            << ": the comparison says nothing on this mesh";
}

TEST(Comparison, BlobsMcSodtBeatsCloserSmoothers) {
  TempDir dir;
  const MeshReport rep = runOn("blobs_mc.ply", sodt::Algorithm::Basic, builtinSmoothers(), dir);
  expectBeatsCloserSmoothers(rep, "sodt_basic");
}

TEST(Comparison, SphereJitterSodtBeatsCloserSmoothers) {
  TempDir dir;
  const MeshReport rep = runOn("sphere_jitter.ply", sodt::Algorithm::Basic, builtinSmoothers(), dir);
  expectBeatsCloserSmoothers(rep, "sodt_basic");
}

TEST(Comparison, CubeJitterSodtBeatsCloserSmoothers) {
  TempDir dir;
  const MeshReport rep = runOn("cube_jitter.ply", sodt::Algorithm::Feature, builtinSmoothers(), dir);
  expectBeatsCloserSmoothers(rep, "sodt_feature");
  expectBeatsCloserSmoothers(rep, "sodt_basic");
}

TEST(Comparison, CubeNoisySodtBeatsCloserSmoothers) {
  TempDir dir;
  const MeshReport rep = runOn("cube_noisy.ply", sodt::Algorithm::Denoise, builtinSmoothers(), dir);
  expectBeatsCloserSmoothers(rep, "sodt_denoise");
  expectBeatsCloserSmoothers(rep, "sodt_basic");
}

// ---------------------------------------------------------------------------
// S-ODT with flips and local repair

/// The in-process rows `ids` on `path` with `variant` as the headline (no MeshLab).
MeshReport runInProcess(const std::string& path, sodt::Algorithm variant, const std::vector<std::string>& ids,
                        const TempDir& dir) {
  Options opt;
  opt.iterations = 20;
  opt.workDir = dir.path() + "/work";
  opt.curves = false;
  opt.quiet = true;
  opt.timingRuns = 1;
  opt.methods = ids;
  MeshJob job;
  job.path = path;
  job.name = baseName(path);
  job.variant = variant;
  return compareMesh(job, opt, nullptr);
}

/// The repair row changed the vertex set exactly as the smoother's
/// statistics say, and did not lower the minimum angle of the same run
/// without the repair.
void expectRepairRowMatchesItsStats(const MeshReport& rep) {
  const Row* f = rep.row("sodt_flips");
  const Row* r = rep.row("sodt_flips_repair");
  ASSERT_TRUE(f && f->m.ok) << "the flips row did not run: " << (f ? f->m.error : std::string("no row"));
  ASSERT_TRUE(r && r->m.ok) << "the repair row did not run: " << (r ? r->m.error : std::string("no row"));
  // Flips alone keep the vertex set and report no repair.
  EXPECT_EQ(f->m.vertices, rep.input.vertices);
  EXPECT_EQ(f->m.verticesAdded, -1);
  EXPECT_GE(f->m.edgeFlips, 0);
  // The repair changed the vertex set, by what its statistics say.
  ASSERT_GE(r->m.verticesAdded, 0) << "the repair row reports no repair statistics";
  ASSERT_GE(r->m.verticesRemoved, 0);
  EXPECT_GT(r->m.verticesAdded + r->m.verticesRemoved, 0) << "the repair changed no vertex on " << rep.job.name;
  EXPECT_EQ(r->m.vertices, rep.input.vertices + r->m.verticesAdded - r->m.verticesRemoved);
  // Measured against the input face under each output face (other connectivity).
  EXPECT_EQ(r->m.inverted, 0) << "the repair turned faces away from the input under them";
  EXPECT_GE(r->m.minDeg, f->m.minDeg) << "the repair lowered the minimum angle of the flips-only run";
  EXPECT_NE(r->m.detail.find("repair: " + std::to_string(r->m.verticesAdded) + " vertices added, " +
                             std::to_string(r->m.verticesRemoved) + " removed"),
            std::string::npos)
      << r->m.detail;
}

TEST(ComparisonRepair, RowsRunTheHeadlineVariantWithFlipsAndRepair) {
  TempDir dir;
  const MeshReport rep = runInProcess(std::string(SODT_MESH_DIR) + "/plane_grid_open.ply", sodt::Algorithm::Basic,
                                      {"sodt_flips", "sodt_flips_repair"}, dir);
  expectRepairRowMatchesItsStats(rep);
  const Row* r = rep.row("sodt_flips_repair");
  ASSERT_TRUE(r && r->m.ok);
  EXPECT_EQ(r->method.label, "S-ODT basic + flips + repair");
  // Nothing was left below the target here, so the target is reached.
  EXPECT_EQ(r->m.belowRepairTarget, 0) << r->m.detail;
  EXPECT_GE(r->m.minDeg, sodt::SodtParams{}.repairAngleDeg - 1e-9);
  EXPECT_TRUE(isFile(dir.path() + "/work/plane_grid_open/sodt_flips_repair.ply"));
}

TEST(ComparisonRepair, RowsFollowTheMeshsVariant) {
  TempDir dir;
  const MeshReport rep = runInProcess(std::string(SODT_MESH_DIR) + "/cube_jitter.ply", sodt::Algorithm::Feature,
                                      {"sodt_flips"}, dir);
  const Row* f = rep.row("sodt_flips");
  ASSERT_TRUE(f && f->m.ok);
  EXPECT_EQ(f->method.label, "S-ODT feature + flips");
  EXPECT_EQ(f->method.algorithm, sodt::Algorithm::Feature);
  EXPECT_NE(f->m.detail.find(" corner"), std::string::npos) << "no vertex classes: not the feature variant";
}

/// A mesh of ../shared/meshes: skipped when absent, unless SODT_REQUIRE_SHARED=1.
std::string sharedMesh(const std::string& name) {
  const char* dir = std::getenv("SODT_SHARED_MESH_DIR");
  return std::string(dir && *dir ? dir : SODT_SHARED_MESH_DIR) + "/" + name;
}

TEST(ComparisonRepair, AgainstRemeshingAndFlippingOnSpotBadquality) {
  const std::string path = sharedMesh("spot_badquality.ply");
  if (!isFile(path)) {
    const char* req = std::getenv("SODT_REQUIRE_SHARED");
    if (req && std::string(req) == "1") FAIL() << path << " is missing and SODT_REQUIRE_SHARED=1";
    GTEST_SKIP() << path << " not present (the shared meshes are not next to the checkout)";
  }
  TempDir dir;
  Options opt;
  opt.iterations = 20;
  opt.workDir = dir.path() + "/work";
  opt.curves = false;
  opt.quiet = true;
  opt.timingRuns = 1;
  opt.methods = {"sodt_flips", "sodt_flips_repair", "ml_isotropic_edge", "ml_planar_flip"};
  MeshLabServer server;
  std::string err;
  ASSERT_TRUE(server.start(defaultMeshLabConfig(), opt.workDir, err)) << err;
  MeshJob job;
  job.path = path;
  job.name = "spot_badquality";
  const MeshReport rep = compareMesh(job, opt, &server);
  expectRepairRowMatchesItsStats(rep);
  const RepairVerdict v = repairVerdict(rep);
  ASSERT_TRUE(v.repair && v.isotropic && v.planarFlip && v.flipsOnly);
  ASSERT_TRUE(v.comparable);
  // A closed mesh stays closed with its genus: F changes by twice V.
  EXPECT_TRUE(v.repair->m.closed);
  EXPECT_EQ(v.repair->m.faces - rep.input.faces, 2 * (v.repair->m.vertices - rep.input.vertices));
  EXPECT_EQ(v.repairChanged, v.repair->m.verticesAdded + v.repair->m.verticesRemoved);
  EXPECT_EQ(v.isotropicChanged, std::llabs(v.isotropic->m.vertices - rep.input.vertices));
  EXPECT_NE(v.isotropic->m.vertices, rep.input.vertices) << "the remesher kept the vertex count";
  EXPECT_EQ(v.planarFlip->m.vertices, rep.input.vertices);
  EXPECT_EQ(v.largerMinAngle, v.repair->m.minDeg > v.isotropic->m.minDeg);
  // The report has the section, with this mesh's row.
  const std::string md = markdownReport({rep}, opt, "sodt_compare ...", "test", "figures");
  EXPECT_NE(md.find("## Local repair against remeshing"), std::string::npos) << md;
  EXPECT_NE(md.find("| spot_badquality | 2930 | "), std::string::npos) << md;
  EXPECT_NE(md.find("| S-ODT basic + flips + repair | " + std::to_string(v.repair->m.vertices) + " | "),
            std::string::npos)
      << md;
  // The histograms show the repair row next to MeshLab's.
  const std::string svg = histogramSvg(rep);
  EXPECT_NE(svg.find("S-ODT basic + flips + repair"), std::string::npos);
  EXPECT_NE(svg.find("Isotropic Explicit Remeshing, target = mean edge"), std::string::npos);
}

/// A measured row for the verdict tests.
Row fakeRow(const std::string& id, double minDeg, double haus, long long vertices) {
  Row r;
  r.method = *findMethod(id);
  r.m.ok = true;
  r.m.minDeg = minDeg;
  r.m.hausInput = haus;
  r.m.vertices = vertices;
  r.m.faces = 2 * vertices - 4;
  return r;
}

TEST(ComparisonRepair, VerdictNeedsAngleDistanceAndFewerVertices) {
  MeshReport rep;
  rep.job.name = "fake";
  rep.input.ok = true;
  rep.input.vertices = 1000;
  rep.input.minDeg = 1;
  Row rp = fakeRow("sodt_flips_repair", 26, 0.0015, 1002);
  rp.m.verticesAdded = 3;
  rp.m.verticesRemoved = 1;
  rp.m.belowRepairTarget = 0;
  rep.rows = {fakeRow("sodt_flips", 20, 0.0012, 1000), rp, fakeRow("ml_planar_flip", 2, 0.0002, 1000),
              fakeRow("ml_isotropic_edge", 20, 0.002, 950)};
  auto withIso = [&](double minDeg, double haus, long long v) {
    MeshReport r = rep;
    r.rows[3] = fakeRow("ml_isotropic_edge", minDeg, haus, v);
    return repairVerdict(r);
  };
  RepairVerdict v = repairVerdict(rep);
  EXPECT_TRUE(v.comparable);
  EXPECT_EQ(v.repairChanged, 4);
  EXPECT_EQ(v.isotropicChanged, 50);
  EXPECT_TRUE(v.beats());
  EXPECT_FALSE(withIso(26, 0.002, 950).beats()) << "an equal minimum angle is not larger";
  EXPECT_FALSE(withIso(20, 0.001, 950).beats()) << "a larger Hausdorff distance";
  EXPECT_TRUE(withIso(20, 0.0015, 950).beats()) << "an equal Hausdorff distance is no larger";
  EXPECT_FALSE(withIso(20, 0.002, 1004).beats()) << "4 changes against a lower bound of 4 are not fewer";
  EXPECT_TRUE(withIso(20, 0.002, 995).beats()) << "the remesher's count is |V_out - V_in|";
  // Without the remeshing row nothing is claimed.
  MeshReport noIso = rep;
  noIso.rows.pop_back();
  EXPECT_FALSE(repairVerdict(noIso).comparable);
  EXPECT_FALSE(repairVerdict(noIso).beats());

  // The report says which criterion failed.
  Options opt;
  MeshReport lost = rep;
  lost.rows[3] = fakeRow("ml_isotropic_edge", 30, 0.001, 1001);
  lost.job.name = "lost";
  const std::string md = markdownReport({rep, lost}, opt, "sodt_compare ...", "test", "figures");
  EXPECT_NE(md.find("| fake | 1000 | 1.00 | basic: 20.00 / 0.12 | 26.00 / 0.15 | 1002 (+3 / −1) | 0 | "
                    "20.00 / 0.2 | 950 (50) | 2.00 / 0.02 | **yes** |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("no: min angle not larger, larger Hausdorff, not fewer vertices changed |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("beats the isotropic remeshing (target = mean edge) on 1 of 2 meshes (fake)"), std::string::npos)
      << md;
}

/// TwoStep Smooth inverts faces on `mesh`; S-ODT basic inverts none.
void expectTwoStepInvertsSodtDoesNot(const std::string& mesh) {
  TempDir dir;
  const MeshReport rep = runOn(mesh, sodt::Algorithm::Basic, {"ml_twostep"}, dir);
  const Row* two = rep.row("ml_twostep");
  const Row* s = rep.row("sodt_basic");
  ASSERT_TRUE(two && two->m.ok) << "TwoStep Smooth failed: " << (two ? two->m.error : std::string("not run"));
  ASSERT_TRUE(s && s->m.ok);
  EXPECT_GT(two->m.inverted, 0) << "TwoStep Smooth no longer inverts faces on " << mesh;
  EXPECT_EQ(s->m.inverted, 0) << "S-ODT inverted faces on " << mesh;
}

TEST(ComparisonRepair, PeerVerdictNeedsALargerAngleAtNoLargerDistance) {
  const Row repair = fakeRow("sodt_flips_repair", 26, 0.0015, 1002);
  const Row peer = fakeRow("cgal_isotropic_edge", 20, 0.002, 990);
  EXPECT_EQ(peerVerdict(&repair, &peer), PeerVerdict::Beats);
  const Row equal = fakeRow("cgal_isotropic_edge", 20, 0.0015, 990);
  EXPECT_EQ(peerVerdict(&repair, &equal), PeerVerdict::Beats) << "an equal distance is no larger";
  const Row closer = fakeRow("cgal_isotropic_edge", 20, 0.001, 990);
  EXPECT_EQ(peerVerdict(&repair, &closer), PeerVerdict::LargerDistance);
  const Row further = fakeRow("cgal_isotropic_edge", 30, 0.05, 222);
  EXPECT_EQ(peerVerdict(&repair, &further), PeerVerdict::PeerMovesFurther);
  const Row better = fakeRow("cgal_isotropic_edge", 26, 0.0015, 990);
  EXPECT_EQ(peerVerdict(&repair, &better), PeerVerdict::Loses) << "an equal angle is not larger";
  Row failed = peer;
  failed.m.ok = false;
  EXPECT_EQ(peerVerdict(&repair, &failed), PeerVerdict::NotRun);
  EXPECT_EQ(peerVerdict(&repair, nullptr), PeerVerdict::NotRun);
  // The report's peer table says it, mesh by mesh.
  MeshReport rep;
  rep.job.name = "fake";
  rep.input.ok = true;
  rep.input.vertices = 1000;
  Row rp = repair;
  rp.m.needles = 2;
  rp.m.caps = 1;
  rep.rows = {rp, peer, further};
  rep.rows[2].method = *findMethod("cgal_degenerate");
  const std::string md = markdownReport({rep}, Options(), "sodt_compare ...", "test", "figures");
  EXPECT_NE(md.find("| fake | 26.00 / 0.15 / 2 + 1 / 1002 | not run | n/a | not run | n/a | 20.00 / 0.2 / -1 + -1 / "
                    "990 | **beats** | 30.00 / 5 / -1 + -1 / 222 | peer's min angle no smaller, but it moves farther |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("the local repair beats every peer on 0 of 1 meshes"), std::string::npos) << md;
}

/// CGAL's two remeshers run through sodt_cgal_remesh on a bundled
/// marching-cubes mesh: remove_almost_degenerate_faces leaves fewer needles
/// and caps than the input had, and both outputs are measured like any row.
TEST(ComparisonRepair, CgalPeersRunOnABundledMesh) {
  ASSERT_FALSE(cgalRemeshTool().empty()) << "CGAL was not found when the build was configured (libcgal-dev)";
  TempDir dir;
  const MeshReport rep = runInProcess(std::string(SODT_MESH_DIR) + "/blobs_mc.ply", sodt::Algorithm::Basic,
                                      {"cgal_isotropic_edge", "cgal_degenerate"}, dir);
  ASSERT_TRUE(rep.input.ok);
  ASSERT_GT(rep.input.needles + rep.input.caps, 0) << "the input has no needle or cap to remove";
  const Row* iso = rep.row("cgal_isotropic_edge");
  const Row* deg = rep.row("cgal_degenerate");
  ASSERT_TRUE(iso && deg);
  ASSERT_TRUE(iso->m.ok) << iso->m.error;
  ASSERT_TRUE(deg->m.ok) << deg->m.error;
  EXPECT_LT(deg->m.needles + deg->m.caps, rep.input.needles + rep.input.caps);
  EXPECT_LT(deg->m.vertices, rep.input.vertices) << "needles are removed by collapses";
  EXPECT_NE(iso->m.vertices, rep.input.vertices);
  for (const Row* r : {iso, deg}) {
    EXPECT_TRUE(std::isfinite(r->m.hausInput) && r->m.hausInput < 0.05) << r->method.label;
    EXPECT_TRUE(r->m.seconds >= 0 && r->m.seconds < 600) << r->method.label;
  }
}

/// A cap (an angle of 170 degrees), a needle (edges 1 : 5) and a fair
/// triangle, by CGAL's definitions.
TEST(ComparisonRepair, NeedlesAndCapsByCgalsDefinitions) {
  TempDir dir;
  const std::string path = dir.path() + "/two.off";
  const double h = std::tan(5 * std::acos(-1.0) / 180);
  std::ostringstream off;
  off.precision(17);
  off << "OFF\n9 3 0\n0 0 0\n2 0 0\n1 " << h << " 0\n10 0 0\n15 0 0\n10 1 0\n20 0 0\n22 0 0\n21 1.7 0\n"
      << "3 0 1 2\n3 3 4 5\n3 6 7 8\n";
  writeFile(path, off.str());
  const MeshReport rep = runInProcess(path, sodt::Algorithm::Basic, {"laplacian"}, dir);
  ASSERT_TRUE(rep.input.ok);
  EXPECT_EQ(rep.input.caps, 1);
  EXPECT_EQ(rep.input.needles, 1);
}

TEST(Comparison, TwoStepInvertsOnBlobsMcSodtDoesNot) { expectTwoStepInvertsSodtDoesNot("blobs_mc.ply"); }
TEST(Comparison, TwoStepInvertsOnSphereJitterSodtDoesNot) { expectTwoStepInvertsSodtDoesNot("sphere_jitter.ply"); }

/// The installed MeshLab plugin that holds a built-in filter.
std::string pluginLibraryOf(const Method& m) {
  const std::string dir = defaultMeshLabConfig().libDir + "/plugins/";
  if (m.filter == "Planar flipping optimization" || m.filter == "Laplacian Smooth (surface preserving)")
    return dir + "libfilter_trioptimize.so";
  if (m.filter == "Remeshing: Isotropic Explicit Remeshing") return dir + "libfilter_meshing.so";
  return dir + "libfilter_unsharp.so";
}

TEST(Scripts, BuiltinScriptsListEveryParameterOfTheFilter) {
  const std::string tool = SODT_SCRIPT_TOOL;
  ASSERT_FALSE(tool.empty()) << "built without the plugin tests' script tool (SODT_BUILD_PLUGIN=OFF)";
  ASSERT_TRUE(isFile(tool)) << "script tool not built: " << tool;
  TempDir dir;
  int checked = 0;
  for (const Method& m : allMethods()) {
    if (m.kind != Kind::Builtin) continue;
    const std::string script = dir.path() + "/" + m.id + ".mlx";
    writeFile(script, mlxScript(m.filter, builtinParams(m, 20, 2.5, 0.05)));
    const std::string log = dir.path() + "/" + m.id + ".log";
    double secs = 0;
    const int rc = proc::run({tool, pluginLibraryOf(m), m.filter, "--check", script}, {}, log, 60, &secs);
    std::string text;
    try {
      text = readFile(log);
    } catch (...) {
    }
    EXPECT_EQ(rc, 0) << m.filter << ": " << text;
    ++checked;

    // Values: MeshLab's defaults (as its serializer writes them for a mesh
    // without selection) wherever the script does not say why it differs.
    const std::string defaults = dir.path() + "/" + m.id + ".defaults.mlx";
    ASSERT_EQ(proc::run({tool, pluginLibraryOf(m), m.filter, "--write", defaults}, {}, log, 60, &secs), 0);
    const std::string d = readFile(defaults);
    for (const MlxParam& q : builtinParams(m, 20, 2.5, 0.05)) {
      const std::size_t at = d.find("name=\"" + q.name + "\"");
      ASSERT_NE(at, std::string::npos) << q.name;
      const std::size_t line = d.rfind('<', at), end = d.find('>', at);
      const std::string elem = d.substr(line, end - line);
      auto attr = [&](const std::string& a) {
        const std::size_t p = elem.find(" " + a + "=\"");
        if (p == std::string::npos) return std::string();
        const std::size_t s = p + a.size() + 3;
        return elem.substr(s, elem.find('"', s) - s);
      };
      if (q.type == "RichAbsPerc") {
        // Absolute in the file: 1% of the mesh's diagonal, which is the max.
        if (q.note.empty()) {
          EXPECT_NEAR(std::stod(attr("value")) / std::stod(attr("max")), std::stod(q.value) / std::stod(q.max), 1e-4)
              << m.filter << " " << q.name;
        }
      } else if (q.note.empty()) {
        EXPECT_EQ(attr("value"), q.value) << m.filter << " " << q.name << ": not MeshLab's default";
      }
    }
  }
  EXPECT_EQ(checked, 9);
}

TEST(Scripts, PluginScriptSetsIterationsOnly) {
  const std::string shipped = readFile(defaultMeshLabConfig().pluginScript);
  const std::string s = pluginScript(shipped, 7);
  EXPECT_NE(s.find("name=\"iterations\" type=\"RichInt\" value=\"7\""), std::string::npos) << s;
  // Every other line is the shipped one.
  auto lines = [](const std::string& t) {
    std::vector<std::string> v;
    std::size_t a = 0;
    while (a < t.size()) {
      const std::size_t e = t.find('\n', a);
      v.push_back(t.substr(a, e == std::string::npos ? std::string::npos : e - a));
      if (e == std::string::npos) break;
      a = e + 1;
    }
    return v;
  };
  const std::vector<std::string> a = lines(shipped), b = lines(s);
  ASSERT_EQ(a.size(), b.size());
  int changed = 0;
  for (std::size_t i = 0; i < a.size(); ++i) changed += a[i] != b[i];
  EXPECT_EQ(changed, 1);
  EXPECT_THROW(pluginScript("<FilterScript/>", 3), std::runtime_error);
}

TEST(Scripts, MlxScriptFormat) {
  const Method* m = findMethod("ml_isotropic");
  ASSERT_TRUE(m);
  const std::string s = mlxScript(m->filter, builtinParams(*m, 12, 4.0, 0.1));
  EXPECT_NE(s.find("<filter name=\"Remeshing: Isotropic Explicit Remeshing\">"), std::string::npos);
  EXPECT_NE(s.find("name=\"Iterations\" type=\"RichInt\" value=\"12\""), std::string::npos);
  EXPECT_NE(s.find("name=\"TargetLen\" type=\"RichAbsPerc\" value=\"0.04\" min=\"0\" max=\"4\""), std::string::npos)
      << s;
  const Method* e = findMethod("ml_isotropic_edge");
  ASSERT_TRUE(e);
  EXPECT_NE(mlxScript(e->filter, builtinParams(*e, 12, 4.0, 0.1)).find("name=\"TargetLen\" type=\"RichAbsPerc\" "
                                                                       "value=\"0.1\""),
            std::string::npos);
  const Method* hc = findMethod("ml_hc");
  ASSERT_TRUE(hc);
  EXPECT_NE(mlxScript(hc->filter, builtinParams(*hc, 12, 4.0, 0.1)).find("<filter name=\"HC Laplacian Smooth\"/>"),
            std::string::npos);
}

TEST(Cli, WritesReportAndFigures) {
  const std::string exe = SODT_COMPARE_EXE;
  ASSERT_TRUE(isFile(exe)) << "sodt_compare not built: " << exe;
  TempDir dir;
  const std::string out = dir.path() + "/out";
  const std::string log = dir.path() + "/run.log";
  double secs = 0;
  const bool plugin = SODT_HAVE_PLUGIN;
  const std::string methods =
      std::string("sodt_basic,sodt_feature,odt,sodt_flips_repair,ml_taubin") + (plugin ? ",plugin_basic" : "");
  // A RESULTS.md from an earlier run, with the section pymeshlab_compare.py
  // writes: the rewrite keeps that section and drops the rest.
  const std::string pymeshlabPart =
      "<!-- pymeshlab-comparison:begin -->\n## PyMeshLab marker test\n<!-- pymeshlab-comparison:end -->";
  ASSERT_EQ(::mkdir(out.c_str(), 0755), 0) << out;
  writeFile(out + "/RESULTS.md", "stale text from an earlier run\n\n" + pymeshlabPart + "\n");
  const int rc = proc::run({exe, std::string(SODT_MESH_DIR) + "/cube_jitter.ply", "--variant", "feature",
                            "--iterations", "4", "--methods", methods, "--out", out, "--quiet"},
                           {}, log, 120, &secs);
  std::string text;
  try {
    text = readFile(log);
  } catch (...) {
  }
  ASSERT_EQ(rc, 0) << text;
  const std::string md = readFile(out + "/RESULTS.md");
  EXPECT_NE(md.find("### cube_jitter"), std::string::npos);
  EXPECT_EQ(md.find("stale text from an earlier run"), std::string::npos) << md;
  EXPECT_NE(md.find(pymeshlabPart), std::string::npos) << md;
  EXPECT_GT(md.find(pymeshlabPart), md.find("### cube_jitter")) << md;
  EXPECT_NE(md.find("| **S-ODT feature (Alg. 2)** | 866 | 1728 |"), std::string::npos) << md;
  if (plugin) {
    EXPECT_NE(md.find("| S-ODT basic, plugin in meshlabserver | 866 | 1728 |"), std::string::npos) << md;
  }
  EXPECT_NE(md.find("| MeshLab Taubin Smooth | 866 | 1728 |"), std::string::npos) << md;
  // The repair row runs the mesh's variant, and has its section.
  EXPECT_NE(md.find("| S-ODT feature + flips + repair | "), std::string::npos) << md;
  EXPECT_NE(md.find("## Local repair against remeshing"), std::string::npos) << md;
  EXPECT_EQ(md.find("| failed: "), std::string::npos) << md;
  // The timings name the processor they were taken on, where it is known.
  std::string cpuinfo;
  try {
    cpuinfo = readFile("/proc/cpuinfo");
  } catch (...) {
  }
  if (cpuinfo.find("model name") != std::string::npos) {
    EXPECT_NE(md.find("(processor: "), std::string::npos) << md;
  }
  // S-ODT and ODT both ran: the unguarded (paper-style) timings are reported.
  EXPECT_NE(md.find("unguarded ODT / S-ODT per sweep"), std::string::npos) << md;
  EXPECT_NE(md.find("without guard (the paper's algorithm, set-up excluded) an ODT sweep took"), std::string::npos)
      << md;
  for (const std::string f : {"cube_jitter_angles.svg", "cube_jitter_convergence.svg", "odt_vs_sodt.svg"}) {
    const std::string svg = readFile(out + "/figures/" + f);
    EXPECT_EQ(svg.compare(0, 4, "<svg"), 0) << f;
    EXPECT_NE(svg.find("</svg>"), std::string::npos) << f;
    EXPECT_LT(svg.size(), 100000u) << f << " is not small";
  }
  EXPECT_TRUE(isFile(out + "/work/cube_jitter/ml_taubin.mlx"));
}

}  // namespace
