// SPDX-License-Identifier: GPL-3.0-or-later
// sodt_compare: S-ODT against the numerical ODT of Eq. 3, a Laplacian
// reference and MeshLab 2020.09's built-in smoothers through meshlabserver,
// on the same inputs; writes DIR/RESULTS.md and SVG figures in DIR/figures.
#include "compare.h"
#include "process.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

int usage(FILE* f, int status) {
  std::fprintf(
      f,
      "usage: sodt_compare MESH [MESH options]... --out DIR [options]\n"
      "\n"
      "Runs on every MESH: S-ODT basic, feature and denoise, the numerical ODT of\n"
      "Eq. 3 and the Laplacian reference (in process, sodt::SodtSmoother<MeshD>),\n"
      "the mesh's --variant with edge flips and with flips and the local repair,\n"
      "S-ODT basic through the freshly built plugin in meshlabserver, and MeshLab\n"
      "2020.09's Laplacian, HC Laplacian, Taubin, TwoStep, surface-preserving\n"
      "Laplacian, planar edge flipping and isotropic remeshing (meshlabserver,\n"
      ".mlx scripts written into the work folder). Measures every output and\n"
      "writes DIR/RESULTS.md and DIR/figures/*.svg.\n"
      "\n"
      "MESH options (apply to the MESH just before them):\n"
      "  --reference CLEAN  clean mesh: distances to it are reported too\n"
      "  --variant V        headline S-ODT variant of this mesh: basic (default),\n"
      "                     feature or denoise (all three always run; the flips\n"
      "                     and repair rows use this one)\n"
      "  --paper MODEL      the paper's Tables 3-4 row shown next to this mesh, e.g.\n"
      "                     \"noise-free fandisk\" or \"noisy fandisk\"\n"
      "options:\n"
      "  --out DIR          report folder (created): RESULTS.md, figures/\n"
      "  --work DIR         meshes, scripts and logs (default DIR/work)\n"
      "  --iterations N     sweeps / step counts, 1..10000 (default 20)\n"
      "  --meshlabserver P  meshlabserver binary to copy into a private prefix with\n"
      "                     the built plugin, or a ready prefix folder (with\n"
      "                     bin/meshlabserver) used as it is\n"
      "                     (default /usr/bin/meshlabserver)\n"
      "  --no-meshlab       skip every meshlabserver run\n"
      "  --no-curves        skip the one-sweep-at-a-time runs (Figure 4 curves)\n"
      "  --methods A,B,...  run only these method ids (default all):\n"
      "                    ");
  for (const sodtcmp::Method& m : sodtcmp::allMethods()) std::fprintf(f, " %s", m.id.c_str());
  std::fprintf(f,
               "\n  --quiet            no progress output\n"
               "\n"
               "exit status: 0 done (failed methods are reported in the tables), 1 an\n"
               "input could not be read or the report not written, 2 bad command line.\n");
  return status;
}

std::string quoteArg(const std::string& a) {
  if (a.find_first_of(" \t\"'$\\") == std::string::npos && !a.empty()) return a;
  std::string q = "'";
  for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

/// The sections other tools write into an existing RESULTS.md between
/// their markers (pymeshlab_compare.py's PyMeshLab section, then
/// noise_bench.py's noise benchmark), to be kept when this tool rewrites
/// the file; empty when there are none.
static std::string keptSections(const std::string& resultsPath) {
  std::ifstream in(resultsPath);
  if (!in) return std::string();
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::string kept;
  for (const char* name : {"pymeshlab-comparison", "noise-benchmark"}) {
    const std::string begin = std::string("<!-- ") + name + ":begin -->", end = std::string("<!-- ") + name + ":end -->";
    const std::size_t b = s.find(begin), e = s.find(end);
    if (b != std::string::npos && e != std::string::npos && e > b) kept += "\n" + s.substr(b, e + end.size() - b) + "\n";
  }
  return kept;
}

int main(int argc, char** argv) {
  using namespace sodtcmp;
  std::vector<MeshJob> jobs;
  Options opt;
  MeshLabConfig mlc = defaultMeshLabConfig();
  std::string outDir;
  bool meshlab = true;
  // The command line as shown in the report: one mesh (with its options) per line.
  std::string shown = argv[0];
  auto need = [&](int& i) -> std::string {
    if (i + 1 >= argc) {
      std::fprintf(stderr, "sodt_compare: %s needs a value\n", argv[i]);
      std::exit(2);
    }
    return argv[++i];
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const std::size_t before = shown.size();
    if (a == "--help" || a == "-h") return usage(stdout, 0);
    if (a == "--reference" || a == "--variant" || a == "--paper") {
      if (jobs.empty()) {
        std::fprintf(stderr, "sodt_compare: %s applies to the mesh before it; give the mesh first\n", a.c_str());
        return 2;
      }
      const std::string v = need(i);
      if (a == "--reference") jobs.back().reference = v;
      if (a == "--paper") {
        if (!findPaperRow(v)) {
          std::fprintf(stderr, "sodt_compare: --paper '%s' is not a model of the paper's Table 3:", v.c_str());
          for (const PaperRow& r : paperTables()) std::fprintf(stderr, " \"%s\"", r.model);
          std::fprintf(stderr, "\n");
          return 2;
        }
        jobs.back().paperModel = v;
      }
      if (a == "--variant") {
        if (v == "basic") jobs.back().variant = sodt::Algorithm::Basic;
        else if (v == "feature") jobs.back().variant = sodt::Algorithm::Feature;
        else if (v == "denoise") jobs.back().variant = sodt::Algorithm::Denoise;
        else {
          std::fprintf(stderr, "sodt_compare: --variant must be basic, feature or denoise\n");
          return 2;
        }
      }
      shown += " " + a + " " + quoteArg(v);
      continue;
    }
    if (a == "--out") outDir = need(i);
    else if (a == "--work") opt.workDir = need(i);
    else if (a == "--iterations") {
      const std::string v = need(i);
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (!end || *end || n < 1 || n > 10000) {
        std::fprintf(stderr, "sodt_compare: --iterations must be in [1, 10000], got '%s'\n", v.c_str());
        return 2;
      }
      opt.iterations = int(n);
    } else if (a == "--meshlabserver") mlc.server = need(i);
    else if (a == "--no-meshlab") meshlab = false;
    else if (a == "--no-curves") opt.curves = false;
    else if (a == "--quiet") opt.quiet = true;
    else if (a == "--methods") {
      const std::string v = need(i);
      std::size_t s = 0;
      while (s <= v.size()) {
        const std::size_t c = v.find(',', s);
        const std::string id = v.substr(s, c == std::string::npos ? std::string::npos : c - s);
        if (!findMethod(id)) {
          std::fprintf(stderr, "sodt_compare: unknown method '%s' (see --help)\n", id.c_str());
          return 2;
        }
        opt.methods.push_back(id);
        if (c == std::string::npos) break;
        s = c + 1;
      }
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "sodt_compare: unknown option '%s' (see --help)\n", a.c_str());
      return 2;
    } else {
      MeshJob j;
      j.path = a;
      j.name = baseName(a);
      for (const MeshJob& o : jobs)
        if (o.name == j.name) {
          std::fprintf(stderr, "sodt_compare: two inputs are named '%s'\n", j.name.c_str());
          return 2;
        }
      jobs.push_back(j);
      shown += " \\\n  " + quoteArg(a);
      continue;
    }
    if (shown.size() == before) {
      // global option (with its value when it has one)
      shown += " \\\n  " + a;
      if (a == "--out" || a == "--work" || a == "--iterations" || a == "--meshlabserver" || a == "--methods")
        shown += " " + quoteArg(argv[i]);
    }
  }
  if (jobs.empty() || outDir.empty()) return usage(stderr, 2);
  if (opt.workDir.empty()) opt.workDir = outDir + "/work";
  const std::string figDir = outDir + "/figures";
  if (!makeDirs(outDir) || !makeDirs(figDir) || !makeDirs(opt.workDir)) {
    std::fprintf(stderr, "sodt_compare: cannot create %s\n", outDir.c_str());
    return 1;
  }

  MeshLabServer server;
  const MeshLabServer* ml = nullptr;
  std::string mlLine = "not run (--no-meshlab)";
  bool anyMeshLabMethod = opt.methods.empty();
  for (const std::string& id : opt.methods) anyMeshLabMethod =
        anyMeshLabMethod || findMethod(id)->kind == Kind::Builtin || findMethod(id)->kind == Kind::Plugin;
  if (meshlab && anyMeshLabMethod) {
    std::string err;
    if (server.start(mlc, opt.workDir, err)) {
      ml = &server;
      mlLine = "meshlabserver 2020.09 from a " + server.describe();
      if (!opt.quiet) std::fprintf(stderr, "MeshLab: %s\n", server.describe().c_str());
    } else {
      std::fprintf(stderr, "sodt_compare: MeshLab rows skipped: %s\n", err.c_str());
      mlLine = "not run: " + err;
    }
  }

  std::vector<MeshReport> reports;
  int failedRows = 0;
  for (const MeshJob& j : jobs) {
    if (!opt.quiet) std::fprintf(stderr, "%s\n", j.path.c_str());
    try {
      reports.push_back(compareMesh(j, opt, ml));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "sodt_compare: %s: %s\n", j.path.c_str(), e.what());
      return 1;
    }
    const MeshReport& r = reports.back();
    for (const Row& row : r.rows)
      if (!row.m.ok) {
        ++failedRows;
        std::fprintf(stderr, "sodt_compare: %s: %s failed: %s\n", j.name.c_str(), row.method.id.c_str(),
                     row.m.error.c_str());
      }
    try {
      writeFile(figDir + "/" + histogramFile(r), histogramSvg(r));
      if (!r.sodtCurve.minDeg.empty()) writeFile(figDir + "/" + convergenceFile(r), convergenceSvg(r));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "sodt_compare: %s\n", e.what());
      return 1;
    }
  }
  try {
    writeFile(figDir + "/" + odtSummaryFile(), odtSummarySvg(reports, opt.iterations));
    writeFile(outDir + "/RESULTS.md", markdownReport(reports, opt, shown, mlLine, "figures") +
                                          keptSections(outDir + "/RESULTS.md"));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sodt_compare: %s\n", e.what());
    return 1;
  }
  if (!opt.quiet)
    std::fprintf(stderr, "wrote %s/RESULTS.md and %s/ (%d failed rows)\n", outDir.c_str(), figDir.c_str(), failedRows);
  return 0;
}
