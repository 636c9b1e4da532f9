// SPDX-License-Identifier: GPL-3.0-or-later
// Configuration and run statistics of the S-ODT smoother, and the table that
// describes every user-facing parameter once (paramTable()): the CLI, the
// plugin, validate() and the docs' tables are built from it. No vcg headers.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace sodt {

/// Which vertex update a sweep applies.
enum class Algorithm : int {
  Basic = 0,    ///< Algorithm 1: closed-form S-ODT move in the tangent plane
  Feature = 1,  ///< Algorithm 2: corners fixed, creases move along the crease, smooth as Basic
  Denoise = 2,  ///< Algorithm 3: as Feature, on fitted planes and crease lines (removes noise)
  Odt = 3,      ///< reference: Eq. 3 with true areas, minimised numerically in the tangent plane
  Laplacian = 4,  ///< reference: Eq. 3 with S'_k = 1, i.e. the centroid of the one-ring
  /// Denoising: feature-preserving normal filtering or Taubin smoothing,
  /// whichever (and as much as) scores best for the mesh's noise
  /// (filter_select.h), then Algorithm 2 on the denoised surface
  Filtered = 5,
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

/// The name of enumerator e of an enum numbered 0..N-1, from names in that
/// order; "?" for a value outside it.
template <class E, std::size_t N>
const char* enumName(E e, const char* const (&names)[N]) {
  const auto i = static_cast<std::size_t>(e);
  return i < N ? names[i] : "?";
}

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
  /// Deviation guard of every algorithm but Denoise: after a move, the
  /// vertex and the centroids and edge midpoints of its faces must lie within
  /// this distance of the input surface around it (its one- and two-ring
  /// faces in the input mesh; of a neighbour with more than 32 faces around
  /// it, the 32 beside the vertex), as a fraction of the bounding-box
  /// diagonal (0 disables the check). Keeps vertices and faces from cutting
  /// across creases and bounds the Hausdorff distance to the input. For
  /// Filtered the input is the surface its filter made (the input itself
  /// when no filter ran). Not used by Denoise, whose purpose is to leave the
  /// noisy input surface, nor with Guard::None. Shown in percent by the CLI
  /// and the plugin (see paramTable()).
  double maxDeviationRel = 0.001;
  /// Flip edges between sweeps (see flips.h): changes the connectivity, so it
  /// is off by default, as in the paper.
  bool flips = false;
  /// Only edges whose two faces' normals differ by less than this are
  /// flipped, in degrees (0..90); creases sharper than it are never flipped.
  double flipMaxDihedralDeg = 20.0;
  /// Return the best state seen instead of the last one, the input included:
  /// the fewest faces turned by more than 90 degrees against their input
  /// orientation, then the largest minimum angle, then the largest 1st
  /// percentile of the per-triangle minimum angle.
  bool keepBest = false;
  /// Stop early once a sweep raises neither the minimum angle nor the 1st
  /// percentile of the per-triangle minimum angle by more than this many
  /// degrees (0 runs every sweep).
  double toleranceDeg = 0.0;
  /// Denoise only: largest displacement of a vertex along its fitted normal in
  /// one sweep, in units of the mesh's mean edge length. Bounds how far the
  /// surface can drift from the input however many sweeps run.
  double maxNormalStepRel = 0.05;
  /// Worker threads for the sweeps (0: all hardware threads; see
  /// resolveThreads()). Vertices are swept colour by colour (no two
  /// neighbours share a colour), so the result is bit-identical for every
  /// thread count.
  int threads = 0;
  /// Largest angle, in degrees (0..90], between a face's normal and its
  /// input normal that a guarded move or a flip may leave (every guard but
  /// Guard::None; not used by Denoise): faces that turn up to 90 degrees
  /// pile up into edges far sharper than the input's; 90 is the fold test
  /// alone.
  double maxFaceTurnDeg = 40.0;
  /// Local repair after the sweeps (see repair.h): where a triangle's
  /// smallest angle is still below repairAngleDeg, collapse, flip and split
  /// edges and relax the changed neighbourhood. Changes the vertex set, so
  /// it is off by default.
  bool repair = false;
  /// The smallest angle the repair aims for, in degrees: 30, the target
  /// finite-element meshers and minimal-angle remeshers work to (above 25,
  /// in two stages: kRepairFirstStageDeg).
  double repairAngleDeg = 30.0;
  /// The repair adds at most this many vertices, in percent of the input's
  /// vertices (those it removes are not counted).
  double repairBudgetPct = 300.0;
  /// Edges whose faces' normals differ by more than this (degrees) are
  /// features: the repair never flips them, collapses them only along
  /// their line and splits them along themselves, so they stay chains of
  /// edges. Filtered's normal
  /// filter keeps edges this sharp (see normal_filter.h).
  double featureAngleDeg = 30.0;
  /// Filtered: the noise along the normals, as a standard deviation in
  /// mean edge lengths, that scores its filters; 0 estimates it from the
  /// mesh (see filter_select.h and noise_estimate.h).
  double noiseLevelEdges = 0.0;
  /// Border vertices slide along the border (see boundary.h): to the
  /// minimiser of Eq. 5 over their open fan along the border direction,
  /// staying on a curve through the input border, under the same guards. Corners of
  /// the border (a turn above kBoundaryCornerDeg, or more than two border
  /// edges) stay fixed, and so do border vertices with more than
  /// kMaxSlidingFan faces. Off: every border vertex stays fixed, as in the paper.
  bool slideBoundary = false;

  /// Throws InvalidInput naming the offending field when a value lies
  /// outside its range in paramTable().
  void validate() const;
};

/// Why the repair left a triangle below its target (see repair.h).
enum class RepairReason : int {
  /// Tried as it is: its edges are features or end at fixed vertices, or no
  /// change improves it; or its smallest angle lies at a protected corner.
  Pinned = 0,
  Bound = 1,        ///< tried as it is: every change that would improve it leaves the deviation or face-turn bound
  NonManifold = 2,  ///< tried as it is: a change would make the mesh non-manifold, or it lies at a border
  Budget = 3,       ///< the budget of added vertices ran out first
  Rounds = 4,       ///< not tried as it is: the rounds ended first (their limit, or rounds without a better state)
};

/// How many RepairReason values there are.
constexpr int kRepairReasonCount = 5;

inline const char* toString(RepairReason r) {
  static const char* const names[] = {"pinned", "bound", "non-manifold", "budget", "rounds"};
  return enumName(r, names);
}

/// A triangle the repair left below its target: where it is (its
/// centroid), its smallest angle and why.
struct RemainingTriangle {
  double centroid[3];
  double minAngleDeg;
  RepairReason why;
};

/// The smoothing filtered's first stage applied before its sweeps (see
/// filter_select.h).
enum class FilterKind {
  None = 0,      ///< no filter: the input's own positions scored best
  Normals = 1,   ///< rounds of guided bilateral normal filtering
  Taubin = 2,    ///< pairs of lambda|mu umbrella steps (Taubin smoothing)
};

inline const char* toString(FilterKind k) {
  static const char* const names[] = {"none", "normals", "taubin"};
  return enumName(k, names);
}

/// What filtered's first stage chose, and from what: the filter and its
/// length with the smallest estimated mean squared error along the
/// normals, in squared mean edges (Stein's unbiased risk estimate), when
/// that is at most kSureMargin of no filter's (filter_select.h).
struct FilterChoice {
  FilterKind kind = FilterKind::None;
  int steps = 0;                ///< rounds (Normals) or step pairs (Taubin)
  double noiseEdges = 0;        ///< the noise level used, in mean edges (NaN: it could not be estimated)
  bool noiseEstimated = false;  ///< from estimateNoise, not the noiseLevel parameter
  /// The filter and length that scored best without beating no filter by
  /// the margin, so none ran (kind is None); None otherwise.
  FilterKind passedOver = FilterKind::None;
  int passedOverSteps = 0;
  /// Of the choice, or of passedOver when set; NaN when nothing was scored
  /// (the noise level is 0 or unknown).
  double risk = 0;
  double riskNone = 0;          ///< of leaving the input as it is (NaN when nothing was scored)
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
  /// Largest angle, in degrees, between a face's normal in the returned mesh
  /// and its input normal (for a face made by a flip, the mean of the input
  /// normals of the two faces it replaced); faces degenerate either way are
  /// left out.
  double maxFaceTurnDeg = 0;
  /// The repair's changes (SodtParams::repair): edges split, collapsed and
  /// flipped, points inserted inside faces, vertices added and removed,
  /// S-ODT moves of the changed neighbourhoods, and the triangles left
  /// below the target.
  int repairSplits = 0, repairCollapses = 0, repairFlips = 0, repairInserts = 0;
  int verticesAdded = 0, verticesRemoved = 0;
  long long repairMoves = 0;
  /// Faces the repair removed before the sweeps because their corners are
  /// not three distinct vertices (see loadWorkingMesh).
  int collapsedFacesRemoved = 0;
  std::vector<RemainingTriangle> belowTarget;
  /// With slideBoundary: border vertices that slide along the border (also
  /// counted in activeVertices, not in fixedBoundary), those kept fixed as
  /// corners of the border (counted in fixedBoundary), and the sliding ones
  /// that end away from their input position.
  int slidingBoundary = 0;
  int boundaryCorners = 0;
  int movedBoundary = 0;
  /// Algorithm::Filtered: the first stage's choice.
  FilterChoice filter;
  /// Algorithm::Filtered: smooth vertices set back on the denoised
  /// surface's quadrics after the sweeps (surface_restore.h).
  int restoredVertices = 0;
  /// Algorithm::Filtered: the sweeps' deviation bound against the denoised
  /// surface, relative to the diagonal (FilterStage::sweepBound).
  double filteredSweepBoundRel = 0;
  /// The last step of a run with the face-turn bound (facing.h): faces
  /// that faced away from the input under them before it, vertices it put
  /// back towards their input positions, edges it flipped (only in a run
  /// that may flip: flips or repair), and faces still facing away.
  int facingAwayFound = 0;
  int unfoldMoves = 0;
  int unfoldFlips = 0;
  int facingAwayLeft = 0;
};

inline const char* toString(Guard g) {
  static const char* const names[] = {"none", "fold", "quality"};
  return enumName(g, names);
}

inline const char* toString(Algorithm a) {
  static const char* const names[] = {"basic", "feature", "denoise", "odt", "laplacian", "filtered"};
  return enumName(a, names);
}

/// Parses "none" | "fold" | "quality"; throws InvalidInput otherwise.
inline Guard guardFromString(const std::string& s) {
  if (s == "none") return Guard::None;
  if (s == "fold") return Guard::Fold;
  if (s == "quality") return Guard::Quality;
  throw InvalidInput("unknown guard '" + s + "' (expected none, fold or quality)");
}

/// Parses "basic" | "feature" | "denoise" | "odt" | "laplacian" | "filtered"; throws InvalidInput otherwise.
inline Algorithm algorithmFromString(const std::string& s) {
  if (s == "basic") return Algorithm::Basic;
  if (s == "feature") return Algorithm::Feature;
  if (s == "denoise") return Algorithm::Denoise;
  if (s == "odt") return Algorithm::Odt;
  if (s == "laplacian") return Algorithm::Laplacian;
  if (s == "filtered") return Algorithm::Filtered;
  throw InvalidInput("unknown algorithm '" + s + "' (expected basic, feature, denoise, odt, laplacian or filtered)");
}

inline const char* toString(VertexClass c) {
  static const char* const names[] = {"smooth", "crease", "corner", "fixed"};
  return enumName(c, names);
}

// ---------------------------------------------------------------------------
// The parameter table

/// How a parameter is set, from the type of its SodtParams field.
enum class ParamType : int {
  Int,     ///< a count (RichInt; CLI: an integer)
  Real,    ///< a number, shown in ParamSpec::unit (RichFloat)
  Bool,    ///< on or off (RichBool; CLI: a switch, or on|off)
  Choice,  ///< one of ParamSpec::choices (RichEnum; CLI and Python: the choice's name)
};

/// One value of a Choice parameter; its index is the enum's integer value.
struct ParamChoice {
  const char* name;   ///< CLI value, and MeshLab 2025.07 / PyMeshLab entry: "feature"
  const char* label;  ///< MeshLab 2020.09 dialog entry: "Feature-preserving (Algorithm 2)"
  const char* help;   ///< one line
};

/// Bit of an Algorithm in ParamSpec::algorithms.
constexpr unsigned algorithmBit(Algorithm a) { return 1u << static_cast<int>(a); }
constexpr unsigned kEveryAlgorithm = 0x3f;

/// One user-facing parameter of a smoothing run: its names in every front
/// end, type, unit, range and help. The default is the SodtParams{} field's.
/// Built with the setters below, one per aspect, so that an entry reads as
/// what it declares.
struct ParamSpec {
  const char* field = "";      ///< SodtParams member: "maxDeviationRel"
  const char* key = "";        ///< MeshLab 2020.09 key (lowerCamelCase, .mlx scripts): "maxDeviation"
  const char* pythonKey = "";  ///< MeshLab 2025.07 / PyMeshLab key (lower_snake_case): "max_deviation"
  const char* cliOption = "";  ///< `sodt smooth` option: "--max-deviation"
  /// Key in the JSON report of `sodt smooth`: pythonKey when "", none when
  /// nullptr (the report's `threads` are the threads used, not asked for).
  const char* reportKey = "";
  /// Placeholder of the option's value in the CLI help ("N", "PERCENT");
  /// nullptr for a switch (a Bool that is off by default and set by naming it).
  const char* cliValue = nullptr;
  const char* label = "";      ///< dialog label: "Max deviation (% of bbox diagonal)"
  ParamType type = ParamType::Real;
  const char* unit = "";       ///< unit of the shown value; "" for counts and plain numbers
  /// Shown value = scale x field value: 100 for a fraction the front ends
  /// show in percent (the only conversion between them and SodtParams).
  double scale = 1;
  double min = 0, max = 0;     ///< range of the field value (Int, Real)
  bool minOpen = false, maxOpen = false;  ///< the bound itself is excluded
  const char* help = "";       ///< one line: what it does
  const char* details = "";    ///< more, for the CLI help and the dialog tooltip ("" if nothing)
  unsigned algorithms = kEveryAlgorithm;  ///< algorithmBit()s of the algorithms that use it
  /// The plugin's default is on when the mesh has a selection (selectedOnly).
  bool defaultOnWithSelection = false;
  std::vector<ParamChoice> choices;  ///< Choice: entry i is the enum value i
  std::function<double(const SodtParams&)> get;  ///< field value (an enum as its integer)
  std::function<void(SodtParams&, double)> set;  ///< sets the field from such a value

  /// The field, its type, get and set.
  template <class T>
  ParamSpec& bind(const char* name, T SodtParams::*m) {
    field = name;
    type = typeOf(static_cast<T*>(nullptr));
    get = [m](const SodtParams& p) { return toNumber(p.*m); };
    set = [m](SodtParams& p, double v) { p.*m = fromNumber(v, static_cast<T*>(nullptr)); };
    return *this;
  }
  ParamSpec& keys(const char* ml2020, const char* python) { key = ml2020; pythonKey = python; return *this; }
  ParamSpec& cli(const char* option, const char* value) { cliOption = option; cliValue = value; return *this; }
  ParamSpec& dialog(const char* text) { label = text; return *this; }
  ParamSpec& reportAs(const char* k) { reportKey = k; return *this; }
  /// The key in the JSON report.
  const char* reportName() const { return reportKey != nullptr && reportKey[0] == '\0' ? pythonKey : reportKey; }
  ParamSpec& range(double lo, double hi, bool loOpen = false, bool hiOpen = false) {
    min = lo; max = hi; minOpen = loOpen; maxOpen = hiOpen;
    return *this;
  }
  ParamSpec& shownIn(const char* u, double s = 1) { unit = u; scale = s; return *this; }
  ParamSpec& usedBy(unsigned bits) { algorithms = bits; return *this; }
  ParamSpec& describe(const char* line, const char* more = "") { help = line; details = more; return *this; }
  ParamSpec& choose(std::vector<ParamChoice> c) { choices = std::move(c); return *this; }
  ParamSpec& onWithSelectionInPlugin() { defaultOnWithSelection = true; return *this; }

  /// The value the front ends show for a field value (percent for a fraction).
  double shown(double fieldValue) const { return fieldValue * scale; }
  /// The field value of a shown value.
  double fromShown(double shownValue) const { return shownValue / scale; }
  /// p's value as shown.
  double shownValue(const SodtParams& p) const { return shown(get(p)); }
  /// Sets p's field from a shown value (checked beforehand with check()).
  void setShown(SodtParams& p, double shownValue) const { set(p, fromShown(shownValue)); }

  /// Shortest text of a number: "2", "0.05", "1e6".
  static std::string numberText(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    std::string s(buf);
    const std::size_t e = s.find("e+");
    if (e != std::string::npos) {  // "1e+06" -> "1e6"
      std::size_t d = e + 2;
      while (d + 1 < s.size() && s[d] == '0') ++d;
      s = s.substr(0, e + 1) + s.substr(d);
    }
    return s;
  }

  /// A shown value as a user writes it: "20", "0.1", "on", "quality".
  std::string valueText(double shownValue) const {
    switch (type) {
      case ParamType::Bool: return shownValue != 0 ? "on" : "off";
      case ParamType::Choice: {
        const int i = static_cast<int>(shownValue);
        return i >= 0 && i < static_cast<int>(choices.size()) ? choices[i].name : "?";
      }
      default: return numberText(shownValue);
    }
  }
  /// The default (SodtParams{}) as shown.
  std::string defaultText() const { return valueText(shownValue(SodtParams{})); }

  /// The range of the shown value: "[0, 100]", "(0, 1e6)"; "" for Bool and
  /// Choice. With shownUnits false, of the field value.
  std::string rangeText(bool shownUnits = true) const {
    if (type == ParamType::Bool || type == ParamType::Choice) return "";
    const double k = shownUnits ? scale : 1;
    return std::string(minOpen ? "(" : "[") + numberText(min * k) + ", " + numberText(max * k) + (maxOpen ? ")" : "]");
  }
  /// "none, fold or quality".
  std::string choiceList() const {
    std::string s;
    for (std::size_t i = 0; i < choices.size(); ++i)
      s += std::string(i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i].name;
    return s;
  }

  /// Throws InvalidInput "NAME must be ..., got V" unless v lies in the
  /// range: a shown value (shownUnits, the message gives the unit), else a
  /// field value. NAME is how the caller's user spells the parameter.
  void check(double v, const std::string& name, bool shownUnits = true) const {
    const double k = shownUnits ? scale : 1;
    bool ok = true;
    switch (type) {
      case ParamType::Bool: return;
      case ParamType::Choice:
        if (!(v >= 0 && v < static_cast<double>(choices.size()) && v == std::floor(v)))
          throw InvalidInput(name + " must be " + choiceList() + ", got " + numberText(v));
        return;
      case ParamType::Int: ok = v == std::floor(v); break;
      case ParamType::Real: ok = std::isfinite(v); break;
    }
    const double lo = min * k, hi = max * k;
    ok = ok && (minOpen ? v > lo : v >= lo) && (maxOpen ? v < hi : v <= hi);
    if (ok) return;
    std::string what;
    if (minOpen && maxOpen && min == 0)
      what = "a positive number below " + numberText(hi);
    else
      what = "in " + rangeText(shownUnits);
    const std::string u = shownUnits && unit[0] != '\0' ? std::string(" (") + unit + ")" : "";
    throw InvalidInput(name + " must be " + what + u + ", got " + numberText(v));
  }

  /// The choice named s; throws InvalidInput naming the parameter otherwise.
  int choiceIndex(const std::string& s, const std::string& name) const {
    for (std::size_t i = 0; i < choices.size(); ++i)
      if (s == choices[i].name) return static_cast<int>(i);
    throw InvalidInput("unknown " + name + " '" + s + "' (expected " + choiceList() + ")");
  }

 private:
  static ParamType typeOf(int*) { return ParamType::Int; }
  static ParamType typeOf(double*) { return ParamType::Real; }
  static ParamType typeOf(bool*) { return ParamType::Bool; }
  template <class E>
  static ParamType typeOf(E*) {
    static_assert(std::is_enum<E>::value, "a parameter is an int, a double, a bool or an enum");
    return ParamType::Choice;
  }
  template <class T>
  static double toNumber(T v) { return static_cast<double>(static_cast<long long>(v)); }
  static double toNumber(double v) { return v; }
  static int fromNumber(double v, int*) { return static_cast<int>(v); }
  static double fromNumber(double v, double*) { return v; }
  static bool fromNumber(double v, bool*) { return v != 0; }
  template <class E>
  static E fromNumber(double v, E*) { return static_cast<E>(static_cast<int>(v)); }
};

/// The face turn bound of the S-ODT sweeps of Algorithm::Filtered after
/// its normal filter, in degrees from the denoised surface. The filter leaves crumpled triangles
/// along creases at high noise, and the sweeps need to turn them to
/// straighten them: with the 40 degree default of the other algorithms the noise
/// benchmark's fandisk (sigma 0.5 edges) kept a 9 degree angle, and its
/// cube 18 degrees, against 23 and 24 with 85. At 90 (the fold test alone)
/// faces may stand on edge: the shared noisy fandisk then ended with a
/// 3 degree angle.
constexpr double kFilteredFaceTurnDeg = 85.0;  // the text of faceTurnParam() names it
/// The face turn bound of filtered's sweeps after Taubin smoothing (or no
/// filter), whose surface has no crumpled creases to straighten: on the
/// noise benchmark's spot, 85 let the sweeps turn 2-6 faces past 90
/// degrees from the clean surface, 40 none, at the same minimum angles.
constexpr double kSmoothedFaceTurnDeg = 40.0;

/// The face turn bound of filtered's sweeps after the given first stage.
inline double filteredFaceTurnDeg(FilterKind filter) {
  return filter == FilterKind::Normals ? kFilteredFaceTurnDeg : kSmoothedFaceTurnDeg;
}

namespace detail {

/// The sliding border's entry of paramTable().
inline void slideBoundaryParam(ParamSpec& t) {
  t.bind("slideBoundary", &SodtParams::slideBoundary).keys("slideBoundary", "slide_boundary")
      .cli("--slide-boundary", nullptr).dialog("Slide boundary")
      .describe("border vertices of an open mesh slide along the border instead of staying fixed",
                "Each moves to the minimiser of the S-ODT energy of its open fan (Eq. 5) along the "
                "direction between its two border neighbours, the step taken along a smooth curve through "
                "the input border, so that the border keeps its place and nearly its length; under the "
                "same guards as the other vertices. Corners of the border (where it turns by more than 30 degrees, or a "
                "vertex with more than two border edges) stay fixed, and so does a border vertex with more "
                "than 64 faces (the apex of a fan-triangulated polygon). With selected only, only selected "
                "border vertices slide.");
}

/// The face-turn bound's entry of paramTable().
inline void faceTurnParam(ParamSpec& t) {
  t.bind("maxFaceTurnDeg", &SodtParams::maxFaceTurnDeg).keys("maxFaceTurn", "max_face_turn")
      .cli("--max-face-turn", "DEG").dialog("Max face turn (deg)").shownIn("degrees").range(0, 90, true)
      .usedBy(kEveryAlgorithm & ~algorithmBit(Algorithm::Denoise) & ~algorithmBit(Algorithm::Filtered))
      .describe("largest angle between a face's normal and its input normal that a move or a flip may leave",
                "Moves and flips that turn a face further are shortened or rejected like any guard veto, "
                "so that faces do not pile up into edges sharper than the input's; 90 only rejects "
                "folds. Unused by denoise, whose moves turn noisy faces into the surface, by filtered, "
                "whose sweeps have their own bound from the denoised surface (85 degrees after its normal "
                "filter, 40 after Taubin smoothing), and with guard none.");
}

/// The local repair's entries of paramTable().
inline void repairParams(ParamSpec& repair, ParamSpec& angle, ParamSpec& budget, ParamSpec& feature) {
  repair.bind("repair", &SodtParams::repair).keys("repair", "repair").cli("--repair", nullptr)
      .reportAs("repair_enabled").dialog("Local repair")
      .describe("after the sweeps, fix the triangles still below the repair angle with the fewest local "
                "changes: collapse the short edge of a needle, flip or split the long edge of a cap or "
                "sliver, and relax the changed neighbourhood with S-ODT (adds and removes vertices)",
                "Feature edges (see feature angle) and border edges are never flipped, are collapsed "
                "only along their line and are split along themselves; corners stay, border vertices "
                "never move, the mesh stays manifold and oriented, "
                "every change keeps the surface within the deviation bound of the input both ways (at "
                "sample points; where that leaves triangles below the target, a last pass allows 1.25 "
                "times the bound, and 1.5 times at the quarter points of new edges), and "
                "every face it makes or moves within the max face turn of the input face under it. Added "
                "vertices get texture coordinates, colour and quality interpolated along the edge they "
                "split; a mesh with per-wedge attributes is refused. Faces whose corners are not three "
                "distinct vertices are removed before the sweeps. The report lists the triangles left "
                "below the target and why.");
  angle.bind("repairAngleDeg", &SodtParams::repairAngleDeg).keys("repairAngle", "repair_angle")
      .cli("--repair-angle", "DEG").dialog("Repair target angle (deg)").shownIn("degrees").range(0, 50)
      .describe("with repair: the smallest triangle angle the repair works towards",
                "Above 25 degrees it works in two stages: to 25, then from there to the target; the "
                "second stage is kept only where it raised the smallest angle.");
  budget.bind("repairBudgetPct", &SodtParams::repairBudgetPct).keys("repairBudget", "repair_budget")
      .cli("--repair-budget", "PERCENT").dialog("Repair vertex budget (%)").shownIn("percent of the input's vertices")
      .range(0, 10000)
      .describe("with repair: the vertices it may add, in percent of the input's vertices",
                "The repair works on the worst triangles first, so when the budget runs out the smallest "
                "angle is as high as it got and the report lists what is left (0: no change at all). A CAD "
                "export whose flat strips run between feature lines needs this much: hinge (598 vertices) "
                "ends at 12.0 degrees with 100, 18.9 with 200 and 25.1 with 300 (184% more vertices). A "
                "mesh the repair mends with fewer vertices does not use the rest.");
  feature.bind("featureAngleDeg", &SodtParams::featureAngleDeg).keys("featureAngle", "feature_angle")
      .cli("--feature-angle", "DEG").dialog("Feature angle (deg)").shownIn("degrees").range(0, 180)
      .describe("with repair: edges whose two faces' normals differ by more than this are features, kept as "
                "chains of edges; with filtered: the edges the normal filter keeps sharp",
                "With feature, denoise or filtered, edges along a classified crease are features too. With filtered, "
                "the range sigma of the normal filter is the difference of two unit normals half this angle "
                "apart, so that faces on either side of an edge this sharp barely mix; smaller keeps more "
                "edges (and more noise).");
}

}  // namespace detail

/// Every user-facing parameter of a smoothing run, in the order of the
/// plugin's dialog (and of `sodt smooth --help`).
inline const std::vector<ParamSpec>& paramTable() {
  static const std::vector<ParamSpec> table = [] {
    const unsigned feature = algorithmBit(Algorithm::Feature), denoise = algorithmBit(Algorithm::Denoise);
    const unsigned filtered = algorithmBit(Algorithm::Filtered);  // its sweeps are Algorithm 2's
    std::vector<ParamSpec> t(22);
    t[0].bind("algorithm", &SodtParams::algorithm).keys("algorithm", "algorithm").cli("--algorithm", "NAME")
        .dialog("Algorithm")
        .describe("vertex update rule")
        .choose({{toString(Algorithm::Basic), "Basic (Algorithm 1)",
                  "paper Algorithm 1: every interior vertex moves in its tangent plane to the closed-form "
                  "minimiser of the suboptimal ODT energy of its one-ring (Eqs. 5-8); no feature handling"},
                 {toString(Algorithm::Feature), "Feature-preserving (Algorithm 2)",
                  "Algorithm 2: the vertices are classified once, on the input, by their normal tensor "
                  "(Eqs. 9-10, see epsilon and eta); corners stay fixed, crease vertices slide along their "
                  "crease, smooth vertices move as with basic"},
                 {toString(Algorithm::Denoise), "Feature-preserving denoising (Algorithm 3)",
                  "Algorithm 3: removes noise while keeping creases and corners: smooth vertices move on "
                  "planes fitted to their neighbours (Eqs. 12-13), crease vertices on fitted crease lines"},
                 {toString(Algorithm::Odt), "Reference: numerical ODT (Eq. 3)",
                  "reference: the 'optimal' ODT of Eq. 3 with true triangle areas, minimised numerically in "
                  "the tangent plane (similar quality, slower)"},
                 {toString(Algorithm::Laplacian), "Reference: Laplacian (Eq. 3, S'k = 1)",
                  "reference: the one-ring centroid (Eq. 3 with S'k = 1); leaves the tangent plane, so it "
                  "shrinks the surface"},
                 {toString(Algorithm::Filtered), "Denoising: filtered normals, then S-ODT",
                  "denoise: filtered normals or Taubin smoothing, then S-ODT: rounds of a normal filter that "
                  "keeps edges sharper than the feature angle (the vertices follow the filtered normals) and "
                  "steps of Taubin's lambda|mu smoothing are scored by their estimated error for the mesh's "
                  "noise level (see noise level); the best of them, or none, is applied, then "
                  "feature-preserving S-ODT sweeps (Algorithm 2) improve the triangles on the denoised "
                  "surface"}});
    t[1].bind("iterations", &SodtParams::iterations).keys("iterations", "iterations").cli("--iterations", "N")
        .dialog("Iterations").range(0, 100000)
        .describe("Gauss-Seidel sweeps over all movable vertices",
                  "Each sweep visits every vertex once; more sweeps improve the angles further, with "
                  "diminishing returns. 0 leaves the mesh unchanged.");
    t[2].bind("guard", &SodtParams::guard).keys("guard", "guard").cli("--guard", "G").dialog("Guard")
        .describe("check applied to every proposed move before it is committed")
        .choose({{toString(Guard::None), "None (paper, literal)",
                  "commit every solved move, as the paper does (on poor input this can fold triangles)"},
                 {toString(Guard::Fold), "Fold",
                  "reject a move that flips or collapses an incident triangle or turns it by more than max "
                  "face turn from its input orientation"},
                 {toString(Guard::Quality), "Quality",
                  "as fold, and the smallest angle of the vertex's one-ring may not decrease"}});
    t[3].bind("maxBacktracks", &SodtParams::maxBacktracks).keys("maxBacktracks", "max_backtracks")
        .cli("--max-backtracks", "N").dialog("Max backtracks").range(0, 60)
        .describe("halvings of a step vetoed by the guard before the vertex is left where it is",
                  "0 means all or nothing. Unused with guard none.");
    t[4].bind("laplacianFallback", &SodtParams::laplacianFallback).keys("laplacianFallback", "laplacian_fallback")
        .cli("--laplacian-fallback", "on|off").dialog("Laplacian fallback")
        .describe("when the guard vetoes the S-ODT step (or the vertex already sits at its S-ODT optimum), "
                  "try the tangential Laplacian step under the same guard",
                  "That step is the S'k = 1 case of Eq. 3, in the same tangent plane (along the crease for "
                  "crease vertices). It lifts the minimum angle much further on sliver meshes. Unused with "
                  "guard none.");
    t[5].bind("maxDeviationRel", &SodtParams::maxDeviationRel).keys("maxDeviation", "max_deviation")
        .cli("--max-deviation", "PERCENT").reportAs("max_deviation_percent").dialog("Max deviation (% of bbox diagonal)")
        .shownIn("percent of the bounding-box diagonal", 100).range(0, 1)
        .usedBy(kEveryAlgorithm & ~denoise)
        .describe("deviation guard: after a move, the vertex and the centroids and edge midpoints of its "
                  "faces must stay this close to the input surface around the vertex (0 disables it)",
                  "A step that would leave that bound is shortened or rejected like any guard veto. It keeps "
                  "faces from cutting across creases and bounds the distance to the input. The other way, "
                  "the input's vertices, edge midpoints and quarter points and face centroids must stay "
                  "within 1.25 times the bound of the output, so a tip or a sharp rim is not cut off. The surface "
                  "around a vertex is its one- and two-ring faces in the input mesh (of a neighbour with "
                  "more than 32 faces around it, the 32 beside the vertex). With filtered, the input is the "
                  "surface its filter made (the input itself when no filter ran). Unused by denoise, whose "
                  "purpose is to leave the noisy surface, and with guard none.");
    t[6].bind("epsilon", &SodtParams::epsilon).keys("epsilon", "epsilon").cli("--epsilon", "X")
        .dialog("Crease sensitivity (epsilon)").range(0, 1e6, true, true).usedBy(feature | denoise | filtered)
        .describe("crease sensitivity epsilon of Eq. 10: larger finds more creases",
                  "A vertex is a crease when epsilon (nu2 - nu3) is the largest of nu1 - nu2, "
                  "epsilon (nu2 - nu3) and epsilon eta nu3, where nu1 >= nu2 >= nu3 are the eigenvalues "
                  "of its normal tensor. Where two flat sides meet (with equal weight in the tensor), a "
                  "vertex is a crease when the angle between their normals exceeds "
                  "acos(epsilon / (epsilon + 2)): 60 deg for 2 (the paper's value), 45 deg for 4.83, "
                  "70.5 deg for 1.");
    t[7].bind("eta", &SodtParams::eta).keys("eta", "eta").cli("--eta", "X").dialog("Corner sensitivity (eta)")
        .range(0, 1e6, true, true).usedBy(feature | denoise | filtered)
        .describe("corner sensitivity eta of Eq. 10: larger turns more crease vertices into corners",
                  "A vertex is a corner (where three or more sides meet) when epsilon eta nu3 is the "
                  "largest of the three terms of Eq. 10. Corners never move. The paper uses 2.");
    t[8].bind("maxNormalStepRel", &SodtParams::maxNormalStepRel).keys("maxNormalStep", "max_normal_step")
        .cli("--max-normal-step", "X").dialog("Max normal step (x mean edge)")
        .shownIn("mean edge lengths").range(0, 10).usedBy(denoise)
        .describe("largest move of a vertex per sweep along the normal of its fitted plane (smooth vertices) "
                  "or across its fitted crease line (crease vertices)",
                  "Bounds how far the surface drifts from the input however many sweeps run; larger values "
                  "remove stronger noise, 0 removes none.");
    t[9].bind("flips", &SodtParams::flips).keys("flips", "flips").cli("--flips", nullptr).reportAs("flips_enabled")
        .dialog("Edge flips")
        .describe("flip edges between sweeps; this changes the connectivity (the vertex and face counts "
                  "stay), which the paper keeps",
                  "After each sweep an interior edge is flipped only when its two triangles are nearly "
                  "coplanar (see flip max dihedral) and the smaller angle of the pair grows; never a "
                  "crease edge of feature, denoise or filtered (both ends crease or corner vertices and the "
                  "edge within 30 degrees of the crease direction and the nearest to it), never onto an "
                  "existing edge (which would make it non-manifold), never into a fold, and with selected "
                  "only never unless both faces are selected or have all their vertices selected. Lifts "
                  "the minimum angle further than moving vertices alone.");
    t[10].bind("flipMaxDihedralDeg", &SodtParams::flipMaxDihedralDeg).keys("flipMaxDihedral", "flip_max_dihedral")
        .cli("--flip-max-dihedral", "DEG").dialog("Flip max dihedral (deg)").shownIn("degrees").range(0, 90)
        .describe("with flips: only edges whose two faces' normals differ by less than this are flipped",
                  "Sharper edges are never flipped, so that flips do not change the shape.");
    t[11].bind("keepBest", &SodtParams::keepBest).keys("keepBest", "keep_best").cli("--keep-best", nullptr)
        .dialog("Keep best")
        .describe("return the best state seen instead of the last one: the fewest faces turned by more than "
                  "90 degrees against their input orientation, then the largest smallest angle, then the "
                  "largest 1st percentile of the per-triangle smallest angle",
                  "The input is a candidate, so the result is never worse than the input by this order.");
    t[12].bind("toleranceDeg", &SodtParams::toleranceDeg).keys("tolerance", "tolerance").cli("--tolerance", "DEG")
        .dialog("Tolerance (deg)").shownIn("degrees").range(0, 180)
        .describe("stop early once a sweep raises neither the smallest angle nor the 1st percentile of the "
                  "per-triangle smallest angle by more than this (0 runs every sweep)");
    t[13].bind("threads", &SodtParams::threads).keys("threads", "threads").cli("--threads", "N").reportAs(nullptr)
        .dialog("Threads").range(0, 1024)
        .describe("worker threads for the sweeps (0: all hardware threads; a build without OpenMP uses one)",
                  "Vertices are swept colour by colour, never two neighbours at once, so the result is "
                  "bit-identical for every thread count: only the run time changes.");
    t[14].bind("selectedOnly", &SodtParams::selectedOnly).keys("selectedOnly", "selected_only")
        .cli("--selected-only", nullptr).dialog("Affect only selection").onWithSelectionInPlugin()
        .describe("move only the selected vertices (the others stay fixed but still shape their "
                  "neighbours' one-rings)");
    detail::faceTurnParam(t[15]);
    detail::repairParams(t[16], t[17], t[18], t[19]);
    detail::slideBoundaryParam(t[20]);
    t[21].bind("noiseLevelEdges", &SodtParams::noiseLevelEdges).keys("noiseLevel", "noise_level")
        .cli("--noise-level", "X").dialog("Noise level (x mean edge, 0 = estimate)").shownIn("mean edge lengths")
        .range(0, 10).usedBy(filtered)
        .describe("the noise's standard deviation along the normals that filtered removes, or 0 to estimate "
                  "it from the mesh",
                  "Each filter length is scored by its expected squared distance to the unknown clean surface "
                  "for this noise (Stein's unbiased risk estimate) and the best one, or none, is applied. The "
                  "estimate (see sodt stats) reads up to 1.3 times high near sharp edges; a larger level "
                  "smooths more, a smaller one less.");
    return t;
  }();
  return table;
}

/// The entry of a SodtParams field ("maxDeviationRel"); throws
/// std::logic_error for a name the table does not have.
inline const ParamSpec& paramSpec(const char* field) {
  for (const ParamSpec& s : paramTable())
    if (std::strcmp(s.field, field) == 0) return s;
  throw std::logic_error(std::string("no parameter '") + field + "' in sodt::paramTable()");
}

inline void SodtParams::validate() const {
  for (const ParamSpec& s : paramTable()) s.check(s.get(*this), s.field, false);
}

/// The worker threads a run asking for `requested` (SodtParams::threads)
/// uses: all hardware threads for 0, and 1 in a build without OpenMP.
inline int resolveThreads(int requested) {
#ifdef _OPENMP
  if (requested > 0) return requested;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
#else
  (void)requested;
  return 1;
#endif
}

}  // namespace sodt
