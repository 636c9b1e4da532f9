// SPDX-License-Identifier: GPL-3.0-or-later
// MeshLab 2020.09 "S-ODT Smoothing" filter: translates the dialog/script values,
// calls sodt::SodtSmoother on CMeshO and logs quality before and after.
#include "filter_sodt.h"

#include "sodt_rich_params.h"

#include <sodt/metrics.h>
#include <sodt/params.h>
#include <sodt/smoother.h>

#include <vcg/complex/algorithms/update/selection.h>

#include <cstdarg>
#include <cstdio>
#include <exception>
#include <string>

namespace {

/// printf into a std::string; the attribute lets the compiler check the
/// arguments, which MeshLab's variadic Log() does not.
__attribute__((format(printf, 1, 2))) std::string strFormat(const char* fmt, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  return std::string(buf);
}

const char* yesNo(bool b) { return b ? "yes" : "no"; }

}  // namespace

FilterSodtPlugin::FilterSodtPlugin() {
  typeList << FP_SODT_SMOOTH;
  for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString FilterSodtPlugin::pluginName() const { return "FilterSodt"; }

QString FilterSodtPlugin::filterName(FilterIDType filter) const {
  switch (filter) {
    case FP_SODT_SMOOTH: return "S-ODT Smoothing";
  }
  return QString();
}

QString FilterSodtPlugin::filterInfo(FilterIDType filter) const {
  switch (filter) {
    case FP_SODT_SMOOTH:
      return "Improves the angles of a triangle mesh by moving every interior vertex to the "
             "minimiser of the suboptimal Delaunay triangulation (S-ODT) energy of its one-ring "
             "(Algorithm 1 of the paper). Each vertex moves only in its tangent plane, which keeps "
             "the shape and, up to floating-point rounding, the enclosed volume of a closed mesh "
             "(paper, Appendix D). The connectivity never changes; boundary and non-manifold "
             "vertices stay fixed.<br>"
             "<br>"
             "<b>Guard</b> decides what a proposed move must satisfy before it is committed. "
             "<i>None (paper, literal)</i> commits every move and reproduces the paper's algorithm "
             "literally; on poor input it can fold triangles. <i>Fold</i> rejects a move that flips "
             "or collapses an incident triangle, and <i>Quality</i> also requires that the smallest "
             "angle of the one-ring does not decrease. A vetoed step is halved up to "
             "<i>Max backtracks</i> times before the vertex is left in place.<br>"
             "<br>"
             "The log reports the smallest and largest angle and the fraction of angles below "
             "30&deg; before and after, the enclosed volume of a closed mesh, and how many vertex "
             "visits moved, were shortened, rejected or had a singular local system.<br>"
             "<br>"
             "See: <br>"
             "<i>Zhanheng Gao, Zeyun Yu, Michael Holst</i><br>"
             "<b>\"Feature-Preserving Surface Mesh Smoothing via Suboptimal Delaunay "
             "Triangulation\"</b><br>"
             "Graphical Models 75 (2013) 23-38, doi:10.1016/j.gmod.2012.10.007<br>";
  }
  return QString();
}

MeshFilterInterface::FilterClass FilterSodtPlugin::getClass(QAction* a) {
  switch (ID(a)) {
    case FP_SODT_SMOOTH: return MeshFilterInterface::Smoothing;
  }
  // MeshLab throws while loading on Generic; every id above has a class.
  return MeshFilterInterface::Smoothing;
}

MeshFilterInterface::FILTER_ARITY FilterSodtPlugin::filterArity(QAction*) const {
  return SINGLE_MESH;
}

int FilterSodtPlugin::getRequirements(QAction*) {
  // The core builds its own one-ring topology from the face list.
  return MeshModel::MM_NONE;
}

int FilterSodtPlugin::getPreConditions(QAction*) const { return MeshModel::MM_FACENUMBER; }

int FilterSodtPlugin::postCondition(QAction* a) const {
  switch (ID(a)) {
    case FP_SODT_SMOOTH:
      // Positions and normals always; the vertex selection when a face
      // selection is converted for "Affect only selection".
      return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL |
             MeshModel::MM_VERTFLAGSELECT;
  }
  return MeshModel::MM_NONE;
}

void FilterSodtPlugin::initParameterSet(QAction* a, MeshModel& m, RichParameterList& par) {
  switch (ID(a)) {
    case FP_SODT_SMOOTH: appendSodtParams(par, m); break;
  }
}

bool FilterSodtPlugin::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                                   vcg::CallBackPos* cb) {
  errorMessage.clear();
  switch (ID(a)) {
    case FP_SODT_SMOOTH: return applySmooth(md, par, cb);
  }
  errorMessage = "S-ODT: unknown filter '" + a->text() + "'";
  return false;
}

bool FilterSodtPlugin::applySmooth(MeshDocument& md, const RichParameterList& par,
                                   vcg::CallBackPos* cb) {
  // meshlabserver prints the filter log but not errorMessage: log the reason too.
  auto fail = [this](const QString& why) {
    errorMessage = why;
    Log(GLLogStream::WARNING, why.toStdString());
    return false;
  };
  MeshModel* mm = md.mm();
  if (mm == nullptr) return fail("S-ODT Smoothing: there is no current mesh.");
  CMeshO& m = mm->cm;
  bool selectionConverted = false;

  // MeshLab 2020.09 catches only std::bad_alloc around applyFilter, so any
  // exception that escapes from here would crash the application.
  try {
    // Everything that can be rejected is checked before the mesh is touched.
    const sodt::SodtParams p = readSodtParams(par);
    p.validate();
    if (m.fn == 0)
      return fail("S-ODT Smoothing needs a triangle mesh, but the current mesh has no faces.");

    if (p.selectedOnly) {
      size_t selected = vcg::tri::UpdateSelection<CMeshO>::VertexCount(m);
      if (selected == 0 && vcg::tri::UpdateSelection<CMeshO>::FaceCount(m) > 0) {
        // Strict: only vertices whose faces are all selected, so that no
        // unselected face changes shape.
        selected = vcg::tri::UpdateSelection<CMeshO>::VertexFromFaceStrict(m);
        m.svn = int(selected);
        selectionConverted = true;
        Log("S-ODT: converted the face selection to %d selected vertices", int(selected));
      }
      if (selected == 0)
        Log(GLLogStream::WARNING,
            "S-ODT: 'Affect only selection' is on but nothing is selected; no vertex will move");
    }

    const sodt::AngleStats before = sodt::computeAngleStats(m);
    const sodt::VolumeResult volBefore = sodt::enclosedVolume(m);

    const sodt::SodtStats s = sodt::SodtSmoother<CMeshO>::Apply(m, p, cb);
    mm->UpdateBoxAndNormals();

    const sodt::AngleStats after = sodt::computeAngleStats(m);
    Log(strFormat("S-ODT: algorithm %s, guard %s, %d iterations, max backtracks %d, "
                  "Laplacian fallback %s, selected only %s",
                  sodt::toString(p.algorithm), sodt::toString(p.guard), p.iterations,
                  p.maxBacktracks, yesNo(p.laplacianFallback), yesNo(p.selectedOnly)));
    Log(strFormat("S-ODT: min angle %.4f -> %.4f deg, max angle %.4f -> %.4f deg, "
                  "angles below 30 deg %.3f%% -> %.3f%%",
                  before.minDeg, after.minDeg, before.maxDeg, after.maxDeg,
                  100.0 * before.fracBelow30, 100.0 * after.fracBelow30));
    if (volBefore.closed) {
      const sodt::VolumeResult volAfter = sodt::enclosedVolume(m);
      const double rel = volBefore.volume != 0.0
                             ? (volAfter.volume - volBefore.volume) / volBefore.volume
                             : 0.0;
      Log(strFormat("S-ODT: enclosed volume %.9g -> %.9g (relative change %+.2e)",
                    volBefore.volume, volAfter.volume, rel));
    } else {
      Log("S-ODT: the mesh is not closed; enclosed volume not reported");
    }
    Log(strFormat("S-ODT: %d sweeps over %d active vertices: %lld moved, %lld backtracked, "
                  "%lld Laplacian fallback, %lld rejected, %lld failed solves, %lld unchanged; "
                  "fixed %d boundary and %d non-manifold vertices",
                  s.iterations, s.activeVertices, s.moved, s.backtracked, s.fallbackMoves,
                  s.rejected, s.failedSolves, s.unchanged, s.fixedBoundary, s.fixedNonManifold));
    if (s.cancelled) Log(GLLogStream::WARNING, "S-ODT: cancelled after %d sweeps", s.iterations);
    return true;
  } catch (const std::exception& e) {
    errorMessage = QString("S-ODT Smoothing failed: ") + QString::fromUtf8(e.what());
  } catch (...) {
    errorMessage = "S-ODT Smoothing failed with an unknown error.";
  }
  // The core throws before it moves anything; undo the selection change too.
  if (selectionConverted) {
    vcg::tri::UpdateSelection<CMeshO>::VertexClear(m);
    m.svn = 0;
  }
  return fail(errorMessage);
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterSodtPlugin)
