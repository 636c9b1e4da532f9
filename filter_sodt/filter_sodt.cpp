// SPDX-License-Identifier: GPL-3.0-or-later
// MeshLab 2020.09 filters "S-ODT Smoothing" and "S-ODT: Classify Feature Vertices":
// translate the dialog/script values, call the core on CMeshO, log the results.
#include "filter_sodt.h"

#include "sodt_rich_params.h"

#include <sodt/classify.h>
#include <sodt/metrics.h>
#include <sodt/output.h>
#include <sodt/params.h>
#include <sodt/smoother.h>

#include <vcg/complex/algorithms/update/flag.h>
#include <vcg/complex/algorithms/update/selection.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <exception>
#include <string>
#include <thread>
#include <vector>

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

/// "smooth 0 light grey (200, 200, 200), ..." as HTML list items, from the
/// core's palette so that the help cannot drift from the colours written.
QString classTableHtml() {
  struct Row {
    sodt::VertexClass c;
    const char* colourName;
    const char* meaning;
  };
  const Row rows[] = {
      {sodt::VertexClass::Smooth, "light grey", "one dominant normal direction; moves in its tangent plane"},
      {sodt::VertexClass::Crease, "blue", "two normal directions (a sharp edge); moves along the crease"},
      {sodt::VertexClass::Corner, "red", "three normal directions (where creases meet); never moves"},
      {sodt::VertexClass::Fixed, "yellow",
       "on a border, non-manifold or isolated; not classified, never moves"},
  };
  QString html = "<ul>";
  for (const Row& r : rows) {
    const vcg::Color4b col = sodt::classColor(r.c);
    html += QString("<li><b>%1</b> %2: %3 RGB (%4, %5, %6), %7</li>")
                .arg(static_cast<int>(r.c))
                .arg(sodt::toString(r.c))
                .arg(r.colourName)
                .arg(int(col[0]))
                .arg(int(col[1]))
                .arg(int(col[2]))
                .arg(r.meaning);
  }
  return html + "</ul>";
}

/// The paper reference in the format of ML20/src/common/interfaces.h.
const char* const kCitation =
    "See: <br>"
    "<i>Zhanheng Gao, Zeyun Yu, Michael Holst</i><br>"
    "<b>\"Feature-Preserving Surface Mesh Smoothing via Suboptimal Delaunay "
    "Triangulation\"</b><br>"
    "Graphical Models 75 (2013) 23-38, doi:10.1016/j.gmod.2012.10.007<br>";

/// One log line with the number of vertices per class.
std::string classCounts(const sodt::Classification& c) {
  return strFormat("%d smooth, %d crease, %d corner, %d fixed (border, non-manifold or isolated)",
                   c.smooth(), c.crease(), c.corner(), c.fixed());
}

}  // namespace

FilterSodtPlugin::FilterSodtPlugin() {
  typeList << FP_SODT_SMOOTH << FP_SODT_CLASSIFY;
  for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString FilterSodtPlugin::pluginName() const { return "FilterSodt"; }

QString FilterSodtPlugin::filterName(FilterIDType filter) const {
  switch (filter) {
    case FP_SODT_SMOOTH: return "S-ODT Smoothing";
    case FP_SODT_CLASSIFY: return "S-ODT: Classify Feature Vertices";
  }
  return QString();
}

QString FilterSodtPlugin::filterInfo(FilterIDType filter) const {
  switch (filter) {
    case FP_SODT_SMOOTH:
      return QString(
                 "Improves the angles of a triangle mesh by moving every interior vertex to the "
                 "minimiser of the suboptimal Delaunay triangulation (S-ODT) energy of its "
                 "one-ring (Eq. 5 of the paper). Boundary and non-manifold vertices stay fixed. "
                 "The connectivity changes only with <i>Edge flips</i>, which is off by default, "
                 "as in the paper.<br>"
                 "<br>"
                 "<b>Algorithm</b>. <i>Basic (Algorithm 1)</i>: each vertex moves in its tangent "
                 "plane to the closed-form minimiser (Eqs. 5-8). This keeps the shape and, up to "
                 "floating-point rounding, the enclosed volume of a closed mesh (Appendix D), but "
                 "it slowly rounds off sharp edges. <i>Feature-preserving (Algorithm 2)</i>: every "
                 "vertex is first classified, once, by the eigenvalues of its normal tensor "
                 "(Eqs. 9-10; <i>epsilon</i> and <i>eta</i>, explained in <i>S-ODT: Classify "
                 "Feature Vertices</i>). Corners stay fixed, crease vertices move only along the "
                 "crease direction e3 to the minimiser of the energy on that line (Eq. 11), smooth "
                 "vertices move as in Basic. <i>Feature-preserving denoising (Algorithm 3)</i>: "
                 "vertices are classified as in Algorithm 2, on a copy of the input whose vertices "
                 "are projected on their fitted planes (so that noise does not fake creases). "
                 "Smooth vertices then move on a weighted least-squares plane fitted to their "
                 "neighbours (Eqs. 12-13), crease vertices on a line fitted to the crease vertices "
                 "around them, corners stay fixed: noise is removed while the features stay "
                 "sharp. Per sweep a vertex moves at most <i>Max normal step</i> mean edge lengths "
                 "off its fitted plane or line direction.<br>"
                 "<br>"
                 "<b>Guard</b> decides what a proposed move must satisfy before it is committed. "
                 "<i>None (paper, literal)</i> commits every move and reproduces the paper's "
                 "algorithms literally; on poor input it can fold triangles. <i>Fold</i> rejects a "
                 "move that flips or collapses an incident triangle, and <i>Quality</i> also "
                 "requires that the smallest angle of the one-ring does not decrease. A vetoed "
                 "step is halved up to <i>Max backtracks</i> times; then the tangential Laplacian "
                 "step is tried under the same guard (<i>Laplacian fallback</i>) before the vertex "
                 "is left in place.<br>"
                 "<br>"
                 "<b>Deviation guard</b> (Basic and Feature-preserving with guard Fold or "
                 "Quality): a move is also vetoed when the vertex, or the midpoint of one of its "
                 "edges, would end up farther than <i>Max deviation</i> (percent of "
                 "the bounding-box diagonal, 0 disables it) from the input surface around the "
                 "vertex (its one- and two-ring faces in the input). This stops faces from cutting "
                 "across creases and bounds the distance to the input. Denoising does not use it, "
                 "since it has to leave the noisy surface.<br>"
                 "<br>"
                 "<b>Edge flips</b> (an extension, not in the paper): after each sweep, an "
                 "interior edge whose two triangles' normals differ by less than <i>Flip max "
                 "dihedral</i> is flipped when that raises the smaller angle of the pair. Crease "
                 "edges of Algorithms 2 and 3 (both ends crease or corner vertices) are never "
                 "flipped, and no flip creates an existing edge (non-manifold) or a fold. The "
                 "vertex and face counts stay the same, but faces get other vertices. Per-face "
                 "colour, quality and selection stay with the face index. Meshes with per-wedge "
                 "attributes or polygonal faces are refused.<br>"
                 "<br>"
                 "<b>Keep best</b> returns the best state seen instead of the last one: the largest "
                 "smallest angle, then the largest 1st percentile of the per-triangle smallest "
                 "angle, the input included. <b>Tolerance</b> (degrees, 0 = off) stops the run "
                 "once a sweep raises neither of the two by more than the tolerance.<br>"
                 "<br>"
                 "<b>Worker threads</b> (0 = all cores) only change the run time: the vertices are swept "
                 "colour by colour, never two neighbours at once, so the result is bit-identical for "
                 "every thread count.<br>"
                 "<br>"
                 "<b>Output vertex class</b> writes the class each vertex had in the run to its "
                 "quality and colour (with Basic every interior vertex is smooth):") +
             classTableHtml() +
             "The log reports the smallest and largest angle and the fraction of angles below "
             "30&deg; before and after, the enclosed volume of a closed mesh, the vertices per "
             "class, how many vertex visits moved, were shortened, rejected or had a "
             "singular local system, the threads used, the number of edge flips, which sweep's "
             "state was returned and whether the run stopped early.<br>"
             "<br>"
             "<b>Erratum</b>: for the crease step x0 + d e3 the paper prints d* = -B/(2A) "
             "(Eq. 11 and Algorithms 2-3). Along e3 the energy of Eq. 5 is A d<sup>2</sup> - B d "
             "+ const with A and B as printed in Eq. 11 (consistent with the plane system of "
             "Eq. 7), so its minimiser is d* = +B/(2A); the printed sign would move crease "
             "vertices to the mirror image of the minimiser. This filter uses +B/(2A), which "
             "matches a brute-force minimisation of the energy along the crease.<br>"
             "<br>" +
             kCitation;
    case FP_SODT_CLASSIFY:
      return QString(
                 "Classifies every vertex as smooth, crease or corner by the eigenvalues nu1 "
                 "&ge; nu2 &ge; nu3 of the normal tensor T = &sum; w<sub>k</sub> n<sub>k</sub> "
                 "n<sub>k</sub><sup>T</sup> of its one-ring (Eq. 9; w<sub>k</sub> weighs the "
                 "triangle areas and the distances of their barycentres), exactly as the "
                 "feature-preserving algorithms of <i>S-ODT Smoothing</i> do (Eq. 10): the class "
                 "is the largest of nu1 - nu2 (smooth), epsilon (nu2 - nu3) (crease) and "
                 "epsilon eta nu3 (corner). The vertices never move. The class code is written to "
                 "the vertex quality and the class colour, from a fixed palette, to the vertex "
                 "colour:") +
             classTableHtml() +
             "With <i>Select feature vertices</i> exactly the crease and corner vertices end up "
             "selected. The log reports the number of vertices per class.<br>"
             "<br>"
             "<b>Tuning</b>. <i>epsilon</i> (crease sensitivity, paper: 2): larger values find "
             "more creases. Where two flat sides meet at an angle theta between their normals "
             "(and weigh equally in the tensor), a vertex is a crease when theta &gt; "
             "acos(epsilon / (epsilon + 2)): 60&deg; for epsilon = 2, 45&deg; for 4.83, "
             "70.5&deg; for 1. <i>eta</i> (corner sensitivity, "
             "paper: 2): larger values turn more crease vertices into corners. Noise makes "
             "smooth vertices look like creases or corners; the denoising algorithm classifies "
             "a denoised copy instead, so on noisy meshes this filter shows more features than "
             "that algorithm uses.<br>"
             "<br>" +
             kCitation;
  }
  return QString();
}

MeshFilterInterface::FilterClass FilterSodtPlugin::getClass(QAction* a) {
  // Both filters are listed under Smoothing only. A VertexColoring bit would
  // also list them under Color Creation, but the class is fixed per filter:
  // for the smoothing filter it would make the GUI switch to vertex colours
  // even with outputClass off, and the classification filter declares its
  // colours through postCondition and updateDataMask already.
  switch (ID(a)) {
    case FP_SODT_SMOOTH: return MeshFilterInterface::Smoothing;
    case FP_SODT_CLASSIFY: return MeshFilterInterface::Smoothing;
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
      // selection is converted for "Affect only selection"; quality and
      // colour with "Output vertex class"; the face-vertex references and the
      // adjacency with "Edge flips". MM_FACEVERT and the topology bits make the
      // GUI rebuild the rendering buffers as for a new connectivity
      // (MainWindow::updateSharedContextDataAfterFilterExecution).
      //
      // MM_FACENUMBER although the face count never changes: it turns off the
      // dialog's Preview (MeshlabStdDialog::isPreviewable), as MeshLab's own
      // connectivity-changing filters do (MM_GEOMETRY_AND_TOPOLOGY_CHANGE,
      // MM_ALL for its edge-flip filters). The preview's undo, MeshModelState,
      // restores coordinates, normals, colours, quality and selection but not
      // the faces' vertex references, so a previewed run with flips would
      // leave the flipped faces on the restored positions (where they may
      // fold) and the next preview or Apply would start from them.
      return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL |
             MeshModel::MM_VERTFLAGSELECT | MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR |
             MeshModel::MM_FACEVERT | MeshModel::MM_VERTFACETOPO | MeshModel::MM_FACEFACETOPO |
             MeshModel::MM_FACENUMBER;
    case FP_SODT_CLASSIFY:
      return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTFLAGSELECT;
  }
  return MeshModel::MM_NONE;
}

void FilterSodtPlugin::initParameterSet(QAction* a, MeshModel& m, RichParameterList& par) {
  switch (ID(a)) {
    case FP_SODT_SMOOTH: appendSodtParams(par, m); break;
    case FP_SODT_CLASSIFY: appendClassifyParams(par); break;
  }
}

bool FilterSodtPlugin::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                                   vcg::CallBackPos* cb) {
  errorMessage.clear();
  switch (ID(a)) {
    case FP_SODT_SMOOTH: return applySmooth(md, par, cb);
    case FP_SODT_CLASSIFY: return applyClassify(md, par);
  }
  return fail("S-ODT: unknown filter '" + a->text() + "'");
}

bool FilterSodtPlugin::fail(const QString& why) {
  errorMessage = why;
  Log(GLLogStream::WARNING, why.toStdString());
  return false;
}

bool FilterSodtPlugin::applySmooth(MeshDocument& md, const RichParameterList& par,
                                   vcg::CallBackPos* cb) {
  MeshModel* mm = md.mm();
  if (mm == nullptr) return fail("S-ODT Smoothing: there is no current mesh.");
  CMeshO& m = mm->cm;
  bool selectionConverted = false;

  // MeshLab 2020.09 catches only std::bad_alloc around applyFilter, so any
  // exception that escapes from here would crash the application.
  try {
    // Everything that can be rejected is checked before the mesh is touched.
    const sodt::SodtParams p = readSodtParams(par);
    const bool outputClass = readOutputClass(par);
    p.validate();
    if (m.fn == 0)
      return fail("S-ODT Smoothing needs a triangle mesh, but the current mesh has no faces.");
    if (p.flips) {
      // A flip rewires two faces' vertex references; the core knows nothing
      // of per-wedge data or of the faux edges that describe polygons.
      if (mm->hasDataMask(MeshModel::MM_WEDGTEXCOORD | MeshModel::MM_WEDGNORMAL | MeshModel::MM_WEDGCOLOR))
        return fail("S-ODT Smoothing: flips would scramble the per-wedge texture coordinates, normals or "
                    "colours of this mesh. Turn 'Edge flips' off, or remove the wedge attributes first.");
      if (mm->hasDataMask(MeshModel::MM_POLYGONAL))
        return fail("S-ODT Smoothing: flips would break the polygonal faces of this mesh. Turn 'Edge flips' "
                    "off, or make it a pure triangle mesh first (filter 'Turn into a Pure-Triangular mesh').");
    }

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

    // The measures do not depend on the number of threads either.
    const int measureThreads =
        p.threads > 0 ? p.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const sodt::AngleStats before = sodt::computeAngleStats(m, measureThreads);
    const sodt::VolumeResult volBefore = sodt::enclosedVolume(m, measureThreads);

    // The faces' vertex references, to tell whether the returned state has
    // other faces (keepBest may return a state from before the flips).
    std::vector<const CVertexO*> faceVertsBefore;
    if (p.flips)
      for (const CFaceO& f : m.face)
        for (int j = 0; j < 3; ++j) faceVertsBefore.push_back(f.IsD() ? nullptr : f.cV(j));

    sodt::Classification classes;
    const sodt::SodtStats s = sodt::SodtSmoother<CMeshO>::Apply(m, p, cb, &classes);
    long long facesChanged = 0;
    if (p.flips)
      for (size_t f = 0; f < m.face.size(); ++f)
        for (int j = 0; j < 3; ++j)
          if (!m.face[f].IsD() && m.face[f].cV(j) != faceVertsBefore[3 * f + size_t(j)]) {
            ++facesChanged;
            break;
          }
    // Flips move edges between face slots: per-face-edge border flags set
    // before the run would now describe other edges. (The core has already
    // rebuilt FF and VF adjacency where they are enabled.)
    if (s.flips > 0) vcg::tri::UpdateFlags<CMeshO>::FaceBorderFromNone(m);
    mm->UpdateBoxAndNormals();
    if (outputClass) {
      // Without the mask the GUI neither shows nor saves the colours (and
      // quality); both components always exist in CMeshO.
      mm->updateDataMask(MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR);
      sodt::writeClassToQuality(m, classes);
      sodt::colorizeByClass(m, classes);
    }

    const sodt::AngleStats after = sodt::computeAngleStats(m, s.threads);
    Log(strFormat("S-ODT: algorithm %s, guard %s, %d iterations, max backtracks %d, "
                  "Laplacian fallback %s, selected only %s",
                  sodt::toString(p.algorithm), sodt::toString(p.guard), p.iterations,
                  p.maxBacktracks, yesNo(p.laplacianFallback), yesNo(p.selectedOnly)));
    if (p.algorithm != sodt::Algorithm::Basic)
      Log(strFormat("S-ODT: epsilon %g, eta %g", p.epsilon, p.eta));
    if (p.algorithm == sodt::Algorithm::Denoise)
      Log(strFormat("S-ODT: max normal step %g x mean edge length", p.maxNormalStepRel));
    else if (p.guard != sodt::Guard::None && p.maxDeviationRel > 0)
      Log(strFormat("S-ODT: deviation guard %g%% of the bounding-box diagonal",
                    100.0 * p.maxDeviationRel));
    Log(strFormat("S-ODT: min angle %.4f -> %.4f deg, max angle %.4f -> %.4f deg, "
                  "angles below 30 deg %.3f%% -> %.3f%%",
                  before.minDeg, after.minDeg, before.maxDeg, after.maxDeg,
                  100.0 * before.fracBelow30, 100.0 * after.fracBelow30));
    if (volBefore.closed) {
      const sodt::VolumeResult volAfter = sodt::enclosedVolume(m, s.threads);
      const double rel = volBefore.volume != 0.0
                             ? (volAfter.volume - volBefore.volume) / volBefore.volume
                             : 0.0;
      Log(strFormat("S-ODT: enclosed volume %.9g -> %.9g (relative change %+.2e)",
                    volBefore.volume, volAfter.volume, rel));
    } else {
      Log("S-ODT: the mesh is not closed; enclosed volume not reported");
    }
    Log(strFormat("S-ODT: vertex classes: %s%s", classCounts(classes).c_str(),
                  outputClass ? "; written to vertex quality and colour" : ""));
    Log(strFormat("S-ODT: %d sweeps over %d active vertices with %d thread%s: %lld moved, %lld backtracked, "
                  "%lld Laplacian fallback, %lld rejected, %lld failed solves, %lld unchanged (%lld repeated "
                  "their previous visit: nothing in their star had moved); fixed %d boundary and %d non-manifold "
                  "vertices",
                  s.iterations, s.activeVertices, s.threads, s.threads == 1 ? "" : "s", s.moved, s.backtracked,
                  s.fallbackMoves, s.rejected, s.failedSolves, s.unchanged, s.skipped, s.fixedBoundary,
                  s.fixedNonManifold));
    if (p.flips)
      Log(strFormat("S-ODT: edge flips: %lld (max dihedral %g deg); %s", s.flips, p.flipMaxDihedralDeg,
                    facesChanged > 0
                        ? strFormat("the connectivity changed: %lld faces have other vertices (same vertex "
                                    "and face counts)", facesChanged).c_str()
                        : "the returned state has the input's connectivity"));
    else
      Log("S-ODT: edge flips: off");
    std::string ending;
    if (s.stoppedEarly)
      ending = strFormat("; stopped early: the last sweep raised the min angle and its 1st percentile by at "
                         "most the tolerance %g deg", p.toleranceDeg);
    else if (p.toleranceDeg > 0)
      ending = strFormat("; tolerance %g deg not reached", p.toleranceDeg);
    Log(strFormat("S-ODT: returned the state after sweep %d of %d run (keep best %s)%s", s.returnedSweep,
                  s.iterations, yesNo(p.keepBest), ending.c_str()));
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

bool FilterSodtPlugin::applyClassify(MeshDocument& md, const RichParameterList& par) {
  MeshModel* mm = md.mm();
  if (mm == nullptr) return fail("S-ODT Classify: there is no current mesh.");
  CMeshO& m = mm->cm;
  try {
    const SodtClassifyParams p = readClassifyParams(par);
    p.validate();
    if (m.fn == 0)
      return fail("S-ODT Classify needs a triangle mesh, but the current mesh has no faces.");

    const sodt::Classification c = sodt::classifyVertices(m, p.epsilon, p.eta);
    mm->updateDataMask(MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR);
    sodt::writeClassToQuality(m, c);
    sodt::colorizeByClass(m, c);
    Log(strFormat("S-ODT classify: epsilon %g, eta %g: %s", p.epsilon, p.eta, classCounts(c).c_str()));
    Log("S-ODT classify: class codes written to vertex quality (0 smooth, 1 crease, 2 corner, "
        "3 fixed), class colours to vertex colour");
    if (p.selectFeatures) {
      m.svn = sodt::selectFeatureVertices(m, c);
      Log("S-ODT classify: selected %d feature (crease or corner) vertices", m.svn);
    }
    return true;
  } catch (const std::exception& e) {
    return fail(QString("S-ODT Classify failed: ") + QString::fromUtf8(e.what()));
  } catch (...) {
    return fail("S-ODT Classify failed with an unknown error.");
  }
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterSodtPlugin)
