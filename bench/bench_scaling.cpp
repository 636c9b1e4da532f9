// SPDX-License-Identifier: GPL-3.0-or-later
// How the cost of an S-ODT sweep scales with the mesh size (about 10k, 100k,
// 1M and 4M vertices) and the thread count (sodt::SodtParams::threads), for
// Algorithms 1-3, next to vcglib's VertexCoordLaplacian on the same meshes.
// The meshes are made in memory by 1-to-4 midpoint subdivision of the bundled
// meshes. Three helper modes support bench/scaling.sh, which measures the
// peak memory of `sodt smooth` against that of the loaded mesh alone.
//
//   sodt_bench_scaling [--sizes 10k,100k,1M,4M] [--sweeps N] [--repeats R]
//                      [--large-sweeps N] [--large-repeats R] [--threads 1,2]
//   sodt_bench_scaling --write-mesh SIZE OUT.ply
//   sodt_bench_scaling --load-only IN.ply
//   sodt_bench_scaling --smooth-only IN.ply OUT.ply [--sweeps N] [--threads T]

#include <sodt_io/io.h>
#include <sodt_io/mesh.h>
#include <sodt_io/metrics.h>
#include <sodt/params.h>
#include <sodt_io/prebuilt.h>

#include <vcg/complex/algorithms/smooth.h>
#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/flag.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/algorithms/update/topology.h>
#include <vcg/complex/complex.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#ifndef SODT_BENCH_MESH_DIR
#define SODT_BENCH_MESH_DIR "meshes"
#endif

namespace {

using Clock = std::chrono::steady_clock;
using MeshF = sodt::MeshF;  // MeshLab's precision
using MeshD = sodt::MeshD;  // the CLI's precision

/// Meshes from this many vertices up get the "large" timing policy.
constexpr int kLargeVertices = 500000;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::vector<std::string> splitComma(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t end = std::min(s.find(',', start), s.size());
    if (end > start) out.push_back(s.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

/// Strict non-negative integer; -1 when s is not one.
int parseCount(const std::string& s) {
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  return (s.empty() || *end || v < 0 || v > 1000000) ? -1 : static_cast<int>(v);
}

// ---------------------------------------------------------------------------
// Memory of this process, from /proc/self/status (Linux).

/// The value of a "Key:   123 kB" line of /proc/self/status, in kB; -1 if absent.
long procStatusKb(const std::string& key) {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.size() > key.size() && line.compare(0, key.size(), key) == 0 && line[key.size()] == ':')
      return std::strtol(line.c_str() + key.size() + 1, nullptr, 10);
  return -1;
}

/// Resets VmHWM (peak RSS) to the current RSS (Linux >= 4.0), so that the next
/// reading is the peak of what runs in between. False if the kernel refuses.
bool resetPeakRss() {
  std::ofstream f("/proc/self/clear_refs");
  f << "5";
  f.flush();
  return f.good();
}

/// Bytes of m's vertex and face vectors (capacity, not size): the mesh proper,
/// without the allocator's overhead.
template <class MeshType>
double meshBytes(const MeshType& m) {
  return double(m.vert.capacity()) * sizeof(typename MeshType::VertexType) +
         double(m.face.capacity()) * sizeof(typename MeshType::FaceType);
}

// ---------------------------------------------------------------------------
// Test meshes: repeated 1-to-4 midpoint subdivision of a bundled mesh.

/// Which mesh a size stands for: `levels` subdivisions of meshes/<base>.
struct SizeSpec {
  std::string label;  ///< "10k", "100k", "1M", "4M", or "BASE:LEVELS"
  std::string base;   ///< file in meshes/, or a path
  int levels = 0;
};

/// The presets. Each subdivision multiplies V by about 4 (V' = V + E), so one
/// base cannot give both 10k and 100k. 100k-4M come from the marching-cubes
/// mesh (4794 vertices: 76,674 / 1,226,754 / 4,907,010), so their rows differ
/// only in size; 10k comes from the jittered sphere (2562 -> 10,242), as
/// blobs_mc gives 4,794 or 19,170 only.
const SizeSpec kPresets[] = {
    {"10k", "sphere_jitter.ply", 1},
    {"100k", "blobs_mc.ply", 2},
    {"1M", "blobs_mc.ply", 4},
    {"4M", "blobs_mc.ply", 5},
};

/// A preset label (case-insensitive) or BASE:LEVELS (e.g. blobs_mc.ply:1).
bool parseSize(const std::string& token, SizeSpec& out) {
  for (const SizeSpec& s : kPresets)
    if (lower(token) == lower(s.label)) {
      out = s;
      return true;
    }
  const std::size_t colon = token.rfind(':');
  if (colon == std::string::npos || colon == 0) return false;
  out.label = token;
  out.base = token.substr(0, colon);
  out.levels = parseCount(token.substr(colon + 1));
  return out.levels >= 0 && out.levels <= 8;
}

std::string basePath(const std::string& base) {
  return base.find('/') == std::string::npos ? std::string(SODT_BENCH_MESH_DIR) + "/" + base : base;
}

/// Positions and triangles, for the subdivision.
struct Soup {
  std::vector<vcg::Point3f> v;
  std::vector<std::array<int, 3>> f;
};

/// One 1-to-4 split. Every edge gets its plain midpoint (computed in double,
/// rounded to float); each triangle becomes three corner triangles and the
/// middle one, all four similar to it. So the surface stays the base
/// polyhedron exactly and every angle of the base mesh survives: the poor
/// triangles of a marching-cubes mesh stay poor at every level. Orientation is
/// kept. Deterministic: new vertices are numbered in the order of the edge
/// table below, which depends on the input only.
void subdivide(Soup& s) {
  const int nv = static_cast<int>(s.v.size());
  // Edge table in compressed rows: edge {a, b} with a < b lives in row a as
  // other[k] = b, for begin[a] <= k < fill[a]. Rows are short (about half the
  // valence), so a linear scan finds an edge.
  std::vector<int> begin(nv + 1, 0);
  for (const auto& t : s.f)
    for (int j = 0; j < 3; ++j) ++begin[std::min(t[j], t[(j + 1) % 3]) + 1];
  for (int i = 0; i < nv; ++i) begin[i + 1] += begin[i];
  std::vector<int> other(begin[nv]), fill(begin.begin(), begin.end() - 1);
  for (const auto& t : s.f)
    for (int j = 0; j < 3; ++j) {
      const int a = std::min(t[j], t[(j + 1) % 3]), b = std::max(t[j], t[(j + 1) % 3]);
      if (std::find(other.begin() + begin[a], other.begin() + fill[a], b) == other.begin() + fill[a])
        other[fill[a]++] = b;
    }
  std::size_t edges = 0;
  for (int a = 0; a < nv; ++a) edges += fill[a] - begin[a];
  std::vector<int> mid(begin[nv], -1);
  s.v.reserve(nv + edges);  // no reallocation below: s.v[a] stays valid
  for (int a = 0; a < nv; ++a)
    for (int k = begin[a]; k < fill[a]; ++k) {
      const vcg::Point3f &p = s.v[a], &q = s.v[other[k]];
      const vcg::Point3f m(float(0.5 * (double(p[0]) + q[0])), float(0.5 * (double(p[1]) + q[1])),
                           float(0.5 * (double(p[2]) + q[2])));
      mid[k] = static_cast<int>(s.v.size());
      s.v.push_back(m);
    }
  auto midpoint = [&](int a, int b) {
    if (a > b) std::swap(a, b);
    const auto it = std::find(other.begin() + begin[a], other.begin() + fill[a], b);
    return mid[it - other.begin()];
  };
  std::vector<std::array<int, 3>> out;
  out.reserve(4 * s.f.size());
  for (const auto& t : s.f) {
    const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
    out.push_back({t[0], ab, ca});
    out.push_back({t[1], bc, ab});
    out.push_back({t[2], ca, bc});
    out.push_back({ab, bc, ca});
  }
  s.f.swap(out);
}

/// Loads meshes/<base> and subdivides it `levels` times into m (float),
/// with bounding box and normals up to date, as after sodt::loadMesh.
void makeMesh(const SizeSpec& spec, MeshF& m) {
  Soup s;
  {
    MeshF base;
    sodt::loadMesh(basePath(spec.base), base);  // compact: index = pointer - &vert[0]
    s.v.reserve(base.vert.size());
    for (const auto& v : base.vert) s.v.push_back(v.cP());
    s.f.reserve(base.face.size());
    for (const auto& f : base.face)
      s.f.push_back({int(f.cV(0) - &base.vert[0]), int(f.cV(1) - &base.vert[0]), int(f.cV(2) - &base.vert[0])});
  }
  for (int l = 0; l < spec.levels; ++l) subdivide(s);

  m.Clear();
  vcg::tri::Allocator<MeshF>::AddVertices(m, s.v.size());
  for (std::size_t i = 0; i < s.v.size(); ++i) m.vert[i].P() = s.v[i];
  s.v = std::vector<vcg::Point3f>();
  vcg::tri::Allocator<MeshF>::AddFaces(m, s.f.size());
  for (std::size_t i = 0; i < s.f.size(); ++i)
    for (int j = 0; j < 3; ++j) m.face[i].V(j) = &m.vert[s.f[i][j]];
  vcg::tri::UpdateBounding<MeshF>::Box(m);
  vcg::tri::UpdateNormal<MeshF>::PerVertexNormalizedPerFace(m);
}

// ---------------------------------------------------------------------------
// Timing.

struct Options {
  std::vector<SizeSpec> sizes;
  int sweeps = 10;       ///< sweeps per timed call below kLargeVertices; ms/sweep = call time / sweeps
  int repeats = 3;       ///< timed calls below kLargeVertices (after one warm-up)
  int largeSweeps = 2;   ///< sweeps per timed call from kLargeVertices up
  int largeRepeats = 1;  ///< timed calls from kLargeVertices up (no warm-up)
  std::vector<int> threads{1, 2};
};

/// One line of the main table.
struct Row {
  std::string size;
  int nv = 0, nf = 0;
  std::string method;
  int threads = 1;        ///< SodtParams::threads as passed (0 = all hardware threads)
  int sweeps = 0;         ///< sweeps per timed call
  double msPerSweep = 0;  ///< median over the timed calls of (call time / sweeps)
  double setupMs = 0;     ///< S-ODT: a call with iterations = 0; Laplacian: FF topology + border flags
  /// S-ODT: the median over the timed calls of SodtStats::sweepSeconds /
  /// sweeps, the sweeps alone as Apply times them; the Laplacian's
  /// msPerSweep already excludes its set-up.
  double sweepOnlyMs = 0;
  std::string note;
};

/// An S-ODT configuration of the table; everything else at SodtParams{}.
struct SodtMethod {
  const char* name;
  sodt::Algorithm algorithm;
  sodt::Guard guard;
};

const SodtMethod kMethods[] = {
    {"S-ODT Alg.1, guard quality (default)", sodt::Algorithm::Basic, sodt::Guard::Quality},
    {"S-ODT Alg.1, guard fold", sodt::Algorithm::Basic, sodt::Guard::Fold},
    {"S-ODT Alg.1, guard none", sodt::Algorithm::Basic, sodt::Guard::None},
    {"S-ODT Alg.2 (feature)", sodt::Algorithm::Feature, sodt::Guard::Quality},
    {"S-ODT Alg.3 (denoise)", sodt::Algorithm::Denoise, sodt::Guard::Quality},
};

std::vector<vcg::Point3f> positions(const MeshF& m) {
  std::vector<vcg::Point3f> p;
  p.reserve(m.vert.size());
  for (const auto& v : m.vert) p.push_back(v.cP());
  return p;
}

void restore(MeshF& m, const std::vector<vcg::Point3f>& p) {
  for (std::size_t i = 0; i < p.size(); ++i) m.vert[i].P() = p[i];
}

/// Times `run()` from the original positions: one untimed warm-up when
/// `warmUp`, then `calls` timed calls. Returns the median call time in ms.
template <class Run>
double timeCalls(MeshF& m, const std::vector<vcg::Point3f>& original, bool warmUp, int calls, Run run) {
  if (warmUp) {
    restore(m, original);
    run();
  }
  std::vector<double> ms;
  for (int k = 0; k < calls; ++k) {
    restore(m, original);
    const Clock::time_point t0 = Clock::now();
    run();
    ms.push_back(msSince(t0));
  }
  restore(m, original);
  return median(ms);
}

/// timeCalls of `run(sweeps)`, divided by sweeps: the cost of one sweep.
template <class Run>
double timeSweeps(MeshF& m, const std::vector<vcg::Point3f>& original, int sweeps, bool warmUp, int calls,
                  Run run) {
  return timeCalls(m, original, warmUp, calls, [&]() { run(sweeps); }) / sweeps;
}

/// Shares of all vertex visits ("unchanged" includes failed solves), and the
/// classes for Algorithms 2 and 3.
std::string statsNote(const sodt::SodtStats& s, sodt::Algorithm a) {
  const double visits = std::max(1.0, double(s.activeVertices) * s.iterations);
  char note[240];
  int n = std::snprintf(note, sizeof note,
                        "visits: %.0f%% moved, %.0f%% fallback, %.0f%% rejected, %.0f%% unchanged",
                        100.0 * (s.moved + s.backtracked) / visits, 100.0 * s.fallbackMoves / visits,
                        100.0 * s.rejected / visits, 100.0 * (s.unchanged + s.failedSolves) / visits);
  if (a != sodt::Algorithm::Basic && n > 0 && n < int(sizeof note))
    std::snprintf(note + n, sizeof note - n, "; %d crease, %d corner vertices", s.creaseVertices,
                  s.cornerVertices);
  return note;
}

/// Mesh properties for the header table.
struct MeshInfo {
  SizeSpec spec;
  int nv = 0, nf = 0;
  double minAngleDeg = 0, below30 = 0, genSeconds = 0, megabytes = 0;
};

void benchSize(const SizeSpec& spec, const Options& o, std::vector<MeshInfo>& infos, std::vector<Row>& rows) {
  MeshInfo info;
  info.spec = spec;
  const Clock::time_point g0 = Clock::now();
  MeshF m;
  makeMesh(spec, m);
  info.genSeconds = msSince(g0) / 1000;
  info.nv = m.vn;
  info.nf = m.fn;
  info.megabytes = meshBytes(m) / (1024.0 * 1024.0);  // MB = 2^20 bytes, like the RSS figures
  const sodt::AngleStats a = sodt::computeAngleStats(m);
  info.minAngleDeg = a.minDeg;
  info.below30 = a.fracBelow30;
  infos.push_back(info);
  std::fprintf(stderr, "[%s] %s x%d: V=%d F=%d, generated in %.1f s\n", spec.label.c_str(), spec.base.c_str(),
               spec.levels, m.vn, m.fn, info.genSeconds);

  const bool large = m.vn >= kLargeVertices;
  const int calls = large ? o.largeRepeats : o.repeats;
  const int sweeps = large ? o.largeSweeps : o.sweeps;
  const auto original = positions(m);
  if (large) {
    // No per-method warm-up for large meshes (a call takes seconds), but one
    // untimed set-up call per mesh, so that the first row does not pay for
    // the first touch of the freshly generated mesh.
    sodt::SodtParams p;
    p.iterations = 0;
    sodt::SodtSmoother<MeshF>::Apply(m, p);
  }

  for (const SodtMethod& method : kMethods)
    for (int threads : o.threads) {
      sodt::SodtParams p;
      p.algorithm = method.algorithm;
      p.guard = method.guard;
      p.threads = threads;
      Row r;
      r.size = spec.label;
      r.nv = m.vn;
      r.nf = m.fn;
      r.method = method.name;
      r.threads = threads;
      r.sweeps = sweeps;
      // Set-up: Apply has no early exit for 0 iterations, so a call with
      // iterations = 0 does everything but the sweeps (positions, ring
      // topology, classification, fits, input copies) plus the final bounding
      // box and normals. Timed under the same policy as the sweeps.
      r.setupMs = timeCalls(m, original, !large, calls, [&]() {
        p.iterations = 0;
        sodt::SodtSmoother<MeshF>::Apply(m, p);
      });
      sodt::SodtStats last;
      std::vector<double> sweepMs;  // per timed call, SodtStats::sweepSeconds
      r.msPerSweep = timeSweeps(m, original, sweeps, !large, calls, [&](int n) {
        p.iterations = n;
        last = sodt::SodtSmoother<MeshF>::Apply(m, p);
        sweepMs.push_back(1000 * last.sweepSeconds / n);
      });
      if (!large) sweepMs.erase(sweepMs.begin());  // the warm-up call
      r.sweepOnlyMs = median(sweepMs);
      r.note = statsNote(last, method.algorithm);
      rows.push_back(r);
      std::fprintf(stderr, "[%s] %s, %d thread(s): %.2f ms/sweep, set-up %.1f ms\n", spec.label.c_str(),
                   method.name, threads, r.msPerSweep, r.setupMs);
    }

  // vcglib's umbrella Laplacian, single-threaded. Its adjacency (FF, and the
  // border flags it reads) does not change with the positions: it is built
  // outside the timed calls (and timed on its own as the set-up), so the
  // calls measure the sweeps only.
  Row r;
  r.size = spec.label;
  r.nv = m.vn;
  r.nf = m.fn;
  r.method = "vcg VertexCoordLaplacian";
  r.threads = 1;
  r.sweeps = sweeps;
  r.setupMs = timeCalls(m, original, !large, calls, [&]() {
    vcg::tri::UpdateTopology<MeshF>::FaceFace(m);
    vcg::tri::UpdateFlags<MeshF>::FaceBorderFromFF(m);
  });
  r.msPerSweep = timeSweeps(m, original, sweeps, !large, calls,
                            [&](int n) { vcg::tri::Smooth<MeshF>::VertexCoordLaplacian(m, n); });
  r.sweepOnlyMs = r.msPerSweep;
  r.note = "reference: no tangential constraint, no guard";
  rows.push_back(r);
  std::fprintf(stderr, "[%s] vcg Laplacian: %.2f ms/sweep\n", spec.label.c_str(), r.msPerSweep);
}

const Row* findRow(const std::vector<Row>& rows, const std::string& size, const std::string& method, int threads) {
  for (const Row& r : rows)
    if (r.size == size && r.method == method && r.threads == threads) return &r;
  return nullptr;
}

/// a / b formatted, or "-" when either is missing; `sweepOnly` compares the
/// sweeps without the set-up.
std::string ratio(const Row* a, const Row* b, bool sweepOnly = false) {
  if (!a || !b) return "-";
  const double x = sweepOnly ? a->sweepOnlyMs : a->msPerSweep, y = sweepOnly ? b->sweepOnlyMs : b->msPerSweep;
  if (!(x > 0) || !(y > 0)) return "-";
  char s[32];
  std::snprintf(s, sizeof s, "%.2f", x / y);
  return s;
}

std::string withCommas(long long v) {
  std::string s = std::to_string(v);
  for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(std::size_t(i), ",");
  return s;
}

void printReport(const Options& o, const std::vector<MeshInfo>& infos, const std::vector<Row>& rows,
                 double totalSeconds) {
  const std::string big = withCommas(kLargeVertices);
  std::printf("sodt_bench_scaling: float mesh sodt::MeshF, %u hardware threads; total wall time %.0f s, peak RSS "
              "%.0f MB\n",
              std::thread::hardware_concurrency(), totalSeconds, procStatusKb("VmHWM") / 1024.0);
  std::printf("- policy: below %s vertices, %d sweeps per call, one untimed warm-up call, then the median of %d "
              "timed calls; from %s vertices up, %d sweeps per call, %d timed call(s), no warm-up (one untimed "
              "set-up call per mesh). The same for the set-up calls. Every call starts from the generated "
              "positions.\n",
              big.c_str(), o.sweeps, o.repeats, big.c_str(), o.largeSweeps, o.largeRepeats);
  std::printf("- S-ODT: ms/sweep = time of one Apply call with iterations = sweeps (set-up included) / sweeps; "
              "set-up = an Apply call with iterations = 0 (no early exit: topology, classification, fits, "
              "normals, everything but the sweeps); without set-up = the sweeps as Apply times them "
              "(SodtStats::sweepSeconds; median over the timed calls) / sweeps\n");
  std::printf("- vcg Laplacian: VertexCoordLaplacian(m, sweeps) / sweeps, single-threaded; its set-up "
              "(FaceFace + FaceBorderFromFF) is built outside the timed calls and timed on its own\n");
  std::printf("- ns/vertex/sweep = ms/sweep / V. The Alg.2, Alg.3 ratios use ms/sweep unless marked; the summary's "
              "speed-ups and the ratios to the Laplacian compare the sweeps without set-up\n\n");

  std::printf("| size | made from | V | F | mesh MB | min angle (deg) | corners < 30 deg | generated in (s) |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|\n");
  for (const MeshInfo& i : infos)
    std::printf("| %s | %s, %d x 1-to-4 | %s | %s | %.0f | %.3f | %.1f%% | %.1f |\n", i.spec.label.c_str(),
                i.spec.base.c_str(), i.spec.levels, withCommas(i.nv).c_str(), withCommas(i.nf).c_str(),
                i.megabytes, i.minAngleDeg, 100.0 * i.below30, i.genSeconds);

  std::printf("\n| size | V | method | threads | sweeps | ms/sweep | ns/vertex/sweep | set-up (ms) | "
              "ms/sweep without set-up | speed-up vs 1 thread | speed-up, sweeps alone | notes (last timed call) |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  for (const Row& r : rows) {
    const Row* one = findRow(rows, r.size, r.method, 1);
    const bool first = r.threads == 1 || !one;
    std::printf("| %s | %s | %s | %d | %d | %.2f | %.0f | %.1f | %.2f | %s | %s | %s |\n", r.size.c_str(),
                withCommas(r.nv).c_str(), r.method.c_str(), r.threads, r.sweeps, r.msPerSweep,
                1e6 * r.msPerSweep / r.nv, r.setupMs, r.sweepOnlyMs, first ? "-" : ratio(one, &r).c_str(),
                first ? "-" : ratio(one, &r, true).c_str(), r.note.c_str());
  }

  // Summary: the unguarded sweep's cost per vertex, the speed-up of the
  // largest thread count over 1 thread (sweeps alone), and the cost ratios
  // between methods, all at 1 thread.
  const int tMax = *std::max_element(o.threads.begin(), o.threads.end());
  const std::string a1 = kMethods[0].name, a1none = kMethods[2].name, a2 = kMethods[3].name,
                    a3 = kMethods[4].name, lap = "vcg VertexCoordLaplacian";
  std::printf("\n| size | V | Alg.1 none, 1 thread: ns/vertex/sweep, sweeps alone | speed-up %d vs 1 thread, "
              "sweeps alone: Alg.1 quality | Alg.1 fold | Alg.1 none | Alg.2 | Alg.3 | "
              "Alg.3 / Alg.1 | Alg.3 / Alg.1 without set-up | Alg.2 / Alg.1 | Alg.1 / vcg Laplacian | "
              "Alg.1 none / vcg Laplacian |\n",
              tMax);
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const MeshInfo& i : infos) {
    const std::string& s = i.spec.label;
    const Row* none1 = findRow(rows, s, a1none, 1);
    char perVertex[32] = "-";
    if (none1) std::snprintf(perVertex, sizeof perVertex, "%.0f", 1e6 * none1->sweepOnlyMs / none1->nv);
    std::printf("| %s | %s | %s |", s.c_str(), withCommas(i.nv).c_str(), perVertex);
    for (const SodtMethod& m : kMethods) {
      const Row *one = findRow(rows, s, m.name, 1), *many = findRow(rows, s, m.name, tMax);
      std::printf(" %s |", tMax == 1 ? "-" : ratio(one, many, true).c_str());
    }
    std::printf(" %s | %s | %s | %s | %s |\n", ratio(findRow(rows, s, a3, 1), findRow(rows, s, a1, 1)).c_str(),
                ratio(findRow(rows, s, a3, 1), findRow(rows, s, a1, 1), true).c_str(),
                ratio(findRow(rows, s, a2, 1), findRow(rows, s, a1, 1)).c_str(),
                ratio(findRow(rows, s, a1, 1), findRow(rows, s, lap, 1), true).c_str(),
                ratio(findRow(rows, s, a1none, 1), findRow(rows, s, lap, 1), true).c_str());
  }
}

// ---------------------------------------------------------------------------
// Helper modes for bench/scaling.sh. They print "key value" lines.

/// --write-mesh SIZE OUT: the benchmark mesh as a file (binary PLY, float).
int writeMesh(const SizeSpec& spec, const std::string& out) {
  MeshF m;
  makeMesh(spec, m);
  sodt::saveMesh(out, m);
  std::printf("mesh %s (%s, %d x 1-to-4)\nvertices %d\nfaces %d\nfile %s\n", spec.label.c_str(),
              spec.base.c_str(), spec.levels, m.vn, m.fn, out.c_str());
  return 0;
}

/// --load-only IN: loads IN exactly as the CLI does (sodt::loadMesh, double
/// mesh) and reports the memory of the loaded mesh: peak and current RSS of
/// the process, and the bytes of its vertex and face vectors.
int loadOnly(const std::string& in) {
  const long baseKb = procStatusKb("VmRSS");
  MeshD m;
  const Clock::time_point t0 = Clock::now();
  sodt::loadMesh(in, m);
  std::printf("vertices %d\nfaces %d\n", m.vn, m.fn);
  std::printf("load_seconds %.2f\n", msSince(t0) / 1000);
  std::printf("mesh_vectors_kb %.0f\n", meshBytes(m) / 1024);
  std::printf("rss_before_load_kb %ld\n", baseKb);
  std::printf("rss_kb %ld\n", procStatusKb("VmRSS"));
  std::printf("peak_rss_kb %ld\n", procStatusKb("VmHWM"));
  return 0;
}

/// --smooth-only IN OUT: what `sodt smooth` does without its measurements and
/// its copy of the input: load (double mesh), Apply with the default
/// parameters, save with the default SaveOptions (binary, read back to
/// verify; the CLI's options for a file without quality, colour or flags,
/// like the benchmark meshes). The peak RSS of each phase is reported when the
/// kernel lets us reset it (/proc/self/clear_refs); peak_rss_kb is the
/// process peak either way.
int smoothOnly(const std::string& in, const std::string& out, int sweeps, int threads) {
  MeshD m;
  Clock::time_point t0 = Clock::now();
  sodt::loadMesh(in, m);
  std::printf("vertices %d\nfaces %d\n", m.vn, m.fn);
  std::printf("load_seconds %.2f\nload_peak_rss_kb %ld\n", msSince(t0) / 1000, procStatusKb("VmHWM"));
  std::printf("mesh_vectors_kb %.0f\n", meshBytes(m) / 1024);
  const long overallBefore = procStatusKb("VmHWM");
  const bool phases = resetPeakRss();

  sodt::SodtParams p;
  p.iterations = sweeps;
  p.threads = threads;
  t0 = Clock::now();
  const sodt::SodtStats st = sodt::SodtSmoother<MeshD>::Apply(m, p);
  std::printf("smooth_seconds %.2f\nsweeps %d\nthreads %d\n", msSince(t0) / 1000, st.iterations, threads);
  long overall = std::max(overallBefore, procStatusKb("VmHWM"));
  if (phases) std::printf("smooth_peak_rss_kb %ld\n", procStatusKb("VmHWM"));
  const bool phases2 = phases && resetPeakRss();

  t0 = Clock::now();
  sodt::saveMesh(out, m);
  std::printf("save_seconds %.2f\n", msSince(t0) / 1000);
  overall = std::max(overall, procStatusKb("VmHWM"));
  if (phases2) std::printf("save_peak_rss_kb %ld\n", procStatusKb("VmHWM"));
  std::printf("peak_rss_kb %ld\n", overall);
  return 0;
}

void usage(FILE* out) {
  const Options d;
  std::fprintf(out,
               "usage: sodt_bench_scaling [--sizes LIST] [--sweeps N] [--repeats R] [--large-sweeps N]\n"
               "                          [--large-repeats R] [--threads LIST]\n"
               "       sodt_bench_scaling --write-mesh SIZE OUT.ply\n"
               "       sodt_bench_scaling --load-only IN\n"
               "       sodt_bench_scaling --smooth-only IN OUT [--sweeps N] [--threads T]\n"
               "  --sizes LIST       comma-separated: 10k, 100k, 1M, 4M (default: all four) or\n"
               "                     BASE:LEVELS, BASE a file in %s or a path\n"
               "  --sweeps N         sweeps per timed call below %d vertices (default %d;\n"
               "                     --smooth-only: the sweeps of the run, default 5)\n"
               "  --repeats R        timed calls below %d vertices, after one warm-up\n"
               "                     (default %d)\n"
               "  --large-sweeps N   sweeps per timed call from %d vertices up (default %d)\n"
               "  --large-repeats R  timed calls from %d vertices up, no warm-up (default %d)\n"
               "  --threads LIST     SodtParams::threads values (default 1,2; 0 = all hardware\n"
               "                     threads; --smooth-only: one value, default %d)\n"
               "  --write-mesh SIZE OUT.ply  write the SIZE mesh as binary PLY (float)\n"
               "  --load-only IN     load IN like the CLI (double mesh), print its memory\n"
               "  --smooth-only IN OUT  load, smooth (defaults), save like the CLI without its\n"
               "                     measurements; print peak RSS per phase\n",
               SODT_BENCH_MESH_DIR, kLargeVertices, d.sweeps, kLargeVertices, d.repeats, kLargeVertices,
               d.largeSweeps, kLargeVertices, d.largeRepeats, sodt::SodtParams{}.threads);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::string mode, arg1, arg2;
  bool sweepsGiven = false, threadsGiven = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--sizes" && hasValue) {
      o.sizes.clear();
      for (const std::string& t : splitComma(argv[++i])) {
        SizeSpec s;
        if (!parseSize(t, s)) {
          std::fprintf(stderr, "error: unknown size '%s'\n", t.c_str());
          return 2;
        }
        o.sizes.push_back(s);
      }
    } else if ((a == "--sweeps" || a == "--repeats" || a == "--large-sweeps" || a == "--large-repeats") &&
               hasValue) {
      const int v = parseCount(argv[++i]);
      if (v < 1 || v > 100000) {
        usage(stderr);
        return 2;
      }
      (a == "--sweeps" ? o.sweeps : a == "--repeats" ? o.repeats : a == "--large-sweeps" ? o.largeSweeps
                                                                                         : o.largeRepeats) = v;
      sweepsGiven = sweepsGiven || a == "--sweeps";
    } else if (a == "--threads" && hasValue) {
      o.threads.clear();
      for (const std::string& t : splitComma(argv[++i])) {
        const int v = parseCount(t);
        if (v < 0 || v > 1024) {
          std::fprintf(stderr, "error: bad thread count '%s'\n", t.c_str());
          return 2;
        }
        o.threads.push_back(v);
      }
      threadsGiven = true;
    } else if (a == "--write-mesh" && i + 2 < argc) {
      mode = a;
      arg1 = argv[++i];
      arg2 = argv[++i];
    } else if (a == "--load-only" && hasValue) {
      mode = a;
      arg1 = argv[++i];
    } else if (a == "--smooth-only" && i + 2 < argc) {
      mode = a;
      arg1 = argv[++i];
      arg2 = argv[++i];
    } else {
      usage(stderr);
      return 2;
    }
  }
  if (o.threads.empty()) {
    usage(stderr);
    return 2;
  }

  try {
    if (mode == "--write-mesh") {
      SizeSpec s;
      if (!parseSize(arg1, s)) {
        std::fprintf(stderr, "error: unknown size '%s'\n", arg1.c_str());
        return 2;
      }
      return writeMesh(s, arg2);
    }
    if (mode == "--load-only") return loadOnly(arg1);
    if (mode == "--smooth-only") {
      if (threadsGiven && o.threads.size() != 1) {
        std::fprintf(stderr, "error: --smooth-only takes one thread count\n");
        return 2;
      }
      const int threads = threadsGiven ? o.threads[0] : sodt::SodtParams{}.threads;
      return smoothOnly(arg1, arg2, sweepsGiven ? o.sweeps : 5, threads);
    }

    if (o.sizes.empty()) o.sizes.assign(std::begin(kPresets), std::end(kPresets));
    const Clock::time_point t0 = Clock::now();
    std::vector<MeshInfo> infos;
    std::vector<Row> rows;
    for (const SizeSpec& s : o.sizes) benchSize(s, o, infos, rows);  // one mesh in memory at a time
    printReport(o, infos, rows, msSince(t0) / 1000);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
