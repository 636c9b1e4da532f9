// SPDX-License-Identifier: GPL-3.0-or-later
// The defect zoo: a clean jittered icosphere (vcg platonic.h) with one defect
// injected at a time, plus special meshes (empty, point cloud, polygons...).
// Every expectation comes from how the defect was built.
#include "defect_zoo.h"

#include <vcg/complex/algorithms/create/platonic.h>
#include <vcg/complex/complex.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>

namespace sodt_zoo {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

Point add(const Point& a, const Point& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Point sub(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point mul(const Point& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Point unit(const Point& a) { return mul(a, 1.0 / std::sqrt(dot(a, a))); }

/// Uniform double in [0, 1) from a 32-bit engine; the same on every platform.
double uniform01(std::mt19937& g) { return (g() >> 5) * (1.0 / 134217728.0); }
double uniform(std::mt19937& g, double lo, double hi) { return lo + (hi - lo) * uniform01(g); }

Point centroid(const Soup& s, int f) {
  const Tri& t = s.tri[f];
  return mul(add(add(s.pos[t[0]], s.pos[t[1]]), s.pos[t[2]]), 1.0 / 3.0);
}

/// The vertex of [begin, end) farthest along dir.
int vertexToward(const Soup& s, const Point& dir, int begin = 0, int end = -1) {
  if (end < 0) end = static_cast<int>(s.pos.size());
  int best = begin;
  for (int i = begin; i < end; ++i)
    if (dot(s.pos[i], dir) > dot(s.pos[best], dir)) best = i;
  return best;
}

/// The face of [begin, end) whose centroid is farthest along dir.
int faceToward(const Soup& s, const Point& dir, int begin = 0, int end = -1) {
  if (end < 0) end = static_cast<int>(s.tri.size());
  int best = begin;
  for (int f = begin; f < end; ++f)
    if (dot(centroid(s, f), dir) > dot(centroid(s, best), dir)) best = f;
  return best;
}

std::vector<int> facesOf(const Soup& s, int v) {
  std::vector<int> r;
  for (int f = 0; f < static_cast<int>(s.tri.size()); ++f)
    if (s.tri[f][0] == v || s.tri[f][1] == v || s.tri[f][2] == v) r.push_back(f);
  return r;
}

/// Appends b to a (vertices shifted); returns the index offset of b's vertices.
int append(Soup& a, const Soup& b) {
  const int off = static_cast<int>(a.pos.size());
  a.pos.insert(a.pos.end(), b.pos.begin(), b.pos.end());
  for (const Tri& t : b.tri) a.tri.push_back({t[0] + off, t[1] + off, t[2] + off});
  return off;
}

/// Removes the faces whose flag is set.
void eraseFaces(Soup& s, const std::vector<char>& drop) {
  std::vector<Tri> keep;
  for (std::size_t f = 0; f < s.tri.size(); ++f)
    if (!drop[f]) keep.push_back(s.tri[f]);
  s.tri = keep;
}

/// Removes vertex v (which no face may reference) and its expectation.
void eraseVertex(ZooMesh& z, int v) {
  z.soup.pos.erase(z.soup.pos.begin() + v);
  z.kind.erase(z.kind.begin() + v);
  for (Tri& t : z.soup.tri)
    for (int& i : t) {
      if (i == v) throw std::logic_error("eraseVertex: vertex still referenced");
      if (i > v) --i;
    }
}

/// Replaces every reference to vertex `from` by `to` (welding).
void redirect(Soup& s, int from, int to) {
  for (Tri& t : s.tri)
    for (int& i : t)
      if (i == from) i = to;
}

ZooMesh start(const std::string& name, const std::string& description, const Soup& s) {
  ZooMesh z;
  z.name = name;
  z.description = description;
  z.soup = s;
  z.kind.assign(s.pos.size(), Kind::Interior);
  return z;
}

/// Marks every vertex of the given faces with kind k.
void markFaces(ZooMesh& z, const std::vector<int>& faces, Kind k) {
  for (int f : faces)
    for (int v : z.soup.tri[f]) z.kind[v] = k;
}

/// Subdivision level of the base sphere: 162 vertices, 320 faces. Small
/// enough to run every setting on every zoo mesh in seconds, large enough
/// for defect sites far apart.
constexpr int kBaseSubdiv = 2;

Soup base(unsigned seed = 1) { return jitteredSphere(kBaseSubdiv, 0.35, seed); }

// ---------------------------------------------------------------------------
// The defects

ZooMesh finEdge() {
  ZooMesh z = start("fin_edge", "non-manifold edge: a fin face on an existing edge", base());
  const int f = faceToward(z.soup, {1, 0.2, 0.1});
  const int a = z.soup.tri[f][0], b = z.soup.tri[f][1];
  const Point mid = mul(add(z.soup.pos[a], z.soup.pos[b]), 0.5);
  z.soup.pos.push_back(mul(mid, 1.25));
  z.kind.push_back(Kind::Boundary);
  z.soup.tri.push_back({a, b, static_cast<int>(z.soup.pos.size()) - 1});
  z.kind[a] = z.kind[b] = Kind::NonManifold;
  z.plugin = true;
  return z;
}

ZooMesh edgeFourFaces() {
  ZooMesh z = start("edge_four_faces", "non-manifold edge with four faces: two fins on one edge", base());
  const int f = faceToward(z.soup, {-0.3, 1, 0.2});
  const int a = z.soup.tri[f][1], b = z.soup.tri[f][2];
  const Point mid = mul(add(z.soup.pos[a], z.soup.pos[b]), 0.5);
  const Point side = unit(cross(sub(z.soup.pos[b], z.soup.pos[a]), mid));
  const int x = static_cast<int>(z.soup.pos.size());
  z.soup.pos.push_back(add(mul(mid, 1.2), mul(side, 0.05)));
  z.soup.pos.push_back(add(mul(mid, 1.2), mul(side, -0.05)));
  z.kind.push_back(Kind::Boundary);
  z.kind.push_back(Kind::Boundary);
  z.soup.tri.push_back({a, b, x});
  z.soup.tri.push_back({b, a, x + 1});
  z.kind[a] = z.kind[b] = Kind::NonManifold;
  return z;
}

/// Second sphere mirrored across a plane through an edge of the first and
/// welded to it along that edge: the edge has four faces.
ZooMesh edgeTwoSpheres() {
  ZooMesh z = start("edge_two_spheres", "two spheres welded along one edge (four faces on it)", base());
  const int f = faceToward(z.soup, {0.2, -0.4, 1});
  const int a = z.soup.tri[f][0], b = z.soup.tri[f][1];
  const Point m = unit(add(z.soup.pos[a], z.soup.pos[b]));
  const double d = 0.5 * (dot(z.soup.pos[a], m) + dot(z.soup.pos[b], m));
  Soup mirror = z.soup;
  for (Point& p : mirror.pos) p = sub(p, mul(m, 2 * (dot(p, m) - d)));
  for (Tri& t : mirror.tri) std::swap(t[1], t[2]);  // a mirror reverses the orientation
  const int off = append(z.soup, mirror);
  z.kind.resize(z.soup.pos.size(), Kind::Interior);
  redirect(z.soup, a + off, a);
  redirect(z.soup, b + off, b);
  z.kind[a + off] = z.kind[b + off] = Kind::Isolated;
  // Drop the two welded copies (highest index first).
  eraseVertex(z, std::max(a, b) + off);
  eraseVertex(z, std::min(a, b) + off);
  z.kind[a] = z.kind[b] = Kind::NonManifold;
  return z;
}

/// Second sphere, the point reflection of the first about one of its
/// vertices p: the two touch only at p, which is welded.
Soup pinchedPair(int subdiv, const Point& dir, int* pinch) {
  Soup a = jitteredSphere(subdiv, 0.35, 7);
  const int p = vertexToward(a, dir);
  Soup b = a;
  for (Point& q : b.pos) q = sub(mul(a.pos[p], 2), q);
  for (Tri& t : b.tri) std::swap(t[1], t[2]);  // a point reflection reverses the orientation
  const int off = append(a, b);
  redirect(a, p + off, p);
  a.pos.erase(a.pos.begin() + p + off);
  for (Tri& t : a.tri)
    for (int& i : t)
      if (i > p + off) --i;
  *pinch = p;
  return a;
}

ZooMesh pinchVertex() {
  int p = -1;
  const Soup s = pinchedPair(kBaseSubdiv, {0.1, 0.2, 1}, &p);
  ZooMesh z = start("pinch_vertex", "non-manifold (pinch) vertex: two spheres sharing one vertex", s);
  z.kind[p] = Kind::NonManifold;
  z.plugin = true;
  return z;
}

/// Removes the star of the vertex toward dir, and drops that vertex.
void punchStar(ZooMesh& z, const Point& dir) {
  const int v = vertexToward(z.soup, dir);
  const std::vector<int> star = facesOf(z.soup, v);
  markFaces(z, star, Kind::Boundary);
  std::vector<char> drop(z.soup.tri.size(), 0);
  for (int f : star) drop[f] = 1;
  eraseFaces(z.soup, drop);
  eraseVertex(z, v);
}

ZooMesh hole() {
  ZooMesh z = start("hole", "boundaries: a vertex star punched out, a missing face, a bowtie hole", base());
  punchStar(z, {0, 0.3, 1});
  // One missing face.
  std::vector<char> drop(z.soup.tri.size(), 0);
  const int f = faceToward(z.soup, {1, -0.2, 0.1});
  markFaces(z, {f}, Kind::Boundary);
  drop[f] = 1;
  // Two faces that share only a vertex w: w's fan opens twice.
  const int w = vertexToward(z.soup, {-1, 0.1, -0.3});
  const std::vector<int> star = facesOf(z.soup, w);
  int g = -1;
  for (int h : star) {
    int shared = 0;
    for (int u : z.soup.tri[h])
      for (int x : z.soup.tri[star[0]]) shared += u == x;
    if (shared == 1) g = h;
  }
  if (g < 0) throw std::logic_error("hole: no bowtie pair");
  markFaces(z, {star[0], g}, Kind::Boundary);
  drop[star[0]] = drop[g] = 1;
  eraseFaces(z.soup, drop);
  z.plugin = true;
  return z;
}

ZooMesh deletedElements() {
  ZooMesh z = start("deleted_elements",
                    "faces flagged deleted (not compacted), a deleted vertex holding NaN", base());
  const int v = vertexToward(z.soup, {0.5, 0.5, -0.7});
  const std::vector<int> star = facesOf(z.soup, v);
  markFaces(z, star, Kind::Boundary);
  z.soup.faceDeleted.assign(z.soup.tri.size(), 0);
  z.soup.vertDeleted.assign(z.soup.pos.size(), 0);
  for (int f : star) z.soup.faceDeleted[f] = 1;
  z.soup.vertDeleted[v] = 1;
  z.soup.pos[v] = {kNaN, kNaN, kNaN};  // never read: deleted
  z.kind[v] = Kind::Deleted;
  z.coreOnly = true;
  return z;
}

ZooMesh zeroAreaCollapsed() {
  ZooMesh z = start("zero_area_collapsed", "zero-area face: its three vertices moved to one point", base());
  const int f = faceToward(z.soup, {0.1, 1, -0.2});
  const Point c = centroid(z.soup, f);
  for (int v : z.soup.tri[f]) z.soup.pos[v] = c;
  z.plugin = true;
  return z;
}

ZooMesh needleCoincident() {
  ZooMesh z = start("needle_coincident", "zero-area needles: the two ends of an edge at one point", base());
  const int f = faceToward(z.soup, {-0.2, -0.1, 1});
  z.soup.pos[z.soup.tri[f][1]] = z.soup.pos[z.soup.tri[f][0]];
  return z;
}

ZooMesh repeatedIndex() {
  ZooMesh z = start("repeated_index", "faces with a repeated vertex index: (a, a, b) and (c, c, c)", base());
  const int f = faceToward(z.soup, {0.2, -1, 0.1});
  const int a = z.soup.tri[f][0], b = z.soup.tri[f][1];
  const int c = vertexToward(z.soup, {0.1, 0.3, -1});
  z.soup.tri.push_back({a, a, b});
  z.soup.tri.push_back({c, c, c});
  z.kind[a] = z.kind[b] = z.kind[c] = Kind::NonManifold;
  return z;
}

ZooMesh duplicateFace(bool flipped) {
  ZooMesh z = start(flipped ? "duplicate_face_flipped" : "duplicate_face",
                    flipped ? "duplicate face with the opposite winding" : "the same triangle twice", base());
  const int f = faceToward(z.soup, flipped ? Point{-0.6, 0.5, 0.4} : Point{0.3, 0.5, 0.8});
  Tri t = z.soup.tri[f];
  if (flipped) std::swap(t[1], t[2]);
  z.soup.tri.push_back(t);
  markFaces(z, {f}, Kind::NonManifold);
  z.plugin = true;
  return z;
}

ZooMesh unreferencedVertices() {
  ZooMesh z = start("unreferenced_vertices", "vertices no face uses: at the origin, far away, on a vertex", base());
  for (const Point& p : {Point{0, 0, 0}, Point{5, 5, 5}, z.soup.pos[0], Point{0.5, 0.5, 0.5}}) {
    z.soup.pos.push_back(p);
    z.kind.push_back(Kind::Isolated);
  }
  return z;
}

/// Splits the sphere along the loop between the faces on either side of a
/// tilted plane: the faces above get their own copies of the loop vertices.
ZooMesh unweldedSeam() {
  ZooMesh z = start("duplicate_vertices_seam", "duplicate vertices: a sphere cut along a loop, both sides unwelded",
                    base());
  const Point n = unit({0.2, 0.1, 1});
  const int nv = static_cast<int>(z.soup.pos.size());
  std::vector<char> above(z.soup.tri.size());
  std::vector<int> side(nv, 0);  // bit 1: touches a face above, bit 2: below
  for (std::size_t f = 0; f < z.soup.tri.size(); ++f) {
    above[f] = dot(centroid(z.soup, static_cast<int>(f)), n) > 0.05;
    for (int v : z.soup.tri[f]) side[v] |= above[f] ? 1 : 2;
  }
  std::vector<int> copy(nv, -1);
  for (int v = 0; v < nv; ++v)
    if (side[v] == 3) {
      copy[v] = static_cast<int>(z.soup.pos.size());
      z.soup.pos.push_back(z.soup.pos[v]);
      z.kind.push_back(Kind::Boundary);
      z.kind[v] = Kind::Boundary;
    }
  for (std::size_t f = 0; f < z.soup.tri.size(); ++f)
    if (above[f])
      for (int& v : z.soup.tri[f])
        if (copy[v] >= 0) v = copy[v];
  return z;
}

ZooMesh inconsistentWinding() {
  // The cap, the minority, is turned back before the run: every vertex
  // stays interior (none is fixed where the winding changed).
  ZooMesh z = start("inconsistent_winding", "inconsistent winding: a cap of faces flipped", base());
  const Point n = unit({0.5, -0.5, 0.7});
  const int nv = static_cast<int>(z.soup.pos.size());
  std::vector<int> side(nv, 0);
  for (std::size_t f = 0; f < z.soup.tri.size(); ++f) {
    const bool flip = dot(centroid(z.soup, static_cast<int>(f)), n) > 0.8;
    if (flip) std::swap(z.soup.tri[f][1], z.soup.tri[f][2]);
    for (int v : z.soup.tri[f]) side[v] |= flip ? 1 : 2;
  }
  z.topologyKind = z.kind;
  for (int v = 0; v < nv; ++v)
    if (side[v] == 3) z.topologyKind[v] = Kind::NonManifold;
  z.plugin = true;
  return z;
}

ZooMesh nonFinite(const std::string& name, const std::string& description,
                  const std::vector<std::pair<int, Point>>& bad, bool appendUnreferenced) {
  ZooMesh z = start(name, description, jitteredSphere(2, 0.35, 3));
  for (const auto& kv : bad) z.soup.pos[kv.first] = kv.second;
  if (appendUnreferenced) z.soup.pos.push_back({kNaN, kNaN, kNaN});
  const int n = static_cast<int>(bad.size()) + (appendUnreferenced ? 1 : 0);
  z.core = CoreOutcome::InvalidInput;
  z.kind.clear();
  z.coreError = std::to_string(n) + (n > 1 ? " vertices have" : " vertex has") + " a non-finite coordinate";
  z.cliError = "non-finite coordinate";
  return z;
}

ZooMesh emptyMesh() {
  ZooMesh z = start("empty", "empty mesh: no vertices, no faces", Soup());
  z.core = CoreOutcome::NoOp;
  z.cliError = "no triangles";
  z.plugin = true;
  return z;
}

ZooMesh pointCloud() {
  Soup s = jitteredSphere(2, 0.35, 5);
  s.tri.clear();
  ZooMesh z = start("point_cloud", "point cloud: vertices, no faces", s);
  z.core = CoreOutcome::NoOp;
  z.kind.assign(s.pos.size(), Kind::Isolated);
  z.cliError = "no triangles";
  z.plugin = true;
  return z;
}

ZooMesh singleDegenerateTriangle() {
  Soup s;
  s.pos.assign(3, Point{0.5, -0.25, 2});
  s.tri.push_back({0, 1, 2});
  ZooMesh z = start("single_degenerate_triangle", "one triangle whose three vertices coincide", s);
  z.kind.assign(3, Kind::Boundary);
  z.plugin = true;
  return z;
}

/// Quad sphere (a cube of n x n quads per side projected on the unit sphere)
/// with a vertex inserted on some edges: quads, pentagons and a hexagon.
ZooMesh polygons() {
  const int n = 3;
  Soup s;
  std::map<std::array<int, 3>, int> index;
  auto vertex = [&](int x, int y, int zc) {
    const std::array<int, 3> key{x, y, zc};
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    const double h = 2.0 / n;
    s.pos.push_back(unit({-1 + x * h, -1 + y * h, -1 + zc * h}));
    index[key] = static_cast<int>(s.pos.size()) - 1;
    return index[key];
  };
  std::vector<std::vector<int>> poly;
  for (int a = 0; a < 3; ++a)
    for (int sd = 0; sd < 2; ++sd) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto at = [&](int di, int dj) {
            std::array<int, 3> c{};
            c[a] = sd * n;
            c[u] = i + di;
            c[v] = j + dj;
            return vertex(c[0], c[1], c[2]);
          };
          std::vector<int> q = {at(0, 0), at(1, 0), at(1, 1), at(0, 1)};
          if (sd == 0) std::swap(q[1], q[3]);  // outward on the low side
          poly.push_back(q);
        }
    }
  // Insert a vertex (on the sphere) into an edge shared by two polygons.
  auto split = [&](int pi, int k) {
    const int p = poly[pi][k], q = poly[pi][(k + 1) % poly[pi].size()];
    s.pos.push_back(unit(add(s.pos[p], s.pos[q])));
    const int r = static_cast<int>(s.pos.size()) - 1;
    for (auto& P : poly)
      for (std::size_t e = 0; e < P.size(); ++e) {
        const int x = P[e], y = P[(e + 1) % P.size()];
        if ((x == p && y == q) || (x == q && y == p)) {
          P.insert(P.begin() + static_cast<std::ptrdiff_t>(e + 1), r);
          break;
        }
      }
  };
  split(4, 0);   // two pentagons
  split(4, 2);   // polygon 4 becomes a hexagon
  split(13, 1);  // two more pentagons
  split(40, 3);
  std::ostringstream off;
  off << "OFF\n# quad sphere with pentagons and a hexagon\n" << s.pos.size() << ' ' << poly.size() << " 0\n";
  off.precision(17);
  for (const Point& p : s.pos) off << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& P : poly) {
    off << P.size();
    for (int v : P) off << ' ' << v;
    off << '\n';
    for (std::size_t k = 1; k + 1 < P.size(); ++k) s.tri.push_back({P[0], P[k], P[k + 1]});  // the loader's fan
  }
  ZooMesh z = start("polygons", "OFF file with quads, pentagons and a hexagon (fan-triangulated on load)", s);
  z.offText = off.str();
  z.polygons = poly;
  z.plugin = true;
  return z;
}

ZooMesh manyComponents() {
  Soup s;
  const double radius[] = {0.5, 0.8, 1.0, 1.3, 0.3};
  for (int k = 0; k < 5; ++k) {
    Soup c = jitteredSphere(2, 0.35, 11 + k);
    for (Point& p : c.pos) p = add(mul(p, radius[k]), Point{3.0 * k, 0.5 * (k % 2), -0.25 * k});
    append(s, c);
  }
  ZooMesh z = start("many_components", "five disjoint spheres, a tetrahedron and a lone triangle", s);
  Soup tet;
  tet.pos = {{0, 0, 5}, {1, 0, 5}, {0, 1, 5}, {0, 0, 6}};
  tet.tri = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  append(z.soup, tet);
  Soup lone;
  lone.pos = {{5, 5, 5}, {6, 5, 5}, {5, 6, 5.5}};
  lone.tri = {{0, 1, 2}};
  append(z.soup, lone);
  z.kind.resize(z.soup.pos.size(), Kind::Interior);
  for (int k = 0; k < 3; ++k) z.kind[z.kind.size() - 1 - k] = Kind::Boundary;
  z.plugin = true;
  return z;
}

ZooMesh scaled(const std::string& name, const std::string& description, double diag) {
  ZooMesh z = start(name, description, scaledToDiagonal(base(), diag));
  return z;
}

/// Pinch + hole + duplicate faces + zero-area + repeated index + an
/// unreferenced vertex, at sites far apart.
ZooMesh combination() {
  int p = -1;
  const Soup s = pinchedPair(kBaseSubdiv, {0, 0, 1}, &p);
  ZooMesh z = start("combination",
                    "pinch + hole + duplicate faces + zero-area face + repeated index + unreferenced vertex", s);
  const Soup one = base();  // the first sphere's counts
  const int nA = static_cast<int>(one.pos.size());
  const int fA = static_cast<int>(one.tri.size());
  z.kind[p] = Kind::NonManifold;
  // Zero-area face on the first sphere.
  const int fz = faceToward(z.soup, {-1, 0, 0}, 0, fA);
  const Point c = centroid(z.soup, fz);
  for (int v : z.soup.tri[fz]) z.soup.pos[v] = c;
  // Duplicate face (same winding) on the first sphere, flipped duplicate on the second.
  const int fd = faceToward(z.soup, {0, 1, 0}, 0, fA);
  z.soup.tri.push_back(z.soup.tri[fd]);
  markFaces(z, {fd}, Kind::NonManifold);
  const int fb = faceToward(z.soup, {1, 0, 2}, fA, 2 * fA);
  Tri t = z.soup.tri[fb];
  std::swap(t[1], t[2]);
  z.soup.tri.push_back(t);
  markFaces(z, {fb}, Kind::NonManifold);
  // Repeated index on the second sphere.
  const int r = vertexToward(z.soup, {-1, 0, 2}, nA);
  const std::vector<int> rs = facesOf(z.soup, r);
  const int r2 = z.soup.tri[rs[0]][0] == r ? z.soup.tri[rs[0]][1] : z.soup.tri[rs[0]][0];
  z.soup.tri.push_back({r, r2, r});
  z.kind[r] = z.kind[r2] = Kind::NonManifold;
  // Unreferenced vertex.
  z.soup.pos.push_back({0, 0, 1});
  z.kind.push_back(Kind::Isolated);
  // Hole in the first sphere, last (it renumbers the vertices after it).
  punchStar(z, {1, 0, -0.2});
  z.plugin = true;
  return z;
}

/// Only zero-area faces over vertices that span a box: collinear triangles
/// (exactly: dyadic coordinates on lines through the origin), and a vertex
/// off the lines that no face uses.
ZooMesh zeroAreaFacesOnly() {
  Soup s;
  for (const Point& d : {Point{1, 0, 0.5}, Point{0, 1, 0.25}, Point{-0.5, 0.5, 1}}) {
    const int b = static_cast<int>(s.pos.size());
    for (double t : {1.0, 2.0, 3.0}) s.pos.push_back(mul(d, t));
    s.tri.push_back({b, b + 1, b + 2});
  }
  s.pos.push_back({0.25, 0.75, -0.5});
  ZooMesh z = start("zero_area_faces_only", "no face has area: three collinear triangles, one lone vertex", s);
  z.kind.assign(s.pos.size(), Kind::Boundary);  // each triangle is alone: an open fan
  z.kind.back() = Kind::Isolated;
  z.plugin = true;
  return z;
}

ZooMesh collapsedToPoint() {
  Soup s = jitteredSphere(2, 0.35, 9);
  for (Point& p : s.pos) p = {0.25, 0.25, 0.25};
  return start("collapsed_to_point", "closed sphere connectivity with every vertex at one point", s);
}

ZooMesh flattened() {
  Soup s = jitteredSphere(2, 0.35, 10);
  for (Point& p : s.pos) p[2] = 0;
  return start("flattened", "closed sphere squashed flat (a doubly covered disc)", s);
}

}  // namespace

// ---------------------------------------------------------------------------

const char* toString(Kind k) {
  switch (k) {
    case Kind::Interior: return "interior";
    case Kind::Boundary: return "boundary";
    case Kind::NonManifold: return "non-manifold";
    case Kind::Isolated: return "isolated";
    case Kind::Deleted: return "deleted";
  }
  return "?";
}

int ZooMesh::count(Kind k) const { return static_cast<int>(std::count(kind.begin(), kind.end(), k)); }

Soup jitteredSphere(int subdiv, double jitter, unsigned seed) {
  sodt::MeshD m;
  vcg::tri::Sphere(m, subdiv);
  vcg::tri::Allocator<sodt::MeshD>::CompactEveryVector(m);
  Soup s = fromMesh(m);
  double mean = 0;
  for (const Tri& t : s.tri) mean += std::sqrt(dot(sub(s.pos[t[0]], s.pos[t[1]]), sub(s.pos[t[0]], s.pos[t[1]])));
  mean /= double(s.tri.size());
  std::mt19937 g(seed);
  for (Point& p : s.pos) {
    Point d{uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1)};
    d = sub(d, mul(p, dot(d, p)));
    p = unit(add(p, mul(d, jitter * mean)));
  }
  return s;
}

double diagonal(const Soup& s) {
  Point lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
  for (std::size_t i = 0; i < s.pos.size(); ++i) {
    if (!s.vertDeleted.empty() && s.vertDeleted[i]) continue;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], s.pos[i][k]);
      hi[k] = std::max(hi[k], s.pos[i][k]);
    }
  }
  return s.pos.empty() ? 0.0 : std::sqrt(dot(sub(hi, lo), sub(hi, lo)));
}

Soup scaledToDiagonal(const Soup& s, double diag) {
  Soup r = s;
  const double f = diag / diagonal(s);
  for (Point& p : r.pos) p = mul(p, f);
  return r;
}

std::vector<char> degenerateFaces(const Soup& s) {
  std::vector<char> d(s.tri.size(), 0);
  for (std::size_t f = 0; f < s.tri.size(); ++f) {
    const Tri& t = s.tri[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      d[f] = 1;
      continue;
    }
    const Point n = cross(sub(s.pos[t[1]], s.pos[t[0]]), sub(s.pos[t[2]], s.pos[t[0]]));
    d[f] = n[0] == 0 && n[1] == 0 && n[2] == 0;
  }
  return d;
}

namespace {

struct Entry {
  const char* name;
  ZooMesh (*make)();
};

/// The generators in zoo order; each returns a mesh whose name is the entry's.
const std::vector<Entry>& registry() {
  static const std::vector<Entry> r = {
      {"clean_sphere", [] { return start("clean_sphere", "control: the clean jittered icosphere", base()); }},
      {"fin_edge", finEdge},
      {"edge_four_faces", edgeFourFaces},
      {"edge_two_spheres", edgeTwoSpheres},
      {"pinch_vertex", pinchVertex},
      {"hole", hole},
      {"deleted_elements", deletedElements},
      {"zero_area_collapsed", zeroAreaCollapsed},
      {"needle_coincident", needleCoincident},
      {"repeated_index", repeatedIndex},
      {"duplicate_face", [] { return duplicateFace(false); }},
      {"duplicate_face_flipped", [] { return duplicateFace(true); }},
      {"unreferenced_vertices", unreferencedVertices},
      {"duplicate_vertices_seam", unweldedSeam},
      {"inconsistent_winding", inconsistentWinding},
      {"nan_coordinate",
       [] { return nonFinite("nan_coordinate", "one vertex with a NaN coordinate", {{17, {0.1, kNaN, 0.2}}}, false); }},
      {"inf_coordinates",
       [] {
         return nonFinite("inf_coordinates", "+inf, -inf and NaN/inf coordinates on three vertices",
                          {{3, {kInf, 0, 0}}, {40, {0, 0, -kInf}}, {100, {kNaN, kInf, 0}}}, false);
       }},
      {"nan_unreferenced", [] { return nonFinite("nan_unreferenced", "a NaN vertex that no face uses", {}, true); }},
      {"empty", emptyMesh},
      {"point_cloud", pointCloud},
      {"single_degenerate_triangle", singleDegenerateTriangle},
      {"polygons", polygons},
      {"many_components", manyComponents},
      {"tiny_scale",
       [] { return scaled("tiny_scale", "the clean sphere scaled to a bounding-box diagonal of 1e-6", 1e-6); }},
      {"huge_scale",
       [] { return scaled("huge_scale", "the clean sphere scaled to a bounding-box diagonal of 1e6", 1e6); }},
      {"combination", combination},
      {"zero_area_faces_only", zeroAreaFacesOnly},
      {"collapsed_to_point", collapsedToPoint},
      {"flattened", flattened},
  };
  return r;
}

}  // namespace

std::vector<std::string> zooNames() {
  std::vector<std::string> n;
  for (const Entry& e : registry()) n.push_back(e.name);
  return n;
}

std::vector<ZooMesh> makeZoo() {
  std::vector<ZooMesh> z;
  for (const Entry& e : registry()) z.push_back(e.make());
  return z;
}

ZooMesh zooMesh(const std::string& name) {
  for (const Entry& e : registry())
    if (name == e.name) {
      ZooMesh z = e.make();
      if (z.name != name) throw std::logic_error("zoo generator '" + name + "' made '" + z.name + "'");
      return z;
    }
  throw std::out_of_range("no zoo mesh named '" + name + "'");
}

// ---------------------------------------------------------------------------
// vcg conversion

template <class M>
void toMesh(const Soup& s, M& m) {
  using C = typename M::CoordType;
  using S = typename M::ScalarType;
  m.Clear();
  if (!s.pos.empty()) vcg::tri::Allocator<M>::AddVertices(m, s.pos.size());
  for (std::size_t i = 0; i < s.pos.size(); ++i) m.vert[i].P() = C(S(s.pos[i][0]), S(s.pos[i][1]), S(s.pos[i][2]));
  if (!s.tri.empty()) vcg::tri::Allocator<M>::AddFaces(m, s.tri.size());
  for (std::size_t f = 0; f < s.tri.size(); ++f)
    for (int j = 0; j < 3; ++j) m.face[f].V(j) = &m.vert[static_cast<std::size_t>(s.tri[f][j])];
  for (std::size_t f = 0; f < s.faceDeleted.size(); ++f)
    if (s.faceDeleted[f]) vcg::tri::Allocator<M>::DeleteFace(m, m.face[f]);
  for (std::size_t i = 0; i < s.vertDeleted.size(); ++i)
    if (s.vertDeleted[i]) vcg::tri::Allocator<M>::DeleteVertex(m, m.vert[i]);
  vcg::tri::UpdateBounding<M>::Box(m);
}

template <class M>
Soup fromMesh(const M& m) {
  Soup s;
  bool anyDeleted = false;
  for (const auto& v : m.vert) {
    s.pos.push_back({double(v.cP()[0]), double(v.cP()[1]), double(v.cP()[2])});
    s.vertDeleted.push_back(v.IsD() ? 1 : 0);
    anyDeleted = anyDeleted || v.IsD();
  }
  for (const auto& f : m.face) {
    s.tri.push_back({int(f.cV(0) - &m.vert[0]), int(f.cV(1) - &m.vert[0]), int(f.cV(2) - &m.vert[0])});
    s.faceDeleted.push_back(f.IsD() ? 1 : 0);
    anyDeleted = anyDeleted || f.IsD();
  }
  if (!anyDeleted) {
    s.vertDeleted.clear();
    s.faceDeleted.clear();
  }
  return s;
}

template void toMesh<sodt::MeshD>(const Soup&, sodt::MeshD&);
template void toMesh<sodt::MeshF>(const Soup&, sodt::MeshF&);
template Soup fromMesh<sodt::MeshD>(const sodt::MeshD&);
template Soup fromMesh<sodt::MeshF>(const sodt::MeshF&);

// ---------------------------------------------------------------------------
// Files

void writeText(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!f) throw std::runtime_error("cannot write " + path);
}

std::string readText(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

namespace {
std::string number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}
}  // namespace

void writePly(const std::string& path, const Soup& s, PlyEncoding enc, bool doubleCoords) {
  std::string out = "ply\nformat ";
  out += enc == PlyEncoding::Ascii ? "ascii 1.0\n" : "binary_little_endian 1.0\n";
  out += "comment sodt defect zoo\n";
  out += "element vertex " + std::to_string(s.pos.size()) + "\n";
  for (const char* c : {"x", "y", "z"}) out += std::string("property ") + (doubleCoords ? "double " : "float ") + c + "\n";
  out += "element face " + std::to_string(s.tri.size()) + "\n";
  out += "property list uchar int vertex_indices\nend_header\n";
  if (enc == PlyEncoding::Ascii) {
    for (const Point& p : s.pos) out += number(p[0]) + " " + number(p[1]) + " " + number(p[2]) + "\n";
    for (const Tri& t : s.tri)
      out += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  } else {
    for (const Point& p : s.pos)
      for (int k = 0; k < 3; ++k) {
        if (doubleCoords) {
          out.append(reinterpret_cast<const char*>(&p[k]), sizeof(double));
        } else {
          const float x = static_cast<float>(p[k]);
          out.append(reinterpret_cast<const char*>(&x), sizeof(float));
        }
      }
    for (const Tri& t : s.tri) {
      out.push_back(char(3));
      for (int k = 0; k < 3; ++k) {
        const std::int32_t i = t[k];
        out.append(reinterpret_cast<const char*>(&i), sizeof i);
      }
    }
  }
  writeText(path, out);
}

void writePlyPolygons(const std::string& path, const Soup& s, const std::vector<std::vector<int>>& polygons) {
  std::string out = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(s.pos.size()) +
                    "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
                    std::to_string(polygons.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Point& p : s.pos) out += number(p[0]) + " " + number(p[1]) + " " + number(p[2]) + "\n";
  for (const auto& P : polygons) {
    out += std::to_string(P.size());
    for (int v : P) out += " " + std::to_string(v);
    out += "\n";
  }
  writeText(path, out);
}

void writeOff(const std::string& path, const Soup& s) {
  std::string out = "OFF\n" + std::to_string(s.pos.size()) + " " + std::to_string(s.tri.size()) + " 0\n";
  for (const Point& p : s.pos) out += number(p[0]) + " " + number(p[1]) + " " + number(p[2]) + "\n";
  for (const Tri& t : s.tri)
    out += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  writeText(path, out);
}

}  // namespace sodt_zoo
