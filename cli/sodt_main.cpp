// SPDX-License-Identifier: GPL-3.0-or-later
// Command-line front end: `sodt smooth` runs the S-ODT smoother on a PLY/OFF
// file, `sodt classify` writes the smooth/crease/corner classification of its
// vertices, `sodt stats` measures a mesh; summaries on stdout, JSON reports,
// exit codes.
#include <sodt/classify.h>
#include <sodt/io.h>
#include <sodt/json.h>
#include <sodt/mesh.h>
#include <sodt/metrics.h>
#include <sodt/output.h>
#include <sodt/params.h>
#include <sodt/prebuilt.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <limits>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#ifndef SODT_VERSION
#define SODT_VERSION "unknown"
#endif

namespace {

using sodt::MeshD;

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

/// A bad command line: exit status 2 and a pointer to the help.
class UsageError : public std::runtime_error {
 public:
  UsageError(const std::string& msg, const std::string& helpCmd)
      : std::runtime_error(msg), helpCommand(helpCmd) {}
  std::string helpCommand;  ///< e.g. "sodt smooth --help"
};

// ---------------------------------------------------------------------------
// Interruption and progress on stderr

// Temporary output files, removed by the signal handler: an interrupted run
// leaves OUT and the report as they were. Fixed storage, no allocation in
// the handler.
constexpr int kMaxTemps = 4;
constexpr std::size_t kTempPathMax = 4096;
char gTempPath[kMaxTemps][kTempPathMax];
volatile std::sig_atomic_t gTempActive[kMaxTemps];

/// Lets the signal handler remove f's temporary file (until the process ends).
void trackTemporary(const sodt::PendingFile& f) {
  if (f.direct()) return;  // a device or FIFO written in place: never removed
  const std::string& p = f.tempPath();
  if (p.size() >= kTempPathMax) return;
  for (int i = 0; i < kMaxTemps; ++i)
    if (!gTempActive[i]) {
      std::memcpy(gTempPath[i], p.c_str(), p.size() + 1);
      std::atomic_signal_fence(std::memory_order_seq_cst);  // path complete before the flag
      gTempActive[i] = 1;
      return;
    }
}

/// SIGINT/SIGTERM/SIGHUP: remove the temporary files, then die of the signal.
extern "C" void onSignal(int sig) {
  for (int i = 0; i < kMaxTemps; ++i)
    if (gTempActive[i]) ::unlink(gTempPath[i]);
  static const char msg[] = "\nsodt: interrupted\n";
  const ssize_t n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
  (void)n;
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

/// One status line on stderr, redrawn with '\r'; only used on a terminal.
struct StatusLine {
  bool enabled = false;
  bool open = false;
  std::size_t width = 0;
  std::string last;

  void draw(const std::string& text) {
    if (!enabled || (open && text == last)) return;
    std::string s = "\r" + text;
    if (text.size() < width) s.append(width - text.size(), ' ');
    std::fputs(s.c_str(), stderr);
    std::fflush(stderr);
    width = std::max(width, text.size());
    last = text;
    open = true;
  }
  /// Keeps the line (newline) or wipes it.
  void end(bool keep) {
    if (!open) return;
    if (keep)
      std::fputc('\n', stderr);
    else
      std::fprintf(stderr, "\r%*s\r", static_cast<int>(width), "");
    std::fflush(stderr);
    open = false;
    width = 0;
    last.clear();
  }
};

StatusLine gStatus;

/// vcg::CallBackPos for the smoother: draws "[#####     ] 45% S-ODT sweep 9/20".
bool progressCallback(const int pos, const char* msg) {
  if (gStatus.enabled) {
    const int pct = std::min(100, std::max(0, pos));
    const int barWidth = 20;
    const int filled = pct * barWidth / 100;
    char head[64];
    std::snprintf(head, sizeof head, "] %3d%% ", pct);
    gStatus.draw("[" + std::string(filled, '#') + std::string(barWidth - filled, ' ') + head + (msg ? msg : ""));
  }
  return true;
}

// ---------------------------------------------------------------------------
// Command-line parsing

/// One option of a subcommand.
struct OptionSpec {
  const char* name;  ///< "--iterations"
  bool takesValue;
};

/// Options and positionals of one subcommand invocation.
struct ParsedArgs {
  bool help = false;
  std::vector<std::string> positionals;
  std::vector<std::pair<std::string, std::string>> options;  ///< name, value ("" for flags)
};

/// Splits args into known options (--name VALUE or --name=VALUE) and
/// positionals; "--" ends the options. Stops at -h/--help.
ParsedArgs parseArgs(const std::vector<std::string>& args, const std::vector<OptionSpec>& specs,
                     const std::string& helpCmd) {
  ParsedArgs r;
  bool optionsEnded = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (optionsEnded || a.size() < 2 || a[0] != '-') {
      r.positionals.push_back(a);
      continue;
    }
    if (a == "--") {
      optionsEnded = true;
      continue;
    }
    if (a == "-h" || a == "--help") {
      r.help = true;
      return r;
    }
    std::string name = a, value;
    bool inlineValue = false;
    const std::size_t eq = a.find('=');
    if (a.compare(0, 2, "--") == 0 && eq != std::string::npos) {
      name = a.substr(0, eq);
      value = a.substr(eq + 1);
      inlineValue = true;
    }
    const OptionSpec* spec = nullptr;
    for (const OptionSpec& s : specs)
      if (name == s.name) spec = &s;
    if (spec == nullptr) throw UsageError("unknown option '" + name + "'", helpCmd);
    if (spec->takesValue) {
      if (!inlineValue) {
        if (i + 1 >= args.size()) throw UsageError("option '" + name + "' needs a value", helpCmd);
        value = args[++i];
      }
    } else if (inlineValue) {
      throw UsageError("option '" + name + "' takes no value", helpCmd);
    }
    r.options.emplace_back(name, value);
  }
  return r;
}

/// Parses a whole decimal int; range checks are left to SodtParams::validate().
int parseIntValue(const std::string& option, const std::string& s, const std::string& helpCmd) {
  std::size_t i = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
  bool digits = i < s.size();
  for (std::size_t k = i; k < s.size(); ++k) digits = digits && s[k] >= '0' && s[k] <= '9';
  if (!digits) throw UsageError("option '" + option + "' needs an integer, got '" + s + "'", helpCmd);
  errno = 0;
  const long long v = std::strtoll(s.c_str(), nullptr, 10);
  if (errno == ERANGE || v < INT_MIN || v > INT_MAX)
    throw UsageError("option '" + option + "': " + s + " is out of range", helpCmd);
  return static_cast<int>(v);
}

/// Parses a whole non-negative decimal number ("2", "0.5", "1e-3"): no sign,
/// no spaces, no hexadecimal, nan or inf. Range checks are left to the caller.
double parseNonNegativeValue(const std::string& option, const std::string& s, const std::string& helpCmd) {
  if (s.empty()) throw UsageError("option '" + option + "' needs a number, got ''", helpCmd);
  if (s[0] == '-') throw UsageError("option '" + option + "' must not be negative, got '" + s + "'", helpCmd);
  bool ok = (s[0] >= '0' && s[0] <= '9') || s[0] == '.';
  for (char c : s) ok = ok && ((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-');
  errno = 0;
  char* end = nullptr;
  const double v = ok ? std::strtod(s.c_str(), &end) : 0.0;
  if (!ok || end != s.c_str() + s.size())
    throw UsageError("option '" + option + "' needs a number, got '" + s + "'", helpCmd);
  if (errno == ERANGE || !std::isfinite(v))
    throw UsageError("option '" + option + "': " + s + " is out of range", helpCmd);
  return v;
}

/// Shortest decimal text of a parameter value for messages and summaries ("2", "0.05").
std::string numberText(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

/// Smallest angle (degrees) between the normals of two equally weighted
/// planes at which a vertex between them is a crease: Eq. 10 with
/// nu = (1 + cos t, 1 - cos t, 0) gives crease when cos t < eps / (eps + 2).
double creaseAngleDeg(double epsilon) { return std::acos(epsilon / (epsilon + 2.0)) * 180.0 / M_PI; }

/// Path with symbolic links and "." / ".." resolved as far as it exists.
std::string canonicalPath(const std::string& p) {
  if (char* r = ::realpath(p.c_str(), nullptr)) {
    std::string s(r);
    std::free(r);
    return s;
  }
  const std::size_t slash = p.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : p.substr(0, slash));
  const std::string base = slash == std::string::npos ? p : p.substr(slash + 1);
  if (char* r = ::realpath(dir.c_str(), nullptr)) {
    std::string s(r);
    std::free(r);
    return s + "/" + base;
  }
  return p;
}

bool samePath(const std::string& a, const std::string& b) { return canonicalPath(a) == canonicalPath(b); }

std::string baseName(const std::string& p) {
  const std::size_t slash = p.find_last_of('/');
  return slash == std::string::npos ? p : p.substr(slash + 1);
}

// ---------------------------------------------------------------------------
// Help

void printMainHelp() {
  std::printf(
      "usage: sodt <command> [options]\n"
      "       sodt --help | --version\n"
      "\n"
      "S-ODT surface mesh smoothing: moves every interior vertex in its tangent plane to\n"
      "the closed-form minimiser of the suboptimal Delaunay triangulation energy, which\n"
      "improves triangle angles while keeping the surface (paper Algorithm 1); variants\n"
      "keep creases and corners (Algorithm 2) or also remove noise (Algorithm 3).\n"
      "\n"
      "commands:\n"
      "  smooth IN OUT       smooth the triangle mesh IN and write it to OUT\n"
      "  classify IN OUT.ply mark every vertex of IN smooth, crease or corner (nothing moves)\n"
      "  stats IN            print quality measures of IN as JSON\n"
      "\n"
      "Mesh files are PLY, OFF, OBJ or STL (binary or ASCII), chosen by extension\n"
      "(case-insensitive). Polygons are fan-triangulated on input; the corners of STL\n"
      "triangles with equal coordinates are welded into one vertex. STL is written in\n"
      "binary single precision, without the vertices no face uses.\n"
      "Run 'sodt <command> --help' for the options of a command.\n"
      "\n"
      "exit status: 0 success, 1 unreadable or invalid input or I/O failure,\n"
      "             2 bad command line. Output files are replaced only at the very\n"
      "             end of a successful run, never partially written.\n");
}

/// The option texts shared by `smooth` and `classify`.
void printClassOptionsHelp(const sodt::SodtParams& d) {
  std::printf(
      "  --epsilon X           crease sensitivity of the vertex classification, > 0\n"
      "                        (default %s): a vertex between two planes whose normals\n"
      "                        differ by more than acos(X/(X+2)) is a crease (%.0f deg at\n"
      "                        the default); larger finds more creases\n"
      "  --eta X               corner sensitivity, > 0 (default %s): larger makes more\n"
      "                        of the vertices where creases meet corners\n",
      numberText(d.epsilon).c_str(), creaseAngleDeg(d.epsilon), numberText(d.eta).c_str());
}

void printSmoothHelp() {
  const sodt::SodtParams d;
  std::printf(
      "usage: sodt smooth IN OUT [options]\n"
      "\n"
      "Smooths the triangle mesh IN with S-ODT and writes the result to OUT (PLY or\n"
      "OFF by OUT's extension; PLY is written binary). Border and non-manifold\n"
      "vertices stay fixed. OUT keeps the per-vertex quality, colour and selection\n"
      "flags found in IN (PLY; OFF keeps colour only). OUT and the other output\n"
      "files are written under temporary names and renamed at the very end, so a\n"
      "failed or interrupted run leaves them as they were; OUT may be IN itself.\n"
      "\n"
      "options (defaults are those of the library, sodt::SodtParams):\n"
      "  --algorithm NAME      vertex update (default %s):\n"
      "                          basic    paper Algorithm 1: every interior vertex moves\n"
      "                                   in its tangent plane; no feature handling\n"
      "                          feature  Algorithm 2: vertices are classified once on\n"
      "                                   the input; corners stay fixed, crease vertices\n"
      "                                   slide along their crease, smooth ones as basic\n"
      "                          denoise  Algorithm 3: removes noise while keeping\n"
      "                                   creases and corners: smooth vertices move on\n"
      "                                   fitted planes, crease vertices on fitted lines\n"
      "                          odt      reference: the 'optimal' ODT of Eq. 3 with true\n"
      "                                   areas, minimised numerically (slower)\n"
      "                          laplacian  reference: the one-ring centroid (Eq. 3 with\n"
      "                                   S'_k = 1); leaves the tangent plane, shrinks\n"
      "  --iterations N        Gauss-Seidel sweeps, 0..100000 (default %d)\n"
      "  --guard G             safeguard on every move (default %s):\n"
      "                          none     commit every solved move (the paper as written)\n"
      "                          fold     reject moves that flip or collapse a triangle\n"
      "                          quality  fold, and the smallest angle around the vertex\n"
      "                                   may not decrease\n"
      "  --max-backtracks N    halvings of a rejected step before the vertex is kept,\n"
      "                        0..60 (default %d)\n"
      "  --laplacian-fallback on|off\n"
      "                        when the guard vetoes the S-ODT step, try the tangential\n"
      "                        Laplacian step under the same guard (default %s;\n"
      "                        not used with --guard none)\n",
      sodt::toString(d.algorithm), d.iterations, sodt::toString(d.guard), d.maxBacktracks,
      d.laplacianFallback ? "on" : "off");
  printClassOptionsHelp(d);
  std::printf(
      "                        (basic does not classify and ignores both)\n"
      "  --max-deviation PERCENT\n"
      "                        basic and feature: a move is rejected when the vertex or\n"
      "                        its faces would leave the input surface around it by more\n"
      "                        than PERCENT %% of the bounding-box diagonal, 0..100\n"
      "                        (default %s; 0 disables; not used with --guard none)\n"
      "  --max-normal-step X   denoise only: largest move of a vertex along its fitted\n"
      "                        normal per sweep, as a fraction of the mean edge length,\n"
      "                        0..10 (default %s)\n"
      "  --flips               flip edges between sweeps (default %s, as in the paper).\n"
      "                        This changes the connectivity (vertex and face counts stay\n"
      "                        the same). An interior edge is flipped only between two\n"
      "                        nearly coplanar triangles (see --flip-max-dihedral) and\n"
      "                        only when the smaller angle of the pair grows; never a\n"
      "                        crease edge of feature or denoise (both ends crease or\n"
      "                        corner vertices), never onto an existing edge (which would\n"
      "                        make it non-manifold), never into a fold. When the\n"
      "                        returned mesh has other faces than IN, the report's\n"
      "                        inverted_faces is null (it compares face by face)\n"
      "  --flip-max-dihedral DEG\n"
      "                        with --flips: flip only edges whose two faces' normals\n"
      "                        differ by less than DEG degrees, 0..90 (default %s)\n"
      "  --keep-best           return the best state seen instead of the last one: the\n"
      "                        fewest faces turned against their input orientation,\n"
      "                        then the largest smallest angle, then the largest 1st\n"
      "                        percentile of the per-triangle smallest angle. IN is a\n"
      "                        candidate, so the result is never worse than IN by this\n"
      "                        order (default %s)\n"
      "  --tolerance DEG       stop early once a sweep raises neither the smallest angle\n"
      "                        nor the 1st percentile of the per-triangle smallest angle\n"
      "                        by more than DEG degrees, 0..180 (default %s: run every\n"
      "                        sweep)\n"
      "  --threads N           worker threads for the sweeps, 0..1024 (default %d: all\n"
      "                        cores; a build without OpenMP always uses 1). The result\n"
      "                        does not depend on N: vertices are swept colour by colour\n"
      "                        (never two neighbours at once), so OUT and the report are\n"
      "                        bit-identical for every N, apart from the report's seconds\n"
      "                        and threads\n"
      "  --selected-only       move only selected vertices. The selection is read from\n"
      "                        the PLY per-vertex 'flags' property (MeshLab: export with\n"
      "                        'Flags' ticked); plain PLY and OFF files select nothing,\n"
      "                        which is an error\n"
      "  --report FILE.json    write measures before/after, distances, counters and the\n"
      "                        class counts as JSON\n"
      "  --distance on|off     measure the sampled surface distance between IN and OUT\n"
      "                        for the summary and the report (default on). It is the\n"
      "                        slowest measure: on a large mesh it takes about as long\n"
      "                        as the smoothing. off leaves it out (the report's\n"
      "                        distances are null); OUT is the same either way\n"
      "  --classes-out FILE.ply\n"
      "                        also write the smoothed mesh with the class of every vertex\n"
      "                        as per-vertex quality (0 smooth, 1 crease, 2 corner,\n"
      "                        3 fixed: border or non-manifold) and colour (grey, blue,\n"
      "                        red, yellow); PLY only. With basic every interior vertex\n"
      "                        is smooth\n"
      "  --quiet               no summary on stdout and no progress bar\n"
      "  -h, --help            show this help\n"
      "\n"
      "The progress bar is drawn on stderr only when stderr is a terminal.\n",
      numberText(100.0 * d.maxDeviationRel).c_str(), numberText(d.maxNormalStepRel).c_str(),
      d.flips ? "on" : "off", numberText(d.flipMaxDihedralDeg).c_str(), d.keepBest ? "on" : "off",
      numberText(d.toleranceDeg).c_str(), d.threads);
}

void printClassifyHelp() {
  const sodt::SodtParams d;
  std::printf(
      "usage: sodt classify IN OUT.ply [--epsilon X] [--eta X] [--json FILE]\n"
      "\n"
      "Classifies every vertex of IN by the normal tensor of its one-ring (paper\n"
      "Eq. 9-10), as 'sodt smooth --algorithm feature' does before smoothing, and\n"
      "writes IN unmoved to OUT (PLY only) with the class as per-vertex quality\n"
      "(0 smooth, 1 crease, 2 corner, 3 fixed: border or non-manifold) and colour\n"
      "(grey, blue, red, yellow). Prints the number of vertices in each class.\n"
      "(--algorithm denoise classifies the input after removing its noise; see\n"
      "'sodt smooth --classes-out'.)\n"
      "\n"
      "options:\n");
  printClassOptionsHelp(d);
  std::printf(
      "  --json FILE           also write the counts and parameters as JSON to FILE\n"
      "  -h, --help            show this help\n");
}

void printStatsHelp() {
  std::printf(
      "usage: sodt stats IN [--reference REF] [--json FILE]\n"
      "\n"
      "Prints as JSON: vertices, faces, closed, min_angle, max_angle, angle_histogram\n"
      "(180 one-degree bins of all corner angles), frac_below_30, frac_above_90,\n"
      "p1_tri_min_angle (1st percentile of the per-triangle smallest angle) and volume\n"
      "(null when the mesh is not closed and consistently oriented).\n"
      "\n"
      "options:\n"
      "  --reference REF   also hausdorff_rel and mean_distance_rel (sampled surface\n"
      "                    distances relative to REF's bounding-box diagonal) and\n"
      "                    inverted_faces (faces turned by more than 90 degrees against\n"
      "                    REF; null unless REF has the same vertices and faces)\n"
      "  --json FILE       write the JSON to FILE instead of stdout\n"
      "  -h, --help        show this help\n");
}

// ---------------------------------------------------------------------------
// Measuring

/// Quality measures of one mesh state.
struct Measures {
  sodt::AngleStats angles;
  sodt::VolumeResult volume;
};

/// On threads threads (the measures do not depend on their number).
Measures measure(const MeshD& m, int threads) {
  Measures r;
  r.angles = sodt::computeAngleStats(m, threads);
  r.volume = sodt::enclosedVolume(m, threads);
  return r;
}

/// The threads of a run asked for requested threads (0: all cores).
int workerThreads(int requested) {
  return requested > 0 ? requested : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// Writes the members of one measures object (inside an open object).
void writeMeasures(sodt::JsonWriter& j, const Measures& s) {
  j.member("closed", s.volume.closed);
  j.member("min_angle", s.angles.minDeg);
  j.member("max_angle", s.angles.maxDeg);
  j.member("angle_histogram", s.angles.histogram);
  j.member("frac_below_30", s.angles.fracBelow30);
  j.member("frac_above_90", s.angles.fracAbove90);
  j.member("p1_tri_min_angle", s.angles.p1TriMinDeg);
  if (s.volume.closed)
    j.member("volume", s.volume.volume);
  else
    j.memberNull("volume");
}

/// Loads a mesh for a subcommand, with the status line, and rejects meshes
/// without triangles.
void loadInput(const std::string& path, MeshD& m, sodt::LoadInfo* info) {
  gStatus.draw("loading " + baseName(path) + "...");
  sodt::loadMesh(path, m, info);
  gStatus.end(false);
  if (m.fn == 0) throw sodt::InvalidInput("'" + path + "': no triangles");
}

/// Surface distance of a mesh to a reference, relative to the reference's
/// bounding-box diagonal.
struct Distance {
  bool measured = true;    ///< false: not asked for (smooth --distance off), the rest unset
  double hausdorff = 0;    ///< symmetric Hausdorff (or its lower bound)
  double mean = 0;         ///< mean two-sided distance (NaN with a lower bound)
  bool lowerBound = false; ///< the mesh left the reference's neighbourhood: vertices only
};

/// Samples both surfaces (sodt::surfaceDistanceInPlace: no copy of a large
/// mesh; it updates their bounding boxes and face normals, which
/// no file written afterwards contains) unless a vertex of m lies more than
/// one diagonal outside ref's bounding box, as after a diverged unguarded
/// run: then sampling says nothing more and can take very long, and the
/// vertex distance to the box is reported as a lower bound. The lookups run
/// on threads threads (the result does not depend on their number).
template <class RefMesh>
Distance distanceTo(MeshD& m, RefMesh& ref, int threads) {
  // The surfaces only: unreferenced vertices are neither measured nor the
  // measure's scale.
  const vcg::Box3d box = sodt::surfaceBox(ref);
  const double diag = box.Diag();
  std::vector<char> onSurface(m.vert.size(), 0);
  for (const auto& f : m.face)
    if (!f.IsD())
      for (int j = 0; j < 3; ++j) onSurface[static_cast<std::size_t>(f.cV(j) - &m.vert[0])] = 1;
  double far = 0;
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    const auto& v = m.vert[i];
    if (v.IsD() || !onSurface[i]) continue;
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double e = std::max({box.min[k] - v.cP()[k], 0.0, v.cP()[k] - box.max[k]});
      d2 += e * e;
    }
    far = std::max(far, std::sqrt(d2));
  }
  Distance r;
  if (diag > 0 && far > diag) {
    r.hausdorff = far / diag;
    r.mean = std::numeric_limits<double>::quiet_NaN();
    r.lowerBound = true;
    return r;
  }
  const sodt::DistanceStats d = sodt::surfaceDistanceInPlace(m, ref, threads);
  r.hausdorff = d.maxRel;
  r.mean = d.meanRel;
  return r;
}

/// What the measures of the output need from the input (distance and
/// inverted faces), kept through the smoothing in a fraction of the memory
/// of a copy of the mesh: 24 bytes per vertex, plus 12 per face when the
/// smoother may change the faces. The reference mesh is rebuilt from it only
/// after the smoothing, when the smoother's working memory is freed.
struct InputGeometry {
  std::vector<vcg::Point3d> positions;   ///< every vertex of the input, in order
  std::vector<std::array<int, 3>> faces;  ///< the input's faces when facesKept
  bool facesKept = false;                 ///< else the output has the input's faces
};

/// Keeps m's positions, and its faces when `facesMayChange` (edge flips).
/// m must be compact, as loadMesh leaves it.
InputGeometry keepInput(const MeshD& m, bool facesMayChange) {
  InputGeometry g;
  g.positions.reserve(m.vert.size());
  for (const auto& v : m.vert) g.positions.push_back(v.cP());
  g.facesKept = facesMayChange;
  if (facesMayChange) {
    g.faces.reserve(m.face.size());
    for (const auto& f : m.face)
      g.faces.push_back({{int(f.cV(0) - &m.vert[0]), int(f.cV(1) - &m.vert[0]), int(f.cV(2) - &m.vert[0])}});
  }
  return g;
}

/// The input mesh for the measures, as its copy would be: its vertices in
/// order, with the faces of `input` or else those of m (which the smoother
/// left unchanged). Frees input's arrays as it goes.
void rebuildInput(InputGeometry& input, const MeshD& m, sodt::SampleMesh& ref) {
  ref.Clear();
  vcg::tri::Allocator<sodt::SampleMesh>::AddVertices(ref, input.positions.size());
  for (std::size_t i = 0; i < input.positions.size(); ++i) ref.vert[i].P() = input.positions[i];
  std::vector<vcg::Point3d>().swap(input.positions);
  const std::size_t nf = input.facesKept ? input.faces.size() : m.face.size();
  vcg::tri::Allocator<sodt::SampleMesh>::AddFaces(ref, nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j)
      ref.face[f].V(j) =
          &ref.vert[input.facesKept ? std::size_t(input.faces[f][j]) : std::size_t(m.face[f].cV(j) - &m.vert[0])];
  std::vector<std::array<int, 3>>().swap(input.faces);
}

/// Writes hausdorff_rel, mean_distance_rel (null when unknown) and
/// hausdorff_is_lower_bound, all three null when the distance was not measured.
void writeDistance(sodt::JsonWriter& j, const Distance& d) {
  if (!d.measured) {
    j.memberNull("hausdorff_rel").memberNull("mean_distance_rel").memberNull("hausdorff_is_lower_bound");
    return;
  }
  j.member("hausdorff_rel", d.hausdorff);
  j.member("mean_distance_rel", d.mean);
  j.member("hausdorff_is_lower_bound", d.lowerBound);
}

/// Parses --epsilon / --eta: a number in (0, 1e6) (SodtParams::validate()).
double parseSensitivity(const std::string& option, const std::string& v, const std::string& helpCmd) {
  const double x = parseNonNegativeValue(option, v, helpCmd);
  if (!(x > 0) || !(x < 1e6))
    throw UsageError("option '" + option + "' must be a positive number below 1e6, got " + v, helpCmd);
  return x;
}

/// Rejects a file name whose extension is not .ply (per-vertex quality is PLY only).
void checkPlyPath(const std::string& option, const std::string& path, const std::string& helpCmd) {
  bool ply = false;
  try {
    ply = sodt::meshFormatFromPath(path) == sodt::MeshFormat::Ply;
  } catch (const sodt::InvalidInput&) {
  }
  if (!ply)
    throw UsageError(option + " must be a .ply file (only PLY stores per-vertex quality), got '" + path + "'",
                     helpCmd);
}

/// Writes m with the classes as per-vertex quality and colour (output.h).
/// Overwrites m's quality and colour.
void saveClassMesh(sodt::PendingFile& f, MeshD& m, const sodt::Classification& c) {
  sodt::writeClassToQuality(m, c);
  sodt::colorizeByClass(m, c);
  sodt::SaveOptions so;
  so.vertexQuality = true;
  so.vertexColor = true;
  sodt::saveMesh(f, m, so);
}

/// Writes "classes": {"smooth": n, "crease": n, "corner": n, "fixed": n}.
void writeClassCounts(sodt::JsonWriter& j, const sodt::Classification& c) {
  j.key("classes").beginObject();
  for (int k = 0; k < 4; ++k) j.member(sodt::toString(static_cast<sodt::VertexClass>(k)), c.count[k]);
  j.endObject();
}

/// "smooth 1200, crease 80, corner 8, fixed 0".
std::string classCountsText(const sodt::Classification& c) {
  std::string s;
  for (int k = 0; k < 4; ++k)
    s += std::string(k ? ", " : "") + sodt::toString(static_cast<sodt::VertexClass>(k)) + " " +
         std::to_string(c.count[k]);
  return s;
}

// ---------------------------------------------------------------------------
// sodt smooth

struct SmoothOptions {
  std::string in, out, report, classesOut;
  sodt::SodtParams params;
  bool quiet = false;
  bool distance = true;  ///< measure the surface distance between IN and OUT
};

const char* const kSmoothHelp = "sodt smooth --help";

/// Returns false when the help was printed.
bool parseSmooth(const std::vector<std::string>& args, SmoothOptions& o) {
  static const std::vector<OptionSpec> specs = {
      {"--algorithm", true}, {"--iterations", true}, {"--guard", true},  {"--max-backtracks", true},
      {"--laplacian-fallback", true}, {"--selected-only", false}, {"--report", true}, {"--quiet", false},
      {"--epsilon", true}, {"--eta", true}, {"--max-deviation", true}, {"--max-normal-step", true},
      {"--classes-out", true}, {"--flips", false}, {"--flip-max-dihedral", true}, {"--keep-best", false},
      {"--tolerance", true}, {"--threads", true}, {"--distance", true}};
  const ParsedArgs a = parseArgs(args, specs, kSmoothHelp);
  if (a.help) {
    printSmoothHelp();
    return false;
  }
  for (const auto& kv : a.options) {
    const std::string& name = kv.first;
    const std::string& v = kv.second;
    try {
      if (name == "--algorithm") {
        o.params.algorithm = sodt::algorithmFromString(v);
      } else if (name == "--iterations") {
        o.params.iterations = parseIntValue(name, v, kSmoothHelp);
      } else if (name == "--guard") {
        o.params.guard = sodt::guardFromString(v);
      } else if (name == "--max-backtracks") {
        o.params.maxBacktracks = parseIntValue(name, v, kSmoothHelp);
      } else if (name == "--threads") {
        o.params.threads = parseIntValue(name, v, kSmoothHelp);
      } else if (name == "--laplacian-fallback") {
        if (v != "on" && v != "off")
          throw UsageError("option '--laplacian-fallback' takes on or off, got '" + v + "'", kSmoothHelp);
        o.params.laplacianFallback = v == "on";
      } else if (name == "--distance") {
        if (v != "on" && v != "off")
          throw UsageError("option '--distance' takes on or off, got '" + v + "'", kSmoothHelp);
        o.distance = v == "on";
      } else if (name == "--selected-only") {
        o.params.selectedOnly = true;
      } else if (name == "--report") {
        if (v.empty()) throw UsageError("option '--report' needs a file name", kSmoothHelp);
        o.report = v;
      } else if (name == "--quiet") {
        o.quiet = true;
      } else if (name == "--epsilon" || name == "--eta") {
        (name == "--epsilon" ? o.params.epsilon : o.params.eta) = parseSensitivity(name, v, kSmoothHelp);
      } else if (name == "--max-deviation") {
        const double pct = parseNonNegativeValue(name, v, kSmoothHelp);
        if (pct > 100) throw UsageError("option '--max-deviation' must be in [0, 100] percent, got " + v, kSmoothHelp);
        o.params.maxDeviationRel = pct / 100.0;
      } else if (name == "--max-normal-step") {
        const double x = parseNonNegativeValue(name, v, kSmoothHelp);
        if (x > 10) throw UsageError("option '--max-normal-step' must be in [0, 10], got " + v, kSmoothHelp);
        o.params.maxNormalStepRel = x;
      } else if (name == "--flips") {
        o.params.flips = true;
      } else if (name == "--flip-max-dihedral") {
        const double x = parseNonNegativeValue(name, v, kSmoothHelp);
        if (x > 90)
          throw UsageError("option '--flip-max-dihedral' must be in [0, 90] degrees, got " + v, kSmoothHelp);
        o.params.flipMaxDihedralDeg = x;
      } else if (name == "--keep-best") {
        o.params.keepBest = true;
      } else if (name == "--tolerance") {
        const double x = parseNonNegativeValue(name, v, kSmoothHelp);
        if (x > 180) throw UsageError("option '--tolerance' must be in [0, 180] degrees, got " + v, kSmoothHelp);
        o.params.toleranceDeg = x;
      } else if (name == "--classes-out") {
        if (v.empty()) throw UsageError("option '--classes-out' needs a file name", kSmoothHelp);
        o.classesOut = v;
      }
    } catch (const sodt::InvalidInput& e) {
      throw UsageError("option '" + name + "': " + e.what(), kSmoothHelp);
    }
  }
  if (a.positionals.size() != 2)
    throw UsageError("'sodt smooth' needs an input and an output file, got " +
                         std::to_string(a.positionals.size()) + " file argument" +
                         (a.positionals.size() == 1 ? "" : "s"),
                     kSmoothHelp);
  o.in = a.positionals[0];
  o.out = a.positionals[1];
  try {
    o.params.validate();
  } catch (const sodt::InvalidInput& e) {
    throw UsageError(e.what(), kSmoothHelp);
  }
  try {
    sodt::meshFormatFromPath(o.out);
  } catch (const sodt::InvalidInput& e) {
    throw UsageError(std::string("output ") + e.what(), kSmoothHelp);
  }
  if (!o.report.empty()) {
    if (samePath(o.report, o.out)) throw UsageError("--report and OUT are the same file", kSmoothHelp);
    if (samePath(o.report, o.in)) throw UsageError("--report would overwrite the input", kSmoothHelp);
  }
  if (!o.classesOut.empty()) {
    checkPlyPath("--classes-out", o.classesOut, kSmoothHelp);
    if (samePath(o.classesOut, o.out)) throw UsageError("--classes-out and OUT are the same file", kSmoothHelp);
    if (samePath(o.classesOut, o.in)) throw UsageError("--classes-out would overwrite the input", kSmoothHelp);
    if (!o.report.empty() && samePath(o.classesOut, o.report))
      throw UsageError("--classes-out and --report are the same file", kSmoothHelp);
  }
  return true;
}

std::string percent(double frac) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f%%", 100.0 * frac);
  return b;
}

void printSmoothSummary(const SmoothOptions& o, const MeshD& m, const Measures& before, const Measures& after,
                        const Distance& dist, long long inverted, const sodt::SodtStats& st,
                        const sodt::Classification& cls, double seconds) {
  std::printf("sodt smooth: %s -> %s\n", o.in.c_str(), o.out.c_str());
  std::printf("  mesh           %d vertices, %d triangles, %s\n", m.vn, m.fn,
              before.volume.closed ? "closed" : "open or not consistently oriented");
  std::printf("  min angle      %.3f -> %.3f deg\n", before.angles.minDeg, after.angles.minDeg);
  std::printf("  max angle      %.3f -> %.3f deg\n", before.angles.maxDeg, after.angles.maxDeg);
  std::printf("  angles < 30    %s -> %s\n", percent(before.angles.fracBelow30).c_str(),
              percent(after.angles.fracBelow30).c_str());
  std::printf("  angles > 90    %s -> %s\n", percent(before.angles.fracAbove90).c_str(),
              percent(after.angles.fracAbove90).c_str());
  std::printf("  p1 tri min     %.3f -> %.3f deg\n", before.angles.p1TriMinDeg, after.angles.p1TriMinDeg);
  if (before.volume.closed && after.volume.closed) {
    const double rel = before.volume.volume != 0
                           ? (after.volume.volume - before.volume.volume) / std::fabs(before.volume.volume)
                           : 0.0;
    std::printf("  volume         %.10g -> %.10g (relative change %+.3e)\n", before.volume.volume,
                after.volume.volume, rel);
  } else {
    std::printf("  volume         n/a (mesh not closed)\n");
  }
  if (!dist.measured)
    std::printf("  distance       not measured (--distance off)\n");
  else if (dist.lowerBound)
    std::printf("  distance       Hausdorff >= %.3e of the input's bbox diagonal (the output left the input's box)\n",
                dist.hausdorff);
  else
    std::printf("  distance       Hausdorff %.3e, mean %.3e (relative to the input's bbox diagonal)\n",
                dist.hausdorff, dist.mean);
  if (inverted >= 0)
    std::printf("  inverted       %lld faces turned by more than 90 deg\n", inverted);
  else
    std::printf("  inverted       n/a (%s)\n",
                st.flips > 0 ? "connectivity changed by flips" : "the faces differ from the input's");
  std::printf("  vertex visits  moved %lld, backtracked %lld, Laplacian fallback %lld, rejected %lld, failed %lld, "
              "unchanged %lld; %lld repeated their previous visit (nothing in their star had moved)\n",
              st.moved, st.backtracked, st.fallbackMoves, st.rejected, st.failedSolves, st.unchanged, st.skipped);
  std::printf("  fixed          %d boundary, %d non-manifold; %d vertices active\n", st.fixedBoundary,
              st.fixedNonManifold, st.activeVertices);
  if (st.reorientedFaces > 0)
    std::printf("  winding        %d faces turned over so that each part of the mesh has one winding "
                "(written so)\n", st.reorientedFaces);
  std::printf("  classes        %s%s\n", classCountsText(cls).c_str(),
              o.params.algorithm == sodt::Algorithm::Basic ? " (basic does not classify)" : "");
  std::printf("  smoothing      %.3f s for %d sweeps on %d thread%s (algorithm %s, guard %s, max backtracks %d)\n",
              seconds, st.iterations, st.threads, st.threads == 1 ? "" : "s", sodt::toString(o.params.algorithm),
              sodt::toString(o.params.guard), o.params.maxBacktracks);
  const sodt::Algorithm a = o.params.algorithm;
  const char* unused = " (unused)";
  std::printf("  parameters     epsilon %s (creases above %.1f deg), eta %s%s; max deviation %s%% of the bbox "
              "diagonal%s; max normal step %s mean edges%s\n",
              numberText(o.params.epsilon).c_str(), creaseAngleDeg(o.params.epsilon),
              numberText(o.params.eta).c_str(), a == sodt::Algorithm::Basic ? unused : "",
              numberText(100.0 * o.params.maxDeviationRel).c_str(),
              a == sodt::Algorithm::Denoise || o.params.guard == sodt::Guard::None ? unused : "",
              numberText(o.params.maxNormalStepRel).c_str(), a != sodt::Algorithm::Denoise ? unused : "");
  if (o.params.flips)
    std::printf("  flips          %lld edges flipped (max dihedral %s deg)%s\n", st.flips,
                numberText(o.params.flipMaxDihedralDeg).c_str(),
                inverted >= 0 && st.flips > 0 ? "; the returned state has the input's connectivity" : "");
  else
    std::printf("  flips          off\n");
  std::printf("  returned       the state after sweep %d of %d (keep best %s)", st.returnedSweep, st.iterations,
              o.params.keepBest ? "on" : "off");
  if (st.stoppedEarly)
    std::printf("; stopped early: the last sweep raised the min angle and p1 by at most %s deg\n",
                numberText(o.params.toleranceDeg).c_str());
  else if (o.params.toleranceDeg > 0)
    std::printf("; tolerance %s deg not reached\n", numberText(o.params.toleranceDeg).c_str());
  else
    std::printf("\n");
  if (!o.classesOut.empty()) std::printf("  classes out    %s\n", o.classesOut.c_str());
}

std::string smoothReport(const SmoothOptions& o, const MeshD& m, const Measures& before, const Measures& after,
                         const Distance& dist, long long inverted, const sodt::SodtStats& st,
                         const sodt::Classification& cls, double seconds) {
  sodt::JsonWriter j;
  j.beginObject();
  j.member("sodt_version", SODT_VERSION);
  j.member("input", o.in);
  j.member("output", o.out);
  j.member("vertices", m.vn);
  j.member("faces", m.fn);
  j.member("algorithm", sodt::toString(o.params.algorithm));
  j.member("guard", sodt::toString(o.params.guard));
  j.member("iterations", o.params.iterations);
  j.member("max_backtracks", o.params.maxBacktracks);
  j.member("laplacian_fallback", o.params.laplacianFallback);
  j.member("selected_only", o.params.selectedOnly);
  j.member("epsilon", o.params.epsilon);
  j.member("eta", o.params.eta);
  j.member("max_deviation_percent", 100.0 * o.params.maxDeviationRel);
  j.member("max_normal_step", o.params.maxNormalStepRel);
  j.member("flips_enabled", o.params.flips);
  j.member("flip_max_dihedral", o.params.flipMaxDihedralDeg);
  j.member("keep_best", o.params.keepBest);
  j.member("tolerance", o.params.toleranceDeg);
  j.member("distance_measured", dist.measured);
  if (o.classesOut.empty())
    j.memberNull("classes_output");
  else
    j.member("classes_output", o.classesOut);
  j.member("sweeps", st.iterations);
  j.member("returned_sweep", st.returnedSweep);
  j.member("stopped_early", st.stoppedEarly);
  j.member("flips", st.flips);
  j.member("reoriented_faces", st.reorientedFaces);
  j.member("seconds", seconds);
  j.member("threads", st.threads);
  j.member("min_angle_before", before.angles.minDeg);
  j.member("min_angle_after", after.angles.minDeg);
  j.member("max_angle_before", before.angles.maxDeg);
  j.member("max_angle_after", after.angles.maxDeg);
  const bool closed = before.volume.closed && after.volume.closed;
  if (closed) {
    j.member("volume_before", before.volume.volume);
    j.member("volume_after", after.volume.volume);
    if (before.volume.volume != 0)
      j.member("volume_rel_change",
               (after.volume.volume - before.volume.volume) / std::fabs(before.volume.volume));
    else
      j.memberNull("volume_rel_change");
  } else {
    j.memberNull("volume_before").memberNull("volume_after").memberNull("volume_rel_change");
  }
  writeDistance(j, dist);
  if (inverted >= 0)
    j.member("inverted_faces", inverted);
  else
    j.memberNull("inverted_faces");
  j.member("moved", st.moved);
  j.member("backtracked", st.backtracked);
  j.member("fallback_moves", st.fallbackMoves);
  j.member("rejected", st.rejected);
  j.member("failed_solves", st.failedSolves);
  j.member("unchanged", st.unchanged);
  j.member("skipped_visits", st.skipped);
  j.member("deviation_queries", st.deviationQueries);
  j.member("deviation_reused", st.deviationReused);
  j.member("lane_visits", st.laneVisits);
  j.member("active_vertices", st.activeVertices);
  j.member("fixed_boundary", st.fixedBoundary);
  j.member("fixed_nonmanifold", st.fixedNonManifold);
  j.member("cancelled", st.cancelled);
  writeClassCounts(j, cls);
  j.key("before").beginObject();
  writeMeasures(j, before);
  j.endObject();
  j.key("after").beginObject();
  writeMeasures(j, after);
  j.endObject();
  j.endObject();
  return j.str();
}

int runSmooth(const std::vector<std::string>& args) {
  SmoothOptions o;
  if (!parseSmooth(args, o)) return kExitOk;
  gStatus.enabled = gStatus.enabled && !o.quiet;

  // Create the temporary outputs first: an unwritable destination fails
  // before any work, and anything that fails later removes them.
  sodt::PendingFile out(o.out);
  trackTemporary(out);
  std::unique_ptr<sodt::PendingFile> report;
  if (!o.report.empty()) {
    report.reset(new sodt::PendingFile(o.report));
    trackTemporary(*report);
  }
  std::unique_ptr<sodt::PendingFile> classesOut;
  if (!o.classesOut.empty()) {
    classesOut.reset(new sodt::PendingFile(o.classesOut));
    trackTemporary(*classesOut);
  }

  MeshD m;
  sodt::LoadInfo info;
  loadInput(o.in, m, &info);
  if (o.params.selectedOnly && info.selectedVertices == 0)
    throw sodt::InvalidInput("'" + o.in + "': --selected-only, but no vertex of the input is selected "
                             "(a PLY 'flags' property with the selection bit; MeshLab: export with Flags)");

  gStatus.draw("measuring input...");
  const Measures before = measure(m, workerThreads(o.params.threads));
  // Not a copy of the mesh: with the smoother's working memory that would
  // more than double the peak on a large mesh.
  InputGeometry input = keepInput(m, o.params.flips);
  gStatus.end(false);

  progressCallback(0, ("S-ODT sweep 0/" + std::to_string(o.params.iterations)).c_str());
  const auto t0 = std::chrono::steady_clock::now();
  sodt::Classification cls;
  const sodt::SodtStats st = sodt::SodtSmoother<MeshD>::Apply(m, o.params, &progressCallback, &cls);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  gStatus.end(true);
  if (st.cancelled) throw std::runtime_error("smoothing was cancelled");

  gStatus.draw("measuring output...");
  const Measures after = measure(m, st.threads);
  Distance dist;
  long long inverted = -1;
  {
    sodt::SampleMesh ref;  // freed before the save, which reads OUT back
    rebuildInput(input, m, ref);
    if (o.distance)
      dist = distanceTo(m, ref, st.threads);
    else
      dist.measured = false;
    inverted = sodt::countInvertedFaces(m, ref, st.threads);
  }
  gStatus.end(false);

  gStatus.draw("writing " + baseName(o.out) + "...");
  sodt::SaveOptions so;
  so.vertexQuality = info.vertexQuality;
  so.vertexColor = info.vertexColor;
  so.vertexSelection = info.vertexSelection;
  sodt::saveMesh(out, m, so);
  if (report) sodt::writeText(*report, smoothReport(o, m, before, after, dist, inverted, st, cls, seconds));
  if (classesOut) {
    gStatus.draw("writing " + baseName(o.classesOut) + "...");
    saveClassMesh(*classesOut, m, cls);  // after OUT: replaces m's quality and colour
  }
  gStatus.end(false);
  out.commit();
  if (classesOut) classesOut->commit();
  if (report) report->commit();

  if (!o.quiet) printSmoothSummary(o, m, before, after, dist, inverted, st, cls, seconds);
  if (!o.quiet && info.weldedCorners > 0)
    std::printf("  STL input      %lld corners with equal coordinates welded into %d vertices\n",
                info.weldedCorners + m.vn, m.vn);
  if (!o.quiet && st.fixedNonManifold > 0)
    std::fprintf(stderr,
                 "sodt: warning: %d vertices stayed fixed: their faces are non-manifold (an edge with three or "
                 "more faces, a pinch) or cannot be given one winding (a Moebius band)\n",
                 st.fixedNonManifold);
  return kExitOk;
}

// ---------------------------------------------------------------------------
// sodt stats

const char* const kStatsHelp = "sodt stats --help";

int runStats(const std::vector<std::string>& args) {
  static const std::vector<OptionSpec> specs = {{"--reference", true}, {"--json", true}};
  const ParsedArgs a = parseArgs(args, specs, kStatsHelp);
  if (a.help) {
    printStatsHelp();
    return kExitOk;
  }
  std::string reference, jsonPath;
  for (const auto& kv : a.options) {
    if (kv.second.empty()) throw UsageError("option '" + kv.first + "' needs a file name", kStatsHelp);
    (kv.first == "--reference" ? reference : jsonPath) = kv.second;
  }
  if (a.positionals.size() != 1)
    throw UsageError("'sodt stats' needs exactly one input file, got " + std::to_string(a.positionals.size()),
                     kStatsHelp);
  const std::string in = a.positionals[0];
  if (!jsonPath.empty() && (samePath(jsonPath, in) || (!reference.empty() && samePath(jsonPath, reference))))
    throw UsageError("--json would overwrite an input file", kStatsHelp);

  std::unique_ptr<sodt::PendingFile> jsonOut;
  if (!jsonPath.empty()) {
    jsonOut.reset(new sodt::PendingFile(jsonPath));
    trackTemporary(*jsonOut);
  }

  MeshD m;
  loadInput(in, m, nullptr);
  MeshD ref;
  if (!reference.empty()) loadInput(reference, ref, nullptr);

  gStatus.draw("measuring...");
  const int threads = workerThreads(0);
  const Measures s = measure(m, threads);
  sodt::JsonWriter j;
  j.beginObject();
  j.member("input", in);
  j.member("vertices", m.vn);
  j.member("faces", m.fn);
  writeMeasures(j, s);
  if (!reference.empty()) {
    const Distance d = distanceTo(m, ref, threads);
    const long long inv = (m.vn == ref.vn && m.fn == ref.fn) ? sodt::countInvertedFaces(m, ref, threads) : -1;
    j.member("reference", reference);
    writeDistance(j, d);
    if (inv >= 0)
      j.member("inverted_faces", inv);
    else
      j.memberNull("inverted_faces");
  }
  j.endObject();
  gStatus.end(false);

  if (jsonOut) {
    sodt::writeText(*jsonOut, j.str());
    jsonOut->commit();
  } else {
    const std::string text = j.str();
    if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0)
      throw sodt::IoError(std::string("cannot write to standard output: ") + std::strerror(errno));
  }
  return kExitOk;
}

// ---------------------------------------------------------------------------
// sodt classify

const char* const kClassifyHelp = "sodt classify --help";

int runClassify(const std::vector<std::string>& args) {
  static const std::vector<OptionSpec> specs = {{"--epsilon", true}, {"--eta", true}, {"--json", true}};
  const ParsedArgs a = parseArgs(args, specs, kClassifyHelp);
  if (a.help) {
    printClassifyHelp();
    return kExitOk;
  }
  sodt::SodtParams p;
  std::string jsonPath;
  for (const auto& kv : a.options) {
    if (kv.first == "--json") {
      if (kv.second.empty()) throw UsageError("option '--json' needs a file name", kClassifyHelp);
      jsonPath = kv.second;
    } else {
      (kv.first == "--epsilon" ? p.epsilon : p.eta) = parseSensitivity(kv.first, kv.second, kClassifyHelp);
    }
  }
  if (a.positionals.size() != 2)
    throw UsageError("'sodt classify' needs an input and an output file, got " +
                         std::to_string(a.positionals.size()) + " file argument" +
                         (a.positionals.size() == 1 ? "" : "s"),
                     kClassifyHelp);
  const std::string in = a.positionals[0], outPath = a.positionals[1];
  checkPlyPath("OUT", outPath, kClassifyHelp);
  if (samePath(outPath, in)) throw UsageError("OUT would overwrite the input", kClassifyHelp);
  if (!jsonPath.empty()) {
    if (samePath(jsonPath, outPath)) throw UsageError("--json and OUT are the same file", kClassifyHelp);
    if (samePath(jsonPath, in)) throw UsageError("--json would overwrite the input", kClassifyHelp);
  }

  sodt::PendingFile out(outPath);
  trackTemporary(out);
  std::unique_ptr<sodt::PendingFile> jsonOut;
  if (!jsonPath.empty()) {
    jsonOut.reset(new sodt::PendingFile(jsonPath));
    trackTemporary(*jsonOut);
  }

  MeshD m;
  loadInput(in, m, nullptr);
  gStatus.draw("classifying...");
  const sodt::Classification cls = sodt::classifyVertices(m, p.epsilon, p.eta);
  gStatus.end(false);

  gStatus.draw("writing " + baseName(outPath) + "...");
  saveClassMesh(out, m, cls);
  if (jsonOut) {
    sodt::JsonWriter j;
    j.beginObject();
    j.member("sodt_version", SODT_VERSION);
    j.member("input", in);
    j.member("output", outPath);
    j.member("vertices", m.vn);
    j.member("faces", m.fn);
    j.member("epsilon", p.epsilon);
    j.member("eta", p.eta);
    j.member("crease_angle_deg", creaseAngleDeg(p.epsilon));
    writeClassCounts(j, cls);
    j.endObject();
    sodt::writeText(*jsonOut, j.str());
  }
  gStatus.end(false);
  out.commit();
  if (jsonOut) jsonOut->commit();

  std::printf("sodt classify: %s -> %s\n", in.c_str(), outPath.c_str());
  std::printf("  mesh           %d vertices, %d triangles\n", m.vn, m.fn);
  std::printf("  parameters     epsilon %s (creases above %.1f deg), eta %s\n", numberText(p.epsilon).c_str(),
              creaseAngleDeg(p.epsilon), numberText(p.eta).c_str());
  std::printf("  classes        %s\n", classCountsText(cls).c_str());
  std::printf("  quality        0 smooth, 1 crease, 2 corner, 3 fixed (border or non-manifold)\n");
  return kExitOk;
}

int run(const std::vector<std::string>& args) {
  if (args.empty()) throw UsageError("no command given", "sodt --help");
  const std::string& cmd = args[0];
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (cmd == "-h" || cmd == "--help" || cmd == "help") {
    printMainHelp();
    return kExitOk;
  }
  if (cmd == "--version") {
    std::printf("sodt %s\n", SODT_VERSION);
    return kExitOk;
  }
  if (cmd == "smooth") return runSmooth(rest);
  if (cmd == "stats") return runStats(rest);
  if (cmd == "classify") return runClassify(rest);
  if (!cmd.empty() && cmd[0] == '-') throw UsageError("unknown option '" + cmd + "'", "sodt --help");
  throw UsageError("unknown command '" + cmd + "' (expected smooth, classify or stats)", "sodt --help");
}

}  // namespace

/// Entry point: every error ends as one "sodt: error: ..." line on stderr and
/// a non-zero exit status (see printMainHelp()).
int main(int argc, char** argv) {
  // A signal the caller ignores stays ignored (nohup, `cmd &` in a
  // non-interactive shell): only the others clean up and end the run.
  for (int sig : {SIGINT, SIGTERM, SIGHUP})
    if (std::signal(sig, onSignal) == SIG_IGN) std::signal(sig, SIG_IGN);
  gStatus.enabled = ::isatty(STDERR_FILENO) == 1;
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    return run(args);
  } catch (const UsageError& e) {
    gStatus.end(false);
    std::fprintf(stderr, "sodt: error: %s (see '%s')\n", e.what(), e.helpCommand.c_str());
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    gStatus.end(false);
    std::fprintf(stderr, "sodt: error: out of memory\n");
    return kExitFailure;
  } catch (const std::exception& e) {
    // sodt::InvalidInput, sodt::IoError and vcglib's exceptions.
    gStatus.end(false);
    std::fprintf(stderr, "sodt: error: %s\n", e.what());
    return kExitFailure;
  } catch (...) {
    gStatus.end(false);
    std::fprintf(stderr, "sodt: error: unexpected failure\n");
    return kExitFailure;
  }
}
