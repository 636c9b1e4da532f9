// SPDX-License-Identifier: GPL-3.0-or-later
// Procedural fixtures for the core tests: spheres, planar grids, bipyramids,
// all deterministic (seeded std::mt19937 with hand-made uniform draws).
#pragma once

#include <sodt_io/mesh.h>

#include <vcg/complex/algorithms/clean.h>
#include <vcg/complex/algorithms/create/platonic.h>

#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace sodt_test {

/// Uniform double in [0, 1) from a 32-bit engine; the same on every platform.
inline double uniform01(std::mt19937& g) { return (g() >> 5) * (1.0 / 134217728.0); }
inline double uniform(std::mt19937& g, double lo, double hi) { return lo + (hi - lo) * uniform01(g); }

inline bool fileExists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

/// Every vertex position, in order (for exact comparisons of two runs).
template <class M>
std::vector<typename M::CoordType> positions(const M& m) {
  std::vector<typename M::CoordType> p;
  for (const auto& v : m.vert) p.push_back(v.cP());
  return p;
}

/// Every face's vertex indices, in order.
template <class M>
std::vector<std::array<int, 3>> faceIndices(const M& m) {
  std::vector<std::array<int, 3>> f;
  for (const auto& F : m.face)
    f.push_back({int(F.cV(0) - &m.vert[0]), int(F.cV(1) - &m.vert[0]), int(F.cV(2) - &m.vert[0])});
  return f;
}

/// True when vertex v's texture coordinates lie in the triangle of a's, b's
/// and c's (barycentric weights of at least -1e-6) and its quality and
/// colour are the same weights' mix of theirs: the attributes of a point
/// inserted inside the face (a, b, c).
template <class V>
bool interpolatedInside(const V& v, const V& a, const V& b, const V& c) {
  const double ax = a.cT().U(), ay = a.cT().V(), bx = b.cT().U(), by = b.cT().V(), cx = c.cT().U(),
               cy = c.cT().V(), px = v.cT().U(), py = v.cT().V();
  const double det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  if (std::abs(det) < 1e-3) return false;
  const double wb = ((px - ax) * (cy - ay) - (py - ay) * (cx - ax)) / det;
  const double wc = ((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / det;
  const double wa = 1 - wb - wc;
  if (wa < -1e-6 || wb < -1e-6 || wc < -1e-6) return false;
  if (std::abs(wa * a.cQ() + wb * b.cQ() + wc * c.cQ() - v.cQ()) > 1e-3) return false;
  for (int k = 0; k < 4; ++k)
    if (std::abs(wa * a.cC()[k] + wb * b.cC()[k] + wc * c.cC()[k] - v.cC()[k]) > 1.0) return false;
  return true;
}

/// Adds a triangle with the given vertex indices.
template <class M>
void addFace(M& m, int a, int b, int c) {
  auto fi = vcg::tri::Allocator<M>::AddFaces(m, 1);
  fi->V(0) = &m.vert[a];
  fi->V(1) = &m.vert[b];
  fi->V(2) = &m.vert[c];
}

/// A half cylinder of radius 1 (the angle along x, the axis along y, 8
/// rings 0.25 apart) with `segments` segments around, its inner vertices
/// moved along the arcs by up to `jitter` segments: two semicircular
/// borders of uneven chords.
template <class M>
void makeHalfCylinder(M& m, int segments, double jitter, unsigned seed) {
  const int na = segments + 1, nl = 9;
  vcg::tri::Allocator<M>::AddVertices(m, na * nl);
  std::mt19937 g(seed);
  const double pi = std::acos(-1.0);
  for (int j = 0; j < nl; ++j)
    for (int i = 0; i < na; ++i) {
      double t = pi * i / (na - 1);
      if (i > 0 && i < na - 1) t += uniform(g, -jitter, jitter) * pi / (na - 1);
      m.vert[j * na + i].P() = vcg::Point3d(std::cos(t), j * 0.25, std::sin(t));
    }
  for (int j = 0; j + 1 < nl; ++j)
    for (int i = 0; i + 1 < na; ++i) {
      const int a = j * na + i, b = a + 1, c = a + na, d = c + 1;
      addFace(m, a, d, b);
      addFace(m, a, c, d);
    }
}

/// Unit icosphere with `subdiv` midpoint subdivisions (10*4^s + 2 vertices).
template <class M>
void makeSphere(M& m, int subdiv) {
  m.Clear();
  vcg::tri::Sphere(m, subdiv);
  vcg::tri::Allocator<M>::CompactEveryVector(m);
}

/// Moves every vertex of a unit sphere tangentially by up to `amount` times
/// the mean edge length, then back onto the sphere: bad angles, same surface.
template <class M>
void jitterOnSphere(M& m, double amount, unsigned seed) {
  std::mt19937 g(seed);
  double mean = 0;
  for (const auto& f : m.face) mean += vcg::Distance(f.cP(0), f.cP(1));
  mean /= double(m.face.size());
  for (auto& v : m.vert) {
    using C = typename M::CoordType;
    C d(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
    C n = v.P();
    d = d - n * (d * n);
    v.P() = v.P() + d * typename M::ScalarType(amount * mean);
    v.P().Normalize();
  }
}

/// Planar grid of n x n vertices in z = 0 over [0,1]^2, interior vertices
/// jittered in-plane by up to `jitter` cell sizes. Open (has a boundary).
template <class M>
void makeGrid(M& m, int n, double jitter, unsigned seed) {
  m.Clear();
  std::mt19937 g(seed);
  vcg::tri::Allocator<M>::AddVertices(m, n * n);
  const double h = 1.0 / (n - 1);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      double px = x * h, py = y * h;
      if (x > 0 && y > 0 && x < n - 1 && y < n - 1) {
        px += uniform(g, -jitter, jitter) * h;
        py += uniform(g, -jitter, jitter) * h;
      }
      m.vert[y * n + x].P() = typename M::CoordType(px, py, 0);
    }
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      const int a = y * n + x, b = a + 1, c = a + n, d = c + 1;
      addFace(m, a, b, d);
      addFace(m, a, d, c);
    }
}

/// Closed bipyramid: vertex 0 is the top apex at `top`, vertex 1 the bottom
/// apex at (0,0,-1), vertices 2.. the ring (in the z = 0 plane, counter-clockwise
/// seen from above). Only vertex 0 is selected.
template <class M>
void makeBipyramid(M& m, const std::vector<vcg::Point3d>& ring, const vcg::Point3d& top) {
  m.Clear();
  const int n = static_cast<int>(ring.size());
  vcg::tri::Allocator<M>::AddVertices(m, n + 2);
  using C = typename M::CoordType;
  m.vert[0].P() = C(top[0], top[1], top[2]);
  m.vert[1].P() = C(0, 0, -1);
  for (int k = 0; k < n; ++k) m.vert[2 + k].P() = C(ring[k][0], ring[k][1], ring[k][2]);
  for (int k = 0; k < n; ++k) {
    addFace(m, 0, 2 + k, 2 + (k + 1) % n);
    addFace(m, 1, 2 + (k + 1) % n, 2 + k);
  }
  for (auto& v : m.vert) v.ClearS();
  m.vert[0].SetS();
}

/// Closed cube [-1,1]^3 whose faces are n x n grids (welded, outward
/// orientation, diagonals alternating in a checkerboard). With jitter > 0,
/// face-interior vertices move within their face plane and edge vertices
/// along their edge line by up to jitter cell sizes; corners never move.
template <class M>
void makeCube(M& m, int n, double jitter = 0.0, unsigned seed = 1) {
  m.Clear();
  std::mt19937 g(seed);
  std::map<std::array<int, 3>, int> index;
  auto vertex = [&](int x, int y, int z) {
    const std::array<int, 3> key{x, y, z};
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    auto vi = vcg::tri::Allocator<M>::AddVertices(m, 1);
    const double h = 2.0 / n;
    vi->P() = typename M::CoordType(-1 + x * h, -1 + y * h, -1 + z * h);
    const int id = static_cast<int>(m.vert.size()) - 1;
    index[key] = id;
    return id;
  };
  // For each of the 6 faces: axis a fixed at 0 or n, (u, v) spanning the face.
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto at = [&](int di, int dj) {
            std::array<int, 3> c{};
            c[a] = side * n;
            c[u] = i + di;
            c[v] = j + dj;
            return vertex(c[0], c[1], c[2]);
          };
          int q[4] = {at(0, 0), at(1, 0), at(1, 1), at(0, 1)};
          if (side == 0) std::swap(q[1], q[3]);  // outward orientation on the low side
          if ((i + j) % 2 == 0) {
            addFace(m, q[0], q[1], q[2]);
            addFace(m, q[0], q[2], q[3]);
          } else {
            addFace(m, q[0], q[1], q[3]);
            addFace(m, q[1], q[2], q[3]);
          }
        }
    }
  if (jitter <= 0) return;
  const double h = 2.0 / n;
  for (auto& vtx : m.vert) {
    auto& p = vtx.P();
    int onFace = 0;
    for (int c = 0; c < 3; ++c) onFace += std::abs(std::abs(double(p[c])) - 1.0) < 1e-12;
    if (onFace >= 3) continue;  // corner
    for (int c = 0; c < 3; ++c) {
      if (std::abs(std::abs(double(p[c])) - 1.0) < 1e-12) continue;  // stay on this face/edge
      p[c] += typename M::ScalarType(uniform(g, -jitter, jitter) * h);
    }
  }
}

/// Angle between the normals of the two faces of every interior edge, in
/// degrees, keyed by the edge's (smaller, larger) vertex index.
template <class M>
std::map<std::pair<int, int>, double> dihedralAngles(const M& m) {
  std::map<std::pair<int, int>, std::vector<vcg::Point3d>> normals;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    const vcg::Point3d a = vcg::Point3d::Construct(f.cP(0)), b = vcg::Point3d::Construct(f.cP(1)),
                       c = vcg::Point3d::Construct(f.cP(2));
    vcg::Point3d n = (b - a) ^ (c - a);
    n.Normalize();
    for (int j = 0; j < 3; ++j) {
      const int u = int(f.cV(j) - &m.vert[0]), v = int(f.cV((j + 1) % 3) - &m.vert[0]);
      normals[{std::min(u, v), std::max(u, v)}].push_back(n);
    }
  }
  std::map<std::pair<int, int>, double> out;
  for (const auto& kv : normals)
    if (kv.second.size() == 2)
      out[kv.first] = std::atan2((kv.second[0] ^ kv.second[1]).Norm(), kv.second[0] * kv.second[1]) * 180.0 / M_PI;
  return out;
}

}  // namespace sodt_test
