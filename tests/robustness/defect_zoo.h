// SPDX-License-Identifier: GPL-3.0-or-later
// A zoo of deterministic defective meshes (non-manifold edges and vertices,
// holes, degenerate and duplicate faces, seams, bad winding, NaN, empty...),
// each with the outcome the core, the CLI and the plugin are expected to give.
#pragma once

#include <sodt_io/mesh.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace sodt_zoo {

using Point = std::array<double, 3>;
using Tri = std::array<int, 3>;

/// What the topology of the core (sodt::buildRingTopology) should say about a
/// vertex, derived from how the generator built the defect, not from the core.
enum class Kind : std::uint8_t {
  Interior,     ///< one closed, consistently oriented fan: smoothed
  Boundary,     ///< open fan (hole, seam, fin tip, lone triangle): fixed
  NonManifold,  ///< pinch, edge with > 2 faces, duplicate face, winding flip, repeated index: fixed
  Isolated,     ///< no face: untouched, not counted as fixed
  Deleted,      ///< flagged deleted (core only): untouched
};

const char* toString(Kind k);

/// What the core does with the mesh.
enum class CoreOutcome {
  Smooths,       ///< SodtSmoother::Apply returns; interior vertices may move
  InvalidInput,  ///< Apply throws sodt::InvalidInput naming the count; mesh untouched
  NoOp,          ///< Apply returns without moving anything (no faces)
};

/// A triangle soup with optional deleted flags, independent of any vcg type
/// (vcg meshes hold pointers into themselves and cannot be copied freely).
struct Soup {
  std::vector<Point> pos;
  std::vector<Tri> tri;
  std::vector<char> vertDeleted;  ///< empty, or one flag per vertex
  std::vector<char> faceDeleted;  ///< empty, or one flag per face
};

/// One defective mesh and its documented outcome.
struct ZooMesh {
  std::string name;         ///< identifier: [a-z0-9_], used for file names and test names
  std::string description;  ///< one line for reports
  Soup soup;                ///< the mesh the core sees (for `polygons`: after fan triangulation)
  /// When not empty: the OFF file that stands for this mesh (polygons); the
  /// project's loader must turn it into exactly `soup`.
  std::string offText;
  /// The polygons of offText (vertex indices into soup.pos), for other formats.
  std::vector<std::vector<int>> polygons;
  CoreOutcome core = CoreOutcome::Smooths;
  std::vector<Kind> kind;   ///< expected per vertex in a run (Smooths only)
  /// What buildRingTopology reports of the mesh as it is, when that differs
  /// from kind (empty otherwise): with inconsistent winding, NonManifold
  /// where it changes, which the smoother removes by turning the minority back.
  std::vector<Kind> topologyKind;
  std::string coreError;    ///< substring of the InvalidInput message
  /// The file cannot be written with live-element semantics (deleted flags):
  /// core-only case.
  bool coreOnly = false;
  /// `sodt smooth` exits 1 with this substring in its one stderr line; empty: exits 0.
  std::string cliError;
  /// Part of the subset run through meshlabserver.
  bool plugin = false;

  int count(Kind k) const;
};

/// Names of all zoo meshes, in a fixed order (cheap: generates nothing).
std::vector<std::string> zooNames();
/// All zoo meshes, in zooNames() order. Deterministic (seeded generators).
std::vector<ZooMesh> makeZoo();
/// The zoo mesh with this name (generates only that one). \throw std::out_of_range when there is none.
ZooMesh zooMesh(const std::string& name);

/// The jittered unit icosphere every defect starts from (closed, 10*4^s+2 vertices).
Soup jitteredSphere(int subdiv, double jitter, unsigned seed);
/// Uniformly scales the soup about the origin so its bounding-box diagonal is `diag`.
Soup scaledToDiagonal(const Soup& s, double diag);
/// Bounding-box diagonal of the non-deleted vertices (NaN-free soups only).
double diagonal(const Soup& s);

/// Faces that are degenerate in the soup: a repeated vertex index or exactly zero area.
std::vector<char> degenerateFaces(const Soup& s);

/// Copies a soup into a vcg mesh (deleted flags included; the counts vn/fn follow).
template <class M>
void toMesh(const Soup& s, M& m);
/// Copies a vcg mesh into a soup (vertex and face indices kept, deleted flags too).
template <class M>
Soup fromMesh(const M& m);

/// File writers of their own (not sodt_io: they must be able to write NaN,
/// repeated indices and exact bytes). PLY: little-endian binary or ASCII, with
/// float or double coordinates. OFF: %.17g, "nan"/"inf" for non-finite values.
enum class PlyEncoding { Ascii, BinaryLE };
void writePly(const std::string& path, const Soup& s, PlyEncoding enc, bool doubleCoords);
void writeOff(const std::string& path, const Soup& s);
/// ASCII PLY of the given polygons over the soup's vertices.
void writePlyPolygons(const std::string& path, const Soup& s, const std::vector<std::vector<int>>& polygons);
void writeText(const std::string& path, const std::string& bytes);
std::string readText(const std::string& path);

}  // namespace sodt_zoo
