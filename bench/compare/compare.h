// SPDX-License-Identifier: GPL-3.0-or-later
// S-ODT against the numerical ODT of Eq. 3, a Laplacian reference and MeshLab
// 2020.09's built-in smoothers (run by meshlabserver from a private prefix):
// the runs, the measures, the Markdown report and the SVG figures of
// sodt_compare and of the comparison tests. This header has no vcg include, so
// the report code and the tests compile fast; the runs live in compare.cpp.
#pragma once

#include <sodt/params.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace sodtcmp {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Where a method runs.
enum class Kind {
  InProcess,  ///< sodt::SodtSmoother<sodt::MeshD> in this process (time: Apply alone)
  Plugin,     ///< the freshly built S-ODT plugin in meshlabserver (time: the whole server run)
  Builtin,    ///< a filter shipped with MeshLab 2020.09, in meshlabserver (time: the whole server run)
  /// A CGAL 5.5 remesher in sodt_cgal_remesh, a child process (filter: its
  /// mode; time: the remesher alone, as the tool reports it)
  External,
};

/// One row of the comparison.
struct Method {
  std::string id;     ///< short key, used in file names and on the command line
  std::string label;  ///< table text
  Kind kind = Kind::InProcess;
  sodt::Algorithm algorithm = sodt::Algorithm::Basic;  ///< InProcess and Plugin
  std::string filter;  ///< MeshLab filter name (Builtin, Plugin), sodt_cgal_remesh mode (External)
  /// Builtin: moves vertices only, same connectivity (a smoother in the sense
  /// of the tests); false for edge flipping and remeshing.
  bool smoother = true;
  std::string colour;  ///< figure colour
  /// InProcess: run the mesh's headline variant (MeshJob::variant) instead
  /// of `algorithm`; the row's label then names the variant.
  bool headlineVariant = false;
  bool flips = false;   ///< InProcess: SodtParams::flips (edge flips between sweeps)
  bool repair = false;  ///< InProcess: SodtParams::repair (local repair after the sweeps)
};

/// Every method, in table order.
const std::vector<Method>& allMethods();
/// The method with this id, or nullptr.
const Method* findMethod(const std::string& id);

/// One parameter of a MeshLab filter as written into an .mlx script.
struct MlxParam {
  std::string name, type, value;
  std::vector<std::string> enumValues;  ///< RichEnum
  std::string min, max;                 ///< RichAbsPerc
  std::string note;                     ///< why the value differs from MeshLab's default (empty: default)
};

/// Every parameter of a built-in filter, with exact names and types
/// (MeshLab 2020.09, initParameterSet of filter_unsharp, filter_trioptimize
/// and filter_meshing), MeshLab's defaults on a mesh without selection, and
/// the step count set to `iterations` where the filter has one. bboxDiag
/// scales the absolute-or-percent defaults (1% of the diagonal); meanEdge is
/// the target edge length of the second remeshing row.
std::vector<MlxParam> builtinParams(const Method& m, int iterations, double bboxDiag, double meanEdge);
/// The .mlx script of one filter with these parameters.
std::string mlxScript(const std::string& filter, const std::vector<MlxParam>& params);
/// The shipped S-ODT example script (every parameter of the plugin) with its
/// iterations set; throws std::runtime_error when it has no iterations parameter.
std::string pluginScript(const std::string& shippedScript, int iterations);

/// Quality and distance measures of one mesh.
struct Metrics {
  bool ok = false;
  std::string error;  ///< why ok is false
  long long vertices = 0, faces = 0;
  double minDeg = kNaN, maxDeg = kNaN;
  double fracBelow30 = kNaN;  ///< fraction of corner angles below 30 degrees
  double p1TriMinDeg = kNaN;  ///< 1st percentile of the per-triangle smallest angle
  std::vector<long long> histogram;  ///< 180 one-degree bins of corner angles
  double hausInput = kNaN, meanInput = kNaN;  ///< symmetric Hausdorff / mean distance to the input, / input diagonal
  double hausRef = kNaN, meanRef = kNaN;      ///< the same to the reference, / reference diagonal
  bool closed = false;                         ///< closed and consistently oriented
  double volume = kNaN;                        ///< enclosed volume when closed
  double volumeChange = kNaN;                  ///< (volume - input volume) / input volume, both closed
  long long inverted = -2;  ///< faces turned > 90 deg from the input (face by face, or against the input face under them); -2: not measured
  /// In-process runs with flips or repair (-1 otherwise): edges flipped,
  /// vertices the repair added and removed (SodtStats), and the triangles it
  /// left below its target angle.
  long long edgeFlips = -1;
  long long verticesAdded = -1, verticesRemoved = -1;
  long long belowRepairTarget = -1;
  /// Faces that are needles (longest / shortest edge >= 4) and caps (an
  /// angle >= 160 degrees), CGAL's definitions (-1: not measured).
  long long needles = -1, caps = -1;
  double seconds = kNaN;    ///< see Kind
  std::string detail;       ///< one line (run counters, server status)
};

/// Min/max angle after each sweep; index 0 is the input.
struct Curve {
  std::vector<double> minDeg, maxDeg;
  std::vector<double> seconds;  ///< time of the run that produced the state (cumulative)
};

/// One input mesh and what to compare it against.
struct MeshJob {
  std::string path;
  std::string reference;  ///< clean mesh for the reference distance (optional)
  std::string name;       ///< file name without folder and extension
  sodt::Algorithm variant = sodt::Algorithm::Basic;  ///< headline S-ODT variant of this mesh
  std::string paperModel;  ///< the model of the paper's Tables 3-4 this mesh stands for (optional)
};

struct Row {
  Method method;
  Metrics m;
};

/// Time of the unguarded local solvers on one mesh (see MeshReport::unguarded).
struct UnguardedTiming {
  bool ok = false;
  std::string error;  ///< why ok is false (empty: not run)
  int iterations = 0;
  /// Medians of `Apply` with `iterations` sweeps and with 0 sweeps (set-up
  /// alone: ring topology, vertex order, colouring), each from the input.
  double sodtSeconds = kNaN, sodtSetupSeconds = kNaN;
  double odtSeconds = kNaN, odtSetupSeconds = kNaN;
  int sodtRuns = 0, odtRuns = 0;  ///< timed runs behind the medians of the N-sweep calls
  /// Quality of the unguarded N-sweep results (only to show why it is not
  /// reported: unguarded runs may fold faces).
  double sodtMinDeg = kNaN, odtMinDeg = kNaN;
  long long sodtInverted = -2, odtInverted = -2;  ///< faces turned > 90 deg against the input
  /// Milliseconds per sweep, set-up excluded.
  double sodtMsPerSweep() const { return 1e3 * (sodtSeconds - sodtSetupSeconds) / iterations; }
  double odtMsPerSweep() const { return 1e3 * (odtSeconds - odtSetupSeconds) / iterations; }
};

/// Everything measured on one input mesh.
struct MeshReport {
  MeshJob job;
  Metrics input;  ///< the input itself (distances to the reference when given)
  std::vector<Row> rows;
  /// States of the table's run after k = 0..N sweeps: a k-sweep run from the
  /// input for every k (empty when curves are off).
  Curve sodtCurve, odtCurve;
  /// One sweep per call, each call starting from the previous result (its
  /// deviation bound then refers to the previous sweep, not to the input).
  Curve sodtSteps, odtSteps;
  /// The local solvers timed the way the paper compares them (Figure 6):
  /// S-ODT basic and the numerical ODT with Guard::None (no guard, no
  /// Laplacian fallback, no deviation bound), one thread. Empty (ok false)
  /// unless both sodt_basic and odt are among the methods.
  UnguardedTiming unguarded;
  double noopSeconds = kNaN;  ///< meshlabserver loading and saving the mesh with no filter
  std::vector<std::string> notes;
  /// The row of a method, or nullptr.
  const Row* row(const std::string& id) const;
};

/// How meshlabserver is found and run.
struct MeshLabConfig {
  /// A meshlabserver binary (copied into a private prefix with the built
  /// plugin) or a prefix folder P that already has P/bin/meshlabserver and its
  /// plugins (used as it is). Empty: /usr/bin/meshlabserver.
  std::string server;
  std::string plugin;        ///< the built libfilter_sodt.so (empty: no plugin row)
  std::string libDir;        ///< folder of libmeshlab-common.so and plugins/
  std::string pluginScript;  ///< shipped sodt_smoothing.mlx, the template of the plugin's script
  int timeoutSec = 900;      ///< per meshlabserver run
};

/// Compile-time defaults of the build (the plugin's path, MeshLab's folders).
MeshLabConfig defaultMeshLabConfig();

/// A private MeshLab prefix and an Xvfb display, for as long as it lives.
class MeshLabServer {
 public:
  MeshLabServer();
  ~MeshLabServer();
  MeshLabServer(const MeshLabServer&) = delete;
  MeshLabServer& operator=(const MeshLabServer&) = delete;

  /// Assembles the prefix under workDir and starts a virtual X server.
  /// Returns false with a message when meshlabserver or Xvfb is unusable.
  bool start(const MeshLabConfig& cfg, const std::string& workDir, std::string& error);
  /// The configuration given to start().
  const MeshLabConfig& config() const;
  /// True when the S-ODT plugin is in the prefix.
  bool hasPlugin() const;
  /// True when `meshlabserver -d` (run by start()) lists a filter of this exact name.
  bool listsFilter(const std::string& name) const;
  /// Prefix folder, display and what was linked, one line.
  std::string describe() const;

  struct Result {
    int status = -1;  ///< exit status; 124 timeout; 128+n killed by signal n
    double seconds = kNaN;
  };
  /// meshlabserver -i in -o out [-s script], output and errors into logPath.
  Result run(const std::string& in, const std::string& out, const std::string& script,
             const std::string& logPath) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// What to run and where.
struct Options {
  int iterations = 20;
  std::string workDir;                ///< meshes, scripts and logs
  std::vector<std::string> methods;   ///< method ids; empty: all
  bool curves = true;                 ///< the one-sweep-at-a-time runs of S-ODT basic and ODT
  /// Time S-ODT basic and ODT without guard as well (MeshReport::unguarded),
  /// when both are among the methods.
  bool unguardedTimings = true;
  bool quiet = false;                 ///< no progress on stderr
  /// In-process methods faster than 1 s are run again, up to this many runs
  /// in all, and the median time is reported (the first run's mesh is measured).
  int timingRuns = 5;
};

/// Runs every selected method on the job's mesh and measures the results.
/// ml may be null (MeshLab rows are then skipped with a note). Throws
/// std::runtime_error when the input cannot be read.
MeshReport compareMesh(const MeshJob& job, const Options& opt, const MeshLabServer* ml);

/// The local repair (the headline variant with flips and repair) against
/// MeshLab's isotropic remeshing at the input's mean edge length, on one mesh.
/// Vertex changes: the repair's are exact (vertices added + removed, from
/// SodtStats); the remesher's is |V_out - V_in|, a lower bound, since it
/// resamples the whole surface.
struct RepairVerdict {
  const Row* repair = nullptr;     ///< sodt_flips_repair (nullptr: not run or failed)
  const Row* flipsOnly = nullptr;  ///< sodt_flips, the same run without the repair
  const Row* isotropic = nullptr;  ///< ml_isotropic_edge
  const Row* planarFlip = nullptr; ///< ml_planar_flip
  long long repairChanged = -1;    ///< vertices added + removed by the repair
  long long isotropicChanged = -1; ///< |V_out - V_in| of the remesher (a lower bound)
  bool comparable = false;         ///< both the repair and the remesher ran
  bool largerMinAngle = false, noLargerHausdorff = false, fewerVertexChanges = false;
  bool beats() const { return comparable && largerMinAngle && noLargerHausdorff && fewerVertexChanges; }
};
RepairVerdict repairVerdict(const MeshReport& r);

/// The local repair against one peer that changes the connectivity, on one
/// mesh: Beats (a larger minimum angle at a Hausdorff distance to the input
/// no larger), LargerDistance (a larger minimum angle, but farther from the
/// input), PeerMovesFurther (the peer's minimum angle is no smaller, but it
/// moves farther from the input) or Loses (the peer's minimum angle is no
/// smaller at no larger a distance). NotRun when either row is missing.
enum class PeerVerdict { NotRun, Beats, LargerDistance, PeerMovesFurther, Loses };
PeerVerdict peerVerdict(const Row* repair, const Row* peer);

/// The peers of the repair, in table order: MeshLab's isotropic remeshing at
/// the mean edge (without and with its surface-distance check at the
/// deviation bound) and CGAL 5.5's isotropic_remeshing and
/// remove_almost_degenerate_faces.
const std::vector<std::string>& repairPeers();

/// The sodt_cgal_remesh this build made ("" when CGAL was not found).
std::string cgalRemeshTool();

/// The paper's Table 3 (min angle) and Table 4 (time) row of one model.
struct PaperRow {
  const char* model;
  double originalMin, oursMin;
  const char* alg;
  double ohtakeMin;
  int vertices;
  double oursSeconds, ohtakeSeconds, sunSeconds;
};
/// The ten rows of the paper's Tables 3-4, in its order.
const std::vector<PaperRow>& paperTables();
const PaperRow* findPaperRow(const std::string& model);

/// docs/RESULTS.md-style report of all meshes. commandLine is shown as the
/// command that produced it; figDir is the figures' folder relative to the report.
std::string markdownReport(const std::vector<MeshReport>& reports, const Options& opt,
                           const std::string& commandLine, const std::string& meshlabLine,
                           const std::string& figDir);

/// SVG figures (written directly, no plotting dependency).
std::string histogramSvg(const MeshReport& r);    ///< input vs output angle histogram per method
std::string convergenceSvg(const MeshReport& r);  ///< min/max angle per sweep, S-ODT basic and ODT
std::string odtSummarySvg(const std::vector<MeshReport>& reports, int iterations);  ///< time and min angle

/// File names of the figures of one mesh (inside the figures folder).
std::string histogramFile(const MeshReport& r);
std::string convergenceFile(const MeshReport& r);
inline const char* odtSummaryFile() { return "odt_vs_sodt.svg"; }

// Small POSIX helpers (no std::filesystem in gnu++14).
bool makeDirs(const std::string& path);
bool isDirectory(const std::string& path);
bool isFile(const std::string& path);
void writeFile(const std::string& path, const std::string& text);  ///< throws std::runtime_error
std::string readFile(const std::string& path);                      ///< throws std::runtime_error
std::string baseName(const std::string& path);  ///< file name without folder and extension
std::string formatG(double v, int digits);      ///< %.{digits}g, "n/a" for NaN

}  // namespace sodtcmp
