// SPDX-License-Identifier: GPL-3.0-or-later
// The S-ODT filters for both MeshLab plugin APIs: help texts, the smoothing
// and classification runs on a MeshModel, their log lines and report.
#include "sodt_filters.h"

#include "sodt_rich_params.h"

#include <sodt/maths/classify.h>
#include <sodt/denoise/filter_select.h>
#include <sodt/denoise/noise_estimate.h>
#include <sodt_io/metrics.h>
#include <sodt/mesh/output.h>
#include <sodt/params.h>
#include <sodt/smoother.h>

#include <vcg/complex/algorithms/update/flag.h>
#include <vcg/complex/algorithms/update/selection.h>

#include <algorithm>
#include <climits>
#include <cstdarg>
#include <cstdio>
#include <string>
#include <vector>

namespace sodt_plugin {
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

/// A table entry's one-line help, as HTML (its "<" and ">" escaped).
QString paramHtml(const char* field) { return QString::fromUtf8(sodt::paramSpec(field).help).toHtmlEscaped(); }

/// A Choice entry's values as an HTML list: "<li><i>basic</i>: help</li>".
QString choicesHtml(const sodt::ParamSpec& s) {
  QString html = "<ul>";
  for (const sodt::ParamChoice& c : s.choices)
    html += QString("<li><i>%1</i>: %2</li>").arg(c.name, QString::fromUtf8(c.help).toHtmlEscaped());
  return html + "</ul>";
}

/// One log line with the number of vertices per class.
std::string classCounts(const sodt::Classification& c) {
  return strFormat("%d smooth, %d crease, %d corner, %d fixed (border, non-manifold or isolated)",
                   c.smooth(), c.crease(), c.corner(), c.fixed());
}

}  // namespace


QString filterName(int id) {
  switch (id) {
    case kSmooth: return "S-ODT Smoothing";
    case kClassify: return "S-ODT: Classify Feature Vertices";
  }
  return QString();
}

QString pythonFilterName(int id) {
  switch (id) {
    case kSmooth: return "apply_coord_sodt_smoothing";
    case kClassify: return "compute_scalar_by_sodt_feature_class_per_vertex";
  }
  return QString();
}

QString filterInfo(int id) {
  switch (id) {
    case kSmooth:
      return QString(
                 "Improves the angles of a triangle mesh by moving every interior vertex, in its "
                 "tangent plane, to the minimiser of the suboptimal Delaunay triangulation (S-ODT) "
                 "energy of its one-ring (Eqs. 5-8 of the paper): the shape and the enclosed volume "
                 "stay. Boundary and non-manifold vertices never move. The connectivity changes only "
                 "with <i>Edge flips</i>, off by default as in the paper.<br><br>"
                 "<b>Algorithm</b>:") +
             choicesHtml(sodt::paramSpec("algorithm")) +
             "<b>Guards</b> (beyond the paper, whose literal update folds triangles on poor input). "
             "<i>Guard</i>, the " + paramHtml("guard") + ":" + choicesHtml(sodt::paramSpec("guard")) +
             "<i>Max deviation</i>, the " + paramHtml("maxDeviationRel") +
             ". No vertex goes farther than its farthest neighbour or leaves the input's bounding box grown "
             "by that bound. A vetoed step is halved (<i>Max backtracks</i>), then the tangential Laplacian "
             "step is tried (<i>Laplacian fallback</i>).<br><br>"
             "<i>Keep best</i>: " + paramHtml("keepBest") + ". The result is the same for any number of "
             "threads. Each parameter's help tells more.<br><br>" +
             QString(
                 "<b>Output vertex class</b> writes the class of every vertex to its quality and "
                 "colour:") +
             classTableHtml() +
             "The log (and, in PyMeshLab, the returned dictionary) reports the angles and the "
             "enclosed volume before and after, the class counts, the move counters and the flips."
             "<br><br>"
             "<b>Erratum</b>: Eq. 11 and Algorithms 2-3 of the paper print the crease step as d* = "
             "-B/(2A); the minimiser of the energy along the crease is d* = +B/(2A), which this "
             "filter uses (the printed sign moves crease vertices uphill).<br><br>" +
             kCitation;
    case kClassify:
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


int postConditionMask(int id) {
  switch (id) {
    case kSmooth:
      // Positions and normals always; the vertex selection when a face
      // selection is converted for "Affect only selection"; quality and
      // colour with "Output vertex class"; the face-vertex references and the
      // adjacency with "Edge flips". MM_FACEVERT and the topology bits make the
      // GUI rebuild the rendering buffers as for a new connectivity.
      //
      // MM_FACENUMBER although the face count never changes: it turns off the
      // dialog's Preview, as MeshLab's own connectivity-changing filters do.
      // The preview's undo restores coordinates, normals, colours, quality
      // and selection but not the faces' vertex references, so a previewed
      // run with flips would leave the flipped faces on the restored
      // positions (where they may fold) and the next preview or Apply would
      // start from them.
      // MM_VERTNUMBER for "Local repair", which adds and removes vertices.
      return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL |
             MeshModel::MM_VERTFLAGSELECT | MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR |
             MeshModel::MM_FACEVERT | MeshModel::MM_VERTFACETOPO | MeshModel::MM_FACEFACETOPO |
             MeshModel::MM_FACENUMBER | MeshModel::MM_VERTNUMBER;
    case kClassify:
      return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR | MeshModel::MM_VERTFLAGSELECT;
  }
  return MeshModel::MM_NONE;
}

QString failureMessage(int id, const char* why) {
  const QString name = id == kClassify ? "S-ODT Classify" : filterName(kSmooth);
  if (why == nullptr) return name + " failed with an unknown error.";
  return name + " failed: " + QString::fromUtf8(why);
}

namespace {

/// The vertices per class, as the report's `smooth`, `crease`, `corner`, `fixed`.
void addClassCounts(Report& r, const sodt::Classification& c) {
  r["smooth"] = c.smooth();
  r["crease"] = c.crease();
  r["corner"] = c.corner();
  r["fixed"] = c.fixed();
}

/// A counter for the report: an int when it fits (Python gets an int), else
/// a double (PyMeshLab converts no 64-bit integer type).
QVariant count(long long n) {
  if (n >= INT_MIN && n <= INT_MAX) return QVariant(static_cast<int>(n));
  return QVariant(static_cast<double>(n));
}

}  // namespace

namespace {

/// What applySmoothing measured and did, for its log and report.
struct SmoothingRun {
  sodt::SodtParams p;
  bool outputClass = false;
  sodt::AngleStats before, after;
  sodt::VolumeResult volBefore, volAfter;
  double volRel = 0;
  sodt::SodtStats s;
  sodt::Classification classes;
  long long facesChanged = 0;  ///< faces whose vertices differ after the run
};

/// Refuses what the smoother cannot do to this mesh with parameters p,
/// before anything is touched.
void checkSmoothable(MeshModel& mm, const sodt::SodtParams& p) {
  CMeshO& m = mm.cm;
  p.validate();
  if (m.fn == 0) throw sodt::InvalidInput("it needs a triangle mesh, but the current mesh has no faces.");
  if (p.flips || p.repair) {
    // A flip, split or collapse rewires faces' vertex references; the core
    // knows nothing of per-wedge data or of the faux edges that describe
    // polygons.
    const char* what = p.flips ? "flips" : "the local repair";
    const char* option = p.flips ? "'Edge flips'" : "'Local repair'";
    if (mm.hasDataMask(MeshModel::MM_WEDGTEXCOORD | MeshModel::MM_WEDGNORMAL | MeshModel::MM_WEDGCOLOR))
      throw sodt::InvalidInput(std::string(what) +
                               " would scramble the per-wedge texture coordinates, normals or colours of this "
                               "mesh. Turn " + option + " off, or remove the wedge attributes first.");
    if (mm.hasDataMask(MeshModel::MM_POLYGONAL))
      throw sodt::InvalidInput(std::string(what) + " would break the polygonal faces of this mesh. Turn " +
                               option + " off, or make it a pure triangle mesh first (filter 'Turn into a "
                               "Pure-Triangular mesh').");
  }
}

/// With 'Affect only selection' and only faces selected: selects the
/// vertices whose faces are all selected (so that no unselected face
/// changes shape). True when it did.
bool selectVerticesOfSelectedFaces(CMeshO& m, const LogFn& log) {
  bool converted = false;
  size_t selected = vcg::tri::UpdateSelection<CMeshO>::VertexCount(m);
  if (selected == 0 && vcg::tri::UpdateSelection<CMeshO>::FaceCount(m) > 0) {
    // Strict: only vertices whose faces are all selected, so that no
    // unselected face changes shape.
    selected = vcg::tri::UpdateSelection<CMeshO>::VertexFromFaceStrict(m);
    m.svn = int(selected);
    converted = true;
    log(LogLevel::Info, strFormat("S-ODT: converted the face selection to %d selected vertices", int(selected)));
  }
  if (selected == 0)
    log(LogLevel::Warning, "S-ODT: 'Affect only selection' is on but nothing is selected; no vertex will move");
  return converted;
}

/// The summary of a run in MeshLab's log.
void logSmoothing(const SmoothingRun& run, const LogFn& log) {
  const sodt::SodtParams& p = run.p;
  const sodt::SodtStats& s = run.s;
  const sodt::AngleStats &before = run.before, &after = run.after;
  const sodt::VolumeResult &volBefore = run.volBefore, &volAfter = run.volAfter;
  const double volRel = run.volRel;
  const sodt::Classification& classes = run.classes;
  const bool outputClass = run.outputClass;
  const long long facesChanged = run.facesChanged;
  log(LogLevel::Info, strFormat("S-ODT: algorithm %s, guard %s, %d iterations, max backtracks %d, "
                                "Laplacian fallback %s, selected only %s",
                                sodt::toString(p.algorithm), sodt::toString(p.guard), p.iterations,
                                p.maxBacktracks, yesNo(p.laplacianFallback), yesNo(p.selectedOnly)));
  if (p.algorithm != sodt::Algorithm::Basic)
    log(LogLevel::Info, strFormat("S-ODT: epsilon %g, eta %g", p.epsilon, p.eta));
  if (p.algorithm == sodt::Algorithm::Filtered) {
    log(LogLevel::Info, "S-ODT: filter: " + sodt::describe(s.filter));
    if (s.filter.kind != sodt::FilterKind::None && s.filter.noiseEdges < sodt::kLittleNoiseEdges)
      log(LogLevel::Warning,
          strFormat("S-ODT: the mesh looks nearly noise-free (noise estimated at %.3f mean edges) but filtering "
                    "still scored better (%s); on a clean mesh that mostly smooths the shape: 'Feature-preserving' "
                    "improves the triangles and keeps the surface, or set the noise level",
                    s.filter.noiseEdges, sodt::describeFilter(s.filter).c_str()));
  }
  if (p.algorithm == sodt::Algorithm::Denoise)
    log(LogLevel::Info, strFormat("S-ODT: max normal step %g x mean edge length", p.maxNormalStepRel));
  else if (p.guard != sodt::Guard::None && p.maxDeviationRel > 0)
    log(LogLevel::Info, strFormat("S-ODT: deviation guard %g%% of the bounding-box diagonal",
                                  sodt::paramSpec("maxDeviationRel").shownValue(p)));
  log(LogLevel::Info, strFormat("S-ODT: min angle %.4f -> %.4f deg, max angle %.4f -> %.4f deg, "
                                "angles below 30 deg %.3f%% -> %.3f%%",
                                before.minDeg, after.minDeg, before.maxDeg, after.maxDeg,
                                100.0 * before.fracBelow30, 100.0 * after.fracBelow30));
  if (volBefore.closed)
    log(LogLevel::Info, strFormat("S-ODT: enclosed volume %.9g -> %.9g (relative change %+.2e)",
                                  volBefore.volume, volAfter.volume, volRel));
  else
    log(LogLevel::Info, "S-ODT: the mesh is not closed; enclosed volume not reported");
  log(LogLevel::Info, strFormat("S-ODT: vertex classes: %s%s", classCounts(classes).c_str(),
                                outputClass ? "; written to vertex quality and colour" : ""));
  log(LogLevel::Info,
      strFormat("S-ODT: %d sweeps over %d active vertices with %d thread%s: %lld moved, %lld backtracked, "
                "%lld Laplacian fallback, %lld rejected, %lld failed solves, %lld unchanged (%lld repeated "
                "their previous visit: nothing in their star had moved); fixed %d boundary and %d non-manifold "
                "vertices",
                s.iterations, s.activeVertices, s.threads, s.threads == 1 ? "" : "s", s.moved, s.backtracked,
                s.fallbackMoves, s.rejected, s.failedSolves, s.unchanged, s.skipped, s.fixedBoundary,
                s.fixedNonManifold));
  if (p.slideBoundary)
    log(LogLevel::Info, strFormat("S-ODT: %d border vertices slid along the border (%d of them moved); %d corners "
                                  "of the border stayed fixed",
                                  s.slidingBoundary, s.movedBoundary, s.boundaryCorners));
  if (p.repair)
    log(LogLevel::Info,
        strFormat("S-ODT: local repair: %d vertices added, %d removed (%d splits, %d points inserted, %d collapses, "
                  "%d flips); %d triangles left below %g deg",
                  s.verticesAdded, s.verticesRemoved, s.repairSplits, s.repairInserts, s.repairCollapses, s.repairFlips,
                  int(s.belowTarget.size()), p.repairAngleDeg));
  if (s.collapsedFacesRemoved > 0)
    log(LogLevel::Info, strFormat("S-ODT: the repair removed %d faces whose corners are not three distinct vertices",
                                  s.collapsedFacesRemoved));
  if (s.reorientedFaces > 0)
    log(LogLevel::Info, strFormat("S-ODT: turned %d faces over so that each part of the mesh has one winding",
                                  s.reorientedFaces));
  if (s.fixedNonManifold > 0)
    log(LogLevel::Warning,
        strFormat("S-ODT: %d vertices stayed fixed: their faces are non-manifold (an edge with three or more "
                  "faces, a pinch) or cannot be given one winding",
                  s.fixedNonManifold));
  if (p.flips)
    log(LogLevel::Info,
        strFormat("S-ODT: edge flips: %lld (max dihedral %g deg); %s", s.flips, p.flipMaxDihedralDeg,
                  facesChanged > 0
                      ? strFormat("the connectivity changed: %lld faces have other vertices (same vertex "
                                  "and face counts)", facesChanged).c_str()
                      : "the returned state has the input's connectivity"));
  else
    log(LogLevel::Info, "S-ODT: edge flips: off");
  std::string ending;
  if (s.stoppedEarly)
    ending = strFormat("; stopped early: the last sweep raised the min angle and its 1st percentile by at "
                       "most the tolerance %g deg", p.toleranceDeg);
  else if (p.toleranceDeg > 0)
    ending = strFormat("; tolerance %g deg not reached", p.toleranceDeg);
  log(LogLevel::Info, strFormat("S-ODT: returned the state after sweep %d of %d run (keep best %s)%s",
                                s.returnedSweep, s.iterations, yesNo(p.keepBest), ending.c_str()));
  if (s.cancelled) log(LogLevel::Warning, strFormat("S-ODT: cancelled after %d sweeps", s.iterations));
}

/// The report of a run (PyMeshLab's return value).
Report smoothingReport(const CMeshO& m, const SmoothingRun& run) {
  const sodt::SodtStats& s = run.s;
  Report r;
  r["vertices"] = m.vn;
  r["faces"] = m.fn;
  const std::pair<const char*, double> angles[] = {
      {"min_angle_before", run.before.minDeg}, {"min_angle_after", run.after.minDeg},
      {"max_angle_before", run.before.maxDeg}, {"max_angle_after", run.after.maxDeg},
      {"frac_below_30_before", run.before.fracBelow30}, {"frac_below_30_after", run.after.fracBelow30}};
  for (const auto& a : angles) r[a.first] = a.second;
  r["closed"] = run.volBefore.closed;
  if (run.volBefore.closed) {
    r["volume_before"] = run.volBefore.volume;
    r["volume_after"] = run.volAfter.volume;
    r["volume_rel_change"] = run.volRel;
  }
  addClassCounts(r, run.classes);
  const std::pair<const char*, int> state[] = {
      {"fixed_boundary", s.fixedBoundary}, {"fixed_nonmanifold", s.fixedNonManifold},
      {"active_vertices", s.activeVertices}, {"sweeps", s.iterations}, {"returned_sweep", s.returnedSweep},
      {"reoriented_faces", s.reorientedFaces}, {"threads", s.threads}};
  for (const auto& v : state) r[v.first] = v.second;
  r["stopped_early"] = s.stoppedEarly;
  r["cancelled"] = s.cancelled;
  const std::pair<const char*, long long> counters[] = {
      {"moved", s.moved}, {"backtracked", s.backtracked}, {"fallback_moves", s.fallbackMoves},
      {"rejected", s.rejected}, {"failed_solves", s.failedSolves}, {"unchanged", s.unchanged},
      {"skipped_visits", s.skipped}, {"flips", s.flips}, {"faces_changed", run.facesChanged},
      {"vertices_added", s.verticesAdded}, {"vertices_removed", s.verticesRemoved},
      {"collapsed_faces_removed", s.collapsedFacesRemoved},
      {"repair_splits", s.repairSplits}, {"repair_inserts", s.repairInserts}, {"repair_collapses", s.repairCollapses},
      {"repair_flips", s.repairFlips}, {"below_repair_angle", static_cast<long long>(s.belowTarget.size())}};
  for (const auto& c : counters) r[c.first] = count(c.second);
  r["seconds"] = s.sweepSeconds;
  if (run.p.algorithm == sodt::Algorithm::Filtered) {  // the first stage's choice (filter_select.h)
    r["filter_kind"] = static_cast<int>(s.filter.kind);  // PyMeshLab passes no strings: 0 none, 1 normals, 2 taubin
    r["filter_steps"] = s.filter.steps;
    r["filter_noise_level"] = s.filter.noiseEdges;
    r["filter_noise_estimated"] = s.filter.noiseEstimated;
    r["filter_risk"] = s.filter.risk;
    r["filter_risk_unfiltered"] = s.filter.riskNone;
    r["filter_restored_vertices"] = s.restoredVertices;
    r["filter_sweep_bound_percent"] = 100.0 * s.filteredSweepBoundRel;
  }
  return r;
}

}  // namespace

Report applySmoothing(MeshModel& mm, const RichParameterList& par, vcg::CallBackPos* cb,
                      const LogFn& log) {
  CMeshO& m = mm.cm;
  bool selectionConverted = false;
  try {
    SmoothingRun run;
    const sodt::SodtParams& p = run.p = readSodtParams(par);
    run.outputClass = readOutputClass(par);
    checkSmoothable(mm, p);
    if (p.selectedOnly) selectionConverted = selectVerticesOfSelectedFaces(m, log);
    // The measures do not depend on the number of threads either.
    const int measureThreads = sodt::resolveThreads(p.threads);
    run.before = sodt::computeAngleStats(m, measureThreads);
    run.volBefore = sodt::enclosedVolume(m, measureThreads);
    if (p.algorithm == sodt::Algorithm::Denoise) {  // filtered's own warning follows its run
      const double noise = sodt::estimateNoiseOf(m).sigmaEdges;
      if (noise < sodt::kLittleNoiseEdges)
        log(LogLevel::Warning,
            strFormat("S-ODT: the mesh looks nearly noise-free (noise estimated at %.3f mean edges): %s removes "
                      "noise, and on a clean mesh it mostly smooths the shape; 'Feature-preserving' improves the "
                      "triangles and keeps the surface",
                      noise, sodt::toString(p.algorithm)));
    }

    // The faces' vertex references, to tell whether the returned state has
    // other faces (keepBest may return a state from before the flips).
    // By index: the repair may reallocate the vertices.
    std::vector<long> faceVertsBefore;
    if (p.flips || p.repair)
      for (const CFaceO& f : m.face)
        for (int j = 0; j < 3; ++j) faceVertsBefore.push_back(f.IsD() ? -1 : long(f.cV(j) - &m.vert[0]));

    const sodt::SodtStats& s = run.s = sodt::SodtSmoother<CMeshO>::Apply(m, p, cb, &run.classes);
    // From here on the mesh has changed: nothing below may throw.
    selectionConverted = false;
    if (p.flips || p.repair)
      for (size_t f = 0; f < m.face.size(); ++f)
        for (int j = 0; j < 3; ++j)
          if (!m.face[f].IsD() && (3 * f >= faceVertsBefore.size() ||
                                   long(m.face[f].cV(j) - &m.vert[0]) != faceVertsBefore[3 * f + size_t(j)])) {
            ++run.facesChanged;  // rewired, or made by the repair
            break;
          }
    // Flips move edges between face slots: per-face-edge border flags set
    // before the run would now describe other edges. (The core has already
    // rebuilt FF and VF adjacency where they are enabled.)
    if (s.flips > 0 || s.reorientedFaces > 0 || p.repair) vcg::tri::UpdateFlags<CMeshO>::FaceBorderFromNone(m);
    sodt_meshlab::updateBoxAndNormals(mm);
    if (run.outputClass) {
      // Without the mask the GUI neither shows nor saves the colours (and
      // quality); both components always exist in CMeshO.
      mm.updateDataMask(MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR);
      sodt::writeClassToQuality(m, run.classes);
      sodt::colorizeByClass(m, run.classes);
    }

    run.after = sodt::computeAngleStats(m, s.threads);
    if (run.volBefore.closed) run.volAfter = sodt::enclosedVolume(m, s.threads);
    if (run.volBefore.closed && run.volBefore.volume != 0.0)
      run.volRel = (run.volAfter.volume - run.volBefore.volume) / run.volBefore.volume;
    logSmoothing(run, log);
    return smoothingReport(m, run);
  } catch (...) {
    // The core throws before it moves anything; undo the selection change too.
    if (selectionConverted) {
      vcg::tri::UpdateSelection<CMeshO>::VertexClear(m);
      m.svn = 0;
    }
    throw;
  }
}

QString runFilter(int id, const QString& filterName, MeshModel* mm, const RichParameterList& par,
                  vcg::CallBackPos* cb, const LogFn& log, Report& report) {
  try {
    if (mm == nullptr) throw std::invalid_argument("there is no current mesh.");
    switch (id) {
      case kSmooth: report = applySmoothing(*mm, par, cb, log); return QString();
      case kClassify: report = applyClassify(*mm, par, log); return QString();
    }
    return "S-ODT: unknown filter '" + filterName + "'";
  } catch (const std::exception& e) {
    return failureMessage(id, e.what());
  } catch (...) {
    return failureMessage(id, nullptr);
  }
}

Report applyClassify(MeshModel& mm, const RichParameterList& par, const LogFn& log) {
  CMeshO& m = mm.cm;
  const SodtClassifyParams p = readClassifyParams(par);
  p.validate();
  if (m.fn == 0) throw sodt::InvalidInput("it needs a triangle mesh, but the current mesh has no faces.");

  const sodt::Classification c = sodt::classifyVertices(m, p.epsilon, p.eta);
  mm.updateDataMask(MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR);
  sodt::writeClassToQuality(m, c);
  sodt::colorizeByClass(m, c);
  log(LogLevel::Info, strFormat("S-ODT classify: epsilon %g, eta %g: %s", p.epsilon, p.eta, classCounts(c).c_str()));
  log(LogLevel::Info, "S-ODT classify: class codes written to vertex quality (0 smooth, 1 crease, 2 corner, "
                      "3 fixed), class colours to vertex colour");
  Report r;
  addClassCounts(r, c);
  if (p.selectFeatures) {
    m.svn = sodt::selectFeatureVertices(m, c);
    log(LogLevel::Info, strFormat("S-ODT classify: selected %d feature (crease or corner) vertices", m.svn));
    r["selected"] = m.svn;
  }
  return r;
}

}  // namespace sodt_plugin
