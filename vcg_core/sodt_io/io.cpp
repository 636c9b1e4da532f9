// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh file I/O: vcglib's PLY importer/exporters behind input checks, a strict
// OFF parser, and temporary-file-plus-rename output (see io.h).
#include "io.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <wrap/io_trimesh/export_off.h>
#include <wrap/io_trimesh/export_ply.h>
#include <wrap/io_trimesh/import_ply.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <fcntl.h>
#include <csignal>
#include <fstream>
#include <sstream>
#include <functional>
#include <limits>
#include <memory>
#include <sys/stat.h>
#include <unistd.h>
#include <unordered_map>
#include <vector>

namespace sodt {
namespace {

std::string quoted(const std::string& path) { return "'" + path + "'"; }

/// A token of a file for a message: quoted, control bytes (a NUL would cut
/// the message short) as \xNN, and at most 40 bytes.
std::string shown(const char* p, std::size_t n) {
  std::string r = "'";
  for (std::size_t i = 0; i < std::min<std::size_t>(n, 40); ++i) {
    const unsigned char c = static_cast<unsigned char>(p[i]);
    if (c < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      r += hex;
    } else {
      r += static_cast<char>(c);
    }
  }
  return r + (n > 40 ? "...'" : "'");
}
std::string shown(const std::string& s) { return shown(s.data(), s.size()); }

/// Largest coordinate magnitude accepted on input.
constexpr double kMaxCoordinate = 1e150;

std::string lowerExtension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

/// Throws InvalidInput unless path names a readable regular file.
void checkReadable(const std::string& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0)
    throw InvalidInput("cannot open " + quoted(path) + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw InvalidInput("cannot open " + quoted(path) + ": is a directory");
  if (::access(path.c_str(), R_OK) != 0)
    throw InvalidInput("cannot open " + quoted(path) + ": " + std::strerror(errno));
}

long long fileSize(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 ? static_cast<long long>(st.st_size) : -1;
}

// ---------------------------------------------------------------------------
// OFF reading

/// Whitespace as std::isspace classifies it in the C locale (and as an
/// istream's >> skips it).
inline bool isSpace(char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }

/// Longest run of bytes without a space or line end a text reader accepts:
/// far more than any number needs, and what keeps binary data read as text
/// (a file of zero bytes, /dev/zero) from growing one token without bound.
constexpr std::size_t kMaxToken = 4096;

/// The whitespace-separated tokens of a text stream, read in large blocks:
/// the tokenizer of the OFF, OBJ and ASCII STL readers and of the ASCII PLY
/// check. Lines end at '\n', "\r\n" or a lone '\r'; with comments, a '#'
/// ends a token and starts a comment that runs to the end of its line.
/// Blocks, with no library call per character and no string per token, keep
/// the tokenizing cheaper than the parsing of the numbers themselves. A
/// token longer than kMaxToken throws InvalidInput.
class TextScanner {
 public:
  /// in is read from its start when format names the file's format ("OBJ",
  /// "OFF", "STL"): a UTF-8 byte-order mark is skipped, and a NUL byte in the
  /// first KB (binary data) throws InvalidInput. With format empty, in is
  /// read from where it is (the data after a PLY header), and messages count
  /// "data line"s. path names the file in messages.
  TextScanner(std::istream& in, bool comments, const std::string& path, const std::string& format)
      : in_(in), comments_(comments), path_(path), format_(format), buf_(kBlock + 1, '\0') {}

  /// Next token, crossing line ends: [p, p + n), valid until the next call
  /// and followed by a character that ends it (whitespace, '#' with
  /// comments, or '\0' at the end of the stream), so that strtod and the
  /// like stop there; false at the end of the stream.
  bool next(const char*& p, std::size_t& n) {
    if (!skipTo(true)) {
      tokenLine_ = lines_ + (midLine_ ? 1 : 0);  // the last line, as getline counts them
      return false;
    }
    return take(p, n);
  }
  bool next(std::string& tok) {
    const char* p = nullptr;
    std::size_t n = 0;
    if (!next(p, n)) return false;
    tok.assign(p, n);
    return true;
  }
  /// The next token of the current line, as next(); false when the line
  /// has no more (its line end, or its comment and line end, are consumed
  /// then) or at the end of the stream.
  bool nextOnLine(const char*& p, std::size_t& n) { return skipTo(false) && take(p, n); }
  /// Skips spaces; true when the current line has no more tokens (a line
  /// end, a comment or the end of the stream comes next, not consumed).
  bool lineEnds() {
    for (;;) {
      if (at_ == end_ && !fill()) return true;
      const char c = buf_[at_];
      if (c == '\n' || c == '\r' || (comments_ && c == '#')) return true;
      if (!isSpace(c)) return false;
      ++at_;
      midLine_ = true;
    }
  }
  /// Drops what is left of the current line, its line end included.
  void skipRestOfLine() {
    for (;;) {
      if (at_ == end_ && !fill()) return;
      if (afterCr_) {  // the '\n' of a "\r\n" whose '\r' ended the last line
        afterCr_ = false;
        if (buf_[at_] == '\n') ++at_;
        continue;
      }
      const char* nl = static_cast<const char*>(std::memchr(buf_.data() + at_, '\n', end_ - at_));
      const char* cr = static_cast<const char*>(std::memchr(buf_.data() + at_, '\r', (nl ? nl : buf_.data() + end_) - (buf_.data() + at_)));
      if (cr && cr + 1 != nl) {  // a lone '\r' (old Mac line ends) ends the line too
        at_ = static_cast<std::size_t>(cr - buf_.data()) + 1;
        newLine();
        afterCr_ = true;
        return;
      }
      if (nl) {
        at_ = static_cast<std::size_t>(nl - buf_.data()) + 1;
        newLine();
        return;
      }
      at_ = end_;
      midLine_ = true;
    }
  }
  /// Takes the tokens left on the current line and its '\n'; throws
  /// InvalidInput when there are more than maxTokens.
  std::vector<std::string> restOfLine(std::size_t maxTokens) {
    std::vector<std::string> r;
    const char* p = nullptr;
    std::size_t n = 0;
    while (skipTo(false)) {
      take(p, n);
      if (r.size() == maxTokens)
        throw InvalidInput(quoted(path_) + ": " + lineWord() + " " + std::to_string(tokenLine_) + ": more than " +
                           std::to_string(maxTokens) + " values on one line");
      r.emplace_back(p, n);
    }
    return r;
  }
  /// The line of the last token, or after the end of the stream the last line.
  long line() const { return tokenLine_; }

 private:
  static constexpr std::size_t kBlock = 1 << 20;

  void newLine() {
    ++lines_;
    midLine_ = false;
  }
  bool ends(char c) const { return isSpace(c) || (comments_ && c == '#'); }
  const char* lineWord() const { return format_.empty() ? "data line" : "line"; }

  /// The start of a file: skips a byte-order mark, refuses NUL bytes.
  void checkStart() {
    static const char bom[] = "\xEF\xBB\xBF";
    if (end_ >= 3 && std::memcmp(buf_.data(), bom, 3) == 0) at_ = 3;
    const char* nul = static_cast<const char*>(std::memchr(buf_.data(), '\0', std::min<std::size_t>(end_, 1024)));
    if (nul == nullptr) return;
    const std::size_t offset = static_cast<std::size_t>(nul - buf_.data());
    const long line = 1 + static_cast<long>(std::count(static_cast<const char*>(buf_.data()), nul, '\n'));
    throw InvalidInput(quoted(path_) + ": not an " + format_ + " file: binary data (a NUL byte at byte offset " +
                       std::to_string(offset) + ", line " + std::to_string(line) + ")");
  }

  /// Reads more of the stream after [at_, end_), which moves to the front of
  /// the buffer (growing it when that is all of it); false at the end.
  bool fill() {
    if (eof_) return false;
    const std::size_t keep = end_ - at_;
    if (keep > 0 && at_ > 0) std::memmove(buf_.data(), buf_.data() + at_, keep);
    at_ = 0;
    end_ = keep;
    std::size_t room = buf_.size() - 1;  // the last byte holds the '\0' after the data
    if (end_ == room) {
      room *= 2;
      buf_.resize(room + 1);
    }
    in_.read(buf_.data() + end_, static_cast<std::streamsize>(room - end_));
    const std::size_t got = static_cast<std::size_t>(in_.gcount());
    end_ += got;
    buf_[end_] = '\0';
    if (got == 0) eof_ = true;
    if (!started_) {
      started_ = true;
      if (!format_.empty()) checkStart();
    }
    return got > 0 && at_ < end_;
  }

  /// Skips whitespace and comments up to the next token (crossLines) or to
  /// the next token of this line (else: then a '\n' reached is consumed and
  /// the answer is false); false at the end of the stream.
  bool skipTo(bool crossLines) {
    for (;;) {
      if (at_ == end_ && !fill()) return false;
      const char c = buf_[at_];
      if (c == '\n' && afterCr_) {  // the '\n' of a "\r\n" whose '\r' ended the line
        ++at_;
        afterCr_ = false;
      } else if (c == '\n' || c == '\r') {
        // '\r' ends a line as '\n' does (a following '\n' belongs to it).
        ++at_;
        newLine();
        afterCr_ = c == '\r';
        if (!crossLines) return false;
      } else if (comments_ && c == '#') {
        skipRestOfLine();
        if (!crossLines) return false;
      } else if (isSpace(c)) {
        ++at_;
        midLine_ = true;
        afterCr_ = false;
      } else {
        afterCr_ = false;
        return true;
      }
    }
  }

  /// The token starting at at_.
  bool take(const char*& p, std::size_t& n) {
    midLine_ = true;
    tokenLine_ = lines_ + 1;
    std::size_t j = at_;
    for (;;) {
      while (j < end_ && !ends(buf_[j])) ++j;
      if (j - at_ > kMaxToken)
        throw InvalidInput(quoted(path_) + ": " + lineWord() + " " + std::to_string(tokenLine_) + ": more than " +
                           std::to_string(kMaxToken) +
                           " bytes without a space or line end (binary data, or not a text mesh file?)");
      if (j < end_ || eof_) break;
      const std::size_t done = j - at_;
      const bool more = fill();
      j = done;  // fill() moved the token to the front
      if (!more) break;
    }
    p = buf_.data() + at_;
    n = j - at_;
    at_ = j;
    return true;
  }

  std::istream& in_;
  bool comments_;
  const std::string path_, format_;
  std::vector<char> buf_;
  std::size_t at_ = 0, end_ = 0;
  bool eof_ = false;
  bool started_ = false;   ///< the first block has been read
  long lines_ = 0;         ///< line ends consumed
  bool afterCr_ = false;   ///< the last character consumed was a '\r' that ended a line
  bool midLine_ = false;   ///< characters consumed after the last '\n'
  long tokenLine_ = 0;
};

/// strtod's reading of the characters [p, p + n), which must be followed by
/// one that cannot continue a number (TextScanner's tokens are; a string's
/// terminating '\0' is): true when all n make one number. Overflow gives
/// +-HUGE_VAL, which the non-finite check reports by vertex.
bool parseDouble(const char* p, std::size_t n, double& out) {
  if (n == 0) return false;
  char* end = nullptr;
  out = std::strtod(p, &end);
  return end == p + n;
}

bool parseDouble(const std::string& s, double& out) { return parseDouble(s.c_str(), s.size(), out); }

/// A decimal integer [+-]digits in the range of long long (as strtoll
/// accepts one in full without ERANGE).
bool parseLong(const char* p, std::size_t n, long long& out) {
  const bool negative = n > 0 && p[0] == '-';
  std::size_t i = n > 0 && (p[0] == '-' || p[0] == '+') ? 1 : 0;
  if (i == n) return false;
  const unsigned long long limit =
      negative ? 0ull - static_cast<unsigned long long>(LLONG_MIN) : static_cast<unsigned long long>(LLONG_MAX);
  unsigned long long v = 0;
  for (; i < n; ++i) {
    const unsigned d = static_cast<unsigned>(static_cast<unsigned char>(p[i])) - '0';
    if (d > 9 || v > (limit - d) / 10) return false;
    v = v * 10 + d;
  }
  out = negative ? (v == limit ? LLONG_MIN : -static_cast<long long>(v)) : static_cast<long long>(v);
  return true;
}

bool parseLong(const std::string& s, long long& out) { return parseLong(s.data(), s.size(), out); }

/// Positions and triangles read from an OFF file.
struct OffData {
  std::vector<double> xyz;
  std::vector<int> tri;
  std::vector<unsigned char> rgba;  ///< 4 per vertex when hasColor
  std::vector<double> normals;      ///< 3 per vertex with the N prefix
  std::vector<float> uv;            ///< 2 per vertex with the ST prefix
  long badUvLine = 0;               ///< the first line whose texture coordinates are missing or not numbers
  bool polygons = false;
  bool color = false;     ///< the keyword has the C prefix
  bool hasColor = false;  ///< some vertex has an RGB(A) colour
};

/// Reads an OFF vertex colour: 3 or 4 integers 0..255 or floats 0..1.
/// A single colour-map index is ignored.
bool parseOffColor(const std::vector<std::string>& t, std::size_t n, unsigned char rgba[4]) {
  if (n != 3 && n != 4) return false;
  bool floats = false;
  for (std::size_t k = 0; k < n; ++k) floats = floats || t[k].find_first_of(".eE") != std::string::npos;
  rgba[3] = 255;
  for (std::size_t k = 0; k < n; ++k) {
    double x = 0;
    if (!parseDouble(t[k], x) || !std::isfinite(x)) return false;
    const double v = floats ? x * 255.0 : x;
    rgba[k] = static_cast<unsigned char>(std::min(255.0, std::max(0.0, std::round(v))));
  }
  return true;
}

void readOff(const std::string& path, OffData& d) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput("cannot open " + quoted(path) + ": " + std::strerror(errno));
  TextScanner t(in, true, path, "OFF");
  // Set at the first vertex whose values run over a line end: a line with
  // more or fewer values than whole vertices shifts every later value, and
  // the error it causes (in the faces, say) is far from that line.
  std::string shiftHint;
  auto fail = [&](const std::string& what) {
    throw InvalidInput(quoted(path) + ": OFF parse error at line " + std::to_string(t.line()) + ": " + what +
                       shiftHint);
  };
  auto eofIn = [&](const std::string& what, long long i, long long count) {
    throw InvalidInput(quoted(path) + ": unexpected end of file in " + what + " " + std::to_string(i) + " of " +
                       std::to_string(count) + shiftHint);
  };
  std::string tok;
  if (!t.next(tok)) throw InvalidInput(quoted(path) + ": empty file");
  if (tok.size() < 3 || tok.compare(tok.size() - 3, 3, "OFF") != 0)
    throw InvalidInput(quoted(path) + ": not an OFF file (no OFF keyword)");
  bool normals = false, texcoords = false;
  for (std::size_t i = 0; i + 3 < tok.size(); ++i) {
    const char c = tok[i];
    if (c == 'C') {
      d.color = true;
    } else if (c == 'N') {
      normals = true;
    } else if (c == 'S' && i + 1 + 3 < tok.size() && tok[i + 1] == 'T') {
      texcoords = true;
      ++i;
    } else if (c == '4' || c == 'n') {
      throw InvalidInput(quoted(path) + ": unsupported OFF variant " + shown(tok) + " (only 3D vertices)");
    } else {
      throw InvalidInput(quoted(path) + ": not an OFF file (keyword " + shown(tok) + ")");
    }
  }
  long long nv = 0, nf = 0;
  if (!t.next(tok) || !parseLong(tok, nv) || nv < 0 || nv > INT_MAX)
    fail("expected the vertex count, got " + shown(tok));
  if (!t.next(tok) || !parseLong(tok, nf) || nf < 0 || nf > INT_MAX)
    fail("expected the face count, got " + shown(tok));
  t.skipRestOfLine();  // the edge count is optional and unused

  // Grow with the data actually present: a huge declared count in a short
  // file fails at end of file instead of allocating first.
  const long long cap = 1 << 20;
  d.xyz.reserve(static_cast<std::size_t>(3 * std::min(nv, cap)));
  const bool lineBased = d.color || texcoords;  // colour counts vary: one vertex per line
  const char* p = nullptr;  // the token [p, p + n) (see TextScanner::next)
  std::size_t n = 0;
  const int perVertex = normals ? 6 : 3;
  for (long long i = 0; i < nv; ++i) {
    long firstLine = 0;
    for (int k = 0; k < perVertex; ++k) {
      if (!t.next(p, n)) eofIn("vertex", i, nv);
      if (k == 0) firstLine = t.line();
      double x = 0;
      if (!parseDouble(p, n, x))
        fail("vertex " + std::to_string(i) + ": expected a number, got " + shown(p, n));
      (k < 3 ? d.xyz : d.normals).push_back(x);
    }
    if (shiftHint.empty() && t.line() != firstLine)
      shiftHint = "; line " + std::to_string(firstLine) + " does not hold whole vertices (an OFF vertex has " +
                  (normals ? "6 values, x y z and a normal" : "3 values, x y z") +
                  "; colours need the COFF keyword), so vertex " + std::to_string(i) + " runs on to line " +
                  std::to_string(t.line()) + " and every later value is shifted";
    if (lineBased) {
      // A colour (3 or 4 values) and texture coordinates (2): a handful.
      const std::vector<std::string> rest = t.restOfLine(16);
      const std::size_t tex = texcoords ? std::min<std::size_t>(2, rest.size()) : 0;
      unsigned char c[4] = {255, 255, 255, 255};
      if (d.color && parseOffColor(rest, rest.size() - tex, c)) d.hasColor = true;
      if (d.color) d.rgba.insert(d.rgba.end(), c, c + 4);
      for (std::size_t k = 0; k < 2 && texcoords; ++k) {
        double x = 0;
        if ((tex < 2 || !parseDouble(rest[rest.size() - 2 + k], x)) && d.badUvLine == 0) d.badUvLine = t.line();
        d.uv.push_back(static_cast<float>(x));
      }
    }
  }
  d.tri.reserve(static_cast<std::size_t>(3 * std::min(nf, cap)));
  std::vector<int> poly;
  for (long long f = 0; f < nf; ++f) {
    long long corners = 0;
    if (!t.next(p, n)) eofIn("face", f, nf);
    if (!parseLong(p, n, corners))
      fail("face " + std::to_string(f) + ": expected a corner count, got " + shown(p, n));
    if (corners < 3 || corners > nv)
      fail("face " + std::to_string(f) + " has " + std::to_string(corners) + " corners");
    poly.clear();
    for (long long k = 0; k < corners; ++k) {
      long long idx = 0;
      if (!t.next(p, n)) eofIn("face", f, nf);
      if (!parseLong(p, n, idx))
        fail("face " + std::to_string(f) + ": expected a vertex index, got " + shown(p, n));
      if (idx < 0 || idx >= nv)
        fail("face " + std::to_string(f) + ": vertex index " + std::to_string(idx) + " out of range [0, " +
             std::to_string(nv) + ")");
      poly.push_back(static_cast<int>(idx));
    }
    t.skipRestOfLine();  // face colour
    if (corners > 3) d.polygons = true;
    for (long long k = 1; k + 1 < corners; ++k) {  // fan
      d.tri.push_back(poly[0]);
      d.tri.push_back(poly[static_cast<std::size_t>(k)]);
      d.tri.push_back(poly[static_cast<std::size_t>(k + 1)]);
    }
  }
}

/// Positions and triangles of an OBJ or STL file.
struct PlainMesh {
  std::vector<double> xyz;
  std::vector<int> tri;
  std::vector<float> uv;  ///< OBJ: 2 per vertex when every vertex has one pair of texture coordinates
  bool normals = false;   ///< OBJ: the file has 'vn' statements
  std::vector<std::string> dropped;  ///< see LoadInfo::dropped
  bool polygons = false;
  long long corners = 0;  ///< STL: face corners read, before welding
};

/// Puts positions (3 per vertex), triangles (3 indices each) and, when
/// given, texture coordinates (2 per vertex) into m.
template <class M>
void fillMesh(const std::vector<double>& xyz, const std::vector<int>& tri, const std::vector<float>& uv, M& m) {
  using Scalar = typename M::ScalarType;
  const std::size_t nv = xyz.size() / 3, nt = tri.size() / 3;
  m.Clear();
  if (nv > 0) vcg::tri::Allocator<M>::AddVertices(m, nv);
  for (std::size_t i = 0; i < nv; ++i)
    m.vert[i].P() = typename M::CoordType(Scalar(xyz[3 * i]), Scalar(xyz[3 * i + 1]), Scalar(xyz[3 * i + 2]));
  if (uv.size() == 2 * nv && vcg::tri::HasPerVertexTexCoord(m))
    for (std::size_t i = 0; i < nv; ++i) m.vert[i].T() = typename M::VertexType::TexCoordType(uv[2 * i], uv[2 * i + 1]);
  if (nt > 0) vcg::tri::Allocator<M>::AddFaces(m, nt);
  for (std::size_t f = 0; f < nt; ++f)
    for (int k = 0; k < 3; ++k) m.face[f].V(k) = &m.vert[static_cast<std::size_t>(tri[3 * f + k])];
}

template <class M>
void loadOff(const std::string& path, M& m, LoadInfo& info) {
  OffData d;
  readOff(path, d);
  if (d.badUvLine > 0) {
    d.uv.clear();
    info.dropped.push_back("texture coordinates (missing or not numbers on line " + std::to_string(d.badUvLine) + ")");
  }
  fillMesh(d.xyz, d.tri, d.uv, m);
  if (d.hasColor) {
    for (std::size_t i = 0; i < m.vert.size(); ++i)
      m.vert[i].C() = vcg::Color4b(d.rgba[4 * i], d.rgba[4 * i + 1], d.rgba[4 * i + 2], d.rgba[4 * i + 3]);
    info.vertexColor = true;
  }
  if (!d.normals.empty()) {
    using NormalType = typename M::VertexType::NormalType;
    using NormalScalar = typename NormalType::ScalarType;
    for (std::size_t i = 0; i < m.vert.size(); ++i)
      m.vert[i].N() = NormalType(NormalScalar(d.normals[3 * i]), NormalScalar(d.normals[3 * i + 1]),
                                 NormalScalar(d.normals[3 * i + 2]));
    info.vertexNormals = true;
  }
  info.vertexTexCoords = !d.uv.empty();
  info.polygons = d.polygons;
}

// ---------------------------------------------------------------------------
// OBJ reading

/// The per-vertex texture coordinates of an OBJ file whose faces name them
/// per corner: kept when every corner of a vertex names the same pair.
class ObjTexCoords {
 public:
  /// A 'vt' statement's values.
  void add(float u, float v) { vt_.insert(vt_.end(), {u, v}); }
  long long count() const { return static_cast<long long>(vt_.size() / 2); }
  /// The texture coordinate index (0-based, -1 for none) of the triangle
  /// corner just added to the mesh's triangle list, whose size is corners.
  void corner(long long t, std::size_t corners) {
    if (t >= 0 && !named_) {  // the first corner with one
      named_ = true;
      corner_.assign(corners - 1, -1);
    }
    if (named_) corner_.push_back(t);
  }
  /// A corner of line line whose texture coordinate index is not one.
  void bad(long line) {
    if (badLine_ == 0) badLine_ = line;
  }
  /// Per-vertex texture coordinates into d.uv, or why not into d.dropped.
  void resolve(PlainMesh& d) const {
    if (badLine_ > 0) {
      d.dropped.push_back("texture coordinates (line " + std::to_string(badLine_) + " has a bad index)");
      return;
    }
    if (!named_) return;
    const std::size_t nv = d.xyz.size() / 3;
    std::vector<long long> of(nv, -1);
    std::vector<char> several(nv, 0);
    bool missing = false;
    for (std::size_t k = 0; k < corner_.size(); ++k) {
      const long long t = corner_[k];
      if (t >= count()) {
        d.dropped.push_back("texture coordinates (face " + std::to_string(k / 3) + " names pair " +
                            std::to_string(t + 1) + ", the file has " + std::to_string(count()) + ")");
        return;
      }
      const std::size_t v = static_cast<std::size_t>(d.tri[k]);
      if (t < 0) {
        missing = true;
      } else if (of[v] < 0) {
        of[v] = t;
      } else if (of[v] != t && (vt_[2 * of[v]] != vt_[2 * t] || vt_[2 * of[v] + 1] != vt_[2 * t + 1])) {
        several[v] = 1;
      }
    }
    const long long seams = std::count(several.begin(), several.end(), 1);
    if (seams > 0) {
      d.dropped.push_back("texture coordinates per face corner (" + std::to_string(seams) +
                          (seams == 1 ? " vertex has" : " vertices have") + " several)");
    } else if (missing) {
      d.dropped.push_back("texture coordinates (some face corners have none)");
    } else {
      d.uv.assign(2 * nv, 0.0f);
      for (std::size_t v = 0; v < nv; ++v)
        if (of[v] >= 0) {
          d.uv[2 * v] = vt_[2 * of[v]];
          d.uv[2 * v + 1] = vt_[2 * of[v] + 1];
        }
    }
  }

 private:
  std::vector<float> vt_;
  long badLine_ = 0;               ///< the first line with a bad texture coordinate index
  bool named_ = false;             ///< a corner has named texture coordinates
  std::vector<long long> corner_;  ///< per triangle corner, once named_
};

/// The statements of an OBJ file that readObj ignores, in order of first
/// appearance, for LoadInfo::dropped.
class ObjIgnored {
 public:
  void add(const std::string& word) {
    if (std::find(words_.begin(), words_.end(), word) != words_.end()) return;
    if (words_.size() < 8)
      words_.push_back(word);
    else
      more_ = true;
  }
  void into(std::vector<std::string>& dropped) const {
    if (words_.empty()) return;
    std::string s = words_.size() == 1 ? "OBJ statement " : "OBJ statements ";
    for (std::size_t k = 0; k < words_.size(); ++k) s += (k ? ", " : "") + shown(words_[k]);
    dropped.push_back(s + (more_ ? " and more" : ""));
  }

 private:
  std::vector<std::string> words_;
  bool more_ = false;
};

/// Reads a Wavefront OBJ file: vertices ('v'), faces ('f', as i, i/t, i//n
/// or i/t/n, with negative indices counting back from the last vertex or
/// texture coordinate so far; polygons fan-triangulated), texture
/// coordinates ('vt': per vertex when every corner of a vertex names the
/// same) and whether there are normals ('vn'). Comments, line continuations
/// and smoothing groups ('s') are accepted; every other statement (groups,
/// materials, lines, vertex colours...) is ignored and listed in d.dropped.
/// Statements are read a token at a time: no line is held in memory.
void readObj(const std::string& path, PlainMesh& d) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput("cannot open " + quoted(path) + ": " + std::strerror(errno));
  TextScanner t(in, true, path, "OBJ");
  long line = 0;  // of the statement
  auto fail = [&](const std::string& what) {
    throw InvalidInput(quoted(path) + ": OBJ parse error at line " + std::to_string(line) + ": " + what);
  };
  const char* p = nullptr;
  std::size_t n = 0;
  // The next value of the statement; a '\' that ends a line continues it on the next.
  auto nextValue = [&]() {
    for (;;) {
      if (!t.nextOnLine(p, n)) return false;
      if (!(n == 1 && *p == '\\' && t.lineEnds())) return true;
      t.skipRestOfLine();
    }
  };
  // The vertex of a corner, the [q, q + len) before its first '/':
  // 1-based, or negative counting back from the last vertex so far (nv);
  // 0-based on return. A number too large for any file is reported as written.
  auto vertexIndex = [&](const char* q, std::size_t len, long long nv) {
    long long v = 0;
    const std::size_t sign = len > 0 && (*q == '-' || *q == '+') ? 1 : 0;
    const bool digits = len > sign && std::all_of(q + sign, q + len, [](char c) { return c >= '0' && c <= '9'; });
    const std::string written(q, len);
    if (!parseLong(q, len, v)) {
      if (!digits) fail("expected a vertex index, got " + shown(p, n));
      v = *q == '-' ? LLONG_MIN : LLONG_MAX;  // beyond any file: reported below
    }
    if (v == 0) fail("expected a vertex index, got " + shown(p, n));
    // Positive indices are checked once the whole file is read (forward references).
    if (v < 0 && v < -nv) fail("vertex index " + written + " reaches before the first vertex");
    if (v - 1 > INT_MAX) fail("vertex index " + written + " is out of range");
    return v < 0 ? v + nv : v - 1;
  };
  ObjTexCoords texcoords;
  ObjIgnored ignored;
  bool vertexColours = false;
  std::vector<long long> poly, polyT;
  while (t.next(p, n)) {
    line = t.line();
    const std::string word(p, n);
    if (word == "v") {
      int k = 0;
      for (; nextValue(); ++k) {
        double x = 0;
        if (k < 3 && !parseDouble(p, n, x))
          fail("vertex " + std::to_string(d.xyz.size() / 3) + ": expected a number, got " + shown(p, n));
        if (k < 3) d.xyz.push_back(x);
      }
      if (k < 3) fail("a vertex needs 3 coordinates, line " + std::to_string(line) + " has " + std::to_string(k));
      vertexColours = vertexColours || k >= 6;  // 'v x y z r g b'
    } else if (word == "vt") {
      double uv[2] = {0, 0};
      int k = 0;
      for (; nextValue(); ++k)
        if (k < 2 && !parseDouble(p, n, uv[k]))
          fail("texture coordinates " + std::to_string(texcoords.count()) + ": expected a number, got " + shown(p, n));
      if (k == 0) fail("texture coordinates need a value");
      texcoords.add(static_cast<float>(uv[0]), static_cast<float>(uv[1]));
    } else if (word == "f") {
      const long long nv = static_cast<long long>(d.xyz.size() / 3);
      poly.clear();
      polyT.clear();
      while (nextValue()) {
        const char* slash = static_cast<const char*>(std::memchr(p, '/', n));
        const std::size_t len = slash ? static_cast<std::size_t>(slash - p) : n;
        poly.push_back(vertexIndex(p, len, nv));
        // Texture coordinates: as vertices, but a bad index only loses them.
        long long ti = -1;
        if (slash != nullptr) {
          const char* tEnd = static_cast<const char*>(std::memchr(slash + 1, '/', n - len - 1));
          const std::size_t tLen = tEnd ? static_cast<std::size_t>(tEnd - slash - 1) : n - len - 1;
          const long long vt = texcoords.count();
          long long tw = 0;  // as written
          if (tLen > 0 && parseLong(slash + 1, tLen, tw) && tw != 0 && tw >= -vt && tw - 1 <= INT_MAX)
            ti = tw < 0 ? tw + vt : tw - 1;
          else if (tLen > 0)
            texcoords.bad(line);
        }
        polyT.push_back(ti);
      }
      if (poly.size() < 3) fail("a face needs 3 corners or more, got " + std::to_string(poly.size()));
      if (poly.size() > 3) d.polygons = true;
      for (std::size_t k = 1; k + 1 < poly.size(); ++k)
        for (std::size_t c : {std::size_t(0), k, k + 1}) {
          d.tri.push_back(static_cast<int>(poly[c]));
          texcoords.corner(polyT[c], d.tri.size());
        }
    } else {
      if (word == "vn")
        d.normals = true;
      else if (word != "s")  // smoothing groups only shade normals, which are computed anew
        ignored.add(word);
      while (nextValue()) {
      }
    }
  }
  const long long nv = static_cast<long long>(d.xyz.size() / 3);
  for (std::size_t k = 0; k < d.tri.size(); ++k)
    if (d.tri[k] >= nv)
      throw InvalidInput(quoted(path) + ": OBJ face " + std::to_string(k / 3) + " refers to vertex " +
                         std::to_string(static_cast<long long>(d.tri[k]) + 1) + ", but the file has " +
                         std::to_string(nv) + " vertices");
  texcoords.resolve(d);
  if (vertexColours) d.dropped.push_back("vertex colours ('v x y z r g b')");
  ignored.into(d.dropped);
}

// ---------------------------------------------------------------------------
// STL reading

/// Welds the corners of STL triangles: corners with equal coordinates
/// (bit for bit, -0 as 0) become one vertex, as a user expects of a mesh.
class CornerWelder {
 public:
  int add(double x, double y, double z, PlainMesh& d) {
    const Key k{x == 0 ? 0.0 : x, y == 0 ? 0.0 : y, z == 0 ? 0.0 : z};
    const auto it = index_.emplace(k, static_cast<int>(d.xyz.size() / 3));
    if (it.second) d.xyz.insert(d.xyz.end(), {k.x, k.y, k.z});
    return it.first->second;
  }

 private:
  struct Key {
    double x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 1469598103934665603ull;
      for (double v : {k.x, k.y, k.z}) {
        std::uint64_t b;
        std::memcpy(&b, &v, sizeof b);
        h = (h ^ b) * 1099511628211ull;
        h ^= h >> 29;
      }
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<Key, int, Hash> index_;
};

/// Whether the STL keyword w is word (lower case), in any case.
bool stlKeyword(const std::string& w, const char* word) {
  if (w.size() != std::strlen(word)) return false;
  for (std::size_t k = 0; k < w.size(); ++k)
    if (std::tolower(static_cast<unsigned char>(w[k])) != word[k]) return false;
  return true;
}

/// Whether the n bytes at p start, after a byte-order mark and whitespace,
/// with "solid" in any case (as ASCII STL does).
bool startsWithSolid(const char* p, std::size_t n) {
  std::size_t i = n >= 3 && std::memcmp(p, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
  while (i < n && isSpace(p[i])) ++i;
  return n - i >= 5 && stlKeyword(std::string(p + i, 5), "solid");
}

/// Reads a binary or ASCII STL file, its corners welded (CornerWelder). A
/// file is binary when its size is 84 bytes plus 50 per triangle of the
/// count at byte 80; else it must be ASCII ("solid ... endsolid", keywords
/// in any case, several solids allowed; a facet may have more than 3
/// vertices, fan-triangulated). A file of another size that starts with
/// "solid" but has a NUL byte in its first KB is a binary STL of the wrong
/// size, and is reported as one.
void readStl(const std::string& path, PlainMesh& d) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput("cannot open " + quoted(path) + ": " + std::strerror(errno));
  struct stat st;
  const bool regular = ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
  const long long size = regular ? static_cast<long long>(st.st_size) : -1;
  CornerWelder weld;
  char head[1024] = {0};
  in.read(head, sizeof head);
  const std::size_t got = static_cast<std::size_t>(in.gcount());
  std::uint32_t count = 0;
  for (int k = 3; k >= 0; --k) count = count << 8 | static_cast<unsigned char>(head[80 + k]);
  const long long binarySize = 84 + 50 * static_cast<long long>(count);
  if (got >= 84 && size == binarySize) {
    in.clear();
    in.seekg(84);
    std::vector<char> rec(50 * 4096);
    for (std::uint32_t done = 0; done < count;) {
      const std::uint32_t n = std::min<std::uint32_t>(count - done, 4096);
      in.read(rec.data(), 50 * static_cast<std::streamsize>(n));
      if (in.gcount() != 50 * static_cast<std::streamsize>(n))
        throw InvalidInput(quoted(path) + ": binary STL ends inside triangle " + std::to_string(done));
      for (std::uint32_t k = 0; k < n; ++k) {
        float c[9];
        std::memcpy(c, rec.data() + 50 * k + 12, sizeof c);  // after the normal; little-endian floats
        for (int j = 0; j < 3; ++j) d.tri.push_back(weld.add(c[3 * j], c[3 * j + 1], c[3 * j + 2], d));
      }
      done += n;
    }
    d.corners = 3 * static_cast<long long>(count);
    return;
  }
  const std::string sizes = "84 + 50 x " + std::to_string(count) + " = " + std::to_string(binarySize);
  const std::string actual = size >= 0 ? std::to_string(size) + " bytes" : "not a regular file";
  if (!startsWithSolid(head, got)) {
    if (got >= 84)
      throw InvalidInput(quoted(path) + ": not an STL file: as binary STL its size should be " + sizes +
                         " bytes (it is " + (size >= 0 ? std::to_string(size) : actual) +
                         "), and it does not start with 'solid'");
    throw InvalidInput(quoted(path) + ": not an STL file (no 'solid' keyword, too short for binary STL)");
  }
  if (got >= 84 && std::memchr(head, '\0', got) != nullptr)
    throw InvalidInput(quoted(path) + ": a binary STL whose header starts with 'solid', but its size is " +
                       (size >= 0 ? actual : "unknown (" + actual + ")") + " where " + sizes +
                       " were expected (truncated or padded?)");
  in.clear();
  in.seekg(0);
  TextScanner t(in, false, path, "STL");
  auto fail = [&](const std::string& what) {
    throw InvalidInput(quoted(path) + ": STL parse error at line " + std::to_string(t.line()) + ": " + what);
  };
  std::string w;
  t.next(w);  // "solid" (startsWithSolid)
  auto expect = [&](const char* word) {
    if (!t.next(w)) fail(std::string("the file ends where '") + word + "' was expected");
    if (!stlKeyword(w, word)) fail(std::string("expected '") + word + "', got " + shown(w));
  };
  auto number = [&](const char* what) {
    if (!t.next(w)) fail(std::string("the file ends inside a ") + what);
    double x = 0;
    if (!parseDouble(w, x)) fail(std::string("expected a number in a ") + what + ", got " + shown(w));
    return x;
  };
  t.skipRestOfLine();  // the solid's name
  std::vector<int> poly;
  for (;;) {
    if (!t.next(w)) fail("the file ends without 'endsolid'");
    if (stlKeyword(w, "endsolid")) {
      t.skipRestOfLine();
      if (!t.next(w)) break;  // the end
      if (!stlKeyword(w, "solid")) fail("expected 'solid' or the end of the file after 'endsolid', got " + shown(w));
      t.skipRestOfLine();
      continue;
    }
    if (!stlKeyword(w, "facet")) fail("expected 'facet' or 'endsolid', got " + shown(w));
    expect("normal");
    for (int k = 0; k < 3; ++k) number("facet normal");
    expect("outer");
    expect("loop");
    poly.clear();
    for (;;) {
      if (!t.next(w)) fail("the file ends inside a facet");
      if (stlKeyword(w, "endloop")) break;
      if (!stlKeyword(w, "vertex")) fail("expected 'vertex' or 'endloop', got " + shown(w));
      const double x = number("vertex"), y = number("vertex"), z = number("vertex");
      poly.push_back(weld.add(x, y, z, d));
    }
    expect("endfacet");
    if (poly.size() < 3) fail("a facet with " + std::to_string(poly.size()) + " vertices");
    if (poly.size() > 3) d.polygons = true;
    d.corners += static_cast<long long>(poly.size());
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) d.tri.insert(d.tri.end(), {poly[0], poly[k], poly[k + 1]});
  }
}

/// Loads path with read (readObj or readStl) into m; returns what read read.
template <class M>
PlainMesh loadPlain(void (*read)(const std::string&, PlainMesh&), const std::string& path, M& m, LoadInfo& info) {
  PlainMesh d;
  read(path, d);
  fillMesh(d.xyz, d.tri, d.uv, m);
  info.polygons = d.polygons;
  info.vertexNormals = d.normals;
  info.vertexTexCoords = !d.uv.empty();
  info.dropped = d.dropped;
  return d;
}

template <class M>
void loadObj(const std::string& path, M& m, LoadInfo& info) {
  loadPlain(readObj, path, m, info);
}

template <class M>
void loadStl(const std::string& path, M& m, LoadInfo& info) {
  const PlainMesh d = loadPlain(readStl, path, m, info);
  info.weldedCorners = d.corners - static_cast<long long>(d.xyz.size() / 3);
}

// ---------------------------------------------------------------------------
// PLY reading

/// Rejects headers whose element counts cannot fit in the file, before
/// vcglib allocates them.
void checkPlyHeader(const std::string& file, const std::string& path) {
  vcg::ply::PlyFile pf;
  if (pf.Open(file.c_str(), vcg::ply::PlyFile::MODE_READ) == -1)
    throw InvalidInput(quoted(path) + ": PLY parse error: " +
                       vcg::tri::io::ImporterPLY<MeshD>::ErrorMsg(pf.GetError()));
  const long long size = fileSize(file);
  long long need = 0;
  for (const auto& e : pf.elements) {
    if (e.number < 0)
      throw InvalidInput(quoted(path) + ": PLY header declares a negative count of '" + e.name + "'");
    need += static_cast<long long>(e.number) * std::max<long long>(1, static_cast<long long>(e.props.size()));
    if (need > size)
      throw InvalidInput(quoted(path) + ": PLY header declares " + std::to_string(e.number) + " '" + e.name +
                         "' elements, more than the file can hold");
  }
}

// ---------------------------------------------------------------------------
// PLY structure check: the header model, its strict reader, the element
// checks and the body walker behind checkPlyStructure

/// Throws InvalidInput "'path': PLY parse error: why".
[[noreturn]] void plyParseError(const std::string& path, const std::string& why) {
  throw InvalidInput(quoted(path) + ": PLY parse error: " + why);
}

/// Size in bytes of a PLY scalar type; 0 for a name PLY does not define.
int plyTypeSize(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

bool plyTypeSigned(const std::string& t) {
  return t == "char" || t == "short" || t == "int" || t == "int8" || t == "int16" || t == "int32";
}

bool plyTypeFloat(const std::string& t) { return t == "float" || t == "double" || t == "float32" || t == "float64"; }

/// One 'property' line of a PLY header, with what the checks need of its types.
struct PlyProperty {
  bool list = false;
  std::string countType, valueType;  ///< countType is empty for a scalar
  int countSize = 0, valueSize = 0;  ///< plyTypeSize of the types (countSize 0 for a scalar)
  bool countSigned = false, valueSigned = false;
  bool countFloat = false, valueFloat = false;  ///< ASCII values read as numbers, not integers
  bool isIndex = false;     ///< a 'vertex_indices' (or 'vertex_index') list
  bool faceValues = false;  ///< a face 'color' or 'texcoord' list (see PlyBodyWalker::skipList)
  std::string name;
};

/// The property name of type valueType, a list with countType counts unless
/// countType is empty, of an element named 'face' when inFace.
PlyProperty plyProperty(const std::string& countType, const std::string& valueType, const std::string& name,
                        bool inFace) {
  PlyProperty pr;
  pr.list = !countType.empty();
  pr.countType = countType;
  pr.valueType = valueType;
  pr.countSize = plyTypeSize(countType);
  pr.valueSize = plyTypeSize(valueType);
  pr.countSigned = plyTypeSigned(countType);
  pr.valueSigned = plyTypeSigned(valueType);
  pr.countFloat = plyTypeFloat(countType);
  pr.valueFloat = plyTypeFloat(valueType);
  pr.isIndex = pr.list && (name == "vertex_indices" || name == "vertex_index");
  pr.faceValues = inFace && (name == "color" || name == "texcoord");
  pr.name = name;
  return pr;
}

/// One 'element' line of a PLY header and its properties.
struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> props;
};

/// A PLY header as readPlyHeader reads it.
struct PlyHeader {
  std::string format;  ///< the value of the last 'format' line
  std::vector<PlyElement> elems;
};

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

/// The whitespace-separated words of a header line.
std::vector<std::string> plyWords(const std::string& line) {
  std::istringstream ls(line);
  std::vector<std::string> tok;
  for (std::string w; ls >> w;) tok.push_back(w);
  return tok;
}

/// The element of header line lineNo, whose words are tok ("element" first).
PlyElement parsePlyElementLine(const std::vector<std::string>& tok, int lineNo, const std::string& path) {
  if (tok.size() < 3) plyParseError(path, "'element' line " + std::to_string(lineNo) + " needs a name and a count");
  PlyElement e;
  e.name = tok[1];
  char* end = nullptr;
  const long long n = std::strtoll(tok[2].c_str(), &end, 10);
  if (end == tok[2].c_str() || *end != '\0' || n < 0) plyParseError(path, "element '" + e.name + "' has a bad count");
  e.count = n;
  return e;
}

/// The property of header line lineNo, whose words are tok ("property"
/// first), of element e.
PlyProperty parsePlyPropertyLine(const std::vector<std::string>& tok, int lineNo, const PlyElement& e,
                                 const std::string& path) {
  PlyProperty pr;
  if (tok.size() >= 2 && tok[1] == "list") {
    if (tok.size() < 5) plyParseError(path, "incomplete list property on line " + std::to_string(lineNo));
    pr = plyProperty(tok[2], tok[3], tok[4], e.name == "face");
  } else {
    if (tok.size() < 3) plyParseError(path, "incomplete property on line " + std::to_string(lineNo));
    pr = plyProperty("", tok[1], tok[2], e.name == "face");
  }
  if ((pr.list && pr.countSize == 0) || pr.valueSize == 0)
    plyParseError(path, "unknown property type on line " + std::to_string(lineNo));
  return pr;
}

/// Longest PLY header line read (a comment of metadata can be long; binary
/// data read as a header line must not grow without bound).
constexpr std::size_t kMaxPlyHeaderLine = 1 << 20;

/// std::getline for PLY header line lineNo, which throws InvalidInput when
/// the line is longer than kMaxPlyHeaderLine.
bool plyHeaderLine(std::istream& in, std::string& line, int lineNo, const std::string& path) {
  line.clear();
  for (int c; (c = in.get()) != std::char_traits<char>::eof();) {
    if (c == '\n') return true;
    if (line.size() == kMaxPlyHeaderLine)
      plyParseError(path, "header line " + std::to_string(lineNo) + " is longer than " +
                              std::to_string(kMaxPlyHeaderLine) + " bytes");
    line += static_cast<char>(c);
  }
  return !line.empty();
}

/// Reads the header of in, up to and including its 'end_header' line, and
/// throws InvalidInput at a line vcglib's header reader cannot tokenize or
/// would misread. A line ends at its first NUL byte; lines other than
/// 'format', 'element', 'property' and 'end_header' (comments) are skipped.
PlyHeader readPlyHeader(std::istream& in, const std::string& path) {
  PlyHeader h;
  std::string line;
  bool ended = false;
  int lineNo = 0;
  while (!ended && plyHeaderLine(in, line, lineNo + 1, path)) {
    ++lineNo;
    const std::size_t nul = line.find('\0');
    if (nul != std::string::npos) line.resize(nul);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> tok = plyWords(line);
    if (tok.empty()) plyParseError(path, "empty line " + std::to_string(lineNo) + " in the header");
    const std::string& word = tok[0];
    if (lineNo == 1) {
      if (word != "ply") plyParseError(path, "the file does not start with 'ply'");
    } else if (word == "format") {
      if (tok.size() < 2) plyParseError(path, "'format' without a value");
      h.format = tok[1];
    } else if (word == "element") {
      h.elems.push_back(parsePlyElementLine(tok, lineNo, path));
    } else if (word == "property") {
      if (h.elems.empty()) plyParseError(path, "a property before any element");
      h.elems.back().props.push_back(parsePlyPropertyLine(tok, lineNo, h.elems.back(), path));
    } else if (word == "end_header") {
      ended = true;
    }
  }
  if (!ended) plyParseError(path, "the header has no 'end_header'");
  return h;
}

/// What vcglib would report only as "Bad vertex index in face" or "No
/// vertex field found": faces declared before the vertices, and vertex
/// coordinates that are missing or not float or double.
void checkPlyVertexElement(const std::vector<PlyElement>& elems, const std::string& path) {
  std::size_t vertexElem = elems.size(), faceElem = elems.size();
  for (std::size_t k = 0; k < elems.size(); ++k) {
    if (elems[k].name == "vertex" && vertexElem == elems.size()) vertexElem = k;
    if (elems[k].name == "face" && faceElem == elems.size()) faceElem = k;
  }
  if (faceElem < vertexElem && vertexElem < elems.size() && elems[faceElem].count > 0)
    plyParseError(path, "the header declares element 'face' before element 'vertex'; the reader needs the "
                        "vertices first (write the vertex element first)");
  if (vertexElem == elems.size() || elems[vertexElem].count == 0) return;
  int coords = 0;
  for (const PlyProperty& pr : elems[vertexElem].props) {
    if (pr.list || (pr.name != "x" && pr.name != "y" && pr.name != "z")) continue;
    if (!pr.valueFloat)
      plyParseError(path, "vertex property '" + pr.name + "' has type '" + pr.valueType +
                              "'; coordinates must be float or double");
    ++coords;
  }
  if (coords < 3) plyParseError(path, "the vertex element lacks float or double properties 'x', 'y' and 'z'");
}

/// vcglib reads triangle strips and range grids with vertex indices it does
/// not fully check, and range grids into a 5-entry buffer.
void checkPlyNoStripsOrGrids(const std::vector<PlyElement>& elems, const std::string& path) {
  for (const PlyElement& e : elems)
    if ((e.name == "tristrips" || e.name == "range_grid") && e.count > 0)
      plyParseError(path, "'" + e.name + "' elements are not supported; save the mesh with a 'face' element");
}

/// The count of the last 'vertex' element (0 without one): the range of
/// face vertex indices.
long long plyVertexCount(const std::vector<PlyElement>& elems) {
  long long vertices = 0;
  for (const PlyElement& e : elems)
    if (e.name == "vertex") vertices = e.count;
  return vertices;
}

/// A non-empty face element needs exactly one vertex index list, of a
/// (count, index) type pair vcglib's importer has a descriptor for.
void checkPlyFaceLists(const std::vector<PlyElement>& elems, const std::string& path) {
  for (const PlyElement& e : elems) {
    if (e.name != "face" || e.count == 0) continue;
    int lists = 0;
    for (const PlyProperty& pr : e.props) {
      if (!pr.isIndex) continue;
      ++lists;
      const std::string& c = pr.countType;
      const std::string& v = pr.valueType;
      const bool countOk = c == "uchar" || c == "char" || c == "int" || c == "uint8" || c == "int8" || c == "int32";
      const bool wideCount = c == "int" || c == "int32";
      const bool indexOk = v == "int" || v == "int32" || ((v == "uint" || v == "uint32") && !wideCount) ||
                           (v == "short" && !wideCount);
      if (!countOk || !indexOk)
        plyParseError(path, "face lists of type '" + c + " " + v + "' are not supported (use 'uchar int')");
    }
    if (lists != 1) plyParseError(path, "the face element needs exactly one 'vertex_indices' list");
  }
}

PlyFormat plyFormat(const std::string& format, const std::string& path) {
  if (format == "ascii") return PlyFormat::Ascii;
  if (format == "binary_big_endian") return PlyFormat::BinaryBigEndian;
  if (format != "binary_little_endian") plyParseError(path, "unknown format '" + format + "'");
  return PlyFormat::BinaryLittleEndian;
}

/// Element counts the file cannot hold (each needs at least a byte per
/// property): refused before walking, so a huge count costs nothing.
void checkPlyCountsFit(const std::vector<PlyElement>& elems, const std::string& file, const std::string& path) {
  const long long size = fileSize(file);
  long long need = 0;
  for (const PlyElement& e : elems) {
    const bool tooMany = e.count > size;  // checked first: the product below must not overflow
    if (!tooMany) need += e.count * static_cast<long long>(std::max<std::size_t>(1, e.props.size()));
    if (tooMany || need > size)
      plyParseError(path, "the header declares " + std::to_string(e.count) + " '" + e.name +
                              "' elements, more than the file can hold");
  }
}

/// Whether the ASCII token [t, t + size) is one plain number: an integer
/// ([+-]digits) when integer, else also a fraction, an exponent, nan or inf.
/// vcglib scans ASCII values with scanf, which stops at the first character
/// that cannot continue a number: "1-1" is read as two values, "3.0" for an
/// integer as "3" then ".0". Tokens it would split that way would put every
/// later value out of step with the body walk (and, in faces, hand vcglib
/// unchecked vertex indices).
bool plainPlyNumber(const char* t, std::size_t size, bool integer) {
  std::size_t i = 0;
  if (i < size && (t[i] == '+' || t[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < size && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++digits;
  if (integer) return digits > 0 && i == size;
  if (digits == 0) {  // scanf also reads nan and inf (the loader then refuses them by name)
    std::string w(t + i, size - i);
    for (char& c : w) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (w == "nan" || w == "inf" || w == "infinity") return true;
  }
  if (i < size && t[i] == '.') {
    ++i;
    while (i < size && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < size && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < size && (t[i] == '+' || t[i] == '-')) ++i;
    std::size_t exp = 0;
    while (i < size && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++exp;
    if (exp == 0) return false;
  }
  return i == size;
}

/// Walks the body of a PLY file (ASCII or binary) after readPlyHeader, value
/// by value where vcglib's reader needs checking, and throws InvalidInput at
/// the first problem: data that ends early, malformed ASCII numbers, faces
/// with fewer than 3 or more than 255 corners or a vertex index out of
/// range, and lists that overflow vcglib's fixed buffers.
class PlyBodyWalker {
 public:
  /// in is positioned at the first byte of the body of file; vertices is the
  /// range of face vertex indices.
  PlyBodyWalker(std::istream& in, const std::string& file, const std::string& path, PlyFormat format,
                long long vertices)
      : in_(in),
        path_(path),
        ascii_(format == PlyFormat::Ascii),
        bigEndian_(format == PlyFormat::BinaryBigEndian),
        vertices_(vertices),
        buf_(ascii_ ? 0 : 1 << 16),
        bodyStart_(in.tellg()),
        size_(fileSize(file)) {
    // An ASCII body is read by a scanner of its own (TextScanner).
    if (ascii_) text_.reset(new TextScanner(in_, false, path, std::string()));
    if (!ascii_ && bodyStart_ >= 0) bufBase_ = static_cast<long long>(bodyStart_);
  }

  /// Walks the elements of the header, in order.
  void walk(const std::vector<PlyElement>& elems) {
    for (const PlyElement& e : elems) {
      if (e.props.empty()) continue;
      if (!ascii_ && std::none_of(e.props.begin(), e.props.end(), [](const PlyProperty& pr) { return pr.list; }))
        jumpFixedRows(e);
      else
        walkRows(e);
    }
  }

 private:
  [[noreturn]] void fail(const std::string& why) const { plyParseError(path_, why); }
  [[noreturn]] void truncated(const PlyElement& e) const { fail("the data ends inside element '" + e.name + "'"); }

  void checkToken(const char* t, std::size_t size, bool floatType) const {
    if (!plainPlyNumber(t, size, !floatType))
      fail("malformed " + std::string(floatType ? "number" : "integer") + " " + shown(t, size) + " in the data");
  }

  /// Where a bad face was read: the byte offset (binary) or line (ASCII),
  /// and, in binary, what most often puts faces out of step.
  std::string where(long long valueBytes) const {
    if (ascii_) return " (line " + std::to_string(text_->line()) + ")";
    return " (byte " + std::to_string(bufBase_ + static_cast<long long>(bufAt_) - valueBytes) +
           " of the file; a header count larger or smaller than the data it describes reads the faces "
           "from the wrong place)";
  }

  // The binary body is read through a buffer of its own: a stream read per
  // value cost more than everything this walk checks.
  bool refill() {
    bufBase_ += static_cast<long long>(bufEnd_);
    in_.read(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    bufEnd_ = static_cast<std::size_t>(in_.gcount());
    bufAt_ = 0;
    in_.clear();  // a short read at the end of the file leaves the stream usable for seeks
    return bufEnd_ > 0;
  }
  bool readBytes(unsigned char* out, int n) {
    for (int k = 0; k < n; ++k) {
      if (bufAt_ == bufEnd_ && !refill()) return false;
      out[k] = static_cast<unsigned char>(buf_[bufAt_++]);
    }
    return true;
  }
  bool skipBytes(long long n) {
    while (n > 0) {
      if (bufAt_ == bufEnd_ && !refill()) return false;
      const long long take = std::min<long long>(n, static_cast<long long>(bufEnd_ - bufAt_));
      bufAt_ += static_cast<std::size_t>(take);
      n -= take;
    }
    return true;
  }

  /// Reads one integer of the given PLY type into out; false at the end of
  /// the data.
  bool readInt(bool floatType, int size, bool sign, long long& out) {
    if (ascii_) return readAsciiInt(floatType, out);
    unsigned char b[8] = {0};
    if (!readBytes(b, size)) return false;
    unsigned long long u = 0;
    for (int k = 0; k < size; ++k) u = (u << 8) | b[bigEndian_ ? k : size - 1 - k];
    if (sign && size < 8 && ((u >> (8 * size - 1)) & 1u))
      out = static_cast<long long>(u) - (1LL << (8 * size));
    else
      out = static_cast<long long>(u);
    return true;
  }
  bool readAsciiInt(bool floatType, long long& out) {
    const char* t = nullptr;
    std::size_t n = 0;
    if (!text_->next(t, n)) return false;
    checkToken(t, n, floatType);
    if (!floatType) {
      // [+-]digits (checkToken): read exactly, -1 beyond 4e9 as below.
      std::size_t i = t[0] == '+' || t[0] == '-' ? 1 : 0;
      while (i + 1 < n && t[i] == '0') ++i;
      if (n - i > 10) {
        out = -1;
        return true;
      }
      long long v = 0;
      for (; i < n; ++i) v = 10 * v + (t[i] - '0');
      out = v > 4000000000LL ? -1 : t[0] == '-' ? -v : v;
      return true;
    }
    // The value as strtod reads it (the token is followed by whitespace or
    // '\0'); -1 when it is not a usable count or index (not finite, or
    // beyond 4e9).
    char* end = nullptr;
    const double d = std::strtod(t, &end);
    if (end == t || !std::isfinite(d) || std::abs(d) > 4e9) {
      out = -1;
      return true;
    }
    out = static_cast<long long>(d);
    return true;
  }

  /// Skips values values of the given PLY type; false at the end of the data.
  bool skip(long long values, bool floatType, int size) {
    if (!ascii_) return skipBytes(values * size);
    const char* t = nullptr;
    std::size_t n = 0;
    for (long long k = 0; k < values; ++k) {
      if (!text_->next(t, n)) return false;
      checkToken(t, n, floatType);
    }
    return true;
  }

  /// Binary rows of scalars only: nothing in them to check, one jump over
  /// all of them.
  void jumpFixedRows(const PlyElement& e) {
    long long row = 0;
    for (const PlyProperty& pr : e.props) row += pr.valueSize;
    const long long at = bufBase_ + static_cast<long long>(bufAt_);
    if (bodyStart_ < 0 || e.count > (size_ - at) / std::max(1LL, row)) truncated(e);
    const long long to = at + e.count * row;
    if (to <= bufBase_ + static_cast<long long>(bufEnd_)) {
      bufAt_ = static_cast<std::size_t>(to - bufBase_);
    } else {
      in_.seekg(static_cast<std::streamoff>(to));
      if (in_.fail()) truncated(e);
      bufBase_ = to;
      bufAt_ = bufEnd_ = 0;
    }
  }

  /// Every row of e, value by value.
  void walkRows(const PlyElement& e) {
    const bool isFace = e.name == "face";
    for (long long i = 0; i < e.count; ++i)
      for (const PlyProperty& pr : e.props) {
        if (!pr.list) {
          if (!skip(1, pr.valueFloat, pr.valueSize)) truncated(e);
          continue;
        }
        long long n = 0;
        if (!readInt(pr.countFloat, pr.countSize, pr.countSigned, n)) truncated(e);
        if (isFace && pr.isIndex)
          checkFaceCorners(e, i, pr, n);
        else
          skipList(e, i, pr, n);
      }
  }

  /// The n vertex indices of face i, after their count.
  void checkFaceCorners(const PlyElement& e, long long i, const PlyProperty& pr, long long n) {
    if (n < 3 || n > 255)
      fail("face " + std::to_string(i) + " has " + (n < 0 ? std::string("an invalid number of") : std::to_string(n)) +
           " corners; faces need 3 to 255 corners" + where(pr.countSize));
    for (long long k = 0; k < n; ++k) {
      long long idx = 0;
      if (!readInt(pr.valueFloat, pr.valueSize, pr.valueSigned, idx)) truncated(e);
      if (idx < 0 || idx >= vertices_)
        fail("face " + std::to_string(i) + " has a vertex index out of range, " +
             (idx < 0 ? std::string("negative") : std::to_string(idx)) + " of " + std::to_string(vertices_) +
             " vertices" + where(pr.valueSize));
    }
  }

  /// The n values of list pr of row i of e (not face indices), after their
  /// count. vcglib reads a face 'color' or 'texcoord' list into a 32-value
  /// buffer, and skips every other binary list with a one-byte count into a
  /// 512-byte buffer.
  void skipList(const PlyElement& e, long long i, const PlyProperty& pr, long long n) {
    if (n < 0) truncated(e);
    if (pr.faceValues && n > 32)
      fail("face " + std::to_string(i) + " has " + std::to_string(n) + " '" + pr.name +
           "' values; at most 32 are supported");
    if (!ascii_ && pr.countSize != 1)
      fail("list property '" + pr.name + "' of element '" + e.name + "' has a " + pr.countType +
           " count; only one-byte counts are supported outside face indices");
    if (!ascii_ && n == 0 && !pr.faceValues)  // vcglib takes its zero-byte read for the end of the file
      fail(e.name + " " + std::to_string(i) + " has an empty '" + pr.name +
           "' list; binary lists the reader skips cannot be empty");
    if (!ascii_ && n * pr.valueSize > 512)
      fail(e.name + " " + std::to_string(i) + " has " + std::to_string(n) + " '" + pr.name +
           "' values, more than the reader can skip (512 bytes)");
    if (!skip(n, pr.valueFloat, pr.valueSize)) truncated(e);
  }

  std::istream& in_;
  const std::string& path_;
  const bool ascii_, bigEndian_;
  const long long vertices_;
  std::unique_ptr<TextScanner> text_;
  std::vector<char> buf_;
  long long bufBase_ = 0;  ///< file offset of buf_[0]
  std::size_t bufAt_ = 0, bufEnd_ = 0;
  const std::istream::pos_type bodyStart_;
  const long long size_;  ///< of the file
};

/// Validates what vcglib 2020.09's PLY reader trusts blindly, before it reads
/// the file: header lines it cannot tokenize (an empty line, an element
/// without a count) crash it; a face list type it has no descriptor for, or a
/// face element without a vertex index list, leaves corners uninitialised;
/// a face with fewer than 3 or more than 255 corners overflows or truncates its
/// fixed corner buffer; it range-checks only some corners of polygons; it
/// reads other lists into fixed buffers (32 face colour or texture values, 512
/// bytes for a skipped binary list, whose count it takes as one byte whatever
/// its declared type) and triangle strips with unchecked indices. Walks
/// the whole body (ASCII or binary) and throws InvalidInput naming the first
/// problem.
PlyHeader checkPlyStructure(const std::string& file, const std::string& path) {
  std::ifstream in(file, std::ios::binary);
  const PlyHeader header = readPlyHeader(in, path);
  checkPlyVertexElement(header.elems, path);
  checkPlyNoStripsOrGrids(header.elems, path);
  checkPlyFaceLists(header.elems, path);
  const PlyFormat format = plyFormat(header.format, path);
  checkPlyCountsFit(header.elems, file, path);
  PlyBodyWalker(in, file, path, format, plyVertexCount(header.elems)).walk(header.elems);
  return header;
}

/// What of a PLY file with header h a mesh read by vcglib's importer (which
/// reported mask) does not keep, for LoadInfo::dropped: vertex properties
/// other than the coordinates, flags (their selection bit), normals,
/// colour, quality and texture coordinates (when texCoords: the mesh has
/// them), face properties other than the vertex indices, other elements.
std::vector<std::string> plyDropped(const PlyHeader& h, int mask, bool texCoords) {
  namespace io = vcg::tri::io;
  std::vector<std::string> kept{"x", "y", "z", "flags"};
  auto keep = [&](bool read, std::initializer_list<const char*> names) {
    if (read) kept.insert(kept.end(), names.begin(), names.end());
  };
  // The names vcglib's importer reads into each component.
  keep(mask & io::Mask::IOM_VERTNORMAL, {"nx", "ny", "nz"});
  keep(mask & io::Mask::IOM_VERTCOLOR, {"red", "green", "blue", "alpha", "diffuse_red", "diffuse_green",
                                         "diffuse_blue", "diffuse_alpha", "intensity"});
  keep(mask & io::Mask::IOM_VERTQUALITY, {"quality", "confidence"});
  keep(texCoords && (mask & io::Mask::IOM_VERTTEXCOORD), {"s", "t", "texture_u", "texture_v"});
  std::vector<std::string> out;
  for (const PlyElement& e : h.elems) {
    if (e.count == 0) continue;
    if (e.name != "vertex" && e.name != "face") {
      out.push_back(std::to_string(e.count) + " '" + e.name + "' element" + (e.count > 1 ? "s" : ""));
      continue;
    }
    std::string names;
    int n = 0;
    for (const PlyProperty& pr : e.props) {
      const bool read = e.name == "vertex" ? !pr.list && std::find(kept.begin(), kept.end(), pr.name) != kept.end()
                                           : pr.isIndex;
      if (read) continue;
      names += (n++ ? ", '" : "'") + pr.name + "'";
    }
    if (n > 0) out.push_back(e.name + (n > 1 ? " properties " : " property ") + names);
  }
  return out;
}

/// A file removed when this goes out of scope.
struct ScratchFile {
  std::string path;
  ~ScratchFile() {
    if (!path.empty()) ::unlink(path.c_str());
  }
};

/// A scratch file of TMPDIR (or /tmp) for scratch, opened for writing.
std::ofstream scratchStream(ScratchFile& scratch, const std::string& path) {
  const char* tmp = std::getenv("TMPDIR");
  std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/sodt_ply_XXXXXX";
  std::vector<char> name(templ.begin(), templ.end());
  name.push_back('\0');
  const int fd = ::mkstemp(name.data());
  if (fd < 0) throw InvalidInput(quoted(path) + ": cannot create a scratch file in " + quoted(templ));
  ::close(fd);
  scratch.path = name.data();
  return std::ofstream(scratch.path, std::ios::binary | std::ios::trunc);
}

/// Longest PLY header read (with kMaxPlyHeaderLine, what keeps a header of
/// endless lines from growing without bound).
constexpr std::size_t kMaxPlyHeader = 16 << 20;

/// The file the PLY checks and vcglib read: path itself, or a copy of it in
/// scratch without what vcglib 2020.09 cannot read: a UTF-8 byte-order mark
/// before "ply", and header comment or obj_info lines longer than its
/// 512-byte line buffer (metadata as JSON, say), shortened. Throws
/// InvalidInput at once when a file that is not empty does not start with
/// "ply" (binary data, or another format).
std::string plyPrepared(const std::string& path, ScratchFile& scratch) {
  const std::size_t kMaxLine = 500;  // below vcglib's limit, with room for "\r\n"
  std::ifstream in(path, std::ios::binary);
  char start[6] = {0};
  in.read(start, sizeof start);
  const std::size_t got = static_cast<std::size_t>(in.gcount());
  const bool bom = got >= 3 && std::memcmp(start, "\xEF\xBB\xBF", 3) == 0;
  const std::size_t from = bom ? 3 : 0;
  if (got > 0 && (got < from + 3 || std::memcmp(start + from, "ply", 3) != 0))
    plyParseError(path, "the file does not start with 'ply'");
  in.clear();
  in.seekg(static_cast<std::streamoff>(from));
  std::vector<std::string> header;
  std::size_t bytes = 0;
  bool tooLong = false, complete = false;
  std::string line;
  for (int lineNo = 1; !complete && plyHeaderLine(in, line, lineNo, path); ++lineNo) {
    bytes += line.size() + 1;
    if (bytes > kMaxPlyHeader)
      plyParseError(path, "the header is longer than " + std::to_string(kMaxPlyHeader) + " bytes");
    const std::string word = line.substr(0, line.find_first_of(" \t\r"));
    if (line.size() > kMaxLine) {
      if (word != "comment" && word != "obj_info") return path;  // let vcglib report it
      tooLong = true;
      line.resize(kMaxLine - 100);
    }
    header.push_back(line);
    complete = word == "end_header";
  }
  if (!bom && (!tooLong || !complete)) return path;
  std::ofstream out = scratchStream(scratch, path);
  for (const std::string& h : header) out << h << '\n';
  if (in.peek() != std::char_traits<char>::eof()) out << in.rdbuf();  // the body, unchanged
  out.close();
  if (!out)
    throw InvalidInput(quoted(path) + ": cannot copy it to " + quoted(scratch.path) +
                       (bom ? " without its byte-order mark" : " to shorten its long header comments"));
  return scratch.path;
}

/// The body of a binary_big_endian PLY file with elements elems, every
/// scalar and list value byte-swapped by its type's size; bytes after the
/// last element are copied unchanged.
std::vector<char> plyBodySwapped(const std::vector<char>& body, const std::vector<PlyElement>& elems,
                                 const std::string& path) {
  std::vector<char> out(body.size());
  std::size_t at = 0;
  auto take = [&](int size) {
    if (at + static_cast<std::size_t>(size) > body.size()) plyParseError(path, "the data ends early");
    for (int k = 0; k < size; ++k) out[at + static_cast<std::size_t>(k)] = body[at + static_cast<std::size_t>(size - 1 - k)];
    at += static_cast<std::size_t>(size);
  };
  for (const PlyElement& e : elems)
    for (long long i = 0; i < e.count; ++i)
      for (const PlyProperty& pr : e.props) {
        if (!pr.list) {
          take(pr.valueSize);
          continue;
        }
        take(pr.countSize);
        unsigned long long n = 0;  // the count, now little-endian
        for (int k = pr.countSize - 1; k >= 0; --k)
          n = (n << 8) | static_cast<unsigned char>(out[at - static_cast<std::size_t>(pr.countSize - k)]);
        for (unsigned long long v = 0; v < n; ++v) take(pr.valueSize);
      }
  std::copy(body.begin() + static_cast<std::ptrdiff_t>(at), body.end(), out.begin() + static_cast<std::ptrdiff_t>(at));
  return out;
}

/// vcglib 2020.09 byte-swaps big-endian chars, shorts, ints and floats but
/// not doubles (its SwapDouble is empty), so a big-endian PLY with double
/// properties loads as garbage. When file is binary_big_endian, writes a
/// little-endian copy into scratch (every scalar and list value swapped by
/// its type's size, the format line changed) and returns its path;
/// otherwise returns file. \pre checkPlyStructure accepted file.
std::string plyInLittleEndian(const std::string& file, const std::string& path, ScratchFile& scratch) {
  std::ifstream in(file, std::ios::binary);
  // Not readPlyHeader: the lines are copied as they are, and this reader is
  // laxer (a line ends at '\n' only, not at a NUL byte).
  std::vector<std::string> header;
  std::vector<PlyElement> elems;  // only counts and the sizes of the types
  bool bigEndian = false;
  std::string line;
  for (int lineNo = 1; plyHeaderLine(in, line, lineNo, path); ++lineNo) {
    const std::vector<std::string> tok = plyWords(line);
    if (!tok.empty() && tok[0] == "format" && tok.size() >= 2) {
      if (tok[1] != "binary_big_endian") return file;
      bigEndian = true;
      line = "format binary_little_endian 1.0";
    } else if (!tok.empty() && tok[0] == "element" && tok.size() >= 3) {
      elems.push_back(PlyElement{std::string(), std::stoll(tok[2]), {}});
    } else if (!tok.empty() && tok[0] == "property" && !elems.empty()) {
      PlyProperty pr;
      if (tok.size() >= 5 && tok[1] == "list")
        pr = plyProperty(tok[2], tok[3], tok[4], false);
      else if (tok.size() >= 3)
        pr = plyProperty("", tok[1], tok[2], false);
      if (pr.valueSize == 0 || (tok[1] == "list" && pr.countSize == 0)) return file;  // let vcglib report it
      elems.back().props.push_back(pr);
    }
    header.push_back(line);
    if (!tok.empty() && tok[0] == "end_header") break;
  }
  if (!bigEndian) return file;
  const std::vector<char> body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::vector<char> out = plyBodySwapped(body, elems, path);
  std::ofstream o = scratchStream(scratch, path);
  for (const std::string& h : header) o << h << '\n';
  o.write(out.data(), static_cast<std::streamsize>(out.size()));
  o.close();
  if (!o) throw InvalidInput(quoted(path) + ": cannot write a little-endian copy to " + quoted(scratch.path));
  return scratch.path;
}

template <class M>
void loadPly(const std::string& path, M& m, LoadInfo& info) {
  ScratchFile prepared, swapped;
  const std::string checked = plyPrepared(path, prepared);
  const PlyHeader header = checkPlyStructure(checked, path);  // first: vcglib's own header reader crashes on some headers
  const std::string file = plyInLittleEndian(checked, path, swapped);
  checkPlyHeader(file, path);
  using Importer = vcg::tri::io::ImporterPLY<M>;
  int mask = 0;
  const int err = Importer::Open(m, file.c_str(), mask);
  if (Importer::ErrorCritical(err))
    throw InvalidInput(quoted(path) + ": PLY parse error: " + Importer::ErrorMsg(err));
  // vcglib range-checks only some corners of triangulated polygons.
  const auto* first = m.vert.empty() ? nullptr : &m.vert[0];
  for (std::size_t f = 0; f < m.face.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto* v = m.face[f].cV(k);
      if (first == nullptr || v == nullptr || std::less<const void*>()(v, first) ||
          !std::less<const void*>()(v, first + m.vert.size()))
        throw InvalidInput(quoted(path) + ": face " + std::to_string(f) + " has a vertex index out of range");
    }
  using VT = typename M::VertexType;
  using FT = typename M::FaceType;
  if (mask & vcg::tri::io::Mask::IOM_VERTFLAGS) {
    // Keep the selection only: other bits (deleted, visited...) are run state.
    for (auto& v : m.vert) v.Flags() &= VT::SELECTED;
    m.vn = static_cast<int>(m.vert.size());  // a stored "deleted" bit no longer hides a vertex
    info.vertexSelection = true;
  }
  if (mask & vcg::tri::io::Mask::IOM_FACEFLAGS)
  {
    for (auto& f : m.face) f.Flags() &= (FT::SELECTED | FT::FAUX0 | FT::FAUX1 | FT::FAUX2);
    m.fn = static_cast<int>(m.face.size());
  }
  info.vertexQuality = (mask & vcg::tri::io::Mask::IOM_VERTQUALITY) != 0;
  info.vertexColor = (mask & vcg::tri::io::Mask::IOM_VERTCOLOR) != 0;
  info.polygons = (mask & vcg::tri::io::Mask::IOM_BITPOLYGONAL) != 0;
  info.vertexNormals = (mask & vcg::tri::io::Mask::IOM_VERTNORMAL) != 0;
  const bool texCoords = vcg::tri::HasPerVertexTexCoord(m);
  info.vertexTexCoords = texCoords && (mask & vcg::tri::io::Mask::IOM_VERTTEXCOORD) != 0;
  info.dropped = plyDropped(header, mask, texCoords);
}

/// Loads file, read as a mesh of format fmt, into m.
template <class M>
void loadFormat(MeshFormat fmt, const std::string& file, M& m, LoadInfo& info) {
  switch (fmt) {
    case MeshFormat::Ply: loadPly(file, m, info); break;
    case MeshFormat::Off: loadOff(file, m, info); break;
    case MeshFormat::Obj: loadObj(file, m, info); break;
    case MeshFormat::Stl: loadStl(file, m, info); break;
  }
}

template <class M>
void loadMeshImpl(const std::string& path, M& m, LoadInfo* infoOut) {
  LoadInfo info;
  m.Clear();
  m.textures.clear();  // vcglib's Clear() keeps them
  const MeshFormat fmt = meshFormatFromPath(path);
  checkReadable(path);
  try {
    loadFormat(fmt, path, m, info);
  } catch (const InvalidInput&) {
    m.Clear();
    throw;
  } catch (const std::bad_alloc&) {
    m.Clear();
    throw InvalidInput(quoted(path) + ": out of memory while reading");
  } catch (const std::exception& e) {
    m.Clear();
    throw InvalidInput(quoted(path) + ": cannot read: " + e.what());
  }
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    const auto& p = m.vert[i].cP();
    if (!std::isfinite(double(p[0])) || !std::isfinite(double(p[1])) || !std::isfinite(double(p[2]))) {
      m.Clear();
      throw InvalidInput(quoted(path) + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
    // Squared lengths of larger coordinates overflow double arithmetic.
    if (std::abs(double(p[0])) > kMaxCoordinate || std::abs(double(p[1])) > kMaxCoordinate ||
        std::abs(double(p[2])) > kMaxCoordinate) {
      m.Clear();
      throw InvalidInput(quoted(path) + ": vertex " + std::to_string(i) + " has a coordinate larger than 1e150");
    }
    if (m.vert[i].IsS()) ++info.selectedVertices;
  }
  // The size of the surface (the vertices of faces; all vertices of a point
  // cloud): every command refuses the sizes the smoother does.
  std::vector<char> onFace(m.vert.size(), 0);
  for (const auto& f : m.face)
    for (int j = 0; j < 3; ++j) onFace[static_cast<std::size_t>(f.cV(j) - &m.vert[0])] = 1;
  vcg::Box3d box;
  for (std::size_t i = 0; i < m.vert.size(); ++i)
    if (onFace[i] || m.fn == 0) box.Add(vcg::Point3d::Construct(m.vert[i].cP()));
  try {
    checkMeshSize(box.IsNull() ? 0.0 : box.Diag());
  } catch (const InvalidInput& e) {
    m.Clear();
    throw InvalidInput(quoted(path) + ": " + e.what());
  }
  vcg::tri::UpdateBounding<M>::Box(m);
  if (m.fn > 0) vcg::tri::UpdateNormal<M>::PerVertexNormalizedPerFace(m);
  if (infoOut) *infoOut = info;
}

// ---------------------------------------------------------------------------
// Writing

[[noreturn]] void throwErrno(const std::string& what) { throw IoError(what + ": " + std::strerror(errno)); }

/// A vcglib writer's failure: the system's reason when errno holds one (as
/// the project's own writers say), else vcglib's message.
[[noreturn]] void throwWriteError(const std::string& target, const char* format, const char* vcgMessage) {
  if (errno != 0) throwErrno(quoted(target) + ": cannot write");
  throw IoError(quoted(target) + ": cannot write " + format + ": " + vcgMessage);
}

/// Copies the live elements of src into dst (positions, normals, quality,
/// colour, texture coordinates and files, selection); vcglib 2020.09's
/// Append does not accept a const source.
template <class M>
void compactCopy(const M& src, M& dst, bool selectionOnly) {
  dst.Clear();
  dst.textures = src.textures;
  std::vector<int> remap(src.vert.size(), -1);
  int nv = 0;
  for (std::size_t i = 0; i < src.vert.size(); ++i)
    if (!src.vert[i].IsD()) remap[i] = nv++;
  if (nv > 0) vcg::tri::Allocator<M>::AddVertices(dst, static_cast<std::size_t>(nv));
  for (std::size_t i = 0; i < src.vert.size(); ++i) {
    if (remap[i] < 0) continue;
    const auto& a = src.vert[i];
    auto& b = dst.vert[static_cast<std::size_t>(remap[i])];
    b.P() = a.cP();
    b.N() = a.cN();
    b.Q() = a.cQ();
    b.C() = a.cC();
    b.T() = a.cT();
    b.Flags() = selectionOnly ? (a.cFlags() & M::VertexType::SELECTED) : a.cFlags();
  }
  int nf = 0;
  for (const auto& f : src.face)
    if (!f.IsD()) ++nf;
  if (nf > 0) vcg::tri::Allocator<M>::AddFaces(dst, static_cast<std::size_t>(nf));
  std::size_t k = 0;
  for (const auto& f : src.face) {
    if (f.IsD()) continue;
    for (int j = 0; j < 3; ++j)
      dst.face[k].V(j) = &dst.vert[static_cast<std::size_t>(remap[static_cast<std::size_t>(f.cV(j) - &src.vert[0])])];
    ++k;
  }
}

/// Throws IoError naming target when rounding the positions of m's face
/// corners to single precision (binary STL's only kind) would make vertices
/// that differ coincide: the STL would read back with fewer vertices and
/// collapsed triangles (a mesh far from the origin for its size).
/// \pre m is compact.
template <class M>
void checkSinglePrecision(const std::string& target, const M& m) {
  if (sizeof(typename M::ScalarType) <= sizeof(float) || m.face.empty()) return;
  using P3 = std::array<double, 3>;
  const auto key = [](double x, double y, double z) { return P3{x == 0 ? 0.0 : x, y == 0 ? 0.0 : y, z == 0 ? 0.0 : z}; };
  const auto rounded = [&](const P3& p) { return key(float(p[0]), float(p[1]), float(p[2])); };
  std::vector<char> used(m.vert.size(), 0);
  for (const auto& f : m.face)
    for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(f.cV(k) - &m.vert[0])] = 1;
  // (rounded, exact) of every distinct used position: groups of equal rounded
  // positions with several exact ones are vertices that would merge.
  std::vector<std::pair<P3, P3>> pts;
  vcg::Box3d box;
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    if (!used[i]) continue;
    const auto& p = m.vert[i].cP();
    const P3 exact = key(double(p[0]), double(p[1]), double(p[2]));
    pts.emplace_back(rounded(exact), exact);
    box.Add(vcg::Point3d(exact[0], exact[1], exact[2]));
  }
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  long long merged = 0, into = 0;
  for (std::size_t a = 0, b = 0; a < pts.size(); a = b) {
    for (b = a + 1; b < pts.size() && pts[b].first == pts[a].first;) ++b;
    if (b - a > 1) {
      merged += static_cast<long long>(b - a);
      ++into;
    }
  }
  if (merged == 0) return;
  long long collapsed = 0;
  for (const auto& f : m.face) {
    P3 c[3];
    for (int k = 0; k < 3; ++k) c[k] = key(double(f.cV(k)->cP()[0]), double(f.cV(k)->cP()[1]), double(f.cV(k)->cP()[2]));
    for (int k = 0; k < 3; ++k)
      if (c[k] != c[(k + 1) % 3] && rounded(c[k]) == rounded(c[(k + 1) % 3])) {
        ++collapsed;
        break;
      }
  }
  char where[96];
  std::snprintf(where, sizeof where, "%.3g across, %.3g from the origin", box.Diag(), box.Center().Norm());
  throw IoError(quoted(target) + ": not written: STL holds coordinates in single precision, and rounding to it "
                "would merge " + std::to_string(merged) + " vertices into " + std::to_string(into) +
                (collapsed > 0 ? " and collapse " + std::to_string(collapsed) + " of the " +
                                     std::to_string(m.face.size()) + " triangles"
                               : std::string()) +
                " (the mesh is " + where + "); write PLY, OFF or OBJ, which keep double precision, or move the "
                "mesh near the origin");
}

/// Writes a compact mesh (no deleted element) as OBJ (ASCII: every vertex,
/// in order, with as many digits as its scalar type needs to read back
/// exactly, then with opt its texture coordinates (vt, exact floats) and
/// normals (vn), and 1-based triangles whose corners name all three by the
/// vertex's index) or binary STL (single precision, as the format is: per
/// triangle a unit normal and three corners; no vertex list, so unreferenced
/// vertices are not kept; see checkSinglePrecision).
template <class M>
void writePlain(const std::string& target, const std::string& file, const M& m, MeshFormat fmt,
                const SaveOptions& opt) {
  if (fmt == MeshFormat::Stl) checkSinglePrecision(target, m);
  FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) throw IoError(quoted(target) + ": cannot write: " + std::strerror(errno));
  std::vector<char> buf(1 << 20);
  std::setvbuf(f, buf.data(), _IOFBF, buf.size());
  bool ok = true;
  if (fmt == MeshFormat::Obj) {
    const int digits = sizeof(typename M::ScalarType) == 4 ? 9 : 17;
    ok = std::fprintf(f, "# written by sodt: %d vertices, %d triangles\n", m.vn, m.fn) > 0;
    for (std::size_t i = 0; ok && i < m.vert.size(); ++i) {
      const auto& p = m.vert[i].cP();
      ok = std::fprintf(f, "v %.*g %.*g %.*g\n", digits, double(p[0]), digits, double(p[1]), digits,
                        double(p[2])) > 0;
    }
    const bool tex = opt.vertexTexCoords && vcg::tri::HasPerVertexTexCoord(m);
    for (std::size_t i = 0; tex && ok && i < m.vert.size(); ++i)
      ok = std::fprintf(f, "vt %.9g %.9g\n", double(m.vert[i].cT().U()), double(m.vert[i].cT().V())) > 0;
    const int normalDigits = sizeof(typename M::VertexType::NormalType::ScalarType) == 4 ? 9 : 17;
    for (std::size_t i = 0; opt.vertexNormals && ok && i < m.vert.size(); ++i) {
      const auto& n = m.vert[i].cN();
      ok = std::fprintf(f, "vn %.*g %.*g %.*g\n", normalDigits, double(n[0]), normalDigits, double(n[1]),
                        normalDigits, double(n[2])) > 0;
    }
    // A corner: "i", "i/i" (texture coordinates), "i//i" (normals) or "i/i/i".
    const char* corner = tex ? (opt.vertexNormals ? "%d/%d/%d" : "%d/%d") : (opt.vertexNormals ? "%d//%d" : "%d");
    for (std::size_t k = 0; ok && k < m.face.size(); ++k) {
      const auto& F = m.face[k];
      ok = std::fputc('f', f) != EOF;
      for (int j = 0; ok && j < 3; ++j) {
        const int v = int(F.cV(j) - &m.vert[0]) + 1;
        ok = std::fputc(' ', f) != EOF && std::fprintf(f, corner, v, v, v) > 0;
      }
      ok = ok && std::fputc('\n', f) != EOF;
    }
  } else {
    char head[80] = {0};
    std::snprintf(head, sizeof head, "binary STL written by sodt");
    const std::uint32_t n = static_cast<std::uint32_t>(m.face.size());
    unsigned char count[4] = {static_cast<unsigned char>(n), static_cast<unsigned char>(n >> 8),
                              static_cast<unsigned char>(n >> 16), static_cast<unsigned char>(n >> 24)};
    ok = std::fwrite(head, 1, 80, f) == 80 && std::fwrite(count, 1, 4, f) == 4;
    for (std::size_t k = 0; ok && k < m.face.size(); ++k) {
      const auto& F = m.face[k];
      using P3 = vcg::Point3d;
      const P3 a = P3::Construct(F.cV(0)->cP()), b = P3::Construct(F.cV(1)->cP()),
                 c = P3::Construct(F.cV(2)->cP());
      P3 nrm = (b - a) ^ (c - a);
      const double len = nrm.Norm();
      nrm = len > 0 ? nrm / len : P3(0, 0, 0);
      float rec[12];
      for (int j = 0; j < 3; ++j) {
        rec[j] = static_cast<float>(nrm[j]);
        rec[3 + j] = static_cast<float>(a[j]);
        rec[6 + j] = static_cast<float>(b[j]);
        rec[9 + j] = static_cast<float>(c[j]);
      }
      const unsigned char attr[2] = {0, 0};
      ok = std::fwrite(rec, sizeof rec, 1, f) == 1 && std::fwrite(attr, 1, 2, f) == 2;  // little-endian host
    }
  }
  if (std::fclose(f) != 0) ok = false;
  if (!ok) throw IoError(quoted(target) + ": cannot write: " + std::strerror(errno));
}

/// Copies the PLY file written by vcglib at from into file (written for
/// target) with a "TextureFile" comment for each of textures after its
/// first three lines ("ply", "format", vcglib's comment), where vcglib puts
/// them. \throw IoError.
void copyWithTextureFiles(const std::string& from, const std::string& target, const std::string& file,
                          const std::vector<std::string>& textures) {
  std::unique_ptr<FILE, int (*)(FILE*)> in(std::fopen(from.c_str(), "rb"), std::fclose);
  if (!in) throwErrno(quoted(target) + ": cannot read back " + quoted(from));
  FILE* out = std::fopen(file.c_str(), "wb");
  if (!out) throwErrno(quoted(target) + ": cannot write");
  bool ok = true;
  int c = 0;
  for (int lines = 0; ok && lines < 3 && (c = std::fgetc(in.get())) != EOF;) {
    ok = std::fputc(c, out) != EOF;
    lines += c == '\n';
  }
  for (const std::string& t : textures) ok = ok && std::fprintf(out, "comment TextureFile %s\n", t.c_str()) > 0;
  std::vector<char> buf(1 << 16);
  for (std::size_t n; ok && (n = std::fread(buf.data(), 1, buf.size(), in.get())) > 0;)
    ok = std::fwrite(buf.data(), 1, n, out) == n;
  int e = errno;
  if (std::fclose(out) != 0 && ok) {
    ok = false;
    e = errno;
  }
  errno = e;
  if (!ok) throwErrno(quoted(target) + ": cannot write");
}

template <class M>
void writeMesh(const std::string& target, const std::string& file, const M& src, const SaveOptions& opt) {
  const MeshFormat fmt = meshFormatFromPath(target);
  for (std::size_t i = 0; i < src.vert.size(); ++i) {
    if (src.vert[i].IsD()) continue;
    const auto& p = src.vert[i].cP();
    if (!std::isfinite(double(p[0])) || !std::isfinite(double(p[1])) || !std::isfinite(double(p[2])))
      throw IoError(quoted(target) + ": not written: vertex " + std::to_string(i) +
                    " has a non-finite coordinate");
  }
  // vcglib's writers take a non-const mesh; they only read it. A copy is made
  // when deleted elements must be dropped (the OFF writer indexes the vector)
  // or when flags must be reduced to the selection bit.
  M copy;
  const bool compact = src.vn == static_cast<int>(src.vert.size()) && src.fn == static_cast<int>(src.face.size());
  const bool selection = opt.vertexSelection && fmt == MeshFormat::Ply;
  M* w = const_cast<M*>(&src);
  if (!compact || selection) {
    compactCopy(src, copy, selection);
    w = &copy;
  }
  if (fmt == MeshFormat::Obj || fmt == MeshFormat::Stl) {
    writePlain(target, file, *w, fmt, opt);
    return;
  }
  namespace io = vcg::tri::io;
  int mask = io::Mask::IOM_VERTCOORD | io::Mask::IOM_FACEINDEX;
  if (opt.vertexColor) mask |= io::Mask::IOM_VERTCOLOR;
  const bool texCoords = opt.vertexTexCoords && vcg::tri::HasPerVertexTexCoord(*w);
  // vcglib's writers report a failed write as "Output Stream Error"; the
  // errno of the failed write says why (a full disk, say).
  errno = 0;
  if (fmt == MeshFormat::Off) {
    // Not the normals: vcglib 2020.09 writes them after the colour and
    // announces them only with a colour, which no OFF reader expects.
    if (texCoords) mask |= io::Mask::IOM_VERTTEXCOORD;
    const int r = io::ExporterOFF<M>::Save(*w, file.c_str(), mask);
    if (r != 0) throwWriteError(target, "OFF", io::ExporterOFF<M>::ErrorMsg(r));
    return;
  }
  if (opt.vertexNormals) mask |= io::Mask::IOM_VERTNORMAL;
  if (selection) mask |= io::Mask::IOM_VERTFLAGS;
  io::PlyInfo pi;
  using VT = typename M::VertexType;
  using QualityType = typename VT::QualityType;
  using TexScalar = typename VT::TexCoordType::ScalarType;
  using Scalar = typename M::ScalarType;
  VT probe;
  // A vertex field written as a float, described by ourselves.
  const auto floatField = [&](const char* name, const void* field, bool memFloat) {
    vcg::ply::PropDescriptor d = vcg::ply::PropDescriptor();
    d.elemname = "vertex";
    d.propname = name;
    d.stotype1 = vcg::ply::T_FLOAT;
    d.memtype1 = memFloat ? vcg::ply::T_FLOAT : vcg::ply::T_DOUBLE;
    d.offset1 = static_cast<std::size_t>(static_cast<const char*>(field) - reinterpret_cast<const char*>(&probe));
    pi.VertDescriptorVec.push_back(d);
  };
  // vcglib 2020.09 names the quality type after the coordinate type in the
  // header but writes QualityType in binary, and declares texture
  // coordinates float but writes them as coordinates: describe the fields
  // ourselves when the types differ.
  if (opt.vertexQuality) {
    if (!opt.binary || sizeof(QualityType) == sizeof(Scalar))
      mask |= io::Mask::IOM_VERTQUALITY;
    else
      floatField("quality", &probe.Q(), sizeof(QualityType) == sizeof(float));
  }
  // Without the mask vcglib names no texture file; they are added after.
  bool textureComments = false;
  if (texCoords) {
    if (!opt.binary || sizeof(Scalar) == sizeof(TexScalar)) {
      mask |= io::Mask::IOM_VERTTEXCOORD;
    } else {
      floatField("texture_u", &probe.T().U(), sizeof(TexScalar) == sizeof(float));
      floatField("texture_v", &probe.T().V(), sizeof(TexScalar) == sizeof(float));
      textureComments = !w->textures.empty();
    }
  }
  pi.mask = mask;
  ScratchFile scratch;
  if (textureComments) scratchStream(scratch, target);
  const int r = io::ExporterPLY<M>::Save(*w, (textureComments ? scratch.path : file).c_str(), opt.binary, pi);
  if (r != 0) throwWriteError(target, "PLY", io::ExporterPLY<M>::ErrorMsg(r));
  if (textureComments) copyWithTextureFiles(scratch.path, target, file, w->textures);
}

/// What verifyWritten reads a written file into: positions, triangles, and
/// the colour and flags that the readers set. About a third of the memory of
/// a MeshD: the mesh being saved is alive at the same time, and a second
/// MeshD would double the peak of a large save.
struct VerifyMeshTypes {
  class Vertex;
  class Face;
  struct UsedTypes : public vcg::UsedTypes<vcg::Use<Vertex>::AsVertexType, vcg::Use<Face>::AsFaceType> {};
  class Vertex : public vcg::Vertex<UsedTypes, vcg::vertex::Coord3d, vcg::vertex::Color4b, vcg::vertex::BitFlags> {};
  class Face : public vcg::Face<UsedTypes, vcg::face::VertexRef, vcg::face::BitFlags> {};
  class Mesh : public vcg::tri::TriMesh<std::vector<Vertex>, std::vector<Face>> {};
};
using VerifyMesh = VerifyMeshTypes::Mesh;

/// Reads a written file back and compares the counts: catches a write that
/// failed when the C library flushed its last buffer on close.
template <class M>
void verifyWritten(const std::string& target, const std::string& file, const M& src) {
  const MeshFormat fmt = meshFormatFromPath(target);
  VerifyMesh back;
  LoadInfo info;
  try {
    loadFormat(fmt, file, back, info);
  } catch (const std::exception& e) {
    throw IoError(quoted(target) + ": the written file does not read back (" + e.what() + ")");
  }
  // STL keeps no vertex list: its vertices are the welded corners.
  if (fmt == MeshFormat::Stl ? back.fn != src.fn : (back.vn != src.vn || back.fn != src.fn))
    throw IoError(quoted(target) + ": the written file does not read back (" + std::to_string(back.vn) +
                  " vertices, " + std::to_string(back.fn) + " faces instead of " + std::to_string(src.vn) +
                  ", " + std::to_string(src.fn) + ")");
}

template <class M>
void saveMeshImpl(PendingFile& out, const M& m, const SaveOptions& opt) {
  try {
    writeMesh(out.target(), out.tempPath(), m, opt);
    // A device or FIFO cannot be read back.
    if (opt.verify && !out.direct()) verifyWritten(out.target(), out.tempPath(), m);
  } catch (const InvalidInput&) {
    throw;
  } catch (const IoError&) {
    throw;
  } catch (const std::exception& e) {
    throw IoError(quoted(out.target()) + ": cannot write: " + e.what());
  }
}

std::atomic<unsigned> tempCounter{0};

}  // namespace

// ---------------------------------------------------------------------------

MeshFormat meshFormatFromPath(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".stl") return MeshFormat::Stl;
  if (ext.empty()) throw InvalidInput(quoted(path) + ": no file extension (expected .ply, .off, .obj or .stl)");
  throw InvalidInput(quoted(path) + ": unsupported file extension '" + ext + "' (expected .ply, .off, .obj or .stl)");
}

void loadMesh(const std::string& path, MeshD& m, LoadInfo* info) { loadMeshImpl(path, m, info); }
void loadMesh(const std::string& path, MeshF& m, LoadInfo* info) { loadMeshImpl(path, m, info); }

namespace {

/// The directory part of a path ("." without one, "/" for the root).
std::string dirOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
}

/// Removes the temporary files of earlier runs for this target that ended
/// without cleaning up (SIGKILL, a crash): names made by PendingFile for the
/// same target whose process no longer exists. Files of live processes, this
/// one included, and anything else are left alone.
void removeStaleTemporaries(const std::string& dir, const std::string& stem) {
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return;
  const long self = static_cast<long>(::getpid());
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name.compare(0, stem.size(), stem) != 0) continue;
    // The rest must be PID "_" COUNTER, both decimal.
    const std::string rest = name.substr(stem.size());
    const std::size_t us = rest.find('_');
    if (us == 0 || us == std::string::npos || us + 1 == rest.size() || us > 9 ||
        rest.find_first_not_of("0123456789", 0) != us ||
        rest.find_first_not_of("0123456789", us + 1) != std::string::npos)
      continue;
    const long pid = std::strtol(rest.substr(0, us).c_str(), nullptr, 10);
    if (pid <= 0 || pid == self) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH) (void)::unlinkat(::dirfd(d), name.c_str(), 0);
  }
  ::closedir(d);
}

}  // namespace

PendingFile::PendingFile(const std::string& target) : target_(target), resolved_(target) {
  if (target.empty()) throw IoError("cannot write: empty file name");
  if (target.back() == '/') throw IoError("cannot write " + quoted(target) + ": is a directory");
  struct stat st;
  // What the path names, links followed. A character device or a FIFO (also
  // /dev/stdout when it is a pipe) cannot be replaced without breaking it: it
  // is written directly. Anything but those and regular files is refused.
  if (::stat(target.c_str(), &st) == 0) {
    if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
      if (::access(target.c_str(), W_OK) != 0) throwErrno("cannot write " + quoted(target));
      direct_ = true;
      temp_ = target;
      return;
    }
    if (S_ISDIR(st.st_mode)) throw IoError("cannot write " + quoted(target) + ": is a directory");
    if (S_ISBLK(st.st_mode))
      throw IoError("cannot write " + quoted(target) + ": is a block device (a disk), not a file");
    if (S_ISSOCK(st.st_mode)) throw IoError("cannot write " + quoted(target) + ": is a socket");
    if (!S_ISREG(st.st_mode)) throw IoError("cannot write " + quoted(target) + ": not a regular file");
  }
  if (::lstat(target.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
    char* real = ::realpath(target.c_str(), nullptr);
    if (real == nullptr) {
      if (errno == ENOENT)
        throw IoError("cannot write " + quoted(target) +
                      ": it is a symbolic link to a file that does not exist (like cp, sodt does not "
                      "create a file through a dangling link; remove the link or write to its target)");
      throwErrno("cannot write " + quoted(target) + " (symbolic link)");
    }
    resolved_ = real;
    std::free(real);
  }
  const bool exists = ::stat(resolved_.c_str(), &st) == 0;
  // rename() would replace a read-only file too; keep its protection.
  if (exists && ::access(resolved_.c_str(), W_OK) != 0) throwErrno("cannot write " + quoted(target));
  const std::size_t slash = resolved_.find_last_of('/');
  const std::string dir = dirOf(resolved_);
  std::string base = slash == std::string::npos ? resolved_ : resolved_.substr(slash + 1);
  // ".BASE.tmpPID_N" must fit in a name of the directory's file system: a
  // long BASE is shortened (the target keeps its name).
  const std::string pid = std::to_string(static_cast<long>(::getpid()));
  long nameMax = ::pathconf(dir.c_str(), _PC_NAME_MAX);
  if (nameMax <= 0) nameMax = 255;
  const std::size_t room = 1 + 4 + pid.size() + 1 + 10;  // "." ".tmp" PID "_" counter
  if (base.size() + room > static_cast<std::size_t>(nameMax))
    base.resize(static_cast<std::size_t>(nameMax) > room ? static_cast<std::size_t>(nameMax) - room : 1);
  const std::string stem = "." + base + ".tmp";
  removeStaleTemporaries(dir, stem);
  const std::string prefix = (slash == std::string::npos ? "" : resolved_.substr(0, slash + 1)) + stem + pid + "_";
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temp_ = prefix + std::to_string(tempCounter++);
    // 0666 lets the umask decide the permissions, as for any new file.
    fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) throwErrno("cannot write " + quoted(target) + ": cannot create a file in " + quoted(dir));
  if (exists) (void)::fchmod(fd, st.st_mode & 07777);
  ::close(fd);
}

PendingFile::~PendingFile() {
  if (!committed_ && !direct_) ::unlink(temp_.c_str());
}

void PendingFile::commit() {
  if (committed_) return;
  if (direct_) {  // written in place; nothing to rename or sync
    committed_ = true;
    return;
  }
  const int fd = ::open(temp_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const int e = errno;
    if (fd >= 0) ::close(fd);
    errno = e;
    throwErrno("cannot write " + quoted(target_));
  }
  ::close(fd);
  if (::rename(temp_.c_str(), resolved_.c_str()) != 0) throwErrno("cannot replace " + quoted(target_));
  committed_ = true;
  // Make the rename itself durable; failing here loses nothing already written.
  const int dfd = ::open(dirOf(resolved_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    (void)::fsync(dfd);
    ::close(dfd);
  }
}

void saveMesh(PendingFile& out, const MeshD& m, const SaveOptions& opt) { saveMeshImpl(out, m, opt); }
void saveMesh(PendingFile& out, const MeshF& m, const SaveOptions& opt) { saveMeshImpl(out, m, opt); }

void saveMesh(const std::string& path, const MeshD& m, const SaveOptions& opt) {
  meshFormatFromPath(path);  // fail before creating anything
  PendingFile out(path);
  saveMeshImpl(out, m, opt);
  out.commit();
}

void saveMesh(const std::string& path, const MeshF& m, const SaveOptions& opt) {
  meshFormatFromPath(path);
  PendingFile out(path);
  saveMeshImpl(out, m, opt);
  out.commit();
}

std::vector<std::string> notKept(const std::string& path, const MeshD& m, const SaveOptions& opt) {
  const MeshFormat fmt = meshFormatFromPath(path);
  const bool ply = fmt == MeshFormat::Ply, off = fmt == MeshFormat::Off, stl = fmt == MeshFormat::Stl;
  std::vector<std::string> out;
  if (opt.vertexNormals && (off || stl)) out.push_back("vertex normals");
  if (opt.vertexTexCoords && stl) out.push_back("vertex texture coordinates");
  if (opt.vertexColor && !ply && !off) out.push_back("vertex colours");
  if (opt.vertexQuality && !ply) out.push_back("vertex quality");
  if (opt.vertexSelection && !ply) out.push_back("the vertex selection");
  // Texture files are named only beside texture coordinates, and only in PLY.
  for (const std::string& t : m.textures)
    if (!ply || !opt.vertexTexCoords) out.push_back("the texture file '" + t + "'");
  if (stl) {
    std::vector<char> used(m.vert.size(), 0);
    for (const auto& f : m.face)
      if (!f.IsD())
        for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(f.cV(k) - &m.vert[0])] = 1;
    long long unused = 0;
    for (std::size_t i = 0; i < m.vert.size(); ++i) unused += !m.vert[i].IsD() && !used[i];
    if (unused > 0) out.push_back(std::to_string(unused) + " unreferenced vert" + (unused > 1 ? "ices" : "ex"));
  }
  return out;
}

void writeText(PendingFile& out, const std::string& text) {
  FILE* f = std::fopen(out.tempPath().c_str(), "wb");
  if (f == nullptr) throwErrno("cannot write " + quoted(out.target()));
  bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0;
  int e = errno;
  if (std::fclose(f) != 0 && ok) {
    ok = false;
    e = errno;
  }
  if (!ok) {
    errno = e;
    throwErrno("cannot write " + quoted(out.target()));
  }
}

void writeTextFile(const std::string& path, const std::string& text) {
  PendingFile out(path);
  writeText(out, text);
  out.commit();
}

}  // namespace sodt
