// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target: mesh file bytes -> sodt::loadMesh -> one guarded S-ODT
// sweep -> metrics, checking that nothing crashes and that every output
// coordinate is finite.
//
// Input layout: byte 0 selects what is exercised, the remaining bytes are the
// file content.
//   bit 0    : 0 = .ply, 1 = .off (the extension the bytes are written under);
//              with bits 1-2 = 3: 0 = .obj, 1 = .stl
//   bits 1-2 : algorithm 0 = basic, 1 = feature, 2 = denoise, 3 = basic (OBJ or STL)
//   bit 3    : edge flips after the sweep
//   bit 4    : guard 0 = quality, 1 = fold
//   bit 5    : keepBest
//   bit 6    : 0 = double mesh (MeshD, the CLI), 1 = float mesh (MeshF, like MeshLab's CMeshO)
//   bit 7    : selectedOnly (moves only the vertices a PLY "flags" property selects)
// A reproducer's mesh file is therefore `tail -c +2 crash-<sha1>`, to be read
// with the extension bits 0-2 of its first byte name.
//
// Expected outcomes: loadMesh throwing sodt::InvalidInput (or another
// std::exception; set SODT_FUZZ_STRICT=1 to abort on anything but
// InvalidInput, which is what io.h documents). Everything else is a finding
// and aborts: a sanitizer report, an exception out of Apply or the metrics, a
// non-finite output coordinate, an inconsistent SodtStats, a face pointing
// outside the vertex vector, a changed vertex/face count, a loaded mesh that
// is not compact (io.h's postcondition), a PLY whose face indices vcglib
// cannot have read.
//
// Environment:
//   SODT_FUZZ_STRICT=1          only InvalidInput is an expected loadMesh outcome
//   SODT_FUZZ_SKIP_KNOWN=1      skip (instead of aborting on) the inputs of the
//                               findings in fuzz/regressions/, to look for new ones
//   SODT_FUZZ_DISTANCE_EVERY=N  run surfaceDistance on 1 input in N (default 8;
//                               1 = always), chosen by a hash of the input
#include <sodt_io/io.h>
#include <sodt_io/metrics.h>
#include <sodt_io/mesh.h>
#include <sodt/params.h>
#include <sodt/smoother.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

/// Meshes with more vertices + faces than this are skipped after loading:
/// the sweep and the surface sampling would make single runs slow.
constexpr int kMaxElements = 20000;

std::string gDir;       // per-process scratch directory (libFuzzer -jobs/-fork run several processes)
bool gStrict = false;   // SODT_FUZZ_STRICT=1: only InvalidInput is an expected loader outcome
bool gSkipKnown = false;  // SODT_FUZZ_SKIP_KNOWN=1: do not abort on the findings already reported
unsigned gDistanceEvery = 8;  // SODT_FUZZ_DISTANCE_EVERY: surfaceDistance on 1 input in N

/// surfaceDistance samples at least 10000 points each way (~50 ms under
/// ASan, 30x the rest of a run), so it runs on the inputs whose hash is 0
/// modulo gDistanceEvery: deterministic, so a crash in it reproduces.
bool wantDistance(const uint8_t* data, size_t size) {
  uint32_t h = 2166136261u;  // FNV-1a
  for (size_t i = 0; i < size; ++i) h = (h ^ data[i]) * 16777619u;
  return gDistanceEvery <= 1 || h % gDistanceEvery == 0;
}

void removeScratch() {
  if (gDir.empty()) return;
  for (const char* ext : {"ply", "off", "obj", "stl"}) ::unlink((gDir + "/input." + ext).c_str());
  ::rmdir(gDir.c_str());
}

[[noreturn]] void fail(const char* what, const std::string& detail = std::string()) {
  std::fprintf(stderr, "fuzz_mesh: FINDING: %s%s%s\n", what, detail.empty() ? "" : ": ", detail.c_str());
  std::fflush(stderr);
  std::abort();
}

bool writeAll(const std::string& path, const uint8_t* data, size_t size) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  const bool ok = (size == 0 || std::fwrite(data, 1, size, f) == size);
  return std::fclose(f) == 0 && ok;
}

/// What a PLY header holds that is known to trip vcglib 2020.09's reader,
/// seen the way it reads the header: fgets() chunks of at most 510 bytes,
/// a NUL ending the string strtok_r() splits at " \t\n\r".
struct PlyHeaderScan {
  /// plylib.cpp PlyFile::OpenRead: an "element NAME" line without a count
  /// passes NULL to atoi (it tests `name` twice instead of `token`): SIGSEGV.
  bool elementWithoutCount = false;
  /// import_ply.h: a "face" element with faces but no vertex index list of a
  /// type it has a descriptor for (e.g. "list uchar ushort vertex_indices",
  /// or none at all) is still read, leaving every face's indices as
  /// uninitialised stack memory.
  bool unreadableFaceIndices = false;
  /// plylib.cpp PlyFile::OpenRead: in the comment loop between "ply" and
  /// "format", a line without tokens after a comment gives strcmp(NULL): SIGSEGV.
  bool blankAfterLeadingComment = false;
  /// io.cpp checkPlyStructure: an element count near LLONG_MAX overflows the
  /// "count x properties" sum (signed overflow, UB) before it is compared
  /// with the file size.
  bool hugeElementCount = false;
};

std::string plyTypeName(const std::string& t) {  // the names FindType() accepts, normalised
  static const char* const alias[][2] = {{"int8", "char"},   {"uint8", "uchar"}, {"int16", "short"},
                                         {"uint16", "ushort"}, {"int32", "int"},   {"uint32", "uint"},
                                         {"float32", "float"}, {"float64", "double"}};
  for (const auto& a : alias)
    if (t == a[0]) return a[1];
  return t;
}

PlyHeaderScan scanPlyHeader(const uint8_t* data, size_t size) {
  // (index type, count type) pairs of vcglib's FaceDesc 0 and 13-24.
  static const char* const indices[][2] = {{"int", "uchar"},  {"int", "char"},    {"int", "int"},
                                           {"uint", "uchar"}, {"uint", "char"},   {"uint", "int"},
                                           {"uint", "ushort"}, {"short", "char"}, {"short", "uchar"},
                                           {"short", "int"}};
  static const char* const index[][2] = {{"int", "uchar"}, {"int", "char"}, {"int", "int"}};
  PlyHeaderScan r;
  bool inFace = false, faceHasIndex = false;
  long faceCount = 0;
  auto endFace = [&]() {
    if (inFace && faceCount > 0 && !faceHasIndex) r.unreadableFaceIndices = true;
    inFace = false;
  };
  size_t i = 0;
  int lineNo = 0;
  bool beforeFormat = true, prevComment = false;
  while (i < size) {
    ++lineNo;
    const size_t start = i;
    while (i < size && i - start < 510 && data[i] != '\n') ++i;
    if (i < size && data[i] == '\n' && i - start < 510) ++i;
    std::string line(reinterpret_cast<const char*>(data + start), i - start);
    line.resize(std::strlen(line.c_str()));
    std::vector<std::string> tok;
    std::size_t a = 0;
    while (tok.size() < 6) {
      a = line.find_first_not_of(" \t\r\n", a);
      if (a == std::string::npos) break;
      const std::size_t b = line.find_first_of(" \t\r\n", a);
      tok.push_back(line.substr(a, b == std::string::npos ? std::string::npos : b - a));
      if (b == std::string::npos) break;
      a = b;
    }
    if (lineNo == 1) continue;  // the magic line
    if (beforeFormat) {
      if (tok.empty()) {
        if (prevComment) r.blankAfterLeadingComment = true;
        break;  // vcglib stops here either way
      }
      prevComment = tok[0] == "comment";
      if (prevComment) continue;
      beforeFormat = false;
    }
    if (tok.empty()) continue;
    if (tok[0] == "end_header") break;
    if (tok[0] == "element") {
      endFace();
      if (tok.size() == 2) r.elementWithoutCount = true;
      if (tok.size() >= 3) {
        errno = 0;
        const long long n = std::strtoll(tok[2].c_str(), nullptr, 10);
        if (errno == ERANGE || n > (1LL << 40)) r.hugeElementCount = true;
      }
      if (tok.size() >= 3 && tok[1] == "face") {
        inFace = true;
        faceHasIndex = false;
        faceCount = std::atol(tok[2].c_str());  // what vcglib's atoi makes of it, near enough
      }
    } else if (tok[0] == "property" && inFace && tok.size() >= 5 && tok[1] == "list") {
      const std::string count = plyTypeName(tok[2]), idx = plyTypeName(tok[3]);
      if (tok[4] == "vertex_indices")
        for (const auto& t : indices) faceHasIndex = faceHasIndex || (idx == t[0] && count == t[1]);
      if (tok[4] == "vertex_index")
        for (const auto& t : index) faceHasIndex = faceHasIndex || (idx == t[0] && count == t[1]);
    }
  }
  endFace();
  return r;
}

/// Overwrites the stack below the caller's frame with zeros, so that what
/// vcglib leaves uninitialised there (see unreadableFaceIndices) reads the
/// same in every run: an input then always loads, or never does.
__attribute__((noinline)) void scrubStack() {
  volatile unsigned char pad[64 * 1024];
  for (std::size_t i = 0; i < sizeof(pad); ++i) pad[i] = 0;
}

/// Reported as fuzz/regressions/distance-*: surfaceDistance builds vcglib's
/// face grid on the faces' bounding box; a vertex (even an unreferenced one)
/// more than ~2^31 grid cells away overflows the cell index (UB) and
/// GridClosest never ends. True when a vertex lies farther than 1e6 face-box
/// diagonals from that box (or the faces have no extent at all).
template <class M>
bool farFromFaces(const M& m) {
  vcg::Box3d fb;
  for (const auto& f : m.face)
    if (!f.IsD())
      for (int k = 0; k < 3; ++k) fb.Add(vcg::Point3d(f.cP(k)[0], f.cP(k)[1], f.cP(k)[2]));
  if (fb.IsNull()) return false;
  const double diag = fb.Diag();
  for (const auto& v : m.vert) {
    if (v.IsD()) continue;
    const vcg::Point3d p(v.cP()[0], v.cP()[1], v.cP()[2]);
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double e = std::max(std::max(fb.min[k] - p[k], 0.0), p[k] - fb.max[k]);
      d2 += e * e;
    }
    if (d2 > 0 && !(std::sqrt(d2) <= 1e6 * diag)) return true;
  }
  return false;
}

template <class M>
bool hugeCoordinates(const M& m) {
  for (const auto& v : m.vert)
    for (int k = 0; k < 3; ++k)
      if (!v.IsD() && std::fabs(double(v.cP()[k])) > 1e150) return true;
  return false;
}

template <class M>
void checkFinite(const M& m, const char* stage) {
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    if (m.vert[i].IsD()) continue;
    const auto& p = m.vert[i].cP();
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(double(p[k])))
        fail("non-finite output coordinate", std::string(stage) + ", vertex " + std::to_string(i));
  }
}

template <class M>
void checkFaces(const M& m, const char* stage) {
  const auto* first = m.vert.empty() ? nullptr : &m.vert[0];
  for (std::size_t f = 0; f < m.face.size(); ++f) {
    if (m.face[f].IsD()) continue;
    for (int k = 0; k < 3; ++k) {
      const auto* v = m.face[f].cV(k);
      if (first == nullptr || v < first || v >= first + m.vert.size())
        fail("face vertex pointer out of range", std::string(stage) + ", face " + std::to_string(f));
    }
  }
}

template <class M>
void run(const std::string& path, uint8_t cfg, bool distance, const PlyHeaderScan& ply) {
  M m;
  sodt::LoadInfo info;
  // Reported as fuzz/regressions/vcgply-face-index-*: vcglib builds such
  // faces from uninitialised stack memory, so loadMesh either accepts
  // garbage faces or, by chance, fails with vcglib's "Bad vertex index in
  // face". Both are findings; a fix rejects the file with its own message
  // (or makes the face list readable: then drop this check).
  const char* const kGarbageIndexMsg = "Bad vertex index in face";
  scrubStack();
  try {
    sodt::loadMesh(path, m, &info);
  } catch (const sodt::InvalidInput& e) {
    if (ply.unreadableFaceIndices && std::strstr(e.what(), kGarbageIndexMsg) && !gSkipKnown)
      fail("loadMesh read a PLY face list vcglib cannot read (uninitialised indices)", e.what());
    return;
  } catch (const std::exception& e) {
    if (gStrict) fail("loadMesh threw something other than InvalidInput", e.what());
    return;
  }
  if (ply.unreadableFaceIndices && !gSkipKnown)
    fail("loadMesh accepted a PLY face list vcglib cannot read (uninitialised indices)");
  checkFinite(m, "after loadMesh");
  checkFaces(m, "after loadMesh");
  if (m.vert.size() + m.face.size() > static_cast<std::size_t>(kMaxElements)) return;
  // io.h: "On return the mesh is compact": no deleted element, vn and fn
  // equal to the vector sizes.
  {
    int liveV = 0, liveF = 0;
    for (const auto& v : m.vert) liveV += v.IsD() ? 0 : 1;
    for (const auto& f : m.face) liveF += f.IsD() ? 0 : 1;
    if (m.vn != static_cast<int>(m.vert.size()) || m.fn != static_cast<int>(m.face.size()) ||
        liveV != m.vn || liveF != m.fn) {
      // Reported as fuzz/regressions/loadply-*-flags-deleted-bit: a PLY
      // "flags" value with bit 0 (vcg DELETED) set.
      if (!gSkipKnown)
        fail("loadMesh returned a mesh that is not compact",
             "vn " + std::to_string(m.vn) + ", live " + std::to_string(liveV) + ", vert.size() " +
                 std::to_string(m.vert.size()) + "; fn " + std::to_string(m.fn) + ", live " +
                 std::to_string(liveF) + ", face.size() " + std::to_string(m.face.size()));
      m.vn = liveV;
      m.fn = liveF;
      if (liveV != static_cast<int>(m.vert.size()) || liveF != static_cast<int>(m.face.size())) return;
    }
  }

  sodt::MeshD ref;  // the loaded input, for the distance
  sodt::detail::copyToDouble(m, ref);

  sodt::SodtParams p;
  p.iterations = 1;
  switch ((cfg >> 1) & 3) {
    case 1: p.algorithm = sodt::Algorithm::Feature; break;
    case 2: p.algorithm = sodt::Algorithm::Denoise; break;
    default: p.algorithm = sodt::Algorithm::Basic; break;
  }
  p.flips = (cfg & 8) != 0;
  p.guard = (cfg & 16) ? sodt::Guard::Fold : sodt::Guard::Quality;
  p.keepBest = (cfg & 32) != 0;
  p.selectedOnly = (cfg & 128) != 0;

  const int vn0 = m.vn, fn0 = m.fn;
  sodt::SodtStats st;
  try {
    st = sodt::SodtSmoother<M>::Apply(m, p);
  } catch (const std::exception& e) {
    // The parameters are valid and loadMesh rejects non-finite coordinates,
    // so Apply has no reason left to throw.
    fail("SodtSmoother::Apply threw", e.what());
  }
  if (m.vn != vn0 || m.fn != fn0) fail("Apply changed the vertex or face count");
  const long long visits = st.moved + st.backtracked + st.fallbackMoves + st.rejected + st.failedSolves + st.unchanged;
  if (visits != static_cast<long long>(st.activeVertices) * st.iterations)
    fail("SodtStats visit counters do not add up",
         std::to_string(visits) + " != " + std::to_string(st.activeVertices) + " x " + std::to_string(st.iterations));
  if (st.flips > 0 && !p.flips) fail("edges flipped with flips off");
  checkFinite(m, "after Apply");
  checkFaces(m, "after Apply");

  // Reported as fuzz/regressions/{distance-huge-coordinate,anglestats-huge-*}:
  // finite coordinates beyond ~1e154 overflow squared norms and bounding-box
  // diagonals (NaN angles, NaN grid cells, SIGSEGV or a hang in surfaceDistance).
  if (gSkipKnown && (hugeCoordinates(m) || hugeCoordinates(ref))) return;
  try {
    const sodt::AngleStats a = sodt::computeAngleStats(m);
    if (a.faces > 0 && !(a.minDeg >= 0 && a.minDeg <= a.maxDeg && a.maxDeg <= 180))
      fail("computeAngleStats out of range", std::to_string(a.minDeg) + " .. " + std::to_string(a.maxDeg));
    (void)sodt::enclosedVolume(m);
    if (distance && !(gSkipKnown && (farFromFaces(m) || farFromFaces(ref)))) (void)sodt::surfaceDistance(m, ref);
  } catch (const std::exception& e) {
    fail("a metric threw", e.what());
  }
  checkFinite(m, "after the metrics");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* tmp = std::getenv("TMPDIR");
  std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/sodt_fuzz_XXXXXX";
  if (::mkdtemp(&templ[0]) == nullptr) {
    std::perror("fuzz_mesh: mkdtemp");
    std::abort();
  }
  gDir = templ;
  std::atexit(removeScratch);
  const char* strict = std::getenv("SODT_FUZZ_STRICT");
  gStrict = strict && *strict && std::strcmp(strict, "0") != 0;
  const char* skip = std::getenv("SODT_FUZZ_SKIP_KNOWN");
  gSkipKnown = skip && *skip && std::strcmp(skip, "0") != 0;
  const char* every = std::getenv("SODT_FUZZ_DISTANCE_EVERY");
  if (every && *every) gDistanceEvery = static_cast<unsigned>(std::strtoul(every, nullptr, 10));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t cfg = data[0];
  const bool plain = ((cfg >> 1) & 3) == 3;  // OBJ or STL
  const std::string path =
      gDir + (plain ? ((cfg & 1) ? "/input.stl" : "/input.obj") : ((cfg & 1) ? "/input.off" : "/input.ply"));
  if (!writeAll(path, data + 1, size - 1)) {
    std::perror("fuzz_mesh: cannot write the scratch file");
    std::abort();
  }
  const PlyHeaderScan ply = (cfg & 1) || plain ? PlyHeaderScan() : scanPlyHeader(data + 1, size - 1);
  if (gSkipKnown &&
      (ply.elementWithoutCount || ply.unreadableFaceIndices || ply.blankAfterLeadingComment || ply.hugeElementCount))
    return 0;
  const bool distance = wantDistance(data, size);
  if (cfg & 64)
    run<sodt::MeshF>(path, cfg, distance, ply);
  else
    run<sodt::MeshD>(path, cfg, distance, ply);
  return 0;
}
