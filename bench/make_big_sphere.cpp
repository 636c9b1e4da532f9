// SPDX-License-Identifier: GPL-3.0-or-later
// Large-input generator for bench/large_input.sh: a closed, consistently
// oriented, tangentially jittered icosphere written as binary PLY.
//
//   sodt_make_big_sphere OUT.ply [--subdiv N | --frequency N] [--jitter F] [--seed S]
//
// Subdivision level N (default 9) gives 10*4^N + 2 vertices and 20*4^N faces:
// N = 9 is 2,621,442 vertices and 5,242,880 faces (about 97 MB of PLY).
// --frequency N makes the geodesic sphere of frequency N instead (the same
// counts as level k for N = 2^k, and any size between): 724 gives 10,483,520
// faces.
// Every vertex then moves in the sphere's tangent plane by up to F (default
// 0.45, as meshes/sphere_jitter.ply) times the mean edge length, uniformly in
// a disc, and is projected back on the unit sphere. A face that would turn
// inwards or get a corner below 0.5 deg sends its vertices back to their
// unjittered positions (repeated until no face does), so the mesh is valid
// but has many poor triangles for S-ODT to improve.
//
// Standalone on purpose: no vcglib, so the generator itself stays small and
// fast (a few seconds for N = 9) and its memory does not count against the
// smoother's. Deterministic: std::mt19937's raw output is standardised.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

struct V3 {
  double x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(V3 a) { return std::sqrt(dot(a, a)); }
V3 normalized(V3 a) { return a * (1.0 / norm(a)); }

using Tri = std::array<std::uint32_t, 3>;

/// Regular icosahedron on the unit sphere, faces counter-clockwise seen from outside.
void icosahedron(std::vector<V3>& v, std::vector<Tri>& f) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (V3& p : v) p = normalized(p);
  f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
       {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
       {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
}

/// One 1-to-4 split; new vertices are edge midpoints pushed onto the sphere.
void subdivide(std::vector<V3>& v, std::vector<Tri>& f) {
  std::unordered_map<std::uint64_t, std::uint32_t> mid;
  mid.reserve(f.size() * 3 / 2 + 16);
  auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    const auto i = static_cast<std::uint32_t>(v.size());
    v.push_back(normalized(v[a] + v[b]));
    mid.emplace(key, i);
    return i;
  };
  std::vector<Tri> out;
  out.reserve(f.size() * 4);
  for (const Tri& t : f) {
    const std::uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
    out.push_back({t[0], a, c});
    out.push_back({t[1], b, a});
    out.push_back({t[2], c, b});
    out.push_back({a, b, c});
  }
  f.swap(out);
}

/// Geodesic sphere of frequency n (class I): each icosahedron face split
/// into n^2 triangles by a triangular lattice, every lattice point pushed
/// onto the sphere; 10 n^2 + 2 vertices and 20 n^2 faces (n = 2^k is
/// subdivision level k). Lattice points on an edge or a corner of the
/// icosahedron are shared by the faces that meet there.
void geodesic(int n, std::vector<V3>& v, std::vector<Tri>& f) {
  std::vector<V3> ico;
  std::vector<Tri> faces;
  icosahedron(ico, faces);
  v = ico;
  f.clear();
  f.reserve(std::size_t(20) * n * n);
  // Interior points of each edge, from its lower-numbered corner on.
  std::unordered_map<std::uint64_t, std::uint32_t> edgeStart;
  const auto edgePoint = [&](std::uint32_t a, std::uint32_t b, int k) -> std::uint32_t {
    if (k == 0) return a;
    if (k == n) return b;
    const bool flip = a > b;
    const std::uint32_t lo = flip ? b : a, hi = flip ? a : b;
    const int at = flip ? n - k : k;
    const std::uint64_t key = (std::uint64_t(lo) << 32) | hi;
    auto it = edgeStart.find(key);
    if (it == edgeStart.end()) {
      it = edgeStart.emplace(key, static_cast<std::uint32_t>(v.size())).first;
      for (int j = 1; j < n; ++j) v.push_back(normalized(ico[lo] * double(n - j) + ico[hi] * double(j)));
    }
    return it->second + std::uint32_t(at - 1);
  };
  std::vector<std::uint32_t> row, next;
  for (const Tri& t : faces) {
    // Lattice point (i, j), i + j <= n: A + (B - A) i / n + (C - A) j / n.
    const auto point = [&](int i, int j) -> std::uint32_t {
      if (j == 0) return edgePoint(t[0], t[1], i);
      if (i == 0) return edgePoint(t[0], t[2], j);
      if (i + j == n) return edgePoint(t[1], t[2], j);
      v.push_back(normalized(ico[t[0]] * double(n - i - j) + ico[t[1]] * double(i) + ico[t[2]] * double(j)));
      return static_cast<std::uint32_t>(v.size() - 1);
    };
    row.clear();
    for (int i = 0; i <= n; ++i) row.push_back(point(i, 0));
    for (int j = 1; j <= n; ++j) {
      next.clear();
      for (int i = 0; i + j <= n; ++i) next.push_back(point(i, j));
      for (int i = 0; i + j <= n; ++i) {
        f.push_back({row[i], row[i + 1], next[i]});
        if (i + 1 + j <= n) f.push_back({row[i + 1], next[i + 1], next[i]});
      }
      row.swap(next);
    }
  }
}

/// Smallest corner angle of (a, b, c) in degrees.
double minAngleDeg(V3 a, V3 b, V3 c) {
  const V3 p[3] = {a, b, c};
  double best = 180.0;
  for (int i = 0; i < 3; ++i) {
    const V3 u = p[(i + 1) % 3] - p[i], w = p[(i + 2) % 3] - p[i];
    const double ang = std::atan2(norm(cross(u, w)), dot(u, w)) * (180.0 / 3.14159265358979323846);
    best = std::min(best, ang);
  }
  return best;
}

bool faceOk(const std::vector<V3>& v, const Tri& t, double minDeg) {
  const V3 a = v[t[0]], b = v[t[1]], c = v[t[2]];
  return dot(cross(b - a, c - a), a + b + c) > 0 && minAngleDeg(a, b, c) >= minDeg;
}

bool writePly(const std::string& path, const std::vector<V3>& v, const std::vector<Tri>& f) {
  const std::uint16_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  if (first != 1) {
    std::fprintf(stderr, "error: this generator writes little-endian PLY and needs a little-endian host\n");
    return false;
  }
  FILE* out = std::fopen(path.c_str(), "wb");
  if (!out) {
    std::perror(path.c_str());
    return false;
  }
  std::fprintf(out,
               "ply\nformat binary_little_endian 1.0\ncomment sodt_make_big_sphere: jittered icosphere\n"
               "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n"
               "element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
               v.size(), f.size());
  std::vector<char> buf;
  buf.reserve(1 << 20);
  auto flush = [&]() {
    if (!buf.empty() && std::fwrite(buf.data(), 1, buf.size(), out) != buf.size()) return false;
    buf.clear();
    return true;
  };
  bool ok = true;
  for (const V3& p : v) {
    const float xyz[3] = {float(p.x), float(p.y), float(p.z)};
    buf.insert(buf.end(), reinterpret_cast<const char*>(xyz), reinterpret_cast<const char*>(xyz) + sizeof xyz);
    if (buf.size() >= (1u << 20)) ok = ok && flush();
  }
  for (const Tri& t : f) {
    const unsigned char n = 3;
    const std::int32_t idx[3] = {std::int32_t(t[0]), std::int32_t(t[1]), std::int32_t(t[2])};
    buf.push_back(static_cast<char>(n));
    buf.insert(buf.end(), reinterpret_cast<const char*>(idx), reinterpret_cast<const char*>(idx) + sizeof idx);
    if (buf.size() >= (1u << 20)) ok = ok && flush();
  }
  ok = ok && flush();
  ok = (std::fclose(out) == 0) && ok;
  if (!ok) std::fprintf(stderr, "error: writing %s failed\n", path.c_str());
  return ok;
}

int usage(int status) {
  std::fprintf(status ? stderr : stdout,
               "usage: sodt_make_big_sphere OUT.ply [--subdiv N | --frequency N] [--jitter F] [--seed S]\n"
               "  --subdiv N     icosphere subdivision level 0..10 (default 9: 2,621,442 vertices,\n"
               "                 5,242,880 faces)\n"
               "  --frequency N  geodesic sphere of frequency 1..2048 instead: 10 N^2 + 2 vertices,\n"
               "                 20 N^2 faces (724: 5,241,762 vertices, 10,483,520 faces)\n"
               "  --jitter F   largest tangential move / mean edge length, 0..1 (default 0.45)\n"
               "  --seed S     random seed (default 20202)\n");
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  std::string outPath;
  int subdiv = 9;
  int frequency = 0;
  double jitter = 0.45;
  unsigned long seed = 20202;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") return usage(0);
    if ((a == "--subdiv" || a == "--frequency" || a == "--jitter" || a == "--seed") && i + 1 < argc) {
      char* end = nullptr;
      const char* s = argv[++i];
      if (a == "--subdiv") subdiv = int(std::strtol(s, &end, 10));
      if (a == "--frequency") frequency = int(std::strtol(s, &end, 10));
      if (a == "--jitter") jitter = std::strtod(s, &end);
      if (a == "--seed") seed = std::strtoul(s, &end, 10);
      if (!end || *end) return usage(2);
    } else if (!a.empty() && a[0] != '-' && outPath.empty()) {
      outPath = a;
    } else {
      return usage(2);
    }
  }
  if (outPath.empty() || subdiv < 0 || subdiv > 10 || frequency < 0 || frequency > 2048 ||
      !(jitter >= 0 && jitter <= 1))
    return usage(2);

  const auto t0 = std::chrono::steady_clock::now();
  std::vector<V3> v;
  std::vector<Tri> f;
  if (frequency > 0) {
    geodesic(frequency, v, f);
  } else {
    icosahedron(v, f);
    for (int s = 0; s < subdiv; ++s) subdivide(v, f);
  }

  // Mean edge length (each interior edge counted twice: same mean).
  double sum = 0;
  for (const Tri& t : f)
    for (int j = 0; j < 3; ++j) sum += norm(v[t[(j + 1) % 3]] - v[t[j]]);
  const double h = sum / (3.0 * double(f.size()));

  // Tangential jitter, drawn for every vertex up front (the stream does not
  // depend on vetoes).
  std::mt19937 rng(static_cast<std::mt19937::result_type>(seed));
  auto uniform01 = [&]() { return static_cast<double>(rng() >> 5) * (1.0 / 134217728.0); };
  const std::vector<V3> base = v;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const V3 n = base[i];
    const V3 helper = std::fabs(n.x) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0};
    const V3 t1 = normalized(cross(n, helper)), t2 = cross(n, t1);
    const double r = jitter * h * std::sqrt(uniform01());
    const double ang = 2 * 3.14159265358979323846 * uniform01();
    v[i] = normalized(n + t1 * (r * std::cos(ang)) + t2 * (r * std::sin(ang)));
  }
  // Veto: vertices of bad faces go back to their base positions until none is bad.
  const double minDeg = 0.5;
  std::size_t reverted = 0;
  for (int pass = 0; pass < 100; ++pass) {
    std::size_t bad = 0;
    for (const Tri& t : f) {
      if (faceOk(v, t, minDeg)) continue;
      ++bad;
      for (std::uint32_t k : t)
        if (v[k].x != base[k].x || v[k].y != base[k].y || v[k].z != base[k].z) {
          v[k] = base[k];
          ++reverted;
        }
    }
    if (bad == 0) break;
  }
  double minAngle = 180.0;
  std::size_t below30 = 0;
  for (const Tri& t : f) {
    const double m = minAngleDeg(v[t[0]], v[t[1]], v[t[2]]);
    minAngle = std::min(minAngle, m);
    if (m < 30) ++below30;
  }
  const double genSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!writePly(outPath, v, f)) return 1;
  const double allSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("sodt_make_big_sphere: %s\n", outPath.c_str());
  if (frequency > 0)
    std::printf("  frequency %d: %zu vertices, %zu faces, mean edge %.3g (unit sphere)\n", frequency, v.size(),
                f.size(), h);
  else
    std::printf("  subdivision %d: %zu vertices, %zu faces, mean edge %.3g (unit sphere)\n", subdiv, v.size(),
                f.size(), h);
  std::printf("  jitter %.2f x mean edge, seed %lu; %zu vertices reverted by the veto\n", jitter, seed, reverted);
  std::printf("  smallest angle %.3f deg; %.2f%% of the triangles have a corner below 30 deg\n", minAngle,
              100.0 * double(below30) / double(f.size()));
  std::printf("  built in %.2f s, written in %.2f s\n", genSeconds, allSeconds - genSeconds);
  return 0;
}
