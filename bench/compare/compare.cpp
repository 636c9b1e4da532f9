// SPDX-License-Identifier: GPL-3.0-or-later
// The runs and measures of sodt_compare (see compare.h).
#include "compare.h"

#include "process.h"

#include <sodt_io/io.h>
#include <sodt_io/mesh.h>
#include <sodt_io/metrics.h>
#include <sodt/smoother.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#ifndef SODT_COMPARE_PLUGIN
#define SODT_COMPARE_PLUGIN ""
#endif
#ifndef SODT_COMPARE_MESHLAB_LIB_DIR
#define SODT_COMPARE_MESHLAB_LIB_DIR "/usr/lib/x86_64-linux-gnu/meshlab"
#endif
#ifndef SODT_COMPARE_PLUGIN_SCRIPT
#define SODT_COMPARE_PLUGIN_SCRIPT ""
#endif

namespace sodtcmp {

// ---------------------------------------------------------------------------
// Methods and MeshLab scripts

const std::vector<Method>& allMethods() {
  using A = sodt::Algorithm;
  static const std::vector<Method> methods = {
      {"sodt_basic", "S-ODT basic (Alg. 1)", Kind::InProcess, A::Basic, "", true, "#1f77b4"},
      {"sodt_feature", "S-ODT feature (Alg. 2)", Kind::InProcess, A::Feature, "", true, "#17becf"},
      {"sodt_denoise", "S-ODT denoise (Alg. 3)", Kind::InProcess, A::Denoise, "", true, "#2ca02c"},
      {"odt", "numerical ODT (Eq. 3)", Kind::InProcess, A::Odt, "", true, "#ff7f0e"},
      {"laplacian", "Laplacian (Eq. 3, S'k = 1)", Kind::InProcess, A::Laplacian, "", true, "#8c564b"},
      // The headline variant with edge flips, and with flips and the local
      // repair: they change the connectivity (and the repair the vertex set),
      // so they stand against MeshLab's flipping and remeshing.
      {"sodt_flips", "S-ODT + flips", Kind::InProcess, A::Basic, "", false, "#6baed6", true, true, false},
      {"sodt_flips_repair", "S-ODT + flips + repair", Kind::InProcess, A::Basic, "", false, "#08306b", true, true,
       true},
      {"plugin_basic", "S-ODT basic, plugin in meshlabserver", Kind::Plugin, A::Basic, "S-ODT Smoothing", true,
       "#9467bd"},
      {"ml_laplacian", "MeshLab Laplacian Smooth", Kind::Builtin, A::Basic, "Laplacian Smooth", true, "#7f7f7f"},
      {"ml_hc", "MeshLab HC Laplacian Smooth", Kind::Builtin, A::Basic, "HC Laplacian Smooth", true, "#bcbd22"},
      {"ml_taubin", "MeshLab Taubin Smooth", Kind::Builtin, A::Basic, "Taubin Smooth", true, "#e377c2"},
      {"ml_twostep", "MeshLab TwoStep Smooth", Kind::Builtin, A::Basic, "TwoStep Smooth", true, "#d62728"},
      {"ml_surface_laplacian", "MeshLab Laplacian Smooth (surface preserving)", Kind::Builtin, A::Basic,
       "Laplacian Smooth (surface preserving)", true, "#393b79"},
      {"ml_planar_flip", "MeshLab Planar flipping optimization", Kind::Builtin, A::Basic,
       "Planar flipping optimization", false, "#637939"},
      {"ml_isotropic", "MeshLab Isotropic Explicit Remeshing", Kind::Builtin, A::Basic,
       "Remeshing: Isotropic Explicit Remeshing", false, "#843c39"},
      {"ml_isotropic_edge", "MeshLab Isotropic Explicit Remeshing, target = mean edge", Kind::Builtin, A::Basic,
       "Remeshing: Isotropic Explicit Remeshing", false, "#e7969c"},
      {"ml_isotropic_edge_dist", "MeshLab Isotropic Explicit Remeshing, target = mean edge, surface distance 0.1%",
       Kind::Builtin, A::Basic, "Remeshing: Isotropic Explicit Remeshing", false, "#ad494a"},
      {"cgal_isotropic_edge", "CGAL isotropic_remeshing, target = mean edge", Kind::External, A::Basic, "isotropic",
       false, "#fd8d3c"},
      {"cgal_degenerate", "CGAL remove_almost_degenerate_faces", Kind::External, A::Basic, "degenerate", false,
       "#31a354"},
  };
  return methods;
}

std::string cgalRemeshTool() { return SODT_COMPARE_CGAL_REMESH; }

const Method* findMethod(const std::string& id) {
  for (const Method& m : allMethods())
    if (m.id == id) return &m;
  return nullptr;
}

namespace {

MlxParam p(const std::string& name, const std::string& type, const std::string& value,
           const std::string& note = "") {
  MlxParam r;
  r.name = name;
  r.type = type;
  r.value = value;
  r.note = note;
  return r;
}

std::string floatText(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string xmlEscape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

}  // namespace

std::vector<MlxParam> builtinParams(const Method& m, int iterations, double bboxDiag, double meanEdge) {
  const std::string n = std::to_string(iterations);
  const std::string matched = "step count matched to the S-ODT sweeps";
  std::vector<MlxParam> v;
  // Names, types and defaults from MeshLab 2020.09's initParameterSet
  // (filter_unsharp.cpp, filter_trioptimize.cpp, filter_meshing.cpp); the
  // labels of `meshlabserver -d` are shown in the comments. "Selected"
  // defaults to (selected faces > 0), i.e. false on our inputs.
  if (m.filter == "Laplacian Smooth") {
    v.push_back(p("stepSmoothNum", "RichInt", n, matched + " (default 3)"));  // Smoothing steps
    v.push_back(p("Boundary", "RichBool", "true"));                           // 1D Boundary Smoothing
    v.push_back(p("cotangentWeight", "RichBool", "true"));                    // Cotangent weighting
    v.push_back(p("Selected", "RichBool", "false"));                          // Affect only selection
  } else if (m.filter == "HC Laplacian Smooth") {
    // No parameters: one HC pass, as the filter always does.
  } else if (m.filter == "Taubin Smooth") {
    v.push_back(p("lambda", "RichFloat", "0.5"));                             // Lambda
    v.push_back(p("mu", "RichFloat", "-0.53"));                               // mu
    v.push_back(p("stepSmoothNum", "RichInt", n, matched + " (default 10)"));  // Smoothing steps
    v.push_back(p("Selected", "RichBool", "false"));                          // Affect only selected faces
  } else if (m.filter == "TwoStep Smooth") {
    v.push_back(p("stepSmoothNum", "RichInt", n, matched + " (default 3)"));  // Smoothing steps
    v.push_back(p("normalThr", "RichFloat", "60"));                           // Feature Angle Threshold (deg)
    v.push_back(p("stepNormalNum", "RichInt", "20"));                         // Normal Smoothing steps
    v.push_back(p("stepFitNum", "RichInt", "20"));                            // Vertex Fitting steps
    v.push_back(p("Selected", "RichBool", "false"));                          // Affect only selected faces
  } else if (m.filter == "Laplacian Smooth (surface preserving)") {
    v.push_back(p("selection", "RichBool", "false"));                         // Update selection
    v.push_back(p("AngleDeg", "RichFloat", "0.5"));                           // Max Normal Dev (deg)
    v.push_back(p("iterations", "RichInt", n, matched + " (default 1)"));     // Iterations
  } else if (m.filter == "Planar flipping optimization") {
    v.push_back(p("selection", "RichBool", "false"));   // Update selection
    v.push_back(p("pthreshold", "RichFloat", "1"));      // Planar threshold (deg)
    MlxParam e = p("planartype", "RichEnum", "0");       // Planar metric
    e.enumValues = {"area/max side", "inradius/circumradius", "mean ratio", "delaunay", "topology"};
    v.push_back(e);
    // Post optimization relax iter: planar Laplacian passes after the flips,
    // not a step count of the optimisation (which runs until no flip helps).
    v.push_back(p("iterations", "RichInt", "1"));
  } else if (m.filter == "Remeshing: Isotropic Explicit Remeshing") {
    const std::string pct = floatText(0.01 * bboxDiag);
    v.push_back(p("Iterations", "RichInt", n, matched + " (default 3)"));  // Iterations
    v.push_back(p("Adaptive", "RichBool", "false"));                       // Adaptive remeshing
    v.push_back(p("SelectedOnly", "RichBool", "false"));                   // Remesh only selected faces
    // Target Length: the default (1% of the diagonal) refines or coarsens the
    // mesh; the second remeshing row keeps the input's resolution instead.
    const bool atMeanEdge = m.id == "ml_isotropic_edge" || m.id == "ml_isotropic_edge_dist";
    const bool checked = m.id == "ml_isotropic_edge_dist";
    MlxParam t = atMeanEdge
                     ? p("TargetLen", "RichAbsPerc", floatText(meanEdge), "the input's mean edge length (default: 1% of the bounding-box diagonal)")
                     : p("TargetLen", "RichAbsPerc", pct);
    t.min = "0";
    t.max = floatText(bboxDiag);
    v.push_back(t);
    v.push_back(p("FeatureDeg", "RichFloat", "30"));  // Crease Angle
    // Check Surface Distance: its default is an uninitialised member in
    // 2020.09 (false in practice); written explicitly.
    v.push_back(checked ? p("CheckSurfDist", "RichBool", "true", "on, at S-ODT's deviation bound (default: off)")
                        : p("CheckSurfDist", "RichBool", "false"));
    MlxParam d = checked ? p("MaxSurfDist", "RichAbsPerc", floatText(0.001 * bboxDiag),
                             "0.1% of the bounding-box diagonal, S-ODT's deviation bound (default: 1%)")
                         : p("MaxSurfDist", "RichAbsPerc", pct);  // Max. Surface Distance
    d.min = "0";
    d.max = floatText(bboxDiag);
    v.push_back(d);
    v.push_back(p("SplitFlag", "RichBool", "true"));      // Refine Step
    v.push_back(p("CollapseFlag", "RichBool", "true"));   // Collapse Step
    v.push_back(p("SwapFlag", "RichBool", "true"));       // Edge-Swap Step
    v.push_back(p("SmoothFlag", "RichBool", "true"));     // Smooth Step
    v.push_back(p("ReprojectFlag", "RichBool", "true"));  // Reproject Step
  } else {
    throw std::runtime_error("no MeshLab script for method " + m.id);
  }
  return v;
}

std::string mlxScript(const std::string& filter, const std::vector<MlxParam>& params) {
  std::ostringstream o;
  o << "<!-- Written by sodt_compare: every parameter of the filter is listed with its exact name"
       " (meshlabserver 2020.09 aborts otherwise). -->\n";
  o << "<!DOCTYPE FilterScript>\n<FilterScript>\n <filter name=\"" << xmlEscape(filter) << "\"";
  if (params.empty()) {
    o << "/>\n";
  } else {
    o << ">\n";
    for (const MlxParam& q : params) {
      o << "  <Param name=\"" << xmlEscape(q.name) << "\" type=\"" << q.type << "\" value=\"" << xmlEscape(q.value)
        << "\"";
      if (q.type == "RichEnum") {
        o << " enum_cardinality=\"" << q.enumValues.size() << "\"";
        for (std::size_t i = 0; i < q.enumValues.size(); ++i)
          o << " enum_val" << i << "=\"" << xmlEscape(q.enumValues[i]) << "\"";
      }
      if (q.type == "RichAbsPerc") o << " min=\"" << q.min << "\" max=\"" << q.max << "\"";
      o << "/>\n";
    }
    o << " </filter>\n";
  }
  o << "</FilterScript>\n";
  return o.str();
}

std::string pluginScript(const std::string& shipped, int iterations) {
  std::istringstream in(shipped);
  std::ostringstream out;
  std::string line;
  bool found = false;
  while (std::getline(in, line)) {
    if (line.find("name=\"iterations\"") != std::string::npos) {
      const std::size_t v = line.find("value=\"");
      const std::size_t e = v == std::string::npos ? v : line.find('"', v + 7);
      if (e == std::string::npos) throw std::runtime_error("malformed iterations parameter in the plugin script");
      line = line.substr(0, v + 7) + std::to_string(iterations) + line.substr(e);
      found = true;
    }
    out << line << "\n";
  }
  if (!found) throw std::runtime_error("the plugin's example script has no iterations parameter");
  return out.str();
}

// ---------------------------------------------------------------------------
// Measures

namespace {

using Clock = std::chrono::steady_clock;
using sodt::MeshD;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void copyMesh(const MeshD& src, MeshD& dst) { sodt::detail::copyToDouble(src, dst); }

void measureAngles(const MeshD& m, Metrics& r) {
  const sodt::AngleStats a = sodt::computeAngleStats(m);
  r.vertices = m.vn;
  r.faces = m.fn;
  r.minDeg = a.minDeg;
  r.maxDeg = a.maxDeg;
  r.fracBelow30 = a.fracBelow30;
  r.p1TriMinDeg = a.p1TriMinDeg;
  r.histogram = a.histogram;
  // Needles and caps by CGAL's definitions (is_needle_triangle_face with
  // threshold 4, is_cap_triangle_face with the cosine of 160 degrees).
  const double capCos = std::cos(160.0 * sodt::kPi / 180.0);
  r.needles = r.caps = 0;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    const sodt::Vec3 p[3] = {f.cP(0), f.cP(1), f.cP(2)};
    double shortest = std::numeric_limits<double>::infinity(), longest = 0;
    bool cap = false;
    for (int j = 0; j < 3; ++j) {
      const sodt::Vec3 u = p[(j + 1) % 3] - p[j], w = p[(j + 2) % 3] - p[j];
      const double l = u.Norm();
      shortest = std::min(shortest, l);
      longest = std::max(longest, l);
      const double uw = u.Norm() * w.Norm();
      cap = cap || (uw > 0 && (u * w) / uw <= capCos);
    }
    if (longest >= 4 * shortest)
      ++r.needles;
    else if (cap)
      ++r.caps;
  }
}

/// Everything but the time; input and reference already loaded.
void measure(const MeshD& out, const MeshD& in, const Metrics& inMetrics, const MeshD* ref, bool isInput,
             Metrics& r) {
  measureAngles(out, r);
  if (isInput) {
    r.hausInput = r.meanInput = 0;
  } else {
    const sodt::DistanceStats d = sodt::surfaceDistance(out, in);
    r.hausInput = d.maxRel;
    r.meanInput = d.meanRel;
  }
  if (ref) {
    const sodt::DistanceStats d = sodt::surfaceDistance(out, *ref);
    r.hausRef = d.maxRel;
    r.meanRef = d.meanRel;
  }
  const sodt::VolumeResult v = sodt::enclosedVolume(out);
  r.closed = v.closed;
  if (v.closed) r.volume = v.volume;
  if (v.closed && inMetrics.closed && inMetrics.volume != 0)
    r.volumeChange = (v.volume - inMetrics.volume) / std::abs(inMetrics.volume);
  r.inverted = isInput ? 0 : sodt::countInvertedFaces(out, in);
  r.ok = true;
}

/// Runs sodt_cgal_remesh in mode m.filter on inPath, writing WORK/ID.off and
/// its log WORK/ID.log; r.seconds gets the remesher's own time, r.error why
/// it failed (empty: the output is there).
void runExternal(const Method& m, const std::string& inPath, const std::string& work, double meanEdge,
                 int iterations, Metrics& r) {
  const std::string tool = cgalRemeshTool();
  if (tool.empty()) {
    r.error = "CGAL was not found when this build was configured (Debian: libcgal-dev)";
    return;
  }
  const std::string out = work + "/" + m.id + ".off", log = work + "/" + m.id + ".log";
  std::vector<std::string> argv = {tool, m.filter, inPath, out, "--feature-angle", "30"};
  if (m.filter == "isotropic")
    argv.insert(argv.end(), {"--target", floatText(meanEdge), "--iterations", std::to_string(iterations)});
  std::remove(log.c_str());
  double wall = 0;
  const int status = proc::run(argv, {}, log, 3600, &wall);
  if (status != 0 || !isFile(out)) {
    r.error = "sodt_cgal_remesh exit status " + std::to_string(status) + " (log: " + log + ")";
    return;
  }
  r.seconds = wall;
  std::istringstream text(readFile(log));
  std::string word;
  double s = 0;
  while (text >> word)
    if (word == "seconds" && text >> s) r.seconds = s;
  r.detail = "sodt_cgal_remesh " + m.filter + ", exit status 0";
}

std::string countersLine(const sodt::SodtStats& s) {
  const double visits = std::max(1.0, double(s.activeVertices) * std::max(1, s.iterations));
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "%d sweeps; visits: %.1f%% moved (%.1f%% shortened), %.1f%% Laplacian fallback, %.1f%% rejected, "
                "%.1f%% failed solves",
                s.iterations, 100.0 * (s.moved + s.backtracked) / visits, 100.0 * s.backtracked / visits,
                100.0 * s.fallbackMoves / visits, 100.0 * s.rejected / visits, 100.0 * s.failedSolves / visits);
  return buf;
}

sodt::SodtParams paramsFor(sodt::Algorithm a, int iterations, bool flips = false, bool repair = false) {
  sodt::SodtParams p;  // library defaults: guard quality, Laplacian fallback, 0.1% deviation bound
  p.algorithm = a;
  p.iterations = iterations;
  p.flips = flips;
  p.repair = repair;  // with the library's target angle and feature angle
  // One thread (the library default, 0, uses every core): the times stay
  // single-core, comparable with earlier reports and with the paper's.
  p.threads = 1;
  return p;
}

/// What the flips and the repair did, for the per-mesh notes.
std::string changesLine(const sodt::SodtParams& p, const sodt::SodtStats& s) {
  std::string t;
  if (p.flips) t += "; " + std::to_string(s.flips) + " edges flipped between sweeps";
  if (!p.repair) return t;
  int why[sodt::kRepairReasonCount] = {};
  for (const sodt::RemainingTriangle& b : s.belowTarget) ++why[static_cast<int>(b.why)];
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "; repair: %d vertices added, %d removed (%d splits, %d points inserted, %d collapses, %d flips, "
                "%lld relaxing moves), %zu triangles left below %g°",
                s.verticesAdded, s.verticesRemoved, s.repairSplits, s.repairInserts, s.repairCollapses, s.repairFlips,
                s.repairMoves,
                s.belowTarget.size(), p.repairAngleDeg);
  t += buf;
  if (!s.belowTarget.empty()) {
    std::string reasons;
    for (int k = 0; k < sodt::kRepairReasonCount; ++k)
      if (why[k])
        reasons += (reasons.empty() ? "" : ", ") + std::to_string(why[k]) + " " +
                   sodt::toString(static_cast<sodt::RepairReason>(k));
    t += " (" + reasons + ")";
  }
  return t;
}

/// The paper's algorithm: no guard, no Laplacian fallback, no deviation bound.
sodt::SodtParams unguardedParamsFor(sodt::Algorithm a, int iterations) {
  sodt::SodtParams p = paramsFor(a, iterations);
  p.guard = sodt::Guard::None;
  p.laplacianFallback = false;
  p.maxDeviationRel = 0;
  return p;
}

/// Wall time of Apply(p) on a copy of the input, with the policy of the
/// table's in-process rows: a run shorter than 1 s is repeated (from the
/// input) up to `timingRuns` runs in all, or until 2 s are spent, and the
/// median is returned. `first` (optional) receives the first run's result.
/// The solvers are compared as such: without S-ODT's 4-lane kernel
/// (lanes.h), which has no ODT counterpart.
double medianApplySeconds(const MeshD& input, const sodt::SodtParams& p, int timingRuns, MeshD* first,
                          int* runs) {
  sodt::SweepTuning scalar;
  scalar.simd = false;
  std::vector<double> times;
  double spent = 0;
  do {
    MeshD m;
    copyMesh(input, m);
    const Clock::time_point t0 = Clock::now();
    sodt::SodtSmoother<MeshD>::Apply(m, p, nullptr, nullptr, scalar);
    times.push_back(since(t0));
    spent += times.back();
    if (first && times.size() == 1) copyMesh(m, *first);
  } while (int(times.size()) < timingRuns && times[0] < 1.0 && spent < 2.0);
  if (runs) *runs = int(times.size());
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

void progress(const Options& o, const std::string& what) {
  if (!o.quiet) std::fprintf(stderr, "  %s\n", what.c_str());
}

bool wanted(const Options& o, const std::string& id) {
  if (o.methods.empty()) return true;
  for (const std::string& m : o.methods)
    if (m == id) return true;
  return false;
}

}  // namespace

const Row* MeshReport::row(const std::string& id) const {
  for (const Row& r : rows)
    if (r.method.id == id) return &r;
  return nullptr;
}

// ---------------------------------------------------------------------------
// MeshLab

MeshLabConfig defaultMeshLabConfig() {
  MeshLabConfig c;
  c.plugin = SODT_COMPARE_PLUGIN;
  c.libDir = SODT_COMPARE_MESHLAB_LIB_DIR;
  c.pluginScript = SODT_COMPARE_PLUGIN_SCRIPT;
  return c;
}

struct MeshLabServer::Impl {
  MeshLabConfig cfg;
  std::string binary;  ///< meshlabserver to run
  std::string prefix, home, runtime;
  bool privatePrefix = false;
  bool plugin = false;
  int linkedPlugins = 0;
  std::string xvfbRun;  ///< fallback when there is no Xvfb binary
  std::vector<std::string> filters;  ///< filter names of `meshlabserver -d`
  proc::Xvfb xvfb;
};

MeshLabServer::MeshLabServer() : impl_(new Impl) {}
MeshLabServer::~MeshLabServer() = default;

bool MeshLabServer::hasPlugin() const { return impl_->plugin; }
const MeshLabConfig& MeshLabServer::config() const { return impl_->cfg; }

bool MeshLabServer::listsFilter(const std::string& name) const {
  for (const std::string& f : impl_->filters)
    if (f == name) return true;
  return false;
}

bool MeshLabServer::start(const MeshLabConfig& cfg, const std::string& workDir, std::string& error) {
  Impl& I = *impl_;
  I.cfg = cfg;
  const std::string server = cfg.server.empty() ? std::string("/usr/bin/meshlabserver") : cfg.server;
  if (!makeDirs(workDir)) {
    error = "cannot create " + workDir;
    return false;
  }
  const std::string work = proc::realPath(workDir);
  if (isDirectory(server)) {
    // A ready prefix (e.g. one kept by the plugin tests): used as it is.
    I.prefix = proc::realPath(server);
    I.binary = I.prefix + "/bin/meshlabserver";
    if (!isFile(I.binary)) {
      error = "no bin/meshlabserver in the prefix " + server;
      return false;
    }
    I.plugin = isFile(I.prefix + "/lib/x86_64-linux-gnu/meshlab/plugins/libfilter_sodt.so");
  } else {
    if (!isFile(server) || access(server.c_str(), X_OK) != 0) {
      error = "meshlabserver not found at " + server + " (apt-get install meshlab, or pass --meshlabserver)";
      return false;
    }
    if (!isFile(cfg.libDir + "/libmeshlab-common.so")) {
      error = "no libmeshlab-common.so in " + cfg.libDir;
      return false;
    }
    // Private prefix (docs MESHLAB-2020.09.md section 5): a copied binary in
    // P/bin loads plugins from P/lib/x86_64-linux-gnu/meshlab/plugins only.
    I.privatePrefix = true;
    I.prefix = work + "/mlprefix";
    const std::string L = I.prefix + "/lib/x86_64-linux-gnu/meshlab";
    proc::removeTree(I.prefix);
    if (!makeDirs(I.prefix + "/bin") || !makeDirs(L + "/plugins")) {
      error = "cannot create the prefix " + I.prefix;
      return false;
    }
    I.binary = I.prefix + "/bin/meshlabserver";
    if (!proc::copyFile(server, I.binary, 0755)) {
      error = "cannot copy " + server + " into " + I.binary;
      return false;
    }
    proc::symlinkTo(cfg.libDir + "/libmeshlab-common.so", L + "/libmeshlab-common.so");
    for (const std::string& f : proc::listDir(cfg.libDir + "/plugins")) {
      // An installed copy of the S-ODT plugin would register the filter twice.
      if (f == "libfilter_sodt.so" || f.size() < 3 || f.compare(f.size() - 3, 3, ".so") != 0) continue;
      if (proc::symlinkTo(cfg.libDir + "/plugins/" + f, L + "/plugins/" + f)) ++I.linkedPlugins;
    }
    const std::string built = cfg.plugin.empty() ? std::string() : proc::realPath(cfg.plugin);
    if (!built.empty()) I.plugin = proc::symlinkTo(built, L + "/plugins/libfilter_sodt.so");
  }
  // MeshLab's QSettings and runtime files stay in the work folder.
  I.home = work + "/mlhome";
  I.runtime = work + "/mlruntime";
  makeDirs(I.home + "/.config");
  makeDirs(I.runtime);
  chmod(I.runtime.c_str(), 0700);

  const std::string xvfb = proc::which("Xvfb");
  if (!xvfb.empty()) {
    if (!I.xvfb.start(xvfb, work + "/xvfb.log", error)) return false;
  } else {
    I.xvfbRun = proc::which("xvfb-run");
    if (I.xvfbRun.empty()) {
      error = "neither Xvfb nor xvfb-run is installed (apt-get install xvfb xauth)";
      return false;
    }
  }
  // The filter names the server knows (`-d` writes one "\section fNN NAME"
  // line per filter): a script naming anything else would fail.
  const std::string dump = work + "/filters.txt";
  std::vector<std::string> argv;
  if (!I.xvfbRun.empty()) argv = {I.xvfbRun, "-a", "-s", "-screen 0 1024x768x24"};
  argv.insert(argv.end(), {I.binary, "-d", dump});
  std::vector<std::string> env = {"HOME=" + I.home, "XDG_CONFIG_HOME=" + I.home + "/.config",
                                  "XDG_RUNTIME_DIR=" + I.runtime};
  if (!I.xvfb.display().empty()) env.push_back("DISPLAY=" + I.xvfb.display());
  double secs = 0;
  unlink(dump.c_str());
  const int rc = proc::run(argv, env, work + "/filters.log", 120, &secs);
  std::string text;
  try {
    text = readFile(dump);
  } catch (const std::exception&) {
  }
  if (rc != 0 || text.empty()) {
    error = "meshlabserver -d failed (exit status " + std::to_string(rc) + ", log " + work + "/filters.log)";
    return false;
  }
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, 10, "\\section f") != 0) continue;
    const std::size_t sp = line.find(' ', 10);
    if (sp == std::string::npos) continue;
    std::string name = line.substr(sp + 1);
    while (!name.empty() && (name.back() == ' ' || name.back() == '\r')) name.pop_back();
    I.filters.push_back(name);
  }
  return true;
}

namespace {

/// path relative to the working directory when it lies below it (the report
/// is generated from the repository root and must not name this machine's
/// folders), else path as it is.
std::string belowWorkingDir(const std::string& path) {
  char buf[4096];
  if (!::getcwd(buf, sizeof buf)) return path;
  const std::string cwd = std::string(buf) + "/";
  return path.compare(0, cwd.size(), cwd) == 0 ? path.substr(cwd.size()) : path;
}

}  // namespace

std::string MeshLabServer::describe() const {
  const Impl& I = *impl_;
  std::ostringstream o;
  if (I.privatePrefix)
    o << "private prefix " << belowWorkingDir(I.prefix) << " (a copy of "
      << (I.cfg.server.empty() ? "/usr/bin/meshlabserver" : belowWorkingDir(I.cfg.server)) << ", " << I.linkedPlugins
      << " system plugins linked from " << I.cfg.libDir << "/plugins, "
      << (I.plugin ? "the freshly built " + belowWorkingDir(I.cfg.plugin) : std::string("no S-ODT plugin")) << ")";
  else
    o << "prefix " << belowWorkingDir(I.prefix) << " as given"
      << (I.plugin ? " (with libfilter_sodt.so)" : " (no S-ODT plugin)");
  o << "; display " << (I.xvfb.display().empty() ? std::string("by xvfb-run -a") : "Xvfb " + I.xvfb.display());
  return o.str();
}

MeshLabServer::Result MeshLabServer::run(const std::string& in, const std::string& out, const std::string& script,
                                         const std::string& logPath) const {
  const Impl& I = *impl_;
  std::vector<std::string> argv;
  if (!I.xvfbRun.empty()) argv = {I.xvfbRun, "-a", "-s", "-screen 0 1024x768x24"};
  argv.push_back(I.binary);
  argv.insert(argv.end(), {"-i", in, "-o", out});
  if (!script.empty()) argv.insert(argv.end(), {"-s", script});
  std::vector<std::string> env = {"HOME=" + I.home, "XDG_CONFIG_HOME=" + I.home + "/.config",
                                  "XDG_RUNTIME_DIR=" + I.runtime};
  if (!I.xvfb.display().empty()) env.push_back("DISPLAY=" + I.xvfb.display());
  unlink(out.c_str());
  unlink(logPath.c_str());
  Result r;
  r.status = proc::run(argv, env, logPath, I.cfg.timeoutSec, &r.seconds);
  return r;
}

// ---------------------------------------------------------------------------
// One mesh

MeshReport compareMesh(const MeshJob& job, const Options& opt, const MeshLabServer* ml) {
  MeshReport rep;
  rep.job = job;
  if (rep.job.name.empty()) rep.job.name = baseName(job.path);
  const std::string work = opt.workDir + "/" + rep.job.name;
  if (!makeDirs(work)) throw std::runtime_error("cannot create " + work);

  MeshD input;
  sodt::loadMesh(job.path, input);
  std::unique_ptr<MeshD> ref;
  if (!job.reference.empty()) {
    ref.reset(new MeshD);
    sodt::loadMesh(job.reference, *ref);
  }
  // The input in the work folder: MeshLab reads the same file.
  const std::string inCopy = work + "/input.ply";
  {
    sodt::SaveOptions so;
    so.verify = false;
    sodt::saveMesh(inCopy, input, so);
  }
  const double diag = sodt::bboxDiagonal(input);
  const double meanEdge = sodt::meanEdgeLength(input);
  {
    const sodt::VolumeResult v = sodt::enclosedVolume(input);
    rep.input.closed = v.closed;
    if (v.closed) rep.input.volume = v.volume;
  }
  measure(input, input, rep.input, ref.get(), true, rep.input);
  rep.input.volumeChange = rep.input.closed ? 0.0 : kNaN;

  for (const Method& m : allMethods()) {
    if (!wanted(opt, m.id)) continue;
    Row row;
    row.method = m;
    if (m.headlineVariant) {
      // "S-ODT + flips" becomes e.g. "S-ODT feature + flips".
      row.method.algorithm = job.variant;
      row.method.label = "S-ODT " + std::string(sodt::toString(job.variant)) + m.label.substr(5);
    }
    Metrics& r = row.m;
    if (m.kind == Kind::InProcess) {
      progress(opt, row.method.label);
      MeshD out;
      copyMesh(input, out);
      const sodt::SodtParams p = paramsFor(row.method.algorithm, opt.iterations, m.flips, m.repair);
      const Clock::time_point t0 = Clock::now();
      sodt::SodtStats s;
      try {
        s = sodt::SodtSmoother<MeshD>::Apply(out, p);
      } catch (const std::exception& e) {
        r.error = e.what();
        rep.rows.push_back(row);
        continue;
      }
      std::vector<double> times = {since(t0)};
      // Short runs are noisy: repeat them (from the input) and take the median.
      double spent = times[0];
      while (int(times.size()) < opt.timingRuns && times[0] < 1.0 && spent < 2.0) {
        MeshD again;
        copyMesh(input, again);
        const Clock::time_point t1 = Clock::now();
        sodt::SodtSmoother<MeshD>::Apply(again, p);
        times.push_back(since(t1));
        spent += times.back();
      }
      std::sort(times.begin(), times.end());
      r.seconds = times[times.size() / 2];
      measure(out, input, rep.input, ref.get(), false, r);
      r.detail = countersLine(s);
      if (row.method.algorithm == sodt::Algorithm::Feature || row.method.algorithm == sodt::Algorithm::Denoise)
        r.detail += "; classes: " + std::to_string(s.smoothVertices) + " smooth, " +
                    std::to_string(s.creaseVertices) + " crease, " + std::to_string(s.cornerVertices) + " corner";
      if (p.flips) r.edgeFlips = s.flips;
      if (p.repair) {
        r.verticesAdded = s.verticesAdded;
        r.verticesRemoved = s.verticesRemoved;
        r.belowRepairTarget = static_cast<long long>(s.belowTarget.size());
      }
      r.detail += changesLine(p, s);
      sodt::SaveOptions so;
      so.verify = false;
      sodt::saveMesh(work + "/" + m.id + ".ply", out, so);
    } else if (m.kind == Kind::External) {
      runExternal(m, inCopy, work, meanEdge, opt.iterations, r);
      if (r.error.empty()) {
        MeshD out;
        try {
          sodt::loadMesh(work + "/" + m.id + ".off", out);
          measure(out, input, rep.input, ref.get(), false, r);
        } catch (const std::exception& e) {
          r.error = e.what();
        }
      }
    } else {
      if (!ml) continue;  // MeshLab off or unavailable: no row (the report says why)
      if (m.kind == Kind::Plugin && !ml->hasPlugin()) {
        r.error = "the S-ODT plugin is not in the MeshLab prefix";
        rep.rows.push_back(row);
        continue;
      }
      if (!ml->listsFilter(m.filter)) {
        r.error = "meshlabserver -d does not list a filter named \"" + m.filter + "\"";
        rep.rows.push_back(row);
        continue;
      }
      progress(opt, m.label + " (meshlabserver)");
      const std::string script = work + "/" + m.id + ".mlx";
      try {
        if (m.kind == Kind::Plugin)
          writeFile(script, pluginScript(readFile(ml->config().pluginScript), opt.iterations));
        else
          writeFile(script, mlxScript(m.filter, builtinParams(m, opt.iterations, diag, meanEdge)));
      } catch (const std::exception& e) {
        r.error = e.what();
        rep.rows.push_back(row);
        continue;
      }
      const std::string outPath = work + "/" + m.id + ".ply";
      const std::string logPath = work + "/" + m.id + ".log";
      const MeshLabServer::Result res = ml->run(inCopy, outPath, script, logPath);
      r.seconds = res.seconds;
      if (res.status != 0 || !isFile(outPath)) {
        r.error = "meshlabserver exit status " + std::to_string(res.status) + " (log: " + logPath + ")";
        rep.rows.push_back(row);
        continue;
      }
      MeshD out;
      try {
        sodt::loadMesh(outPath, out);
      } catch (const std::exception& e) {
        r.error = e.what();
        rep.rows.push_back(row);
        continue;
      }
      measure(out, input, rep.input, ref.get(), false, r);
      r.detail = "meshlabserver exit status 0";
    }
    rep.rows.push_back(row);
  }

  // The local solvers as the paper compares them (Figure 6): no guard.
  if (opt.unguardedTimings && wanted(opt, "sodt_basic") && wanted(opt, "odt")) {
    progress(opt, "unguarded S-ODT basic and ODT (guard none), timing only");
    UnguardedTiming& u = rep.unguarded;
    u.iterations = opt.iterations;
    try {
      MeshD s, d;
      u.sodtSetupSeconds =
          medianApplySeconds(input, unguardedParamsFor(sodt::Algorithm::Basic, 0), opt.timingRuns, nullptr, nullptr);
      u.sodtSeconds = medianApplySeconds(input, unguardedParamsFor(sodt::Algorithm::Basic, opt.iterations),
                                         opt.timingRuns, &s, &u.sodtRuns);
      u.odtSetupSeconds =
          medianApplySeconds(input, unguardedParamsFor(sodt::Algorithm::Odt, 0), opt.timingRuns, nullptr, nullptr);
      u.odtSeconds = medianApplySeconds(input, unguardedParamsFor(sodt::Algorithm::Odt, opt.iterations),
                                        opt.timingRuns, &d, &u.odtRuns);
      u.sodtMinDeg = sodt::computeAngleStats(s).minDeg;
      u.odtMinDeg = sodt::computeAngleStats(d).minDeg;
      u.sodtInverted = sodt::countInvertedFaces(s, input);
      u.odtInverted = sodt::countInvertedFaces(d, input);
      u.ok = true;
    } catch (const std::exception& e) {
      u.error = e.what();
    }
  }

  // Load and save alone: the part of a meshlabserver run that is not the filter.
  bool anyMeshLab = false;
  for (const Row& r : rep.rows) anyMeshLab = anyMeshLab || r.method.kind != Kind::InProcess;
  if (ml && anyMeshLab) {
    const MeshLabServer::Result res = ml->run(inCopy, work + "/noop.ply", "", work + "/noop.log");
    if (res.status == 0) rep.noopSeconds = res.seconds;
  }

  if (opt.curves) {
    const sodt::Algorithm algs[] = {sodt::Algorithm::Basic, sodt::Algorithm::Odt};
    for (sodt::Algorithm alg : algs) {
      Curve& prefix = alg == sodt::Algorithm::Basic ? rep.sodtCurve : rep.odtCurve;
      Curve& steps = alg == sodt::Algorithm::Basic ? rep.sodtSteps : rep.odtSteps;
      for (Curve* c : {&prefix, &steps}) {
        c->minDeg.push_back(rep.input.minDeg);
        c->maxDeg.push_back(rep.input.maxDeg);
        c->seconds.push_back(0);
      }
      // The states of the N-sweep run: a k-sweep run from the input for every
      // k (Gauss-Seidel sweeps are deterministic, so sweep k of the N-sweep run
      // is the result of the k-sweep run).
      progress(opt, std::string("per-sweep states (k-sweep runs, k = 1..N): ") + sodt::toString(alg));
      for (int k = 1; k <= opt.iterations; ++k) {
        MeshD m;
        copyMesh(input, m);
        const Clock::time_point t0 = Clock::now();
        sodt::SodtSmoother<MeshD>::Apply(m, paramsFor(alg, k));
        const double t = since(t0);
        const sodt::AngleStats a = sodt::computeAngleStats(m);
        prefix.minDeg.push_back(a.minDeg);
        prefix.maxDeg.push_back(a.maxDeg);
        prefix.seconds.push_back(t);
      }
      // One sweep per call, each call on the previous result.
      progress(opt, std::string("one sweep per call: ") + sodt::toString(alg));
      MeshD m;
      copyMesh(input, m);
      double total = 0;
      for (int k = 1; k <= opt.iterations; ++k) {
        const Clock::time_point t0 = Clock::now();
        sodt::SodtSmoother<MeshD>::Apply(m, paramsFor(alg, 1));
        total += since(t0);
        const sodt::AngleStats a = sodt::computeAngleStats(m);
        steps.minDeg.push_back(a.minDeg);
        steps.maxDeg.push_back(a.maxDeg);
        steps.seconds.push_back(total);
      }
    }
  }
  return rep;
}

}  // namespace sodtcmp
