// SPDX-License-Identifier: GPL-3.0-or-later
// Wall-clock cost of one S-ODT sweep (Algorithm 1, each guard) on float and double
// vcg meshes, next to vcglib's VertexCoordLaplacian on the same mesh for reference.

#include <sodt_io/mesh.h>
#include <sodt/params.h>
#include <sodt_io/prebuilt.h>

#include <vcg/complex/algorithms/smooth.h>
#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/flag.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/algorithms/update/topology.h>
#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import_off.h>
#include <wrap/io_trimesh/import_ply.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#ifndef SODT_BENCH_DEFAULT_MESH
#define SODT_BENCH_DEFAULT_MESH ""
#endif
#ifndef SODT_BENCH_FALLBACK_MESH
#define SODT_BENCH_FALLBACK_MESH ""
#endif

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  std::string mesh;
  int sweeps = sodt::SodtParams{}.iterations;  ///< sweeps per timed run (the paper's 20); ms/sweep = run time / sweeps
  int repeats = 5;   ///< timed runs per method; the table shows their median
  int threads = 1;   ///< SodtParams::threads (0: all cores)
};

/// One table row.
struct Row {
  std::string scalar;
  std::string method;
  double medianMs = 0;     ///< median over repeats of (run time / sweeps)
  double minMs = 0;        ///< fastest repeat, same unit
  double firstCallMs = 0;  ///< one run of a single sweep: mostly set-up for the fast methods
  std::string note;
};

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

bool fileExists(const std::string& path) { return !path.empty() && std::ifstream(path).good(); }

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

template <class MeshType>
bool loadMesh(MeshType& m, const std::string& path) {
  const int err = endsWith(path, ".off") ? vcg::tri::io::ImporterOFF<MeshType>::Open(m, path.c_str())
                                         : vcg::tri::io::ImporterPLY<MeshType>::Open(m, path.c_str());
  if (err != 0) {
    std::fprintf(stderr, "error: cannot read %s (vcg error %d)\n", path.c_str(), err);
    return false;
  }
  vcg::tri::UpdateBounding<MeshType>::Box(m);
  return true;
}

/// Vertex positions and face corners, so that every run starts from the
/// input (edge flips change the faces).
template <class MeshType>
struct State {
  std::vector<typename MeshType::CoordType> pos;
  std::vector<int> corner;  ///< 3 per face
};

template <class MeshType>
State<MeshType> snapshot(const MeshType& m) {
  State<MeshType> st;
  st.pos.reserve(m.vert.size());
  for (const auto& v : m.vert) st.pos.push_back(v.cP());
  for (const auto& f : m.face)
    for (int j = 0; j < 3; ++j) st.corner.push_back(static_cast<int>(f.cV(j) - &m.vert[0]));
  return st;
}

template <class MeshType>
void restore(MeshType& m, const State<MeshType>& st) {
  for (std::size_t i = 0; i < st.pos.size(); ++i) m.vert[i].P() = st.pos[i];
  for (std::size_t f = 0; f < m.face.size(); ++f)
    for (int j = 0; j < 3; ++j) m.face[f].V(j) = &m.vert[st.corner[3 * f + j]];
}

/// Times `run(sweeps)` on the original positions `repeats` times after one
/// untimed warm-up, then `run(1)` once. A run is a complete call as a user
/// makes it: set-up (topology, flags), the sweeps, bounding box and normals.
template <class MeshType, class Run>
Row timeMethod(MeshType& m, const State<MeshType>& original, const Options& o, Run run) {
  Row r;
  restore(m, original);
  run(o.sweeps);
  std::vector<double> perSweep;
  for (int k = 0; k < o.repeats; ++k) {
    restore(m, original);
    const Clock::time_point t0 = Clock::now();
    run(o.sweeps);
    perSweep.push_back(msSince(t0) / o.sweeps);
  }
  r.medianMs = median(perSweep);
  r.minMs = *std::min_element(perSweep.begin(), perSweep.end());
  restore(m, original);
  const Clock::time_point t0 = Clock::now();
  run(1);
  r.firstCallMs = msSince(t0);
  restore(m, original);
  return r;
}

template <class MeshType>
void benchScalar(const std::string& scalar, const Options& o, std::vector<Row>& rows, int& nv, int& nf) {
  MeshType m;
  if (!loadMesh(m, o.mesh)) std::exit(1);
  nv = m.vn;
  nf = m.fn;
  const State<MeshType> original = snapshot(m);

  // Each guard, then the default and no guard again with keepBest, which
  // measures the quality (smallest angle, 1st percentile, inverted faces)
  // after every sweep: what that measurement adds to a sweep; last the
  // default with edge flips between the sweeps.
  struct Variant {
    sodt::Guard guard;
    bool keepBest;
    bool flips;
  };
  const Variant variants[] = {{sodt::Guard::Quality, false, false},
                              {sodt::Guard::Fold, false, false},
                              {sodt::Guard::None, false, false},
                              {sodt::Guard::Quality, true, false},
                              {sodt::Guard::None, true, false},
                              {sodt::Guard::Quality, false, true}};
  const std::size_t first = rows.size();
  for (const Variant& v : variants) {
    const sodt::Guard g = v.guard;
    sodt::SodtParams p;
    p.guard = g;
    p.keepBest = v.keepBest;
    p.flips = v.flips;
    p.threads = o.threads;
    sodt::SodtStats full;  // counters of the last o.sweeps-sweep call
    // Apply builds its ring topology and updates normals once per call.
    Row r = timeMethod(m, original, o, [&](int sweeps) {
      p.iterations = sweeps;
      const sodt::SodtStats s = sodt::SodtSmoother<MeshType>::Apply(m, p);
      if (sweeps == o.sweeps) full = s;
    });
    const double visits = std::max(1.0, double(full.activeVertices) * full.iterations);
    char note[200];
    std::snprintf(note, sizeof note,
                  "of all vertex visits: %.1f%% moved (%.1f%% after backtracking), %.1f%% Laplacian fallback, "
                  "%.1f%% rejected; %.1f%% skipped (star unchanged)",
                  100.0 * (full.moved + full.backtracked) / visits, 100.0 * full.backtracked / visits,
                  100.0 * full.fallbackMoves / visits, 100.0 * full.rejected / visits,
                  100.0 * full.skipped / visits);
    r.scalar = scalar;
    r.method = std::string("S-ODT Alg.1, guard ") + sodt::toString(g) + (v.keepBest ? ", keep best" : "") +
               (v.flips ? ", flips" : "");
    r.note = note;
    if (v.flips) {
      std::snprintf(note, sizeof note, "%lld flips in %d sweeps", full.flips, full.iterations);
      r.note = note;
    }
    if (v.keepBest) {
      // The same run without keepBest is among the rows above.
      for (std::size_t k = first; k < rows.size(); ++k)
        if (rows[k].method == std::string("S-ODT Alg.1, guard ") + sodt::toString(g)) {
          std::snprintf(note, sizeof note, "quality measured after each sweep: %+.2f ms/sweep (median) over the row without",
                        r.medianMs - rows[k].medianMs);
          r.note = note;
        }
    }
    rows.push_back(r);
  }

  // vcglib's umbrella Laplacian needs face-face adjacency and face border
  // flags (border vertices then only average along the border); MeshLab's
  // filter builds them on every call too.
  Row r = timeMethod(m, original, o, [&](int sweeps) {
    vcg::tri::UpdateTopology<MeshType>::FaceFace(m);
    vcg::tri::UpdateFlags<MeshType>::FaceBorderFromFF(m);
    vcg::tri::Smooth<MeshType>::VertexCoordLaplacian(m, sweeps);
    vcg::tri::UpdateBounding<MeshType>::Box(m);
    vcg::tri::UpdateNormal<MeshType>::PerVertexNormalizedPerFace(m);
  });
  r.scalar = scalar;
  r.method = "vcg VertexCoordLaplacian";
  r.note = "reference (no tangential constraint)";
  rows.push_back(r);
}

void usage() {
  std::fprintf(stderr,
               "usage: sodt_bench [MESH.ply|MESH.off] [--sweeps N] [--repeats R] [--threads T]\n"
               "  --threads T: S-ODT worker threads (default 1; 0: all cores)\n"
               "  default mesh: %s if it exists, else %s\n",
               SODT_BENCH_DEFAULT_MESH, SODT_BENCH_FALLBACK_MESH);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threads" && i + 1 < argc) {
      o.threads = std::atoi(argv[++i]);
      if (o.threads < 0) {
        usage();
        return 2;
      }
    } else if ((a == "--sweeps" || a == "--repeats") && i + 1 < argc) {
      const int v = std::atoi(argv[++i]);
      if (v < 1) {
        usage();
        return 2;
      }
      (a == "--sweeps" ? o.sweeps : o.repeats) = v;
    } else if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else if (!a.empty() && a[0] == '-') {
      usage();
      return 2;
    } else {
      o.mesh = a;
    }
  }
  if (o.mesh.empty()) o.mesh = fileExists(SODT_BENCH_DEFAULT_MESH) ? SODT_BENCH_DEFAULT_MESH : SODT_BENCH_FALLBACK_MESH;
  if (!fileExists(o.mesh)) {
    std::fprintf(stderr, "error: mesh '%s' not found\n", o.mesh.c_str());
    usage();
    return 1;
  }

  std::vector<Row> rows;
  int nv = 0, nf = 0;
  benchScalar<sodt::MeshF>("float", o, rows, nv, nf);
  benchScalar<sodt::MeshD>("double", o, rows, nv, nf);

  // The file name alone: the output goes into bench/RESULTS.md as it is.
  const std::string name = o.mesh.substr(o.mesh.find_last_of('/') + 1);
  std::printf("mesh %s: V=%d F=%d; ms/sweep = time of one call doing %d sweeps / %d, median and min of %d calls; "
              "S-ODT threads: %d\n\n",
              name.c_str(), nv, nf, o.sweeps, o.sweeps, o.repeats, o.threads);
  std::printf("| mesh | V | F | scalar | method | ms/sweep (median) | ms/sweep (min) | ms for a 1-sweep call | notes |\n");
  std::printf("|---|---:|---:|---|---|---:|---:|---:|---|\n");
  for (const Row& r : rows)
    std::printf("| %s | %d | %d | %s | %s | %.2f | %.2f | %.2f | %s |\n", name.c_str(), nv, nf, r.scalar.c_str(),
                r.method.c_str(), r.medianMs, r.minMs, r.firstCallMs, r.note.c_str());
  return 0;
}
