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
// * sodt_compare writes RESULTS.md and the SVG figures.

#include "compare.h"
#include "process.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
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
  EXPECT_EQ(checked, 8);
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
  const std::string methods = std::string("sodt_basic,sodt_feature,odt,ml_taubin") + (plugin ? ",plugin_basic" : "");
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
