// SPDX-License-Identifier: GPL-3.0-or-later
// RichParameterList <-> core parameters for the S-ODT filters; defaults come
// from SodtParams{} so the dialog, the script and the core always agree.
#include "sodt_rich_params.h"

#include "sodt_meshlab_api.h"

#include <QStringList>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

/// A parameter key in the spelling of the API built against (see
/// sodt_meshlab::kSnakeCaseKeys).
constexpr const char* key(const char* lowerCamel, const char* lowerSnake) {
  return sodt_meshlab::kSnakeCaseKeys ? lowerSnake : lowerCamel;
}

// Parameter keys. They become script attributes and Python keyword arguments,
// so they never change once released.
const char* const kAlgorithm = "algorithm";
const char* const kIterations = "iterations";
const char* const kGuard = "guard";
const char* const kMaxBacktracks = key("maxBacktracks", "max_backtracks");
const char* const kLaplacianFallback = key("laplacianFallback", "laplacian_fallback");
const char* const kMaxDeviation = key("maxDeviation", "max_deviation");
const char* const kEpsilon = "epsilon";
const char* const kEta = "eta";
const char* const kMaxNormalStep = key("maxNormalStep", "max_normal_step");
const char* const kFlips = "flips";
const char* const kFlipMaxDihedral = key("flipMaxDihedral", "flip_max_dihedral");
const char* const kKeepBest = key("keepBest", "keep_best");
const char* const kTolerance = "tolerance";
const char* const kThreads = "threads";
const char* const kSelectedOnly = key("selectedOnly", "selected_only");
const char* const kOutputClass = key("outputClass", "output_class");
const char* const kSelectFeatures = key("selectFeatures", "select_features");

/// MeshLab keeps float parameters as float: 0.1 typed in a dialog, a script
/// or Python arrives as 0.100000001. Read back as the shortest decimal with a
/// float's 7 significant digits, the value is the one the user wrote, so the
/// plugin and the command line run with the same parameters.
double typedValue(double storedAsFloat) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.7g", static_cast<double>(static_cast<float>(storedAsFloat)));
  return std::strtod(buf, nullptr);
}

/// "key must be in [lo, hi] (unit), got v", naming the key as the user wrote it.
std::string outOfRange(const char* k, const char* range, double v) {
  return std::string(k) + " must be in " + range + ", got " + std::to_string(v);
}

/// `maxDeviation` is shown in percent of the bbox diagonal; the core takes a fraction.
constexpr double kPercent = 100.0;

static_assert(static_cast<int>(sodt::Algorithm::Basic) == 0 &&
                  static_cast<int>(sodt::Algorithm::Feature) == 1 &&
                  static_cast<int>(sodt::Algorithm::Denoise) == 2 &&
                  static_cast<int>(sodt::Algorithm::Odt) == 3 &&
                  static_cast<int>(sodt::Algorithm::Laplacian) == 4,
              "algorithmLabels() is indexed by sodt::Algorithm");
static_assert(static_cast<int>(sodt::Guard::None) == 0 && static_cast<int>(sodt::Guard::Fold) == 1 &&
                  static_cast<int>(sodt::Guard::Quality) == 2,
              "guardLabels() is indexed by sodt::Guard");

/// Dialog entries of `algorithm`; entry i is sodt::Algorithm(i). With
/// snake_case keys (MeshLab 2021.05+) they are the command line's names, so
/// that Python passes algorithm='feature' as the CLI takes --algorithm feature.
QStringList algorithmLabels() {
  if (sodt_meshlab::kSnakeCaseKeys) {
    QStringList names;
    for (int a = 0; a <= static_cast<int>(sodt::Algorithm::Laplacian); ++a)
      names << sodt::toString(static_cast<sodt::Algorithm>(a));
    return names;
  }
  return QStringList{"Basic (Algorithm 1)", "Feature-preserving (Algorithm 2)",
                     "Feature-preserving denoising (Algorithm 3)", "Reference: numerical ODT (Eq. 3)",
                     "Reference: Laplacian (Eq. 3, S'k = 1)"};
}

/// Dialog entries of `guard`; entry i is sodt::Guard(i) (the CLI's names with
/// snake_case keys, as for algorithmLabels()).
QStringList guardLabels() {
  if (sodt_meshlab::kSnakeCaseKeys) {
    QStringList names;
    for (int g = 0; g <= static_cast<int>(sodt::Guard::Quality); ++g)
      names << sodt::toString(static_cast<sodt::Guard>(g));
    return names;
  }
  return QStringList{"None (paper, literal)", "Fold", "Quality"};
}

// Shared by both filters, so the two dialogs explain the classification alike.
const char* const kEpsilonHelp =
    "Crease sensitivity epsilon of Eq. 10 (dimensionless, greater than 0; the paper uses 2). "
    "A vertex is a crease when epsilon (nu2 - nu3) is the largest of nu1 - nu2, "
    "epsilon (nu2 - nu3) and epsilon eta nu3, where nu1 >= nu2 >= nu3 are the eigenvalues of "
    "its normal tensor. Larger values find more creases: where two flat sides meet (with "
    "equal weight in the tensor), a vertex is a crease when the angle theta between their "
    "normals exceeds acos(epsilon / (epsilon + 2)), i.e. 60 deg for 2, 45 deg for 4.83, 70.5 deg for 1.";
const char* const kEtaHelp =
    "Corner sensitivity eta of Eq. 10 (dimensionless, greater than 0; the paper uses 2). "
    "A vertex is a corner when epsilon eta nu3 is the largest of the three terms: larger "
    "values turn more crease vertices into corners (where three or more sides meet).";

}  // namespace

void appendSodtParams(RichParameterList& list, const MeshModel& m) {
  const sodt::SodtParams d{};
  list.addParam(RichEnum(
      kAlgorithm, static_cast<int>(d.algorithm), algorithmLabels(), "Algorithm",
      "Vertex update rule. Basic (Algorithm 1 of the paper): every interior vertex moves "
      "in its tangent plane to the closed-form minimiser of the suboptimal ODT energy "
      "(Eqs. 5-8), with its one-ring neighbours held fixed. Feature-preserving (Algorithm 2): "
      "the vertices are first classified by their normal tensor (Eqs. 9-10, see epsilon and "
      "eta); corners stay fixed, crease vertices slide along their crease, smooth vertices "
      "move as in Basic. Feature-preserving denoising (Algorithm 3): as Algorithm 2, but "
      "smooth vertices move on a plane fitted to their neighbours (Eqs. 12-13) and crease "
      "vertices on a line fitted along the crease, which removes noise (see Max normal step). "
      "The two reference updates are for comparisons: the 'optimal' ODT of Eq. 3 with true "
      "triangle areas, minimised numerically in the tangent plane (similar quality, slower), "
      "and Laplacian smoothing, the S'k = 1 case of Eq. 3 (moves to the one-ring centroid, "
      "off the tangent plane, so it shrinks the surface)."));
  list.addParam(RichInt(
      kIterations, d.iterations, "Iterations",
      "Number of Gauss-Seidel sweeps over all movable vertices (a count, 0 to 100000). "
      "Each sweep visits every vertex once; more sweeps improve the angles further with "
      "diminishing returns. 0 leaves the mesh unchanged."));
  list.addParam(RichEnum(
      kGuard, static_cast<int>(d.guard), guardLabels(), "Guard",
      "Check applied to every proposed move before it is committed (all algorithms). "
      "None: commit every solved move, exactly as the paper does (on poor input this can "
      "fold triangles). Fold: reject a move that flips or collapses an incident triangle. "
      "Quality: as Fold, and the smallest angle of the vertex's one-ring must not decrease."));
  list.addParam(RichInt(
      kMaxBacktracks, d.maxBacktracks, "Max backtracks",
      "How many times a step vetoed by the guard is halved and checked again before the "
      "vertex is left where it is (a count, 0 to 60; 0 means all or nothing). "
      "Ignored when Guard is None."));
  list.addParam(RichBool(
      kLaplacianFallback, d.laplacianFallback, "Laplacian fallback",
      "When the guard vetoes the S-ODT step (or the vertex already sits at its S-ODT "
      "optimum), try the tangential Laplacian step (the S'_k = 1 case of Eq. 3, in the same "
      "tangent plane, or along the crease for crease vertices) under the same guard. Lifts "
      "the minimum angle much further on sliver meshes. Ignored when Guard is None."));
  list.addParam(RichFloat(
      kMaxDeviation, float(kPercent * d.maxDeviationRel), "Max deviation (% of bbox diagonal)",
      "Deviation guard, in percent of the bounding-box diagonal (0.1 means a thousandth of "
      "it; 0 to 100, 0 disables the check). After a move, the vertex and the centroids and "
      "edge midpoints of its faces must stay within this distance of the input surface "
      "around the vertex; otherwise the step is shortened or rejected like any guard veto. "
      "Keeps faces from cutting across creases and bounds the distance to the input. Used by "
      "Basic and Feature-preserving (Algorithms 1 and 2) with Guard Fold or Quality; ignored "
      "by denoising, whose purpose is to leave the noisy surface, and with Guard None."));
  list.addParam(RichFloat(kEpsilon, float(d.epsilon), "Crease sensitivity (epsilon)",
                          QString(kEpsilonHelp) +
                              " Used by Algorithms 2 and 3 (and by Output class with them); "
                              "ignored by Basic."));
  list.addParam(RichFloat(kEta, float(d.eta), "Corner sensitivity (eta)",
                          QString(kEtaHelp) + " Corners never move. Used by Algorithms 2 and 3; "
                                              "ignored by Basic."));
  list.addParam(RichFloat(
      kMaxNormalStep, float(d.maxNormalStepRel), "Max normal step (x mean edge)",
      "Feature-preserving denoising (Algorithm 3) only: the largest distance a vertex may move "
      "in one sweep along the normal of its fitted plane (smooth vertices) or across its "
      "fitted crease line (crease vertices), as a fraction of the mean edge length (0 to 10; "
      "0.05 = 5%). Bounds how far the surface drifts from the input however many sweeps run; "
      "larger values remove stronger noise. 0 removes no noise."));
  list.addParam(RichBool(
      kFlips, d.flips, "Edge flips",
      "Flip edges between sweeps (off by default, as in the paper). This changes the "
      "connectivity: the vertex and face counts stay, but faces get other vertices. After each "
      "sweep an interior edge is flipped only when its two triangles are nearly coplanar (see "
      "Flip max dihedral) and the smaller angle of the pair grows. A crease edge of Algorithms 2 "
      "and 3 (both ends crease or corner vertices) is never flipped, and no flip creates an edge "
      "that already exists (non-manifold) or folds the pair. With Affect only selection both "
      "faces must be selected or have all their vertices selected. Lifts the minimum angle "
      "further than moving vertices alone. Refused on meshes with per-wedge texture "
      "coordinates, normals or colours, which a flip would scramble."));
  list.addParam(RichFloat(
      kFlipMaxDihedral, float(d.flipMaxDihedralDeg), "Flip max dihedral (deg)",
      "With Edge flips: only edges whose two triangles' normals differ by less than this angle, "
      "in degrees (0 to 90), are flipped, so that flips do not change the shape. Sharper edges "
      "are never flipped."));
  list.addParam(RichBool(
      kKeepBest, d.keepBest, "Keep best",
      "Return the best state seen during the run instead of the last one: the one with the "
      "fewest faces turned against their input orientation, then the largest smallest angle, "
      "then the largest 1st percentile of the per-triangle smallest angle. The input is a "
      "candidate, so the result is never worse than the input by this order."));
  list.addParam(RichFloat(
      kTolerance, float(d.toleranceDeg), "Tolerance (deg)",
      "Stop before Iterations sweeps once a sweep raises neither the smallest angle nor the 1st "
      "percentile of the per-triangle smallest angle by more than this many degrees (0 to 180). "
      "0 runs every sweep."));
  list.addParam(RichInt(
      kThreads, d.threads, "Threads",
      "Worker threads (0: all cores); the result does not depend on it. Number of threads that sweep the vertices (0 to 1024; 0 uses every hardware thread, and a "
      "build without OpenMP always uses one). The vertices are swept colour by colour, never two "
      "neighbours at once, so the result is bit-identical for every thread count: only the run "
      "time changes. The log reports the threads used."));
  list.addParam(RichBool(
      kSelectedOnly, m.cm.svn > 0 || m.cm.sfn > 0, "Affect only selection",
      "Move only the selected vertices. With a face selection and no vertex selection, the "
      "vertices whose faces are all selected are selected first, so faces outside the "
      "selection keep their shape. Unselected vertices stay fixed but still shape the "
      "one-rings of their selected neighbours."));
  list.addParam(RichBool(
      kOutputClass, true, "Output vertex class",
      "After smoothing, write the class of every vertex to its quality (0 smooth, 1 crease, "
      "2 corner, 3 fixed: border or non-manifold) and colour it with a fixed palette (smooth "
      "light grey, crease blue, corner red, fixed yellow). These are the classes the run used: "
      "computed on the input by Algorithms 2 and 3; with Basic every interior vertex is "
      "smooth. Replaces the vertex quality and colour. meshlabserver saves them with -m vq vc."));
}

sodt::SodtParams readSodtParams(const RichParameterList& list) {
  sodt::SodtParams p;
  p.algorithm = static_cast<sodt::Algorithm>(list.getEnum(kAlgorithm));
  p.iterations = list.getInt(kIterations);
  p.guard = static_cast<sodt::Guard>(list.getEnum(kGuard));
  p.maxBacktracks = list.getInt(kMaxBacktracks);
  if (p.maxBacktracks < 0 || p.maxBacktracks > 60)
    throw sodt::InvalidInput(outOfRange(kMaxBacktracks, "[0, 60]", p.maxBacktracks));
  p.laplacianFallback = list.getBool(kLaplacianFallback);
  const double maxDeviation = typedValue(list.getFloat(kMaxDeviation));
  if (!(maxDeviation >= 0 && maxDeviation <= kPercent))
    throw sodt::InvalidInput(outOfRange(kMaxDeviation, "[0, 100] (percent of the bounding-box diagonal)",
                                        maxDeviation));
  p.maxDeviationRel = maxDeviation / kPercent;
  p.epsilon = typedValue(list.getFloat(kEpsilon));
  p.eta = typedValue(list.getFloat(kEta));
  p.maxNormalStepRel = typedValue(list.getFloat(kMaxNormalStep));
  if (!(p.maxNormalStepRel >= 0 && p.maxNormalStepRel <= 10))
    throw sodt::InvalidInput(outOfRange(kMaxNormalStep, "[0, 10] (mean edge lengths)", p.maxNormalStepRel));
  p.flips = list.getBool(kFlips);
  // Range-checked here so that the message names the dialog's keys (the core
  // names its fields flipMaxDihedralDeg and toleranceDeg).
  const double flipMaxDihedral = typedValue(list.getFloat(kFlipMaxDihedral));
  if (!(flipMaxDihedral >= 0 && flipMaxDihedral <= 90))
    throw sodt::InvalidInput(outOfRange(kFlipMaxDihedral, "[0, 90] (degrees)", flipMaxDihedral));
  p.flipMaxDihedralDeg = flipMaxDihedral;
  p.keepBest = list.getBool(kKeepBest);
  const double tolerance = typedValue(list.getFloat(kTolerance));
  if (!(tolerance >= 0 && tolerance <= 180))
    throw sodt::InvalidInput(outOfRange(kTolerance, "[0, 180] (degrees)", tolerance));
  p.toleranceDeg = tolerance;
  p.threads = list.getInt(kThreads);
  p.selectedOnly = list.getBool(kSelectedOnly);
  return p;
}

bool readOutputClass(const RichParameterList& list) { return list.getBool(kOutputClass); }

void appendClassifyParams(RichParameterList& list) {
  const SodtClassifyParams d{};
  list.addParam(RichFloat(kEpsilon, float(d.epsilon), "Crease sensitivity (epsilon)", kEpsilonHelp));
  list.addParam(RichFloat(kEta, float(d.eta), "Corner sensitivity (eta)", kEtaHelp));
  list.addParam(RichBool(
      kSelectFeatures, d.selectFeatures, "Select feature vertices",
      "Select exactly the crease and corner vertices and clear the selection of every other "
      "vertex (the face selection is left alone). Handy for inspecting the features or for "
      "protecting them from filters that have an 'Affect only selection' option."));
}

SodtClassifyParams readClassifyParams(const RichParameterList& list) {
  SodtClassifyParams c;
  c.epsilon = typedValue(list.getFloat(kEpsilon));
  c.eta = typedValue(list.getFloat(kEta));
  c.selectFeatures = list.getBool(kSelectFeatures);
  return c;
}
