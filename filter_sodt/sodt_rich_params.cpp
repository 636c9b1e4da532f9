// SPDX-License-Identifier: GPL-3.0-or-later
// RichParameterList <-> sodt::SodtParams for the S-ODT filter; defaults come
// from SodtParams{} so the dialog, the script and the core always agree.
#include "sodt_rich_params.h"

#include <common/filter_parameter/rich_parameter_list.h>
#include <common/meshmodel.h>

#include <QStringList>

namespace {

// Parameter keys. They become script attributes and pymeshlab keyword
// arguments, so they never change once released.
const char* const kAlgorithm = "algorithm";
const char* const kIterations = "iterations";
const char* const kGuard = "guard";
const char* const kMaxBacktracks = "maxBacktracks";
const char* const kLaplacianFallback = "laplacianFallback";
const char* const kSelectedOnly = "selectedOnly";

static_assert(static_cast<int>(sodt::Algorithm::Basic) == 0,
              "algorithmLabels() is indexed by sodt::Algorithm");
static_assert(static_cast<int>(sodt::Guard::None) == 0 && static_cast<int>(sodt::Guard::Fold) == 1 &&
                  static_cast<int>(sodt::Guard::Quality) == 2,
              "guardLabels() is indexed by sodt::Guard");

/// Dialog entries of `algorithm`; entry i is sodt::Algorithm(i).
QStringList algorithmLabels() { return QStringList{"Basic (Algorithm 1)"}; }

/// Dialog entries of `guard`; entry i is sodt::Guard(i).
QStringList guardLabels() { return QStringList{"None (paper, literal)", "Fold", "Quality"}; }

}  // namespace

void appendSodtParams(RichParameterList& list, const MeshModel& m) {
  const sodt::SodtParams d{};
  list.addParam(RichEnum(
      kAlgorithm, static_cast<int>(d.algorithm), algorithmLabels(), "Algorithm",
      "Vertex update rule. Basic (Algorithm 1 of the paper): every interior vertex moves "
      "in its tangent plane to the closed-form minimiser of the suboptimal ODT energy "
      "(Eqs. 5-8), with its one-ring neighbours held fixed."));
  list.addParam(RichInt(
      kIterations, d.iterations, "Iterations",
      "Number of Gauss-Seidel sweeps over all movable vertices (a count, 0 to 100000). "
      "Each sweep visits every vertex once; more sweeps improve the angles further with "
      "diminishing returns. 0 leaves the mesh unchanged."));
  list.addParam(RichEnum(
      kGuard, static_cast<int>(d.guard), guardLabels(), "Guard",
      "Check applied to every proposed move before it is committed. "
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
      "tangent plane) under the same guard. Lifts the minimum angle much further on sliver "
      "meshes and keeps the volume. Ignored when Guard is None."));
  list.addParam(RichBool(
      kSelectedOnly, m.cm.svn > 0 || m.cm.sfn > 0, "Affect only selection",
      "Move only the selected vertices. With a face selection and no vertex selection, the "
      "vertices whose faces are all selected are selected first, so faces outside the "
      "selection keep their shape. Unselected vertices stay fixed but still shape the "
      "one-rings of their selected neighbours."));
}

sodt::SodtParams readSodtParams(const RichParameterList& list) {
  sodt::SodtParams p;
  p.algorithm = static_cast<sodt::Algorithm>(list.getEnum(kAlgorithm));
  p.iterations = list.getInt(kIterations);
  p.guard = static_cast<sodt::Guard>(list.getEnum(kGuard));
  p.maxBacktracks = list.getInt(kMaxBacktracks);
  p.laplacianFallback = list.getBool(kLaplacianFallback);
  p.selectedOnly = list.getBool(kSelectedOnly);
  return p;
}
