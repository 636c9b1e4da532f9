// SPDX-License-Identifier: GPL-3.0-or-later
// Configuration and run statistics of the S-ODT smoother. Plain data, no vcg
// headers: the plugin, the CLI and the tests all fill SodtParams from here.
#pragma once

#include <stdexcept>
#include <string>

namespace sodt {

/// Which vertex update a sweep applies.
enum class Algorithm : int {
  Basic = 0,  ///< Algorithm 1 of the paper: closed-form S-ODT move in the tangent plane.
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

/// Parameters of one smoothing run. Defaults live here only; the plugin dialog,
/// the CLI help and the README table are derived from SodtParams{}.
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

  /// Throws InvalidInput naming the offending parameter.
  void validate() const {
    if (iterations < 0 || iterations > 100000)
      throw InvalidInput("iterations must be in [0, 100000], got " + std::to_string(iterations));
    if (maxBacktracks < 0 || maxBacktracks > 60)
      throw InvalidInput("maxBacktracks must be in [0, 60], got " + std::to_string(maxBacktracks));
    const int g = static_cast<int>(guard);
    if (g < 0 || g > 2) throw InvalidInput("guard must be none, fold or quality");
    if (static_cast<int>(algorithm) != 0) throw InvalidInput("algorithm must be basic");
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
  bool cancelled = false;      ///< the progress callback asked to stop
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

/// Parses "basic"; throws InvalidInput otherwise.
inline Algorithm algorithmFromString(const std::string& s) {
  if (s == "basic") return Algorithm::Basic;
  throw InvalidInput("unknown algorithm '" + s + "' (expected basic)");
}

}  // namespace sodt
