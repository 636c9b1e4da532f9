// SPDX-License-Identifier: GPL-3.0-or-later
// Configuration and run statistics of the S-ODT smoother. Plain data, no vcg
// headers: the plugin, the CLI and the tests all fill SodtParams from here.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>

namespace sodt {

/// Which vertex update a sweep applies.
enum class Algorithm : int {
  Basic = 0,    ///< Algorithm 1: closed-form S-ODT move in the tangent plane
  Feature = 1,  ///< Algorithm 2: corners fixed, creases move along the crease, smooth as Basic
  Denoise = 2,  ///< Algorithm 3: as Feature, on fitted planes and crease lines (removes noise)
  Odt = 3,      ///< reference: Eq. 3 with true areas, minimised numerically in the tangent plane
  Laplacian = 4,  ///< reference: Eq. 3 with S'_k = 1, i.e. the centroid of the one-ring
};

/// Per-vertex class of the normal-tensor analysis (paper Eq. 9-10). The
/// numbers are a documented contract: they are written as vertex quality.
enum class VertexClass : int {
  Smooth = 0,  ///< one dominant normal direction
  Crease = 1,  ///< two normal directions; moves along the crease direction e3
  Corner = 2,  ///< three normal directions; never moves
  Fixed = 3,   ///< border, non-manifold, isolated: never moves, not classified
};

/// What a proposed move must satisfy before it is committed.
enum class Guard : int {
  None = 0,     ///< commit every solved move: the paper taken literally
  Fold = 1,     ///< reject moves that flip or collapse an incident triangle
  Quality = 2,  ///< Fold, and the smallest angle of the vertex's star may not decrease
};

/// Thrown when the input mesh or the parameters cannot be processed.
class InvalidInput : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The mesh sizes (bounding-box diagonal of the vertices of its faces) the
/// smoother and the classification are verified at, with a margin: the same
/// result, scaled, from 1e-40 to 1e50; beyond, powers of edge lengths in
/// the local systems underflow or overflow double precision.
constexpr double kMinMeshSize = 1e-30;
constexpr double kMaxMeshSize = 1e40;

/// Throws InvalidInput when a mesh of size diagonal (> 0) lies outside
/// [kMinMeshSize, kMaxMeshSize]; a mesh of size 0 (one point) is left to the
/// caller.
inline void checkMeshSize(double diagonal) {
  if (diagonal == 0 || (diagonal >= kMinMeshSize && diagonal <= kMaxMeshSize)) return;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", diagonal);
  throw InvalidInput(std::string("the mesh is too ") + (diagonal < kMinMeshSize ? "small" : "large") +
                     ": its bounding-box diagonal is " + buf +
                     ", outside the range sodt works in, 1e-30 to 1e40; scale it into that range first");
}

/// Parameters of one smoothing run. Defaults live here only; the plugin dialog,
/// the CLI help and the table of docs/parameters.md follow SodtParams{}.
struct SodtParams {
  Algorithm algorithm = Algorithm::Basic;
  int iterations = 20;           ///< number of Gauss-Seidel sweeps over all vertices
  Guard guard = Guard::Quality;  ///< safeguard applied to every move
  int maxBacktracks = 4;         ///< halvings of a rejected step before the vertex is kept
  /// When the guard rejects the S-ODT step (or the vertex already sits at
  /// its S-ODT minimiser), try the tangential Laplacian step under the same
  /// guard. Ignored with Guard::None, which reproduces the paper.
  bool laplacianFallback = true;
  bool selectedOnly = false;     ///< move only selected vertices (the others still shape the stars)
  /// Crease sensitivity epsilon of Eq. 10 (> 0): larger finds more creases.
  double epsilon = 2.0;
  /// Corner sensitivity eta of Eq. 10 (> 0): larger finds more corners among the creases.
  double eta = 2.0;
  /// Basic and Feature: after a move, the vertex and the midpoints of its
  /// edges must lie within this distance of the input
  /// surface around it (its one- and two-ring faces in the input mesh; of a
  /// neighbour with more than 32 faces around it, the 32 beside the
  /// vertex), as a
  /// fraction of the bounding-box diagonal (0 disables the check). Keeps
  /// vertices and faces from cutting across creases and bounds the Hausdorff
  /// distance to the input. Not used by Denoise, whose purpose is to leave
  /// the noisy input surface, nor with Guard::None.
  double maxDeviationRel = 0.001;
  /// Flip edges between sweeps (see flips.h): changes the connectivity, so it
  /// is off by default, as in the paper.
  bool flips = false;
  /// Only edges whose two faces' normals differ by less than this are
  /// flipped, in degrees (0..90); creases sharper than it are never flipped.
  double flipMaxDihedralDeg = 20.0;
  /// Return the best state seen (largest minimum angle, then largest 1st
  /// percentile of the per-triangle minimum angle), the input included,
  /// instead of the last one.
  bool keepBest = false;
  /// Stop early once a sweep raises neither the minimum angle nor the 1st
  /// percentile of the per-triangle minimum angle by more than this many
  /// degrees (0 runs every sweep).
  double toleranceDeg = 0.0;
  /// Denoise only: largest displacement of a vertex along its fitted normal in
  /// one sweep, in units of the mesh's mean edge length. Bounds how far the
  /// surface can drift from the input however many sweeps run.
  double maxNormalStepRel = 0.05;
  /// Worker threads for the sweeps (0: all hardware threads). Vertices are
  /// swept colour by colour (no two neighbours share a colour), so the result
  /// is bit-identical for every thread count.
  int threads = 0;

  /// Throws InvalidInput naming the offending parameter.
  void validate() const {
    if (iterations < 0 || iterations > 100000)
      throw InvalidInput("iterations must be in [0, 100000], got " + std::to_string(iterations));
    if (maxBacktracks < 0 || maxBacktracks > 60)
      throw InvalidInput("maxBacktracks must be in [0, 60], got " + std::to_string(maxBacktracks));
    const int g = static_cast<int>(guard);
    if (g < 0 || g > 2) throw InvalidInput("guard must be none, fold or quality");
    const int a = static_cast<int>(algorithm);
    if (a < 0 || a > 4) throw InvalidInput("algorithm must be basic, feature, denoise, odt or laplacian");
    if (!(epsilon > 0) || !(epsilon < 1e6))
      throw InvalidInput("epsilon must be a positive number below 1e6, got " + std::to_string(epsilon));
    if (!(eta > 0) || !(eta < 1e6))
      throw InvalidInput("eta must be a positive number below 1e6, got " + std::to_string(eta));
    if (!(maxDeviationRel >= 0) || !(maxDeviationRel <= 1))
      throw InvalidInput("maxDeviationRel must be in [0, 1], got " + std::to_string(maxDeviationRel));
    if (!(flipMaxDihedralDeg >= 0) || !(flipMaxDihedralDeg <= 90))
      throw InvalidInput("flipMaxDihedralDeg must be in [0, 90], got " + std::to_string(flipMaxDihedralDeg));
    if (!(toleranceDeg >= 0) || !(toleranceDeg <= 180))
      throw InvalidInput("toleranceDeg must be in [0, 180], got " + std::to_string(toleranceDeg));
    if (!(maxNormalStepRel >= 0) || !(maxNormalStepRel <= 10))
      throw InvalidInput("maxNormalStepRel must be in [0, 10], got " + std::to_string(maxNormalStepRel));
    if (threads < 0 || threads > 1024)
      throw InvalidInput("threads must be in [0, 1024] (0: all cores), got " + std::to_string(threads));
  }
};

/// Counters of one run; every vertex visit ends in exactly one of
/// moved / backtracked / fallbackMoves / rejected / failedSolves / unchanged.
struct SodtStats {
  int iterations = 0;          ///< sweeps actually performed
  long long moved = 0;         ///< visits that committed the full step
  long long backtracked = 0;   ///< visits that committed a shortened step
  long long rejected = 0;      ///< visits where every step length was vetoed by the guard
  long long failedSolves = 0;  ///< visits where the 2x2 system was singular or not convex
  long long unchanged = 0;     ///< visits where the solution equalled the current position
  long long fallbackMoves = 0; ///< visits that committed a (possibly shortened) Laplacian fallback step
  int fixedBoundary = 0;       ///< vertices kept fixed because they lie on a border
  int fixedNonManifold = 0;    ///< vertices kept fixed because their star is not a single disc
  int activeVertices = 0;      ///< vertices the sweeps visit
  int smoothVertices = 0;      ///< classified smooth (all of them with Algorithm::Basic)
  int creaseVertices = 0;      ///< classified crease (Feature, Denoise)
  int cornerVertices = 0;      ///< classified corner, kept fixed (Feature, Denoise)
  long long flips = 0;         ///< edges flipped between sweeps
  /// Faces turned over before the run so that each component of the mesh
  /// has one winding (see orientCoherently); they are written back so.
  int reorientedFaces = 0;
  int returnedSweep = -1;      ///< sweeps behind the returned state (keepBest may return an earlier one)
  bool stoppedEarly = false;   ///< a sweep improved the quality by less than toleranceDeg
  bool cancelled = false;      ///< the progress callback asked to stop
  /// Visits (each also counted above, under the outcome it repeats) answered
  /// from the previous one: the vertex did not move at its previous visit and
  /// nothing in its star has moved since, so it would not move now either.
  long long skipped = 0;
  /// Visits solved by the 4-lane kernel (see SweepTuning::simd), skipped ones aside.
  long long laneVisits = 0;
  /// Points the deviation guard checked (a vertex, a centroid or an edge
  /// midpoint of its star): by a distance query to the input, or from the
  /// margin the vertex's previous move left (see SweepTuning::reuseDeviationMargins).
  long long deviationQueries = 0;
  long long deviationReused = 0;
  int threads = 1;             ///< worker threads the sweeps used
  /// Wall-clock seconds of the sweeps themselves (with the flips, quality
  /// measurements and progress callbacks between them), without the set-up
  /// before them and the write-back after.
  double sweepSeconds = 0;
};

inline const char* toString(Guard g) {
  switch (g) {
    case Guard::None: return "none";
    case Guard::Fold: return "fold";
    case Guard::Quality: return "quality";
  }
  return "?";
}

inline const char* toString(Algorithm a) {
  switch (a) {
    case Algorithm::Basic: return "basic";
    case Algorithm::Feature: return "feature";
    case Algorithm::Denoise: return "denoise";
    case Algorithm::Odt: return "odt";
    case Algorithm::Laplacian: return "laplacian";
  }
  return "?";
}

/// Parses "none" | "fold" | "quality"; throws InvalidInput otherwise.
inline Guard guardFromString(const std::string& s) {
  if (s == "none") return Guard::None;
  if (s == "fold") return Guard::Fold;
  if (s == "quality") return Guard::Quality;
  throw InvalidInput("unknown guard '" + s + "' (expected none, fold or quality)");
}

/// Parses "basic" | "feature" | "denoise" | "odt" | "laplacian"; throws InvalidInput otherwise.
inline Algorithm algorithmFromString(const std::string& s) {
  if (s == "basic") return Algorithm::Basic;
  if (s == "feature") return Algorithm::Feature;
  if (s == "denoise") return Algorithm::Denoise;
  if (s == "odt") return Algorithm::Odt;
  if (s == "laplacian") return Algorithm::Laplacian;
  throw InvalidInput("unknown algorithm '" + s + "' (expected basic, feature, denoise, odt or laplacian)");
}

inline const char* toString(VertexClass c) {
  switch (c) {
    case VertexClass::Smooth: return "smooth";
    case VertexClass::Crease: return "crease";
    case VertexClass::Corner: return "corner";
    case VertexClass::Fixed: return "fixed";
  }
  return "?";
}

}  // namespace sodt
