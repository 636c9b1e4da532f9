// SPDX-License-Identifier: GPL-3.0-or-later
// End-to-end tests of the `sodt` executable: exit codes and messages on bad
// input, outputs never created or modified on failure, reports, round trips.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#ifndef SODT_BIN
#error "SODT_BIN must name the sodt executable"
#endif

namespace {

// ---------------------------------------------------------------------------
// Files and processes

/// A fresh directory under $TMPDIR (or /tmp), removed with its files.
class TempDir {
 public:
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string templ = std::string(base && *base ? base : "/tmp") + "/sodt_cli_test_XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    if (::mkdtemp(buf.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = buf.data();
  }
  ~TempDir() {
    for (const std::string& name : entries()) ::unlink((path_ + "/" + name).c_str());
    ::rmdir(path_.c_str());
  }
  /// Path of a file in the directory.
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }
  /// Names in the directory, without "." and "..".
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    if (DIR* d = ::opendir(path_.c_str())) {
      while (dirent* e = ::readdir(d)) {
        const std::string n = e->d_name;
        if (n != "." && n != "..") names.push_back(n);
      }
      ::closedir(d);
    }
    return names;
  }

 private:
  std::string path_;
};

bool exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

void writeFile(const std::string& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f << bytes;
  ASSERT_TRUE(f.good()) << p;
}

std::string readFile(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// Single-quotes a word for /bin/sh.
std::string shellQuote(const std::string& s) {
  std::string r = "'";
  for (char c : s) r += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return r + "'";
}

struct RunResult {
  int exitCode = -1;  ///< -1 when the process did not exit normally
  std::string out, err;
};

/// Runs the sodt binary with the given arguments, capturing stdout and stderr.
RunResult runSodt(const std::vector<std::string>& args, const TempDir& dir) {
  std::string cmd = shellQuote(SODT_BIN);
  for (const std::string& a : args) cmd += " " + shellQuote(a);
  const std::string outPath = dir / "stdout.txt", errPath = dir / "stderr.txt";
  cmd += " </dev/null >" + shellQuote(outPath) + " 2>" + shellQuote(errPath);
  const int status = std::system(cmd.c_str());
  RunResult r;
  if (status != -1 && WIFEXITED(status)) r.exitCode = WEXITSTATUS(status);
  r.out = readFile(outPath);
  r.err = readFile(errPath);
  ::unlink(outPath.c_str());
  ::unlink(errPath.c_str());
  return r;
}

/// The number after "key": in a JSON text; NaN when absent or null.
double jsonNumber(const std::string& json, const std::string& key) {
  const std::string k = "\"" + key + "\":";
  const std::size_t at = json.find(k);
  if (at == std::string::npos) return std::numeric_limits<double>::quiet_NaN();
  const char* p = json.c_str() + at + k.size();
  while (*p == ' ') ++p;
  char* end = nullptr;
  const double v = std::strtod(p, &end);
  return end == p ? std::numeric_limits<double>::quiet_NaN() : v;
}

/// Number of elements of the integer array after "key": (-1 when absent).
int jsonArrayLength(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\": [");
  if (at == std::string::npos) return -1;
  const std::size_t open = json.find('[', at), close = json.find(']', open);
  const std::string body = json.substr(open + 1, close - open - 1);
  if (body.find_first_not_of(" ") == std::string::npos) return 0;
  int n = 1;
  for (char c : body) n += c == ',';
  return n;
}

// ---------------------------------------------------------------------------
// Test meshes

/// Triangle mesh as plain arrays.
struct SimpleMesh {
  std::vector<double> xyz;
  std::vector<int> tri;
  int vertices() const { return static_cast<int>(xyz.size() / 3); }
  int faces() const { return static_cast<int>(tri.size() / 3); }
};

double uniform(std::mt19937& g, double lo, double hi) { return lo + (hi - lo) * ((g() >> 5) * (1.0 / 134217728.0)); }

/// Unit icosphere (10*4^s+2 vertices, outward orientation) whose vertices are
/// moved tangentially by up to `jitter` mean edge lengths and put back on the
/// sphere: a closed mesh with poor angles.
SimpleMesh jitteredSphere(int subdiv, double jitter, unsigned seed) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  SimpleMesh m;
  m.xyz = {-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t,
           0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1};
  m.tri = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
           3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  auto normalize = [&m](int v) {
    double* p = &m.xyz[3 * v];
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; ++k) p[k] /= n;
  };
  for (int v = 0; v < m.vertices(); ++v) normalize(v);
  for (int s = 0; s < subdiv; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      for (int k = 0; k < 3; ++k) m.xyz.push_back(0.5 * (m.xyz[3 * a + k] + m.xyz[3 * b + k]));
      const int v = m.vertices() - 1;
      normalize(v);
      mid[key] = v;
      return v;
    };
    std::vector<int> next;
    for (int f = 0; f < m.faces(); ++f) {
      const int a = m.tri[3 * f], b = m.tri[3 * f + 1], c = m.tri[3 * f + 2];
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      const int sub[12] = {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca};
      next.insert(next.end(), sub, sub + 12);
    }
    m.tri.swap(next);
  }
  const double edge = 1.1 / std::pow(2.0, subdiv);  // about the icosphere's mean edge
  std::mt19937 g(seed);
  for (int v = 0; v < m.vertices(); ++v) {
    double* p = &m.xyz[3 * v];
    double d[3] = {uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1)};
    const double dn = d[0] * p[0] + d[1] * p[1] + d[2] * p[2];
    for (int k = 0; k < 3; ++k) p[k] += jitter * edge * (d[k] - dn * p[k]);
    normalize(v);
  }
  return m;
}

std::string toOff(const SimpleMesh& m) {
  std::string s = "OFF\n" + std::to_string(m.vertices()) + " " + std::to_string(m.faces()) + " 0\n";
  char buf[128];
  for (int v = 0; v < m.vertices(); ++v) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]);
    s += buf;
  }
  for (int f = 0; f < m.faces(); ++f)
    s += "3 " + std::to_string(m.tri[3 * f]) + " " + std::to_string(m.tri[3 * f + 1]) + " " +
         std::to_string(m.tri[3 * f + 2]) + "\n";
  return s;
}

/// ASCII PLY with a per-vertex "flags" property; the first `selected`
/// vertices carry vcglib's selection bit (0x20).
std::string toPlyWithFlags(const SimpleMesh& m, int selected) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(m.vertices()) +
                  "\nproperty double x\nproperty double y\nproperty double z\nproperty int flags\n"
                  "element face " +
                  std::to_string(m.faces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  char buf[160];
  for (int v = 0; v < m.vertices(); ++v) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %d\n", m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2],
                  v < selected ? 0x20 : 0);
    s += buf;
  }
  for (int f = 0; f < m.faces(); ++f)
    s += "3 " + std::to_string(m.tri[3 * f]) + " " + std::to_string(m.tri[3 * f + 1]) + " " +
         std::to_string(m.tri[3 * f + 2]) + "\n";
  return s;
}

/// A test directory holding in.off, a jittered icosphere with 642 vertices.
class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    mesh_ = jitteredSphere(3, 0.35, 7u);
    in_ = dir_ / "in.off";
    writeFile(in_, toOff(mesh_));
  }
  /// Asserts a usage error: exit 2, one error line and the help hint.
  static void expectUsageError(const RunResult& r) {
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.find("sodt: error: "), 0u) << r.err;
    EXPECT_NE(r.err.find("see 'sodt"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  /// Asserts an input/output failure: exit 1 and one error line.
  static void expectFailure(const RunResult& r) {
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(r.err.find("sodt: error: "), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  /// Asserts that the directory holds nothing but the given names.
  void expectOnly(std::vector<std::string> names) const {
    std::vector<std::string> got = dir_.entries();
    std::sort(got.begin(), got.end());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(got, names);
  }

  TempDir dir_;
  SimpleMesh mesh_;
  std::string in_;
};

// ---------------------------------------------------------------------------
// Usage errors: exit 2, OUT untouched

TEST_F(CliTest, NoArgumentsIsUsageError) { expectUsageError(runSodt({}, dir_)); }

TEST_F(CliTest, UnknownSubcommandIsUsageError) {
  const RunResult r = runSodt({"frobnicate", in_}, dir_);
  expectUsageError(r);
  EXPECT_NE(r.err.find("frobnicate"), std::string::npos);
}

TEST_F(CliTest, UnknownOptionIsUsageError) {
  const std::string out = dir_ / "out.ply";
  const RunResult r = runSodt({"smooth", in_, out, "--bogus"}, dir_);
  expectUsageError(r);
  EXPECT_NE(r.err.find("--bogus"), std::string::npos);
  EXPECT_FALSE(exists(out));
  expectUsageError(runSodt({"--bogus"}, dir_));
  expectUsageError(runSodt({"stats", in_, "--iterations", "3"}, dir_));
}

TEST_F(CliTest, BadIterationValuesAreUsageErrors) {
  const std::string out = dir_ / "out.ply";
  for (const char* v : {"-1", "abc", "1.5", "", "12x", "99999999999999999999", "100001"})
    expectUsageError(runSodt({"smooth", in_, out, "--iterations", v}, dir_));
  expectUsageError(runSodt({"smooth", in_, out, "--iterations=-1"}, dir_));
  expectUsageError(runSodt({"smooth", in_, out, "--max-backtracks", "61"}, dir_));
  expectUsageError(runSodt({"smooth", in_, out, "--laplacian-fallback", "maybe"}, dir_));
  EXPECT_FALSE(exists(out));
}

TEST_F(CliTest, MissingOptionValueIsUsageError) {
  const RunResult r = runSodt({"smooth", in_, dir_ / "out.ply", "--iterations"}, dir_);
  expectUsageError(r);
  EXPECT_NE(r.err.find("needs a value"), std::string::npos) << r.err;
  expectUsageError(runSodt({"smooth", in_, dir_ / "out.ply", "--quiet=yes"}, dir_));
}

TEST_F(CliTest, UnknownGuardOrAlgorithmIsUsageError) {
  const std::string out = dir_ / "out.ply";
  const RunResult r = runSodt({"smooth", in_, out, "--guard", "bogus"}, dir_);
  expectUsageError(r);
  EXPECT_NE(r.err.find("bogus"), std::string::npos);
  expectUsageError(runSodt({"smooth", in_, out, "--algorithm", "optimal"}, dir_));
  EXPECT_FALSE(exists(out));
}

TEST_F(CliTest, WrongNumberOfFilesIsUsageError) {
  expectUsageError(runSodt({"smooth", in_}, dir_));
  expectUsageError(runSodt({"smooth", in_, dir_ / "a.ply", dir_ / "b.ply"}, dir_));
  expectUsageError(runSodt({"stats"}, dir_));
  expectUsageError(runSodt({"stats", in_, in_}, dir_));
  expectOnly({"in.off"});
}

TEST_F(CliTest, UnsupportedOutputExtensionIsUsageError) {
  const RunResult r = runSodt({"smooth", in_, dir_ / "out.stl"}, dir_);
  expectUsageError(r);
  expectUsageError(runSodt({"smooth", in_, dir_ / "out.obj"}, dir_));
  expectOnly({"in.off"});
}

TEST_F(CliTest, ReportMayNotOverwriteOutOrInput) {
  const std::string out = dir_ / "out.ply";
  expectUsageError(runSodt({"smooth", in_, out, "--report", out}, dir_));
  expectUsageError(runSodt({"smooth", in_, out, "--report", in_}, dir_));
  expectUsageError(runSodt({"stats", in_, "--json", in_}, dir_));
  expectOnly({"in.off"});
}

TEST_F(CliTest, SelectedOnlyWithoutSelectionIsUsageError) {
  const std::string out = dir_ / "out.ply";
  const RunResult r = runSodt({"smooth", in_, out, "--selected-only"}, dir_);
  expectUsageError(r);
  EXPECT_NE(r.err.find("no selected vertices"), std::string::npos) << r.err;
  expectOnly({"in.off"});
}

TEST_F(CliTest, HelpAndVersion) {
  RunResult r = runSodt({"--help"}, dir_);
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("usage: sodt"), std::string::npos);
  r = runSodt({"smooth", "--help"}, dir_);
  EXPECT_EQ(r.exitCode, 0);
  for (const char* opt : {"--iterations", "--guard", "--max-backtracks", "--selected-only", "--report", "--quiet"})
    EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
  EXPECT_NE(r.out.find("(default "), std::string::npos);
  r = runSodt({"stats", "-h"}, dir_);
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("--reference"), std::string::npos);
  r = runSodt({"--version"}, dir_);
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_EQ(r.out.find("sodt "), 0u);
}

// ---------------------------------------------------------------------------
// Input errors: exit 1, OUT never created or modified

TEST_F(CliTest, MissingInputFileFails) {
  const std::string out = dir_ / "out.ply";
  const RunResult r = runSodt({"smooth", dir_ / "nope.ply", out}, dir_);
  expectFailure(r);
  EXPECT_NE(r.err.find("nope.ply"), std::string::npos) << r.err;
  expectOnly({"in.off"});
  expectFailure(runSodt({"stats", dir_ / "nope.off"}, dir_));
}

TEST_F(CliTest, ObjInputIsRejected) {
  const std::string obj = dir_ / "in.OBJ";
  writeFile(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const RunResult r = runSodt({"smooth", obj, dir_ / "out.ply"}, dir_);
  expectFailure(r);
  EXPECT_NE(r.err.find("OBJ is not supported; convert to PLY or OFF"), std::string::npos) << r.err;
  expectOnly({"in.off", "in.OBJ"});
}

TEST_F(CliTest, CorruptPlyFails) {
  const std::string bad = dir_ / "bad.ply";
  std::string garbage;
  std::mt19937 g(3);
  for (int i = 0; i < 4096; ++i) garbage += static_cast<char>(g() & 0xff);
  writeFile(bad, garbage);
  const RunResult r = runSodt({"smooth", bad, dir_ / "out.ply"}, dir_);
  expectFailure(r);
  EXPECT_NE(r.err.find("bad.ply"), std::string::npos) << r.err;

  // A valid header with too few vertices after it, and an absurd count.
  writeFile(bad, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0\n1 0 0\n");
  expectFailure(runSodt({"smooth", bad, dir_ / "out.ply"}, dir_));
  writeFile(bad, "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\n"
                 "property float y\nproperty float z\nend_header\n");
  expectFailure(runSodt({"stats", bad}, dir_));
  // A face index past the vertex count.
  writeFile(bad, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  expectFailure(runSodt({"smooth", bad, dir_ / "out.ply"}, dir_));
  expectOnly({"in.off", "bad.ply"});
}

TEST_F(CliTest, CorruptOffFails) {
  const std::string bad = dir_ / "bad.off";
  const std::vector<std::string> cases = {
      "",                                                     // empty
      "PLY\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",           // no OFF keyword
      "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n",           // index out of range
      "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n",          // negative index
      "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n",             // two-corner face
      "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",           // truncated faces
      "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",           // truncated vertices
      "OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n",        // bad number
      "OFF\n999999999 1 0\n0 0 0\n",                          // absurd count
  };
  for (const std::string& c : cases) {
    writeFile(bad, c);
    const RunResult r = runSodt({"smooth", bad, dir_ / "out.off"}, dir_);
    expectFailure(r);
    EXPECT_NE(r.err.find("bad.off"), std::string::npos) << r.err;
  }
  expectOnly({"in.off", "bad.off"});
}

TEST_F(CliTest, NonFiniteCoordinateFails) {
  const std::string bad = dir_ / "nan.off";
  writeFile(bad, "OFF\n4 4 0\n0 0 0\n1 0 0\nnan 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n");
  RunResult r = runSodt({"smooth", bad, dir_ / "out.ply"}, dir_);
  expectFailure(r);
  EXPECT_NE(r.err.find("vertex 2"), std::string::npos) << r.err;
  writeFile(bad, "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 inf\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n");
  r = runSodt({"stats", bad}, dir_);
  expectFailure(r);
  EXPECT_NE(r.err.find("vertex 3"), std::string::npos) << r.err;
  expectOnly({"in.off", "nan.off"});
}

TEST_F(CliTest, MeshWithoutTrianglesFails) {
  const std::string pts = dir_ / "points.off";
  writeFile(pts, "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  const RunResult r = runSodt({"smooth", pts, dir_ / "out.ply"}, dir_);
  expectFailure(r);
  EXPECT_NE(r.err.find("no triangles"), std::string::npos) << r.err;
  expectOnly({"in.off", "points.off"});
}

TEST_F(CliTest, FailureLeavesExistingOutputByteIdentical) {
  const std::string out = dir_ / "out.ply", report = dir_ / "r.json";
  const std::string before = "not a mesh, but must survive\n";
  writeFile(out, before);
  writeFile(report, "{}\n");
  const std::string bad = dir_ / "bad.ply";
  writeFile(bad, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nzzz\n");
  expectFailure(runSodt({"smooth", bad, out, "--report", report}, dir_));
  expectFailure(runSodt({"smooth", dir_ / "missing.off", out, "--report", report}, dir_));
  expectUsageError(runSodt({"smooth", in_, out, "--iterations", "abc", "--report", report}, dir_));
  EXPECT_EQ(readFile(out), before);
  EXPECT_EQ(readFile(report), "{}\n");
  expectOnly({"in.off", "out.ply", "r.json", "bad.ply"});  // no temporary files left
}

TEST_F(CliTest, UnwritableOutputDirectoryFails) {
  const RunResult r = runSodt({"smooth", in_, dir_ / "no_such_dir/out.ply"}, dir_);
  expectFailure(r);
  EXPECT_NE(r.err.find("out.ply"), std::string::npos) << r.err;
  expectOnly({"in.off"});
}

// ---------------------------------------------------------------------------
// Successful runs

TEST_F(CliTest, SmoothImprovesMinAngleAndWritesReport) {
  const std::string out = dir_ / "out.ply", report = dir_ / "report.json";
  const RunResult r = runSodt({"smooth", in_, out, "--report", report}, dir_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;  // no progress bar when stderr is not a terminal
  EXPECT_NE(r.out.find("min angle"), std::string::npos) << r.out;
  ASSERT_TRUE(exists(out));
  const std::string json = readFile(report);
  for (const char* key :
       {"input", "output", "vertices", "faces", "algorithm", "guard", "iterations", "seconds", "before", "after",
        "min_angle", "max_angle", "angle_histogram", "frac_below_30", "frac_above_90", "p1_tri_min_angle",
        "volume", "volume_before", "volume_after", "volume_rel_change", "hausdorff_rel", "inverted_faces", "moved", "fallback_moves", "laplacian_fallback",
        "backtracked", "rejected", "failed_solves", "unchanged", "fixed_boundary", "fixed_nonmanifold",
        "cancelled", "min_angle_before", "min_angle_after", "max_angle_before", "max_angle_after"})
    EXPECT_NE(json.find("\"" + std::string(key) + "\":"), std::string::npos) << key;
  EXPECT_EQ(jsonNumber(json, "vertices"), mesh_.vertices());
  EXPECT_EQ(jsonNumber(json, "faces"), mesh_.faces());
  EXPECT_EQ(jsonArrayLength(json, "angle_histogram"), 180);
  const double lo0 = jsonNumber(json, "min_angle_before"), lo1 = jsonNumber(json, "min_angle_after");
  ASSERT_TRUE(std::isfinite(lo0) && std::isfinite(lo1)) << json;
  EXPECT_GE(lo1, lo0);
  EXPECT_GT(jsonNumber(json, "frac_below_30"), 0.0);  // the "before" object comes first
  EXPECT_EQ(jsonNumber(json, "inverted_faces"), 0);
  EXPECT_LT(jsonNumber(json, "hausdorff_rel"), 0.1);
  EXPECT_TRUE(std::isfinite(jsonNumber(json, "volume_rel_change"))) << "the sphere is closed";
  EXPECT_EQ(jsonNumber(json, "iterations"), 20);
  expectOnly({"in.off", "out.ply", "report.json"});

  // The output reads back with the same counts and the reported angles.
  const RunResult s = runSodt({"stats", out}, dir_);
  ASSERT_EQ(s.exitCode, 0) << s.err;
  EXPECT_EQ(jsonNumber(s.out, "vertices"), mesh_.vertices());
  EXPECT_NEAR(jsonNumber(s.out, "min_angle"), lo1, 1e-9);
}

TEST_F(CliTest, GuardNoneAndFoldRun) {
  for (const char* g : {"none", "fold", "quality"}) {
    const std::string out = dir_ / (std::string("out_") + g + ".ply"), report = dir_ / "r.json";
    const RunResult r =
        runSodt({"smooth", in_, out, "--guard", g, "--iterations", "5", "--report", report, "--quiet"}, dir_);
    ASSERT_EQ(r.exitCode, 0) << g << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << "--quiet prints nothing: " << r.out;
    EXPECT_TRUE(exists(out)) << g;
    const std::string json = readFile(report);
    EXPECT_NE(json.find(std::string("\"guard\": \"") + g + "\""), std::string::npos) << json;
    EXPECT_EQ(jsonNumber(json, "sweeps"), 5);
  }
}

TEST_F(CliTest, OffRoundTripKeepsTheMesh) {
  const std::string out = dir_ / "out.OFF";
  const RunResult r = runSodt({"smooth", in_, out, "--iterations", "0", "--quiet"}, dir_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const RunResult s = runSodt({"stats", out, "--reference", in_}, dir_);
  ASSERT_EQ(s.exitCode, 0) << s.err;
  EXPECT_EQ(jsonNumber(s.out, "vertices"), mesh_.vertices());
  EXPECT_EQ(jsonNumber(s.out, "faces"), mesh_.faces());
  EXPECT_LT(jsonNumber(s.out, "hausdorff_rel"), 1e-12);
  EXPECT_EQ(jsonNumber(s.out, "inverted_faces"), 0);

  // Smoothed, written as OFF, read back: same counts as the PLY path.
  const std::string smoothed = dir_ / "smoothed.off";
  ASSERT_EQ(runSodt({"smooth", in_, smoothed, "--quiet"}, dir_).exitCode, 0);
  const RunResult t = runSodt({"stats", smoothed}, dir_);
  ASSERT_EQ(t.exitCode, 0) << t.err;
  EXPECT_EQ(jsonNumber(t.out, "faces"), mesh_.faces());
}

TEST_F(CliTest, StatsPrintsJson) {
  const RunResult r = runSodt({"stats", in_}, dir_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out.front(), '{');
  EXPECT_EQ(jsonNumber(r.out, "vertices"), mesh_.vertices());
  EXPECT_EQ(jsonNumber(r.out, "faces"), mesh_.faces());
  EXPECT_NE(r.out.find("\"closed\": true"), std::string::npos) << r.out;
  EXPECT_GT(jsonNumber(r.out, "volume"), 0.0) << "outward orientation gives a positive volume";
  EXPECT_EQ(jsonArrayLength(r.out, "angle_histogram"), 180);
  EXPECT_EQ(r.out.find("hausdorff_rel"), std::string::npos) << "only with --reference";

  const std::string file = dir_ / "stats.json";
  const RunResult f = runSodt({"stats", in_, "--json", file}, dir_);
  ASSERT_EQ(f.exitCode, 0) << f.err;
  EXPECT_TRUE(f.out.empty());
  EXPECT_EQ(readFile(file), r.out);
}

TEST_F(CliTest, StatsAgainstItselfHasZeroDistance) {
  const RunResult r = runSodt({"stats", in_, "--reference", in_}, dir_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // Zero up to the rounding of the sample points placed on the triangles.
  EXPECT_LE(jsonNumber(r.out, "hausdorff_rel"), 1e-12) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "inverted_faces"), 0.0) << r.out;

  // A reference with other counts: distances, but no face correspondence.
  const std::string other = dir_ / "other.off";
  writeFile(other, toOff(jitteredSphere(2, 0.0, 1u)));
  const RunResult o = runSodt({"stats", in_, "--reference", other}, dir_);
  ASSERT_EQ(o.exitCode, 0) << o.err;
  EXPECT_NE(o.out.find("\"inverted_faces\": null"), std::string::npos) << o.out;
  EXPECT_LT(jsonNumber(o.out, "hausdorff_rel"), 0.1);
}

TEST_F(CliTest, OutputMayReplaceTheInput) {
  const std::string work = dir_ / "work.off";
  const std::string original = toOff(mesh_);
  writeFile(work, original);
  const RunResult r = runSodt({"smooth", work, work, "--quiet"}, dir_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(readFile(work), original);
  EXPECT_EQ(jsonNumber(runSodt({"stats", work}, dir_).out, "vertices"), mesh_.vertices());
  expectOnly({"in.off", "work.off"});
}

TEST_F(CliTest, SelectionFromPlyFlagsLimitsTheMovedVertices) {
  const std::string in = dir_ / "sel.ply", out = dir_ / "out.ply", report = dir_ / "r.json";
  writeFile(in, toPlyWithFlags(mesh_, 100));
  const RunResult r = runSodt({"smooth", in, out, "--selected-only", "--report", report, "--quiet"}, dir_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(jsonNumber(readFile(report), "active_vertices"), 100);
  EXPECT_NE(readFile(out).find("property int flags"), std::string::npos) << "the selection is kept";

  // The selection survives the round trip: the output drives a second run.
  const std::string out2 = dir_ / "out2.ply";
  ASSERT_EQ(runSodt({"smooth", out, out2, "--selected-only", "--report", report, "--quiet"}, dir_).exitCode, 0);
  EXPECT_EQ(jsonNumber(readFile(report), "active_vertices"), 100);
}

TEST_F(CliTest, PlyWithLongHeaderCommentLoads) {
  // vcglib's header parser stops at 512-byte lines; the loader works around it.
  std::string ply = toPlyWithFlags(mesh_, 0);
  const std::size_t at = ply.find("element vertex");
  ply.insert(at, "comment meta: " + std::string(700, 'x') + "\n");
  const std::string in = dir_ / "long.ply";
  writeFile(in, ply);
  const RunResult r = runSodt({"stats", in}, dir_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(jsonNumber(r.out, "vertices"), mesh_.vertices());
  expectOnly({"in.off", "long.ply"});
}

TEST_F(CliTest, BundledBlobsMesh) {
  const std::string blobs = std::string(SODT_MESH_DIR) + "/blobs_mc.ply";
  if (!exists(blobs)) GTEST_SKIP() << blobs << " is missing (generated into meshes/)";
  const std::string out = dir_ / "blobs.ply", report = dir_ / "r.json";
  const RunResult r = runSodt({"smooth", blobs, out, "--report", report, "--quiet"}, dir_);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string json = readFile(report);
  EXPECT_GE(jsonNumber(json, "min_angle_after"), jsonNumber(json, "min_angle_before"));
  EXPECT_EQ(jsonNumber(json, "inverted_faces"), 0);
}

}  // namespace
