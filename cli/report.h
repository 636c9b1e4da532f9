// SPDX-License-Identifier: GPL-3.0-or-later
// What `sodt` measures and reports: angle and volume measures, the surface
// distance to the input, the summaries on stdout and the JSON reports of the
// three commands.
#pragma once

#include "options.h"

#include <sodt/maths/classify.h>
#include <sodt_io/corners.h>
#include <sodt_io/io.h>
#include <sodt_io/mesh.h>
#include <sodt_io/metrics.h>
#include <sodt/params.h>

#include <array>
#include <string>
#include <vector>

namespace sodt_cli {

using sodt::MeshD;

/// Quality measures of one mesh state.
struct Measures {
  sodt::AngleStats angles;
  sodt::VolumeResult volume;
  double borderLength = 0;  ///< length of the edges of one face (0 for a closed mesh)
  /// Estimated noise along the normals, in mean edge lengths
  /// (sodt::estimateNoise; NaN when too few vertices qualify).
  double noiseEdges = 0;
};

/// On threads threads (the measures do not depend on their number).
Measures measure(const MeshD& m, int threads);

/// Surface distance of a mesh to a reference, relative to the reference's
/// bounding-box diagonal.
struct Distance {
  bool measured = true;    ///< false: not asked for (smooth --distance off), the rest unset
  double hausdorff = 0;    ///< symmetric Hausdorff (or its lower bound)
  double mean = 0;         ///< mean two-sided distance (NaN with a lower bound)
  double edges = 0;        ///< largest distance with points along every edge too (>= hausdorff)
  bool lowerBound = false; ///< the mesh left the reference's neighbourhood: vertices only
};

/// Samples both surfaces (sodt::surfaceDistanceInPlace: no copy of a large
/// mesh; it updates their bounding boxes and face normals, which
/// no file written afterwards contains) unless a vertex of m lies more than
/// one diagonal outside ref's bounding box, as after a diverged unguarded
/// run: then sampling says nothing more and can take very long, and the
/// vertex distance to the box is reported as a lower bound. The lookups run
/// on threads threads (the result does not depend on their number).
/// RefMesh is sodt::SampleMesh or MeshD.
template <class RefMesh>
Distance distanceTo(MeshD& m, RefMesh& ref, int threads);

/// What the measures of the output need from the input (distance and
/// inverted faces), kept through the smoothing in a fraction of the memory
/// of a copy of the mesh: 24 bytes per vertex, plus 12 per face when the
/// smoother may change the faces. The reference mesh is rebuilt from it only
/// after the smoothing, when the smoother's working memory is freed.
struct InputGeometry {
  std::vector<vcg::Point3d> positions;   ///< every vertex of the input, in order
  std::vector<std::array<int, 3>> faces;  ///< the input's faces when facesKept
  bool facesKept = false;                 ///< else the output has the input's faces
};

/// Keeps m's positions, and its faces when `facesMayChange` (edge flips).
/// m must be compact, as loadMesh leaves it.
InputGeometry keepInput(const MeshD& m, bool facesMayChange);

/// The input mesh for the measures, as its copy would be: its vertices in
/// order, with the faces of `input` or else those of m (which the smoother
/// left unchanged but for their orientation). With `reoriented` (the
/// smoother oriented the faces coherently) the faces of `input` are
/// oriented the same way, so that a face it turned on purpose does not
/// count as turned over. Frees input's arrays as it goes.
void rebuildInput(InputGeometry& input, const MeshD& m, sodt::SampleMesh& ref, bool reoriented = false);

/// Writes m with the classes as per-vertex quality and colour (output.h).
/// Overwrites m's quality and colour.
void saveClassMesh(sodt::PendingFile& f, MeshD& m, const sodt::Classification& c);

/// Everything `sodt smooth` reports about a run.
struct SmoothResult {
  Measures before, after;
  Distance distance;
  /// Faces turned by more than 90 degrees from the input (sodt::countInvertedFaces).
  long long inverted = 0;
  /// inverted was counted face by face (the returned mesh has the input's
  /// faces), else each face against the input face under it.
  bool invertedFaceByFace = true;
  sodt::SodtStats stats;
  sodt::Classification classes;
  double seconds = 0;       ///< the smoothing alone
  /// With the repair: the output's corners between features sharper than
  /// its target (sodt::protectedAngles with the repair's feature angle).
  sodt::ProtectedAngles corners;
};

/// The summary of `sodt smooth` on stdout.
void printSmoothSummary(const SmoothOptions& o, const MeshD& m, const SmoothResult& r);

/// The JSON report of `sodt smooth` (--report).
std::string smoothReport(const SmoothOptions& o, const MeshD& m, const SmoothResult& r);

/// The summary of `sodt classify` on stdout.
void printClassifySummary(const ClassifyOptions& o, const MeshD& m, const sodt::Classification& c);

/// The JSON of `sodt classify --json`.
std::string classifyReport(const ClassifyOptions& o, const MeshD& m, const sodt::Classification& c);

/// The JSON of `sodt stats`: the measures of m and, with a reference, its
/// distance and inverted faces against it (on threads threads).
std::string statsReport(const StatsOptions& o, MeshD& m, MeshD* ref, int threads);

}  // namespace sodt_cli
