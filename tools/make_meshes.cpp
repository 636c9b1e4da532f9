// SPDX-License-Identifier: GPL-3.0-or-later
// Deterministic generator of the project's small test/demo meshes (meshes/):
// a sliver-rich marching-cubes blob surface, a jittered icosphere, a torus, an open grid,
// and two cubes with sharp edges (in-plane jitter; noise along the normals).

#include "mesh_check.h"

#include <sodt/maths/geometry.h>
#include <sodt_io/io.h>
#include <sodt_io/mesh.h>
#include <sodt_io/metrics.h>

#include <vcg/complex/algorithms/create/marching_cubes.h>
#include <vcg/complex/algorithms/create/mc_trivial_walker.h>
#include <vcg/complex/algorithms/create/platonic.h>
#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/export_off.h>
#include <wrap/io_trimesh/export_ply.h>
#include <wrap/io_trimesh/import_off.h>
#include <wrap/io_trimesh/import_ply.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

using sodt::MeshF;
using sodt::Vec3;
using sodt::tools::MeshCheck;
using CoordF = MeshF::CoordType;

// ---------------------------------------------------------------------------
// Randomness: std::mt19937 is specified bit-exactly by the standard, the std
// distributions are not, so uniform numbers are derived from its raw output.

class Rng {
 public:
  explicit Rng(std::uint32_t seed) : g_(seed) {}
  /// Uniform in [0, 1) on a grid of 2^-27, from the top 27 bits of one draw.
  double uniform01() { return static_cast<double>(g_() >> 5) * (1.0 / 134217728.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }
  /// Uniform on the unit sphere, by rejection from the cube [-1, 1]^3.
  Vec3 unitVector() {
    for (;;) {
      const Vec3 p(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      const double n2 = p.SquaredNorm();
      if (n2 > 1e-4 && n2 <= 1.0) return p / std::sqrt(n2);
    }
  }
  bool coin() { return uniform01() < 0.5; }

 private:
  std::mt19937 g_;
};

Vec3 toVec3(const CoordF& c) { return Vec3(c[0], c[1], c[2]); }
CoordF toCoordF(const Vec3& p) { return CoordF(float(p[0]), float(p[1]), float(p[2])); }

/// Smallest corner angle of triangle (a, b, c), in degrees.
double minAngleDeg(const Vec3& a, const Vec3& b, const Vec3& c) {
  return sodt::triangleMinAngle(a, b, c) * sodt::kRadToDeg;
}

double meanEdgeLength(const MeshF& m) {
  double sum = 0;
  long long n = 0;
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    for (int j = 0; j < 3; ++j, ++n) sum += (toVec3(f.cP(j)) - toVec3(f.cP((j + 1) % 3))).Norm();
  }
  return n ? sum / double(n) : 0.0;
}

std::vector<std::vector<int>> incidentFaces(const MeshF& m) {
  std::vector<std::vector<int>> vf(m.vert.size());
  for (std::size_t i = 0; i < m.face.size(); ++i)
    for (int j = 0; j < 3; ++j) vf[m.face[i].cV(j) - &m.vert[0]].push_back(static_cast<int>(i));
  return vf;
}

/// Moves every vertex in index order to propose(i, scale) for scale = 1, 1/2,
/// 1/4, 1/8, keeping the first position (stored as float) for which faceOk
/// holds on all its faces; otherwise the vertex stays where it is.
void jitterVertices(MeshF& m, const std::function<Vec3(int, double)>& propose,
                    const std::function<bool(const Vec3&, const Vec3&, const Vec3&)>& faceOk) {
  const auto vf = incidentFaces(m);
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    const CoordF old = m.vert[i].P();
    bool placed = false;
    for (double s = 1.0; s >= 0.125 && !placed; s *= 0.5) {
      m.vert[i].P() = toCoordF(propose(static_cast<int>(i), s));
      placed = true;
      for (int fi : vf[i]) {
        const auto& f = m.face[fi];
        if (!faceOk(toVec3(f.cP(0)), toVec3(f.cP(1)), toVec3(f.cP(2)))) {
          placed = false;
          break;
        }
      }
    }
    if (!placed) m.vert[i].P() = old;
  }
}

// ---------------------------------------------------------------------------
// blobs_mc.ply: marching cubes on a sum of Gaussians, like a molecular surface.

struct Blob {
  Vec3 center;
  double sigma;
  double amplitude;
};

constexpr std::uint32_t kBlobSeed = 20201;
constexpr int kBlobCount = 7;
constexpr double kBlobIso = 0.45;     // iso-value of the field
constexpr double kBlobVoxel = 0.065;  // grid spacing

std::vector<Blob> makeBlobs() {
  Rng rng(kBlobSeed);
  std::vector<Blob> blobs;
  Vec3 c(0, 0, 0);
  for (int i = 0; i < kBlobCount; ++i) {
    // A random walk keeps consecutive blobs overlapping, so the surface is connected.
    if (i > 0) c += rng.unitVector() * rng.uniform(0.6, 0.9);
    const double sigma = rng.uniform(0.30, 0.45);
    const double amplitude = rng.uniform(0.8, 1.2);
    blobs.push_back(Blob{c, sigma, amplitude});
  }
  return blobs;
}

double blobField(const std::vector<Blob>& blobs, const Vec3& p) {
  double f = 0;
  for (const Blob& b : blobs) f += b.amplitude * std::exp(-(p - b.center).SquaredNorm() / (2 * b.sigma * b.sigma));
  return f;
}

void flipAllFaces(MeshF& m) {
  for (auto& f : m.face)
    if (!f.IsD()) std::swap(f.V(1), f.V(2));
}

/// The blob surface by marching cubes on a grid of the given spacing.
bool buildBlobsAt(MeshF& m, double voxel) {
  using Volume = vcg::SimpleVolume<vcg::SimpleVoxel<float>>;
  using Walker = vcg::tri::TrivialWalker<MeshF, Volume>;
  using MarchingCubes = vcg::tri::MarchingCubes<MeshF, Walker>;

  const std::vector<Blob> blobs = makeBlobs();
  vcg::Box3d box;
  for (const Blob& b : blobs) {
    // Beyond 3 sigma of every blob the field is below 7 * 1.2 * exp(-4.5) < 0.1,
    // far under the iso-value, so the box holds the whole surface.
    box.Add(b.center + Vec3(3 * b.sigma, 3 * b.sigma, 3 * b.sigma));
    box.Add(b.center - Vec3(3 * b.sigma, 3 * b.sigma, 3 * b.sigma));
  }
  // TrivialWalker never visits the cells next to the high faces of the grid,
  // so keep a margin of empty voxels on every side.
  box.Offset(3 * voxel);
  vcg::Point3i size;
  for (int k = 0; k < 3; ++k) size[k] = static_cast<int>(std::ceil(box.Dim()[k] / voxel)) + 1;
  // BasicGrid spaces samples by (max-min)/size; choose max so the spacing is exact.
  const vcg::Point3f lo = toCoordF(box.min);
  const vcg::Point3f hi(lo[0] + float(size[0] * voxel), lo[1] + float(size[1] * voxel),
                        lo[2] + float(size[2] * voxel));
  Volume volume;
  volume.Init(size, vcg::Box3f(lo, hi));
  for (int z = 0; z < size[2]; ++z)
    for (int y = 0; y < size[1]; ++y)
      for (int x = 0; x < size[0]; ++x) {
        vcg::Point3f p;
        volume.IPiToPf(vcg::Point3i(x, y, z), p);
        volume.Val(x, y, z) = static_cast<float>(blobField(blobs, toVec3(p)));
      }

  Walker walker;
  MarchingCubes mc(m, walker);
  walker.BuildMesh(m, volume, mc, static_cast<float>(kBlobIso));
  vcg::tri::Allocator<MeshF>::CompactEveryVector(m);

  // The lookup table's winding depends on which side is "inside": make the
  // normals point out of the region where the field exceeds the iso-value.
  const sodt::VolumeResult vol = sodt::enclosedVolume(m);
  if (!vol.closed) return false;
  if (vol.volume < 0) flipAllFaces(m);
  return true;
}

bool buildBlobs(MeshF& m) { return buildBlobsAt(m, kBlobVoxel); }

// ---------------------------------------------------------------------------
// sphere_jitter.ply: icosphere with tangentially jittered vertices.

constexpr std::uint32_t kSphereSeed = 20202;
constexpr int kSphereSubdiv = 4;           // 2562 vertices
constexpr double kSphereJitter = 0.45;     // max tangential displacement / mean edge length
constexpr double kJitterMinAngleDeg = 0.5;  // jitter never makes a corner smaller than this

bool buildSphere(MeshF& m) {
  vcg::tri::Sphere(m, kSphereSubdiv);
  vcg::tri::Allocator<MeshF>::CompactEveryVector(m);
  const double h = meanEdgeLength(m);
  Rng rng(kSphereSeed);
  // Draw every vertex's displacement up front so the stream does not depend on vetoes.
  std::vector<Vec3> offset(m.vert.size());
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    Vec3 t1, t2;
    sodt::tangentFrame(toVec3(m.vert[i].P()).Normalize(), t1, t2);
    const double r = kSphereJitter * h * std::sqrt(rng.uniform01());  // uniform in a disc
    const double a = 2 * sodt::kPi * rng.uniform01();
    offset[i] = t1 * (r * std::cos(a)) + t2 * (r * std::sin(a));
  }
  std::vector<Vec3> base(m.vert.size());
  for (std::size_t i = 0; i < m.vert.size(); ++i) base[i] = toVec3(m.vert[i].P()).Normalize();
  jitterVertices(
      m, [&](int i, double s) { return (base[i] + offset[i] * s).Normalize(); },
      [](const Vec3& a, const Vec3& b, const Vec3& c) {
        const Vec3 n = sodt::doubleAreaVector(a, b, c);
        return n * (a + b + c) > 0 && minAngleDeg(a, b, c) >= kJitterMinAngleDeg;
      });
  return true;
}

// ---------------------------------------------------------------------------
// torus.off: regular parametric torus.

constexpr int kTorusMajorDiv = 48;
constexpr int kTorusMinorDiv = 16;
constexpr double kTorusMajorRadius = 1.0;
constexpr double kTorusMinorRadius = 0.4;

bool buildTorus(MeshF& m) {
  const int nu = kTorusMajorDiv, nv = kTorusMinorDiv;
  vcg::tri::Allocator<MeshF>::AddVertices(m, nu * nv);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * sodt::kPi * i / nu, v = 2 * sodt::kPi * j / nv;
      const double rho = kTorusMajorRadius + kTorusMinorRadius * std::cos(v);
      m.vert[i * nv + j].P() = toCoordF(Vec3(rho * std::cos(u), rho * std::sin(u), kTorusMinorRadius * std::sin(v)));
    }
  vcg::tri::Allocator<MeshF>::AddFaces(m, 2 * nu * nv);
  auto vp = [&](int i, int j) { return &m.vert[((i + nu) % nu) * nv + (j + nv) % nv]; };
  int k = 0;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      // d/du x d/dv points outwards, so (i,j) -> (i+1,j) -> (i+1,j+1) is counter-clockwise seen from outside.
      m.face[k].V(0) = vp(i, j), m.face[k].V(1) = vp(i + 1, j), m.face[k].V(2) = vp(i + 1, j + 1), ++k;
      m.face[k].V(0) = vp(i, j), m.face[k].V(1) = vp(i + 1, j + 1), m.face[k].V(2) = vp(i, j + 1), ++k;
    }
  return true;
}

// ---------------------------------------------------------------------------
// plane_grid_open.ply: jittered planar grid with a boundary.

constexpr std::uint32_t kGridSeed = 20204;
constexpr int kGridSide = 20;          // vertices per side
constexpr double kGridJitter = 0.35;   // max displacement per axis / grid spacing

bool buildPlaneGrid(MeshF& m) {
  const int n = kGridSide;
  const double h = 1.0 / (n - 1);
  Rng rng(kGridSeed);
  vcg::tri::Allocator<MeshF>::AddVertices(m, n * n);
  std::vector<Vec3> base(n * n), offset(n * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int i = y * n + x;
      base[i] = Vec3(x * h, y * h, 0);
      m.vert[i].P() = toCoordF(base[i]);
      // Boundary vertices slide along their side only, and corners stay, so the outline stays a square.
      const double dx = rng.uniform(-kGridJitter, kGridJitter) * h;
      const double dy = rng.uniform(-kGridJitter, kGridJitter) * h;
      const bool xFixed = x == 0 || x == n - 1, yFixed = y == 0 || y == n - 1;
      offset[i] = Vec3(xFixed ? 0 : dx, yFixed ? 0 : dy, 0);
    }
  vcg::tri::Allocator<MeshF>::AddFaces(m, 2 * (n - 1) * (n - 1));
  int k = 0;
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      MeshF::VertexPointer a = &m.vert[y * n + x], b = &m.vert[y * n + x + 1];
      MeshF::VertexPointer c = &m.vert[(y + 1) * n + x + 1], d = &m.vert[(y + 1) * n + x];
      if (rng.coin()) {  // diagonal a-c
        m.face[k].V(0) = a, m.face[k].V(1) = b, m.face[k].V(2) = c, ++k;
        m.face[k].V(0) = a, m.face[k].V(1) = c, m.face[k].V(2) = d, ++k;
      } else {  // diagonal b-d
        m.face[k].V(0) = a, m.face[k].V(1) = b, m.face[k].V(2) = d, ++k;
        m.face[k].V(0) = b, m.face[k].V(1) = c, m.face[k].V(2) = d, ++k;
      }
    }
  jitterVertices(
      m, [&](int i, double s) { return base[i] + offset[i] * s; },
      [](const Vec3& a, const Vec3& b, const Vec3& c) {
        return sodt::doubleAreaVector(a, b, c)[2] > 0 && minAngleDeg(a, b, c) >= kJitterMinAngleDeg;
      });
  return true;
}

// ---------------------------------------------------------------------------
// cube_jitter.ply, cube_noisy.ply: the cube [-1, 1]^3 with sharp edges and corners.
//
// Each cube face is a kCubeCells x kCubeCells grid; the vertices are the
// surface points of the integer lattice {0..n}^3, so the vertices shared by two
// or three faces exist once. Vertex i has lattice coordinates cubeLattice[i]; a
// lattice coordinate equal to 0 or n is "fixed" (the vertex lies on that face
// plane). One fixed coordinate: face-interior vertex, two: crease (cube edge)
// vertex, three: corner.

constexpr std::uint32_t kCubeGridSeed = 20205;    // diagonal of each quad
constexpr std::uint32_t kCubeJitterSeed = 20206;  // cube_jitter.ply displacements
constexpr std::uint32_t kCubeNoiseSeed = 20207;   // cube_noisy.ply displacements
constexpr int kCubeCells = 12;                    // cells per face side: 6 n^2 + 2 = 866 vertices
constexpr double kCubeJitter = 0.35;              // max in-plane displacement per axis / cell size
constexpr double kCubeNoise = 0.15;               // max normal displacement / cell size
constexpr double kCubeCell = 2.0 / kCubeCells;    // cell size

using Lattice = std::array<int, 3>;

bool latticeFixed(int c) { return c == 0 || c == kCubeCells; }

/// Position of a lattice point; fixed coordinates are exactly -1 or +1.
Vec3 cubePoint(const Lattice& l) {
  Vec3 p;
  for (int k = 0; k < 3; ++k)
    p[k] = l[k] == 0 ? -1.0 : l[k] == kCubeCells ? 1.0 : -1.0 + kCubeCell * l[k];
  return p;
}

/// Outward normal of the cube face that a triangle of these meshes lies on
/// (or came from): the axis of the centroid's largest |coordinate|. In both
/// cube meshes the displacements are far too small for a triangle's centroid
/// to reach another face's axis (see the README).
Vec3 cubeFaceNormal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 g = a + b + c;
  int k = 0;
  for (int j = 1; j < 3; ++j)
    if (std::abs(g[j]) > std::abs(g[k])) k = j;
  Vec3 n(0, 0, 0);
  n[k] = g[k] > 0 ? 1.0 : -1.0;
  return n;
}

/// No flip against the cube face, and no corner below kJitterMinAngleDeg.
bool cubeFaceOk(const Vec3& a, const Vec3& b, const Vec3& c) {
  return sodt::doubleAreaVector(a, b, c) * cubeFaceNormal(a, b, c) > 0 && minAngleDeg(a, b, c) >= kJitterMinAngleDeg;
}

/// The exact cube: vertices in lattice order (z, y, x), faces -x, +x, -y, +y,
/// -z, +z, each quad split along a random diagonal (seed kCubeGridSeed), the
/// triangles wound outwards. Returns the lattice coordinates of the vertices.
std::vector<Lattice> buildCubeGrid(MeshF& m) {
  const int n = kCubeCells;
  std::vector<Lattice> lattice;
  std::vector<int> index((n + 1) * (n + 1) * (n + 1), -1);
  auto at = [n](const Lattice& l) { return (l[2] * (n + 1) + l[1]) * (n + 1) + l[0]; };
  for (int z = 0; z <= n; ++z)
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x) {
        const Lattice l = {{x, y, z}};
        if (!latticeFixed(x) && !latticeFixed(y) && !latticeFixed(z)) continue;
        index[at(l)] = static_cast<int>(lattice.size());
        lattice.push_back(l);
      }
  vcg::tri::Allocator<MeshF>::AddVertices(m, lattice.size());
  for (std::size_t i = 0; i < lattice.size(); ++i) m.vert[i].P() = toCoordF(cubePoint(lattice[i]));

  Rng rng(kCubeGridSeed);
  vcg::tri::Allocator<MeshF>::AddFaces(m, 6 * 2 * n * n);
  int k = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      // (u, v, axis) is a cyclic permutation of (x, y, z), so e_u x e_v = +e_axis:
      // a -> b -> c winds outwards on the + face and inwards on the - face.
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          auto vp = [&](int di, int dj) {
            Lattice l;
            l[axis] = side * n, l[u] = i + di, l[v] = j + dj;
            return &m.vert[index[at(l)]];
          };
          MeshF::VertexPointer a = vp(0, 0), b = vp(1, 0), c = vp(1, 1), d = vp(0, 1);
          MeshF::VertexPointer tri[2][3];
          if (rng.coin()) {  // diagonal a-c
            tri[0][0] = a, tri[0][1] = b, tri[0][2] = c;
            tri[1][0] = a, tri[1][1] = c, tri[1][2] = d;
          } else {  // diagonal b-d
            tri[0][0] = a, tri[0][1] = b, tri[0][2] = d;
            tri[1][0] = b, tri[1][1] = c, tri[1][2] = d;
          }
          for (auto& t : tri) {
            if (side == 0) std::swap(t[1], t[2]);
            m.face[k].V(0) = t[0], m.face[k].V(1) = t[1], m.face[k].V(2) = t[2], ++k;
          }
        }
    }
  return lattice;
}

bool buildCubeJitter(MeshF& m) {
  const std::vector<Lattice> lattice = buildCubeGrid(m);
  Rng rng(kCubeJitterSeed);
  std::vector<Vec3> base(lattice.size()), offset(lattice.size());
  for (std::size_t i = 0; i < lattice.size(); ++i) {
    base[i] = cubePoint(lattice[i]);
    // Three draws for every vertex; a fixed coordinate ignores its draw, so
    // face vertices stay on their plane, crease vertices on their edge line,
    // and corners where they are.
    for (int k = 0; k < 3; ++k) {
      const double d = rng.uniform(-kCubeJitter, kCubeJitter) * kCubeCell;
      offset[i][k] = latticeFixed(lattice[i][k]) ? 0.0 : d;
    }
  }
  jitterVertices(
      m, [&](int i, double s) { return base[i] + offset[i] * s; }, cubeFaceOk);
  return true;
}

bool buildCubeNoisy(MeshF& m) {
  const std::vector<Lattice> lattice = buildCubeGrid(m);
  Rng rng(kCubeNoiseSeed);
  std::vector<Vec3> base(lattice.size()), offset(lattice.size());
  for (std::size_t i = 0; i < lattice.size(); ++i) {
    base[i] = cubePoint(lattice[i]);
    // Direction: the normalised sum of the outward normals of the faces the
    // vertex lies on (one face, two at a crease, three at a corner).
    Vec3 dir(0, 0, 0);
    for (int k = 0; k < 3; ++k)
      if (latticeFixed(lattice[i][k])) dir[k] = lattice[i][k] == 0 ? -1.0 : 1.0;
    offset[i] = dir.Normalize() * (rng.uniform(-kCubeNoise, kCubeNoise) * kCubeCell);
  }
  jitterVertices(
      m, [&](int i, double s) { return base[i] + offset[i] * s; }, cubeFaceOk);
  return true;
}

/// Checks that need the coordinates of the file as read back.
struct CubeCheck {
  int corners = 0;         ///< vertices exactly at (+-1, +-1, +-1)
  int creases = 0;         ///< vertices with exactly two coordinates equal to +-1
  int offSurface = 0;      ///< vertices whose largest |coordinate| is not exactly 1
  int flipped = 0;         ///< faces whose normal points away from their cube face
  double maxDistance = 0;  ///< largest | max_k |p_k| - 1 |, the L-inf distance to the cube surface
};

CubeCheck checkCube(const MeshF& m) {
  CubeCheck c;
  for (const auto& v : m.vert) {
    if (v.IsD()) continue;
    int ones = 0;
    double big = 0;
    for (int k = 0; k < 3; ++k) {
      const double a = std::abs(double(v.cP()[k]));
      ones += a == 1.0;
      big = std::max(big, a);
    }
    c.corners += ones == 3;
    c.creases += ones == 2;
    c.offSurface += big != 1.0;
    c.maxDistance = std::max(c.maxDistance, std::abs(big - 1.0));
  }
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    const Vec3 a = toVec3(f.cP(0)), b = toVec3(f.cP(1)), d = toVec3(f.cP(2));
    c.flipped += !(sodt::doubleAreaVector(a, b, d) * cubeFaceNormal(a, b, d) > 0);
  }
  return c;
}

// ---------------------------------------------------------------------------
// I/O and checks.

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// Writes binary little-endian PLY (float x y z, int indices) or ASCII OFF
/// with vcglib, OBJ or binary STL with the project's writer.
bool saveMesh(MeshF& m, const std::string& path) {
  if (endsWith(path, ".stl") || endsWith(path, ".obj")) {
    try {
      sodt::saveMesh(path, m, sodt::SaveOptions());
      return true;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return false;
    }
  }
  int err;
  if (endsWith(path, ".off"))
    err = vcg::tri::io::ExporterOFF<MeshF>::Save(m, path.c_str(), vcg::tri::io::Mask::IOM_VERTCOORD);
  else
    err = vcg::tri::io::ExporterPLY<MeshF>::Save(m, path.c_str(), vcg::tri::io::Mask::IOM_VERTCOORD, true);
  if (err != 0) std::fprintf(stderr, "error: cannot write %s (code %d)\n", path.c_str(), err);
  return err == 0;
}

bool loadMesh(MeshF& m, const std::string& path) {
  if (endsWith(path, ".stl") || endsWith(path, ".obj")) {
    try {
      sodt::loadMesh(path, m);
      return true;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return false;
    }
  }
  int err;
  if (endsWith(path, ".off"))
    err = vcg::tri::io::ImporterOFF<MeshF>::Open(m, path.c_str());
  else
    err = vcg::tri::io::ImporterPLY<MeshF>::Open(m, path.c_str());
  if (err != 0) std::fprintf(stderr, "error: cannot read %s (code %d)\n", path.c_str(), err);
  return err == 0;
}

/// Reports each failed expectation on stderr; returns true when all hold.
bool expect(const std::string& name, std::initializer_list<std::pair<bool, const char*>> checks) {
  bool ok = true;
  for (const auto& c : checks)
    if (!c.first) {
      std::fprintf(stderr, "error: %s: expected %s\n", name.c_str(), c.second);
      ok = false;
    }
  return ok;
}

bool expectations(const std::string& file, const MeshCheck& c, const MeshF& m) {
  // The STL and OBJ copies keep the expectations of the meshes they copy.
  const std::string name = file == "cube_jitter.stl" ? "cube_jitter.ply" : file == "torus.obj" ? "torus.off" : file;
  const bool clean = c.isolatedVertices == 0 && c.zeroAreaFaces == 0 && c.components == 1;
  if (name == "blobs_mc.ply")
    return expect(name, {{c.closedManifold(), "closed manifold"},
                         {clean, "no isolated vertex, no zero-area face, one component"},
                         {c.volume > 0, "outward normals (positive volume)"},
                         {c.vertices >= 3000 && c.vertices <= 8000, "3000..8000 vertices"},
                         {c.angles.minDeg < 1.0 && c.angles.minDeg > 0.0, "0 < min angle < 1 deg"},
                         {c.angles.fracBelow30 > 0.10, "more than 10% of angles below 30 deg"}});
  if (name == "sphere_jitter.ply")
    return expect(name, {{c.closedManifold() && c.eulerCharacteristic() == 2, "closed sphere"},
                         {clean, "no isolated vertex, no zero-area face, one component"},
                         {c.volume > 0, "outward normals (positive volume)"}});
  if (name == "torus.off")
    return expect(name, {{c.closedManifold() && c.eulerCharacteristic() == 0, "closed torus"},
                         {clean, "no isolated vertex, no zero-area face, one component"},
                         {c.volume > 0, "outward normals (positive volume)"}});
  if (name == "plane_grid_open.ply")
    return expect(name, {{c.openManifold() && c.boundaryLoops == 1 && c.eulerCharacteristic() == 1, "a disc"},
                         {clean, "no isolated vertex, no zero-area face, one component"}});
  const int cubeVertices = 6 * kCubeCells * kCubeCells + 2, cubeFaces = 12 * kCubeCells * kCubeCells;
  if (name == "cube_jitter.ply") {
    const CubeCheck q = checkCube(m);
    return expect(name, {{c.closedManifold() && c.eulerCharacteristic() == 2, "closed sphere"},
                         {clean, "no isolated vertex, no zero-area face, one component"},
                         {c.vertices == cubeVertices && c.faces == cubeFaces, "6 n^2 + 2 vertices, 12 n^2 faces"},
                         {q.corners == 8, "exactly 8 vertices at the cube corners"},
                         {q.creases == 12 * (kCubeCells - 1), "12 (n - 1) vertices on the cube edges"},
                         {q.offSurface == 0, "every vertex on the cube surface (max |coordinate| == 1)"},
                         {q.flipped == 0, "no face flipped against its cube face"},
                         {std::abs(c.volume - 8.0) < 1e-9, "volume 8 (the faces stay planar)"},
                         {c.angles.minDeg >= kJitterMinAngleDeg && c.angles.minDeg < 20.0,
                          "0.5 deg <= min angle < 20 deg"}});
  }
  if (name == "cube_noisy.ply") {
    const CubeCheck q = checkCube(m);
    const double amplitude = kCubeNoise * kCubeCell;
    return expect(name, {{c.closedManifold() && c.eulerCharacteristic() == 2, "closed sphere"},
                         {clean, "no isolated vertex, no zero-area face, one component"},
                         {c.vertices == cubeVertices && c.faces == cubeFaces, "6 n^2 + 2 vertices, 12 n^2 faces"},
                         {q.flipped == 0, "no face flipped against its cube face"},
                         {c.volume > 0, "outward normals (positive volume)"},
                         {q.maxDistance > 0.5 * amplitude && q.maxDistance <= amplitude * (1 + 1e-6),
                          "L-inf distance to the cube in (amplitude / 2, amplitude]"}});
  }
  return true;
}

long fileSize(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return -1;
  std::fseek(f, 0, SEEK_END);
  const long n = std::ftell(f);
  std::fclose(f);
  return n;
}

int printStats(int argc, char** argv) {
  std::printf("%s\n", sodt::tools::tableHeader());
  int status = 0;
  for (int i = 2; i < argc; ++i) {
    MeshF m;
    if (!loadMesh(m, argv[i])) {
      status = 1;
      continue;
    }
    std::printf("%s\n", sodt::tools::formatRow(argv[i], sodt::tools::checkMesh(m)).c_str());
  }
  return status;
}

int generate(const std::string& outDir) {
  struct Job {
    const char* file;
    bool (*build)(MeshF&);
  };
  const Job jobs[] = {{"blobs_mc.ply", buildBlobs},
                      {"sphere_jitter.ply", buildSphere},
                      {"torus.off", buildTorus},
                      {"plane_grid_open.ply", buildPlaneGrid},
                      {"cube_jitter.ply", buildCubeJitter},
                      {"cube_noisy.ply", buildCubeNoisy},
                      {"cube_jitter.stl", buildCubeJitter},
                      {"torus.obj", buildTorus}};
  int status = 0;
  std::printf("%s\n", sodt::tools::tableHeader());
  for (const Job& job : jobs) {
    const std::string path = outDir + "/" + job.file;
    MeshF m;
    if (!job.build(m)) {
      std::fprintf(stderr, "error: %s: construction failed (marching cubes surface not closed)\n", job.file);
      status = 1;
      continue;
    }
    vcg::tri::UpdateBounding<MeshF>::Box(m);
    if (!saveMesh(m, path)) {
      status = 1;
      continue;
    }
    // Check what a user of the file gets, not the in-memory mesh.
    MeshF back;
    if (!loadMesh(back, path)) {
      status = 1;
      continue;
    }
    const MeshCheck c = sodt::tools::checkMesh(back);
    std::printf("%s  (%ld bytes)\n", sodt::tools::formatRow(job.file, c).c_str(), fileSize(path));
    if (!expectations(job.file, c, back)) status = 1;
  }
  return status;
}

/// The meshes of the high-valence guards (bench/high_valence.sh, the ctest
/// label "valence"), written as OFF text: "fan", a closed double fan (apexes
/// at z = +-0.3 over a unit rim of n vertices: two vertices of valence n and
/// 2n needle faces), or "polygon", one n-gon that readers fan-triangulate from
/// its first vertex. Every rim vertex carries a random 3-D wobble of up to a
/// sixth of the rim spacing in x, y and z (seeded), so nothing is exactly
/// symmetric or flat. "torus" is their yardstick: a regular closed torus of
/// 100 x n/100 vertices (radii 1 and 0.3), 2n faces like the fan of rim n.
/// The torus of writeValenceMesh into f.
void writeTorus(FILE* f, long n) {
  const long rings = 100, segments = n / rings;
  std::fprintf(f, "OFF\n%ld %ld 0\n", rings * segments, 2 * rings * segments);
  for (long i = 0; i < segments; ++i)
    for (long j = 0; j < rings; ++j) {
      const double u = 2 * sodt::kPi * double(i) / double(segments), v = 2 * sodt::kPi * double(j) / double(rings);
      const double r = 1 + 0.3 * std::cos(v);
      std::fprintf(f, "%.17g %.17g %.17g\n", r * std::cos(u), r * std::sin(u), 0.3 * std::sin(v));
    }
  for (long i = 0; i < segments; ++i)
    for (long j = 0; j < rings; ++j) {
      const long a = i * rings + j, b = ((i + 1) % segments) * rings + j;
      const long c = ((i + 1) % segments) * rings + (j + 1) % rings, d = i * rings + (j + 1) % rings;
      std::fprintf(f, "3 %ld %ld %ld\n3 %ld %ld %ld\n", a, b, c, a, c, d);
    }
}

/// The double fan (fan) or the n-gon of writeValenceMesh into f.
void writeFanOrPolygon(FILE* f, bool fan, long n) {
  const double h = 2 * sodt::kPi / double(n), wobble = h / 6;
  Rng rng(7);
  std::fprintf(f, "OFF\n%ld %ld 0\n", fan ? n + 2 : n, fan ? 2 * n : 1L);
  if (fan) std::fprintf(f, "0 0 0.3\n0 0 -0.3\n");
  for (long k = 0; k < n; ++k) {
    const double a = double(k) * h;
    std::fprintf(f, "%.17g %.17g %.17g\n", std::cos(a) + rng.uniform(-wobble, wobble),
                 std::sin(a) + rng.uniform(-wobble, wobble), rng.uniform(-wobble, wobble));
  }
  if (fan) {
    for (long k = 0; k < n; ++k) std::fprintf(f, "3 0 %ld %ld\n", 2 + k, 2 + (k + 1) % n);
    for (long k = 0; k < n; ++k) std::fprintf(f, "3 1 %ld %ld\n", 2 + (k + 1) % n, 2 + k);
  } else {
    std::fprintf(f, "%ld", n);
    for (long k = 0; k < n; ++k) std::fprintf(f, " %ld", k);
    std::fprintf(f, "\n");
  }
}

int writeValenceMesh(const std::string& kind, long n, const std::string& path) {
  if ((kind != "fan" && kind != "polygon" && kind != "torus") || n < 3 || n > 50000000 ||
      (kind == "torus" && n < 300)) {
    std::fprintf(stderr, "error: --valence needs fan|polygon|torus and 3 <= N <= 50000000 (300 for a torus)\n");
    return 2;
  }
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "error: cannot write %s\n", path.c_str());
    return 1;
  }
  if (kind == "torus")
    writeTorus(f, n);
  else
    writeFanOrPolygon(f, kind == "fan", n);
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) {
    std::fprintf(stderr, "error: writing %s failed\n", path.c_str());
    return 1;
  }
  return 0;
}

/// blobs_mc.ply's surface on a grid `factor` times finer (about 4800 factor^2
/// vertices: 5.4 gives 139,558), a large marching-cubes mesh for the
/// benchmarks; checked like blobs_mc.ply but for its size.
int writeFineBlobs(double factor, const std::string& path) {
  if (!(factor >= 1 && factor <= 64)) {
    std::fprintf(stderr, "error: --mc-resolution needs 1 <= FACTOR <= 64\n");
    return 2;
  }
  MeshF m;
  if (!buildBlobsAt(m, kBlobVoxel / factor)) {
    std::fprintf(stderr, "error: marching cubes surface not closed\n");
    return 1;
  }
  vcg::tri::UpdateBounding<MeshF>::Box(m);
  if (!saveMesh(m, path)) return 1;
  const MeshCheck c = sodt::tools::checkMesh(m);
  std::printf("%s\n%s\n", sodt::tools::tableHeader(), sodt::tools::formatRow(path, c).c_str());
  const bool clean = c.isolatedVertices == 0 && c.zeroAreaFaces == 0 && c.components == 1;
  return expect(path, {{c.closedManifold(), "closed manifold"},
                       {clean, "no isolated vertex, no zero-area face, one component"},
                       {c.volume > 0, "outward normals (positive volume)"}})
             ? 0
             : 1;
}

void usage() {
  std::fprintf(stderr,
               "usage: sodt_make_meshes OUTDIR          write the project's test meshes into OUTDIR\n"
               "       sodt_make_meshes --stats FILE... print the report of .ply/.off files\n"
               "       sodt_make_meshes --valence fan|polygon N OUT.off\n"
               "       sodt_make_meshes --valence torus N OUT.off\n"
               "                                        a closed double fan over a rim of N vertices, an N-gon,\n"
               "                                        or a 100 x N/100 torus with as many faces as the fan\n"
               "       sodt_make_meshes --mc-resolution FACTOR OUT.ply\n"
               "                                        blobs_mc.ply's surface on a grid FACTOR times finer\n"
               "                                        (about 4800 FACTOR^2 vertices; 5.4 gives 139,558)\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    usage();
    return 2;
  }
  const std::string first = argv[1];
  if (first == "--stats") return printStats(argc, argv);
  if (first == "--valence") {
    if (argc != 5) {
      usage();
      return 2;
    }
    return writeValenceMesh(argv[2], std::atol(argv[3]), argv[4]);
  }
  if (first == "--mc-resolution") {
    if (argc != 4) {
      usage();
      return 2;
    }
    return writeFineBlobs(std::atof(argv[2]), argv[3]);
  }
  if (first == "-h" || first == "--help") {
    usage();
    return 0;
  }
  return generate(first);
}
