// SPDX-License-Identifier: GPL-3.0-or-later
// The defect zoo, bad files and bad parameters through the built `sodt`
// binary. Never a crash or a hang; either exit 0 with a finite output whose
// fixed vertices kept their bits, or exit 1 with one "sodt: error:" line and
// OUT left exactly as it was (usage errors: exit 2). No temporary file is
// ever left behind.
#include "cli_runner.h"
#include "defect_zoo.h"
#include "zoo_checks.h"

#include <gtest/gtest.h>

#include <sodt_io/io.h>
#include <sodt_io/metrics.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace {

using sodt_zoo::Kind;
using sodt_zoo::RunResult;
using sodt_zoo::TempDir;
using sodt_zoo::ZooMesh;

const char kSentinel[] = "sentinel: OUT existed before the run and must survive a failed run\n";

/// The number after "key": in a JSON text; NaN when absent or null.
double jsonNumber(const std::string& json, const std::string& key) {
  const std::string k = "\"" + key + "\":";
  const std::size_t at = json.find(k);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + at + k.size(), nullptr);
}

/// The run failed the documented way: exit 1, exactly one stderr line
/// "sodt: error: ..." containing `what`, OUT untouched, nothing new in dir.
void expectCleanFailure(const RunResult& r, const std::string& what, const TempDir& dir, const std::string& out,
                        const std::vector<std::string>& entriesBefore) {
  ASSERT_FALSE(r.crashed()) << r.describe();
  EXPECT_EQ(r.exitCode, 1) << r.describe();
  const std::vector<std::string> lines = r.errLines();
  ASSERT_EQ(lines.size(), 1u) << "expected one stderr line: " << r.describe();
  EXPECT_EQ(lines[0].rfind("sodt: error: ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(what), std::string::npos) << "'" << lines[0] << "' does not mention '" << what << "'";
  EXPECT_EQ(sodt_zoo::slurp(out), kSentinel) << "OUT was modified by a failed run";
  EXPECT_EQ(dir.entries(), entriesBefore) << "files were created or removed";
}

/// One successful run: output readable, finite, same counts as the input as
/// the project's loader reads it; with `fixedBits`, every vertex the zoo
/// expects to stay fixed has the same bits in OUT as in IN.
void expectSmoothed(const RunResult& r, const ZooMesh& z, const std::string& in, const std::string& out,
                    bool fixedBits) {
  ASSERT_FALSE(r.crashed()) << r.describe();
  ASSERT_EQ(r.exitCode, 0) << r.describe();
  EXPECT_EQ(r.err, "");
  sodt::MeshD a, b;
  ASSERT_NO_THROW(sodt::loadMesh(in, a));
  try {
    sodt::loadMesh(out, b);
  } catch (const std::exception& e) {
    FAIL() << "output does not load: " << e.what();
  }
  EXPECT_TRUE(sodt_zoo::allFinite(b));
  ASSERT_EQ(a.vn, b.vn);
  ASSERT_EQ(a.fn, b.fn);
  if (!fixedBits) return;
  ASSERT_EQ(static_cast<std::size_t>(a.vn), z.kind.size()) << "the loader changed the vertex list";
  for (std::size_t i = 0; i < z.kind.size(); ++i) {
    if (z.kind[i] == Kind::Interior) continue;
    EXPECT_TRUE(sodt_zoo::sameBits<sodt::MeshD>(a.vert[i].cP(), b.vert[i].cP()))
        << sodt_zoo::toString(z.kind[i]) << " vertex " << i << " moved";
  }
}

// ---------------------------------------------------------------------------
// The zoo

std::vector<std::string> cliZooNames() {
  std::vector<std::string> names;
  for (const std::string& n : sodt_zoo::zooNames())
    if (!sodt_zoo::zooMesh(n).coreOnly) names.push_back(n);
  return names;
}

class CliZoo : public testing::TestWithParam<std::string> {};

TEST_P(CliZoo, SmoothsOrFailsCleanly) {
  const ZooMesh z = sodt_zoo::zooMesh(GetParam());
  TempDir dir;
  const std::string plyIn = dir / "in.ply", asciiIn = dir / "in_ascii.ply", offIn = dir / "in.off";
  sodt_zoo::writePly(plyIn, z.soup, sodt_zoo::PlyEncoding::BinaryLE, true);
  sodt_zoo::writePly(asciiIn, z.soup, sodt_zoo::PlyEncoding::Ascii, false);
  if (z.offText.empty())
    sodt_zoo::writeOff(offIn, z.soup);
  else
    sodt_zoo::writeText(offIn, z.offText);

  struct Variant {
    std::string in, out;
    std::vector<std::string> options;
    bool fixedBits;  ///< compare the fixed vertices bit for bit (PLY in and out)
  };
  const std::vector<Variant> variants = {
      {plyIn, dir / "out.ply", {"--report", dir / "report.json"}, true},
      {offIn, dir / "out.off", {"--algorithm", "feature", "--flips"}, false},
      {asciiIn, dir / "out_ascii.ply", {"--algorithm", "denoise", "--guard", "fold", "--keep-best"}, true},
  };
  for (const Variant& v : variants) {
    SCOPED_TRACE(v.in + " -> " + v.out);
    std::vector<std::string> args = {"smooth", v.in, v.out, "--quiet"};
    args.insert(args.end(), v.options.begin(), v.options.end());
    if (!z.cliError.empty()) {
      // Without an OUT: none is created. With one: it is left as it was.
      std::vector<std::string> before = dir.entries();
      const RunResult fresh = sodt_zoo::runSodt(args);
      ASSERT_FALSE(fresh.crashed()) << fresh.describe();
      EXPECT_EQ(fresh.exitCode, 1) << fresh.describe();
      EXPECT_EQ(dir.entries(), before) << "a failed run created files";
      sodt_zoo::writeText(v.out, kSentinel);
      before = dir.entries();
      expectCleanFailure(sodt_zoo::runSodt(args), z.cliError, dir, v.out, before);
      continue;
    }
    const RunResult r = sodt_zoo::runSodt(args);
    expectSmoothed(r, z, v.in, v.out, v.fixedBits);
  }
  {
    // `sodt stats` measures what `sodt smooth` accepts and rejects the rest.
    const RunResult r = sodt_zoo::runSodt({"stats", plyIn});
    ASSERT_FALSE(r.crashed()) << r.describe();
    EXPECT_EQ(r.exitCode, z.cliError.empty() ? 0 : 1) << r.describe();
  }
  if (z.cliError.empty()) {
    // The report counts the fixed vertices as the zoo expects.
    const std::string report = sodt_zoo::slurp(dir / "report.json");
    EXPECT_EQ(jsonNumber(report, "fixed_boundary"), z.count(Kind::Boundary)) << report;
    EXPECT_EQ(jsonNumber(report, "fixed_nonmanifold"), z.count(Kind::NonManifold)) << report;
    EXPECT_EQ(jsonNumber(report, "active_vertices"), z.count(Kind::Interior)) << report;
  }
  // Nothing but the inputs, the outputs and the report.
  std::vector<std::string> expected = {"in.off", "in.ply", "in_ascii.ply"};
  if (z.cliError.empty())
    expected.insert(expected.end(), {"out.off", "out.ply", "out_ascii.ply", "report.json"});
  else
    expected.insert(expected.end(), {"out.off", "out.ply", "out_ascii.ply"});  // the sentinels
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(dir.entries(), expected);
}

std::string paramName(const testing::TestParamInfo<std::string>& info) { return info.param; }

INSTANTIATE_TEST_SUITE_P(Cli, CliZoo, testing::ValuesIn(cliZooNames()), paramName);

/// The polygon mesh as a PLY with polygon faces: vcglib's reader triangulates
/// it (same vertex list, one triangle fewer than corners per polygon).
TEST(CliPolygons, PlyPolygonsAreTriangulatedAndSmoothed) {
  const ZooMesh z = sodt_zoo::zooMesh("polygons");
  ASSERT_FALSE(z.polygons.empty());
  TempDir dir;
  const std::string in = dir / "poly.ply", out = dir / "out.ply";
  sodt_zoo::writePlyPolygons(in, z.soup, z.polygons);
  const RunResult r = sodt_zoo::runSodt({"smooth", in, out, "--quiet"});
  ASSERT_FALSE(r.crashed()) << r.describe();
  ASSERT_EQ(r.exitCode, 0) << r.describe();
  sodt::MeshD m;
  sodt::loadMesh(out, m);
  EXPECT_TRUE(sodt_zoo::allFinite(m));
  EXPECT_EQ(static_cast<std::size_t>(m.vn), z.soup.pos.size());
  EXPECT_EQ(static_cast<std::size_t>(m.fn), z.soup.tri.size());
  EXPECT_TRUE(sodt::isClosedOriented(m));
}

// ---------------------------------------------------------------------------
// Bad files

/// Bytes of a small valid mesh (the clean zoo sphere) in several encodings.
std::string validFile(sodt_zoo::PlyEncoding enc, bool off = false) {
  TempDir d;
  const sodt_zoo::Soup s = sodt_zoo::zooMesh("clean_sphere").soup;
  const std::string p = d / (off ? "v.off" : "v.ply");
  if (off)
    sodt_zoo::writeOff(p, s);
  else
    sodt_zoo::writePly(p, s, enc, false);
  return sodt_zoo::slurp(p);
}

std::string randomBytes(std::size_t n, unsigned seed) {
  std::mt19937 g(seed);
  std::string s(n, '\0');
  for (char& c : s) c = static_cast<char>(g() & 0xff);
  return s;
}

std::string plyHeader(const std::string& format, const std::string& nv, const std::string& nf,
                      const std::string& listTypes = "uchar int") {
  return "ply\nformat " + format + " 1.0\nelement vertex " + nv +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + nf + "\nproperty list " +
         listTypes + " vertex_indices\nend_header\n";
}

const char kTetVerts[] = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const char kTetFaces[] = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";

std::string asciiTet(const std::string& nv = "4", const std::string& nf = "4",
                     const std::string& faces = kTetFaces) {
  return plyHeader("ascii", nv, nf) + kTetVerts + faces;
}

/// A binary little-endian tetrahedron whose vertices carry an extra list
/// property 'extra' (count type countType, int values); vertex 0 has n values,
/// the others `others`.
std::string binaryTetWithVertexList(const std::string& countType, int n, int others = 1) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                  "property float z\nproperty list " + countType + " int extra\nelement face 4\n"
                  "property list uchar int vertex_indices\nend_header\n";
  auto put = [&s](const void* p, std::size_t bytes) { s.append(static_cast<const char*>(p), bytes); };
  const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int countSize = countType == "uchar" ? 1 : 4;
  for (int i = 0; i < 4; ++i) {
    put(v[i], sizeof v[i]);
    const auto count = static_cast<std::uint32_t>(i == 0 ? n : others);  // little-endian host
    put(&count, countSize);
    for (std::uint32_t k = 0; k < count; ++k) put(&i, 4);
  }
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  for (const auto& face : f) {
    const unsigned char three = 3;
    put(&three, 1);
    put(face, sizeof face);
  }
  return s;
}

struct BadFile {
  std::string name;  ///< file name (its extension picks the parser)
  std::function<std::string()> bytes;
  std::string message;  ///< part of the expected error line
};

std::vector<BadFile> badFiles() {
  using E = sodt_zoo::PlyEncoding;
  auto half = [](const std::string& s) { return s.substr(0, s.size() / 2); };
  return {
      {"zero_bytes.ply", [] { return std::string(); }, "no 'end_header'"},
      {"zero_bytes.off", [] { return std::string(); }, "empty file"},
      {"garbage.ply", [] { return randomBytes(4096, 1); }, "does not start with 'ply'"},
      {"garbage.off", [] { return randomBytes(4096, 2); }, "not an OFF file"},
      {"ply_magic_then_garbage.ply", [] { return "ply\n" + randomBytes(4096, 3); }, "PLY parse error"},
      {"truncated_binary_half.ply", [half] { return half(validFile(E::BinaryLE)); }, "PLY"},
      {"truncated_ascii_half.ply", [half] { return half(validFile(E::Ascii)); }, "PLY parse error"},
      {"truncated_off_half.off", [half] { return half(validFile(E::Ascii, true)); }, "unexpected end of file"},
      {"truncated_in_header.ply", [] { return validFile(E::BinaryLE).substr(0, 60); }, "PLY parse error"},
      {"truncated_binary_in_vertices.ply",
       [] {
         const std::string v = validFile(E::BinaryLE);
         // Past the check of one byte per value, short of the vertex block.
         return v.substr(0, v.find("end_header\n") + 11 + 1000);
       },
       "the data ends inside element 'vertex'"},
      {"truncated_binary_in_faces.ply",
       [] {
         const std::string v = validFile(E::BinaryLE);
         return v.substr(0, v.size() - 5);  // the last face loses its last index and a byte
       },
       "the data ends inside element 'face'"},
      {"header_only.ply", [] { return plyHeader("ascii", "4", "4"); }, "PLY parse error"},
      {"more_vertices_than_present_ascii.ply", [] { return asciiTet("1000"); }, "more than the file can hold"},
      {"more_vertices_than_present_binary.ply",
       [] {
         const std::string v = validFile(E::BinaryLE);
         const std::size_t at = v.find("element vertex 162");
         return v.substr(0, at) + "element vertex 16200" + v.substr(at + 18);
       },
       "more than the file can hold"},
      {"more_faces_than_present.ply", [] { return asciiTet("4", "50"); }, "PLY parse error"},
      {"more_faces_than_present.off", [] { return std::string("OFF\n4 40 0\n") + kTetVerts + "3 0 2 1\n"; },
       "unexpected end of file in face 1 of 40"},
      {"huge_count_int_max.ply", [] { return asciiTet("2147483647"); }, "more than the file can hold"},
      {"huge_count_uint_max.ply", [] { return asciiTet("4294967295"); }, "'vertex' elements, more than the file can hold"},
      {"huge_count_20_digits.ply", [] { return asciiTet("99999999999999999999"); }, "'vertex' elements, more than the file can hold"},
      {"huge_face_count.ply", [] { return asciiTet("4", "2000000000"); }, "more than the file can hold"},
      {"negative_count.ply", [] { return asciiTet("-5"); }, "has a bad count"},
      {"huge_count.off", [] { return std::string("OFF\n2147483647 1 0\n0 0 0\n"); }, "unexpected end of file"},
      {"count_beyond_int.off", [] { return std::string("OFF\n99999999999 1 0\n0 0 0\n"); }, "vertex count"},
      {"huge_corner_count.off", [] { return std::string("OFF\n4 1 0\n") + kTetVerts + "2000000000 0 1 2\n"; },
       "corners"},
      {"huge_list_count_ascii.ply", [] { return asciiTet("4", "1", "255 0 1 2\n"); }, "PLY parse error"},
      {"face_index_out_of_range.ply", [] { return asciiTet("4", "1", "3 0 1 99\n"); }, "vertex index out of range"},
      {"face_index_negative.ply", [] { return asciiTet("4", "1", "3 0 -1 2\n"); }, "vertex index out of range"},
      // Tokens scanf would split ("1-1" as 1 and -1, "2.0" as 2 and .0) put the
      // rest of the file out of step with the pre-check (a fuzzing finding).
      {"ascii_split_token_in_vertex.ply",
       [] { return plyHeader("ascii", "4", "1") + "0 0 0\n1 0 0\n0 1 0\n0 0 1-1\n3 0 1 2\n"; },
       "malformed number '1-1'"},
      {"ascii_fraction_as_index.ply", [] { return asciiTet("4", "1", "3 0 1 2.0\n"); }, "malformed integer '2.0'"},
      {"face_index_out_of_range.off", [] { return std::string("OFF\n4 1 0\n") + kTetVerts + "3 0 1 7\n"; },
       "out of range"},
      {"face_two_corners.off", [] { return std::string("OFF\n4 1 0\n") + kTetVerts + "2 0 1\n"; }, "corners"},
      {"nan_ascii.ply",
       [] { return plyHeader("ascii", "4", "4") + "0 0 0\nnan 0 0\n0 1 0\n0 0 1\n" + kTetFaces; },
       "non-finite coordinate"},
      {"inf_overflow.off", [] { return std::string("OFF\n4 4 0\n0 0 0\n1 0 1e999\n0 1 0\n0 0 1\n") + kTetFaces; },
       "non-finite coordinate"},
      {"off_text_in_ply.ply", [] { return std::string("OFF\n4 4 0\n") + kTetVerts + kTetFaces; },
       "does not start with 'ply'"},
      {"ply_text_in_off.off", [] { return asciiTet(); }, "not an OFF file"},
      {"big_endian_mislabelled.ply",
       [] {
         std::string s = validFile(E::BinaryLE);
         const std::size_t at = s.find("binary_little_endian");
         return s.replace(at, 20, "binary_big_endian");
       },
       "PLY parse error"},
      {"long_property_name.ply",
       [] {
         std::string s = asciiTet();
         const std::size_t at = s.find("property float x");
         return s.insert(at + 16, std::string(2000, 'x'));
       },
       "PLY parse error"},
      // Lists vcglib reads into fixed buffers (fuzzing findings): a skipped
      // binary list of more than 512 bytes, a face colour list of more than
      // 32 values; it takes every skipped binary list count as one byte.
      {"binary_extra_list_too_long.ply", [] { return binaryTetWithVertexList("uchar", 200); },
       "vertex 0 has 200 'extra' values, more than the reader can skip"},
      {"binary_extra_list_int_count.ply", [] { return binaryTetWithVertexList("int", 2); },
       "'extra' of element 'vertex' has a int count"},
      {"binary_extra_list_empty.ply", [] { return binaryTetWithVertexList("uchar", 1, 0); },
       "vertex 1 has an empty 'extra' list"},
      {"face_colour_list_too_long.ply",
       [] {
         std::string s = asciiTet("4", "4", "");
         s.replace(s.find("end_header"), 0, "property list uchar float color\n");
         std::string faces = kTetFaces, colours = " 255";
         for (int k = 0; k < 255; ++k) colours += " 0.5";
         for (std::size_t at = faces.find('\n'); at != std::string::npos; at = faces.find('\n', at + colours.size() + 1))
           faces.insert(at, colours);
         return s + faces;
       },
       "face 0 has 255 'color' values; at most 32 are supported"},
      {"tristrips.ply",
       [] {
         return std::string("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                            "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
                            "end_header\n") +
                kTetVerts + "4 0 1 2 3\n";
       },
       "'tristrips' elements are not supported"},
      {"unsupported.stp", [] { return std::string("ISO-10303-21;\n"); }, "unsupported file extension '.stp'"},
  };
}

std::vector<std::string> badFileNames() {
  std::vector<std::string> n;
  for (const BadFile& b : badFiles()) n.push_back(b.name);
  return n;
}

std::string fileParamName(const testing::TestParamInfo<std::string>& info) {
  std::string s = info.param;
  for (char& c : s)
    if (c == '.') c = '_';
  return s;
}

class CliBadFile : public testing::TestWithParam<std::string> {};

/// `sodt smooth` and `sodt stats` on the bad file: exit 1, one clear line, OUT untouched.
TEST_P(CliBadFile, FailsCleanly) {
  BadFile bad;
  for (const BadFile& b : badFiles())
    if (b.name == GetParam()) bad = b;
  TempDir dir;
  const std::string in = dir / bad.name, out = dir / "out.ply";
  sodt_zoo::writeText(in, bad.bytes());
  {
    SCOPED_TRACE("sodt smooth without an existing OUT");
    const RunResult r = sodt_zoo::runSodt({"smooth", in, out, "--quiet"}, 30);
    ASSERT_FALSE(r.crashed()) << r.describe();
    EXPECT_EQ(r.exitCode, 1) << r.describe();
    EXPECT_EQ(dir.entries(), std::vector<std::string>{bad.name}) << "a failed run created files";
  }
  sodt_zoo::writeText(out, kSentinel);
  const std::vector<std::string> before = dir.entries();
  {
    SCOPED_TRACE("sodt smooth");
    expectCleanFailure(sodt_zoo::runSodt({"smooth", in, out, "--quiet"}, 30), bad.message, dir, out, before);
  }
  {
    SCOPED_TRACE("sodt stats");
    expectCleanFailure(sodt_zoo::runSodt({"stats", in}, 30), bad.message, dir, out, before);
  }
}

INSTANTIATE_TEST_SUITE_P(Cli, CliBadFile, testing::ValuesIn(badFileNames()), fileParamName);

/// Extra list properties within vcglib's limits still load: a short binary
/// list with a one-byte count is skipped, a short face colour list is read.
TEST(CliExtraLists, ShortListsLoadAndSmooth) {
  TempDir dir;
  const std::string binary = dir / "binary.ply", ascii = dir / "ascii.ply";
  sodt_zoo::writeText(binary, binaryTetWithVertexList("uchar", 128));  // exactly 512 bytes
  std::string faces = kTetFaces;
  for (std::size_t at = faces.find('\n'); at != std::string::npos; at = faces.find('\n', at + 11))
    faces.insert(at, " 3 1 0.5 0");
  std::string text = asciiTet("4", "4", faces);
  text.replace(text.find("end_header"), 0, "property list uchar float color\n");
  sodt_zoo::writeText(ascii, text);
  for (const std::string& in : {binary, ascii}) {
    SCOPED_TRACE(in);
    const std::string out = dir / "out.ply";
    const RunResult r = sodt_zoo::runSodt({"smooth", in, out, "--quiet"});
    ASSERT_FALSE(r.crashed()) << r.describe();
    ASSERT_EQ(r.exitCode, 0) << r.describe();
    sodt::MeshD m;
    sodt::loadMesh(out, m);
    EXPECT_EQ(m.vn, 4);
    EXPECT_EQ(m.fn, 4);
    EXPECT_TRUE(sodt::isClosedOriented(m));
  }
}

/// Input that is a directory, a missing file, an unreadable file.
TEST(CliBadPath, FailsCleanly) {
  TempDir dir;
  const std::string out = dir / "out.ply";
  sodt_zoo::writeText(out, kSentinel);
  ASSERT_EQ(::mkdir((dir / "dir.ply").c_str(), 0700), 0);
  sodt_zoo::writeText(dir / "unreadable.ply", asciiTet());
  ASSERT_EQ(::chmod((dir / "unreadable.ply").c_str(), 0), 0);
  const bool root = ::geteuid() == 0;  // root reads anything
  const std::vector<std::string> before = dir.entries();
  for (const auto& c : std::vector<std::pair<std::string, std::string>>{
           {"dir.ply", "is a directory"}, {"missing.ply", "No such file"}, {"unreadable.ply", "Permission denied"}}) {
    if (root && c.first == "unreadable.ply") continue;
    SCOPED_TRACE(c.first);
    expectCleanFailure(sodt_zoo::runSodt({"smooth", dir / c.first, out, "--quiet"}), c.second, dir, out, before);
  }
}

// ---------------------------------------------------------------------------
// Bad parameters

/// Every bad option value is a usage error: exit 2, "sodt: error: ..." then
/// the help pointer, OUT untouched, nothing created.
TEST(CliBadParameters, AreUsageErrors) {
  TempDir dir;
  const std::string in = dir / "in.ply", out = dir / "out.ply";
  sodt_zoo::writePly(in, sodt_zoo::zooMesh("combination").soup, sodt_zoo::PlyEncoding::BinaryLE, true);
  sodt_zoo::writeText(out, kSentinel);
  const std::vector<std::string> before = dir.entries();
  const std::vector<std::vector<std::string>> bad = {
      {"--iterations", "-1"},          {"--iterations", "100001"},     {"--iterations", "1e3"},
      {"--iterations", "99999999999"}, {"--iterations", ""},           {"--max-backtracks", "61"},
      {"--guard", "xyz"},              {"--algorithm", ""},            {"--algorithm", "BASIC"},
      {"--epsilon", "nan"},            {"--epsilon", "inf"},           {"--epsilon", "-1"},
      {"--epsilon", "0"},              {"--eta", "1e6"},               {"--max-deviation", "101"},
      {"--max-deviation", "1e400"},    {"--max-normal-step", "11"},    {"--flip-max-dihedral", "91"},
      {"--tolerance", "-0.5"},         {"--tolerance", "0x10"},        {"--laplacian-fallback", "yes"},
      {"--report", ""},                {"--classes-out", "c.off"},     {"--no-such-option"},
      {"--report", out},               {"--distance", "yes"},
  };
  for (const auto& opts : bad) {
    std::string what;
    for (const auto& o : opts) what += o + " ";
    SCOPED_TRACE(what);
    std::vector<std::string> args = {"smooth", in, out};
    args.insert(args.end(), opts.begin(), opts.end());
    const RunResult r = sodt_zoo::runSodt(args);
    ASSERT_FALSE(r.crashed()) << r.describe();
    EXPECT_EQ(r.exitCode, 2) << r.describe();
    const std::vector<std::string> lines = r.errLines();
    ASSERT_EQ(lines.size(), 1u) << r.describe();
    EXPECT_EQ(lines[0].rfind("sodt: error: ", 0), 0u) << lines[0];
    EXPECT_NE(lines[0].find(" (see 'sodt smooth --help')"), std::string::npos) << lines[0];
    EXPECT_EQ(sodt_zoo::slurp(out), kSentinel);
    EXPECT_EQ(dir.entries(), before);
  }
  // A file without a selection is a problem of the input, not of the
  // command line: exit 1, one line, nothing written.
  const RunResult r = sodt_zoo::runSodt({"smooth", in, out, "--selected-only"});
  EXPECT_EQ(r.exitCode, 1) << r.describe();
  ASSERT_EQ(r.errLines().size(), 1u) << r.describe();
  EXPECT_NE(r.err.find("no vertex of the input is selected"), std::string::npos) << r.err;
  EXPECT_EQ(sodt_zoo::slurp(out), kSentinel);
  EXPECT_EQ(dir.entries(), before);
}

}  // namespace
