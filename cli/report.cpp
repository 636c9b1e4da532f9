// SPDX-License-Identifier: GPL-3.0-or-later
// The measures, summaries and JSON reports of `sodt smooth`, `sodt classify`
// and `sodt stats` (see report.h).
#include "report.h"

#include <sodt/denoise/filter_select.h>
#include <sodt/denoise/noise_estimate.h>
#include <sodt/mesh/output.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#ifndef SODT_VERSION
#define SODT_VERSION "unknown"
#endif

namespace sodt_cli {

namespace {

/// JSON objects keep their members in the order written.
using Json = nlohmann::ordered_json;

/// x, or null when it is not finite (JSON has no NaN or infinity).
Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

/// The document as the reports are written: two-space indent, a final newline.
std::string text(const Json& j) { return j.dump(2) + "\n"; }

/// `sodt stats` estimates the noise of this many components (those with the
/// most faces) on their own.
constexpr int kNoiseComponentsListed = 16;

/// The deviation bound, in percent in the summary and the report.
const sodt::ParamSpec& maxDeviation = sodt::paramSpec("maxDeviationRel");

/// Adds the members of one measures object to j.
void writeMeasures(Json& j, const Measures& s) {
  j["closed"] = s.volume.closed;
  j["min_angle"] = number(s.angles.minDeg);
  j["max_angle"] = number(s.angles.maxDeg);
  j["angle_histogram"] = s.angles.histogram;
  j["frac_below_30"] = number(s.angles.fracBelow30);
  j["frac_above_90"] = number(s.angles.fracAbove90);
  j["p1_tri_min_angle"] = number(s.angles.p1TriMinDeg);
  j["volume"] = s.volume.closed ? number(s.volume.volume) : Json(nullptr);
  j["border_length"] = number(s.borderLength);
  j["noise_estimate"] = number(s.noiseEdges);
}

/// Writes hausdorff_rel, hausdorff_edges_rel, mean_distance_rel (null when
/// unknown) and hausdorff_is_lower_bound, all four null when the distance
/// was not measured.
void writeDistance(Json& j, const Distance& d) {
  j["hausdorff_rel"] = d.measured ? number(d.hausdorff) : Json(nullptr);
  j["hausdorff_edges_rel"] = d.measured ? number(d.edges) : Json(nullptr);
  j["mean_distance_rel"] = d.measured ? number(d.mean) : Json(nullptr);
  j["hausdorff_is_lower_bound"] = d.measured ? Json(d.lowerBound) : Json(nullptr);
}

/// Writes "classes": {"smooth": n, "crease": n, "corner": n, "fixed": n}.
void writeClassCounts(Json& j, const sodt::Classification& c) {
  Json& counts = j["classes"] = Json::object();
  for (int k = 0; k < 4; ++k) counts[sodt::toString(static_cast<sodt::VertexClass>(k))] = c.count[k];
}

/// "smooth 1200, crease 80, corner 8, fixed 0".
std::string classCountsText(const sodt::Classification& c) {
  std::string s;
  for (int k = 0; k < 4; ++k)
    s += std::string(k ? ", " : "") + sodt::toString(static_cast<sodt::VertexClass>(k)) + " " +
         std::to_string(c.count[k]);
  return s;
}

/// Writes the parameters of a run, each under its report key in
/// sodt::paramTable(), as shown (maxDeviation in percent).
void writeParameters(Json& j, const sodt::SodtParams& p) {
  for (const sodt::ParamSpec& s : sodt::paramTable()) {
    if (s.reportName() == nullptr) continue;
    const double v = s.shownValue(p);
    Json& member = j[s.reportName()];
    switch (s.type) {
      case sodt::ParamType::Int: member = static_cast<int>(v); break;
      case sodt::ParamType::Real: member = number(v); break;
      case sodt::ParamType::Bool: member = v != 0; break;
      case sodt::ParamType::Choice: member = s.valueText(v); break;
    }
  }
}

/// Writes the members every command's report starts with.
void writeRunHeader(Json& j, const std::string& in, const std::string& out, const MeshD& m) {
  j["sodt_version"] = SODT_VERSION;
  j["input"] = in;
  j["output"] = out;
  j["vertices"] = m.vn;
  j["faces"] = m.fn;
}

/// "12.34%".
std::string percent(double frac) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f%%", 100.0 * frac);
  return b;
}

}  // namespace

Measures measure(const MeshD& m, int threads) {
  Measures r;
  r.angles = sodt::computeAngleStats(m, threads);
  r.volume = sodt::enclosedVolume(m, threads);
  r.borderLength = sodt::borderLength(m);
  r.noiseEdges = sodt::estimateNoiseOf(m).sigmaEdges;
  return r;
}






template <class RefMesh>
Distance distanceTo(MeshD& m, RefMesh& ref, int threads) {
  // The surfaces only: unreferenced vertices are neither measured nor the
  // measure's scale.
  const vcg::Box3d box = sodt::surfaceBox(ref);
  const double diag = box.Diag();
  std::vector<char> onSurface(m.vert.size(), 0);
  for (const auto& f : m.face)
    if (!f.IsD())
      for (int j = 0; j < 3; ++j) onSurface[static_cast<std::size_t>(f.cV(j) - &m.vert[0])] = 1;
  double far = 0;
  for (std::size_t i = 0; i < m.vert.size(); ++i) {
    const auto& v = m.vert[i];
    if (v.IsD() || !onSurface[i]) continue;
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double e = std::max({box.min[k] - v.cP()[k], 0.0, v.cP()[k] - box.max[k]});
      d2 += e * e;
    }
    far = std::max(far, std::sqrt(d2));
  }
  Distance r;
  if (diag > 0 && far > diag) {
    r.hausdorff = r.edges = far / diag;
    r.mean = std::numeric_limits<double>::quiet_NaN();
    r.lowerBound = true;
    return r;
  }
  const sodt::DistanceStats d = sodt::surfaceDistanceInPlace(m, ref, threads);
  r.hausdorff = d.maxRel;
  r.mean = d.meanRel;
  r.edges = d.maxEdgeRel;
  return r;
}

template Distance distanceTo(MeshD&, sodt::SampleMesh&, int);
template Distance distanceTo(MeshD&, MeshD&, int);

InputGeometry keepInput(const MeshD& m, bool facesMayChange) {
  InputGeometry g;
  g.positions.reserve(m.vert.size());
  for (const auto& v : m.vert) g.positions.push_back(v.cP());
  g.facesKept = facesMayChange;
  if (facesMayChange) {
    g.faces.reserve(m.face.size());
    for (const auto& f : m.face)
      g.faces.push_back({{int(f.cV(0) - &m.vert[0]), int(f.cV(1) - &m.vert[0]), int(f.cV(2) - &m.vert[0])}});
  }
  return g;
}

void rebuildInput(InputGeometry& input, const MeshD& m, sodt::SampleMesh& ref, bool reoriented) {
  if (input.facesKept && reoriented) {
    sodt::FaceList faces;
    faces.tri.swap(input.faces);
    faces.live.assign(faces.tri.size(), 1);
    faces.flippable.assign(faces.tri.size(), 1);
    std::vector<sodt::Vec3> pos;
    pos.reserve(input.positions.size());
    for (const auto& p : input.positions) pos.push_back(sodt::Vec3::Construct(p));
    sodt::orientCoherently(faces, pos);
    faces.tri.swap(input.faces);
  }
  ref.Clear();
  vcg::tri::Allocator<sodt::SampleMesh>::AddVertices(ref, input.positions.size());
  for (std::size_t i = 0; i < input.positions.size(); ++i) ref.vert[i].P() = input.positions[i];
  std::vector<vcg::Point3d>().swap(input.positions);
  const std::size_t nf = input.facesKept ? input.faces.size() : m.face.size();
  vcg::tri::Allocator<sodt::SampleMesh>::AddFaces(ref, nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int j = 0; j < 3; ++j)
      ref.face[f].V(j) =
          &ref.vert[input.facesKept ? std::size_t(input.faces[f][j]) : std::size_t(m.face[f].cV(j) - &m.vert[0])];
  std::vector<std::array<int, 3>>().swap(input.faces);
}


void saveClassMesh(sodt::PendingFile& f, MeshD& m, const sodt::Classification& c) {
  sodt::writeClassToQuality(m, c);
  sodt::colorizeByClass(m, c);
  sodt::SaveOptions so;
  so.vertexQuality = true;
  so.vertexColor = true;
  sodt::saveMesh(f, m, so);
}




/// The repair's line: what it changed, and what it left below the target.
void printRepairSummary(const sodt::SodtParams& p, const sodt::SodtStats& st) {
  int why[sodt::kRepairReasonCount] = {};
  for (const sodt::RemainingTriangle& t : st.belowTarget) ++why[static_cast<int>(t.why)];
  std::printf("  repair         %d vertices added, %d removed (%d splits, %d points inserted, %d collapses, %d flips, "
              "%lld moves); %zu triangles below %s deg",
              st.verticesAdded, st.verticesRemoved, st.repairSplits, st.repairInserts, st.repairCollapses,
              st.repairFlips, st.repairMoves, st.belowTarget.size(), numberText(p.repairAngleDeg).c_str());
  if (!st.belowTarget.empty()) {
    std::printf(" (");
    const char* sep = "";
    for (int k = 0; k < sodt::kRepairReasonCount; ++k)
      if (why[k] > 0) {
        std::printf("%s%d %s", sep, why[k], sodt::toString(static_cast<sodt::RepairReason>(k)));
        sep = ", ";
      }
    std::printf("; listed in the report)");
  }
  std::printf("\n");
  if (st.collapsedFacesRemoved > 0)
    std::printf("  repair         %d faces removed whose corners are not three distinct vertices (no area)\n",
                st.collapsedFacesRemoved);
}

/// The report's list of the triangles the repair left below its target.
Json remainingTriangles(const sodt::SodtStats& st) {
  Json list = Json::array();
  for (const sodt::RemainingTriangle& t : st.belowTarget)
    list.push_back({{"centroid", {number(t.centroid[0]), number(t.centroid[1]), number(t.centroid[2])}},
                    {"min_angle_deg", number(t.minAngleDeg)},
                    {"reason", sodt::toString(t.why)}});
  return list;
}

void printSmoothSummary(const SmoothOptions& o, const MeshD& m, const SmoothResult& r) {
  const Measures& before = r.before;
  const Measures& after = r.after;
  const Distance& dist = r.distance;
  const sodt::SodtStats& st = r.stats;
  const long long inverted = r.inverted;
  std::printf("sodt smooth: %s -> %s\n", o.in.c_str(), o.out.c_str());
  std::printf("  mesh           %d vertices, %d triangles, %s\n", m.vn, m.fn,
              before.volume.closed ? "closed" : "open or not consistently oriented");
  std::printf("  min angle      %.3f -> %.3f deg\n", before.angles.minDeg, after.angles.minDeg);
  std::printf("  max angle      %.3f -> %.3f deg\n", before.angles.maxDeg, after.angles.maxDeg);
  std::printf("  angles < 30    %s -> %s\n", percent(before.angles.fracBelow30).c_str(),
              percent(after.angles.fracBelow30).c_str());
  std::printf("  angles > 90    %s -> %s\n", percent(before.angles.fracAbove90).c_str(),
              percent(after.angles.fracAbove90).c_str());
  std::printf("  p1 tri min     %.3f -> %.3f deg\n", before.angles.p1TriMinDeg, after.angles.p1TriMinDeg);
  std::printf("  noise          %.3f -> %.3f mean edges (estimated)\n", before.noiseEdges, after.noiseEdges);
  if (before.borderLength > 0)
    std::printf("  border length  %.10g -> %.10g (relative change %+.3e)\n", before.borderLength, after.borderLength,
                (after.borderLength - before.borderLength) / before.borderLength);
  if (before.volume.closed && after.volume.closed) {
    const double rel = before.volume.volume != 0
                           ? (after.volume.volume - before.volume.volume) / std::fabs(before.volume.volume)
                           : 0.0;
    std::printf("  volume         %.10g -> %.10g (relative change %+.3e)\n", before.volume.volume,
                after.volume.volume, rel);
  } else {
    std::printf("  volume         n/a (mesh not closed)\n");
  }
  if (!dist.measured)
    std::printf("  distance       not measured (--distance off)\n");
  else if (dist.lowerBound)
    std::printf("  distance       Hausdorff >= %.3e of the input's bbox diagonal (the output left the input's box)\n",
                dist.hausdorff);
  else
    std::printf("  distance       Hausdorff %.3e (%.3e along the edges), mean %.3e (relative to the input's bbox "
                "diagonal)\n",
                dist.hausdorff, dist.edges, dist.mean);
  if (o.params.algorithm == sodt::Algorithm::Filtered) {
    std::printf("  filter         %s\n", sodt::describe(st.filter).c_str());
    std::printf("  restored       %d smooth vertices set back on the denoised surface after the sweeps\n",
                st.restoredVertices);
    if (o.params.maxDeviationRel > 0)
      std::printf("  sweep bound    %.4g%% of the diagonal from the denoised surface%s\n",
                  100.0 * st.filteredSweepBoundRel,
                  st.filteredSweepBoundRel > o.params.maxDeviationRel ? " (half the noise level: above --max-deviation)"
                                                                       : "");
  }
  if (o.params.algorithm == sodt::Algorithm::Filtered && o.params.guard != sodt::Guard::None)
    std::printf("  face turn      at most %.3f deg from the denoised surface's orientation (bound %s deg for the "
                "filtered sweeps; --max-face-turn unused)\n",
                st.maxFaceTurnDeg, numberText(sodt::filteredFaceTurnDeg(st.filter.kind)).c_str());
  else
    std::printf("  face turn      at most %.3f deg from the input orientation (bound %s deg%s)\n", st.maxFaceTurnDeg,
                numberText(o.params.maxFaceTurnDeg).c_str(),
                o.params.guard == sodt::Guard::None || o.params.algorithm == sodt::Algorithm::Denoise ? ", unused" : "");
  std::printf("  inverted       %lld faces turned by more than 90 deg%s\n", inverted,
              r.invertedFaceByFace ? "" : " from the input face under them (the faces differ from the input's)");
  std::printf("  vertex visits  moved %lld, backtracked %lld, Laplacian fallback %lld, rejected %lld, failed %lld, "
              "unchanged %lld; %lld repeated their previous visit (nothing in their star had moved)\n",
              st.moved, st.backtracked, st.fallbackMoves, st.rejected, st.failedSolves, st.unchanged, st.skipped);
  std::printf("  fixed          %d boundary, %d non-manifold; %d vertices active\n", st.fixedBoundary,
              st.fixedNonManifold, st.activeVertices);
  if (o.params.slideBoundary)
    std::printf("  border         %d vertices slide along the border (%d of them moved), %d corners of the border "
                "fixed\n", st.slidingBoundary, st.movedBoundary, st.boundaryCorners);
  if (st.reorientedFaces > 0)
    std::printf("  winding        %d faces turned over so that each part of the mesh has one winding, "
                "outward on closed parts (written so)\n", st.reorientedFaces);
  std::printf("  classes        %s%s\n", classCountsText(r.classes).c_str(),
              o.params.algorithm == sodt::Algorithm::Basic ? " (basic does not classify)" : "");
  std::printf("  smoothing      %.3f s for %d sweeps on %d thread%s (algorithm %s, guard %s, max backtracks %d)\n",
              r.seconds, st.iterations, st.threads, st.threads == 1 ? "" : "s", sodt::toString(o.params.algorithm),
              sodt::toString(o.params.guard), o.params.maxBacktracks);
  const sodt::Algorithm a = o.params.algorithm;
  const char* unused = " (unused)";
  std::printf("  parameters     epsilon %s (creases above %.1f deg), eta %s%s; max deviation %s%% of the bbox "
              "diagonal%s; max normal step %s mean edges%s\n",
              numberText(o.params.epsilon).c_str(), creaseAngleDeg(o.params.epsilon),
              numberText(o.params.eta).c_str(), a == sodt::Algorithm::Basic ? unused : "",
              numberText(maxDeviation.shownValue(o.params)).c_str(),
              a == sodt::Algorithm::Denoise || o.params.guard == sodt::Guard::None ? unused : "",
              numberText(o.params.maxNormalStepRel).c_str(), a != sodt::Algorithm::Denoise ? unused : "");
  if (o.params.flips)
    std::printf("  flips          %lld edges flipped (max dihedral %s deg)%s\n", st.flips,
                numberText(o.params.flipMaxDihedralDeg).c_str(),
                r.invertedFaceByFace && st.flips > 0 ? "; the returned state has the input's connectivity" : "");
  else
    std::printf("  flips          off\n");
  if (o.params.repair) {
    printRepairSummary(o.params, st);
    if (r.corners.corners > 0)
      std::printf("  corners        %d between features sharper than %s deg (smallest %.2f deg, %lld faces); "
                  "min angle elsewhere %.2f deg\n",
                  r.corners.corners, numberText(o.params.repairAngleDeg).c_str(), r.corners.smallestDeg,
                  r.corners.faces, r.corners.minAngleElsewhereDeg);
  }
  std::printf("  returned       the state after sweep %d of %d (keep best %s)", st.returnedSweep, st.iterations,
              o.params.keepBest ? "on" : "off");
  if (st.stoppedEarly)
    std::printf("; stopped early: the last sweep raised the min angle and p1 by at most %s deg\n",
                numberText(o.params.toleranceDeg).c_str());
  else if (o.params.toleranceDeg > 0)
    std::printf("; tolerance %s deg not reached\n", numberText(o.params.toleranceDeg).c_str());
  else
    std::printf("\n");
  if (!o.classesOut.empty()) std::printf("  classes out    %s\n", o.classesOut.c_str());
}

std::string smoothReport(const SmoothOptions& o, const MeshD& m, const SmoothResult& r) {
  const Measures& before = r.before;
  const Measures& after = r.after;
  const Distance& dist = r.distance;
  const sodt::SodtStats& st = r.stats;
  const long long inverted = r.inverted;
  Json j = Json::object();
  writeRunHeader(j, o.in, o.out, m);
  writeParameters(j, o.params);
  j["distance_measured"] = dist.measured;
  j["classes_output"] = o.classesOut.empty() ? Json(nullptr) : Json(o.classesOut);
  j["sweeps"] = st.iterations;
  j["returned_sweep"] = st.returnedSweep;
  j["stopped_early"] = st.stoppedEarly;
  j["flips"] = st.flips;
  j["reoriented_faces"] = st.reorientedFaces;
  j["vertices_added"] = st.verticesAdded;
  j["vertices_removed"] = st.verticesRemoved;
  j["collapsed_faces_removed"] = st.collapsedFacesRemoved;
  j["repair_splits"] = st.repairSplits;
  j["repair_inserts"] = st.repairInserts;
  j["repair_collapses"] = st.repairCollapses;
  j["repair_flips"] = st.repairFlips;
  j["repair_moves"] = st.repairMoves;
  j["below_repair_angle"] = remainingTriangles(st);
  if (o.params.repair) {
    j["protected_angles"] = {{"corners", r.corners.corners},
                             {"smallest_deg", number(r.corners.smallestDeg)},
                             {"faces", r.corners.faces}};
    j["min_angle_unprotected"] = number(r.corners.minAngleElsewhereDeg);
  } else {
    j["protected_angles"] = nullptr;
    j["min_angle_unprotected"] = nullptr;
  }
  j["seconds"] = number(r.seconds);
  j["threads"] = st.threads;
  j["min_angle_before"] = number(before.angles.minDeg);
  j["min_angle_after"] = number(after.angles.minDeg);
  j["max_angle_before"] = number(before.angles.maxDeg);
  j["max_angle_after"] = number(after.angles.maxDeg);
  const bool closed = before.volume.closed && after.volume.closed;
  j["volume_before"] = closed ? number(before.volume.volume) : Json(nullptr);
  j["volume_after"] = closed ? number(after.volume.volume) : Json(nullptr);
  j["volume_rel_change"] =
      closed && before.volume.volume != 0
          ? number((after.volume.volume - before.volume.volume) / std::fabs(before.volume.volume))
          : Json(nullptr);
  writeDistance(j, dist);
  j["inverted_faces"] = inverted;
  j["max_face_turn_deg"] = number(st.maxFaceTurnDeg);
  Json unfold;
  unfold["found"] = st.facingAwayFound;
  unfold["moves"] = st.unfoldMoves;
  unfold["flips"] = st.unfoldFlips;
  unfold["left"] = st.facingAwayLeft;
  j["facing_away_mended"] = unfold;
  if (o.params.algorithm == sodt::Algorithm::Filtered) {
    Json f;
    f["kind"] = sodt::toString(st.filter.kind);
    f["steps"] = st.filter.steps;
    f["noise_level"] = number(st.filter.noiseEdges);
    f["noise_estimated"] = st.filter.noiseEstimated;
    if (st.filter.passedOver != sodt::FilterKind::None) {
      Json passed;
      passed["kind"] = sodt::toString(st.filter.passedOver);
      passed["steps"] = st.filter.passedOverSteps;
      f["passed_over"] = passed;
    } else {
      f["passed_over"] = nullptr;
    }
    f["risk"] = number(st.filter.risk);
    f["risk_unfiltered"] = number(st.filter.riskNone);
    f["restored_vertices"] = st.restoredVertices;
    f["sweep_bound_percent"] = number(100.0 * st.filteredSweepBoundRel);
    j["filter"] = f;
  }
  j["moved"] = st.moved;
  j["backtracked"] = st.backtracked;
  j["fallback_moves"] = st.fallbackMoves;
  j["rejected"] = st.rejected;
  j["failed_solves"] = st.failedSolves;
  j["unchanged"] = st.unchanged;
  j["skipped_visits"] = st.skipped;
  j["deviation_queries"] = st.deviationQueries;
  j["deviation_reused"] = st.deviationReused;
  j["lane_visits"] = st.laneVisits;
  j["active_vertices"] = st.activeVertices;
  j["fixed_boundary"] = st.fixedBoundary;
  j["fixed_nonmanifold"] = st.fixedNonManifold;
  j["sliding_boundary"] = st.slidingBoundary;
  j["boundary_corners"] = st.boundaryCorners;
  j["moved_boundary"] = st.movedBoundary;
  j["cancelled"] = st.cancelled;
  writeClassCounts(j, r.classes);
  writeMeasures(j["before"] = Json::object(), before);
  writeMeasures(j["after"] = Json::object(), after);
  return text(j);
}

void printClassifySummary(const ClassifyOptions& o, const MeshD& m, const sodt::Classification& c) {
  std::printf("sodt classify: %s -> %s\n", o.in.c_str(), o.out.c_str());
  std::printf("  mesh           %d vertices, %d triangles\n", m.vn, m.fn);
  std::printf("  parameters     epsilon %s (creases above %.1f deg), eta %s\n", numberText(o.params.epsilon).c_str(),
              creaseAngleDeg(o.params.epsilon), numberText(o.params.eta).c_str());
  std::printf("  classes        %s\n", classCountsText(c).c_str());
  std::printf("  quality        0 smooth, 1 crease, 2 corner, 3 fixed (border or non-manifold)\n");
}

std::string classifyReport(const ClassifyOptions& o, const MeshD& m, const sodt::Classification& c) {
  Json j = Json::object();
  writeRunHeader(j, o.in, o.out, m);
  j["epsilon"] = number(o.params.epsilon);
  j["eta"] = number(o.params.eta);
  j["crease_angle_deg"] = number(creaseAngleDeg(o.params.epsilon));
  writeClassCounts(j, c);
  return text(j);
}

std::string statsReport(const StatsOptions& o, MeshD& m, MeshD* ref, int threads) {
  const Measures s = measure(m, threads);
  Json j = Json::object();
  j["input"] = o.in;
  j["vertices"] = m.vn;
  j["faces"] = m.fn;
  writeMeasures(j, s);
  // noise_estimate is a median over the whole mesh: a small noisy part
  // beside a large clean one reads clean. Each part on its own:
  int components = 0;
  const std::vector<sodt::ComponentNoise> parts =
      sodt::estimateNoiseByComponentOf(m, kNoiseComponentsListed, &components);
  j["components"] = components;
  Json& list = j["noise_by_component"] = Json::array();
  for (const sodt::ComponentNoise& c : parts)
    list.push_back(Json{{"faces", c.faces}, {"vertices", c.vertices}, {"noise_estimate", number(c.noise.sigmaEdges)}});
  if (ref != nullptr) {
    const Distance d = distanceTo(m, *ref, threads);
    const long long inv = sodt::countInvertedFaces(m, *ref, threads);
    j["reference"] = o.reference;
    writeDistance(j, d);
    j["inverted_faces"] = inv;
  }
  return text(j);
}

}  // namespace sodt_cli
