// SPDX-License-Identifier: GPL-3.0-or-later
// Compares a mesh before and after the plugin ran in meshlabserver (same
// vertices and faces, moved coordinates, larger smallest angle, selection kept,
// class codes and colours, cube features kept).
//
// Usage:
//   sodt_plugin_mesh_check INPUT.ply OUTPUT.ply
//       same vertex and face lists, some vertex moved, the smallest angle grew.
//   sodt_plugin_mesh_check --select-half INPUT.ply SELECTED.ply
//       writes INPUT with a face selection (PLY face "flags"): the faces whose
//       centroid has x below the median.
//   sodt_plugin_mesh_check --selection INPUT.ply OUTPUT.ply
//       OUTPUT was smoothed from --select-half's file with selectedOnly: only
//       vertices whose faces are all selected moved, and some did.
//   sodt_plugin_mesh_check --classes INPUT.ply OUTPUT.ply [--codes DIGITS]
//                          [--corners N] [--cube-corners] [--unmoved] [--selected-features]
//       OUTPUT (saved with -m vq vc, plus vf for --selected-features) carries
//       class codes: every vertex quality is a code in DIGITS (default 0123)
//       and its colour is the palette colour of that code. --corners: exactly
//       N vertices have code 2; --cube-corners: they are the corners
//       (+-1, +-1, +-1) of INPUT; --unmoved: every vertex is bit-identical
//       to INPUT; --selected-features: exactly the code 1 and 2 vertices are
//       selected, and there are some.
//   sodt_plugin_mesh_check --cube-feature INPUT.ply OUTPUT.ply
//       INPUT is a mesh of the cube [-1,1]^3 smoothed into OUTPUT by the
//       feature-preserving algorithm: its 8 corners are bit-identical, every
//       vertex lies on the cube surface (largest |coordinate| is 1 within float
//       rounding), every vertex on a cube edge stays on it, some vertex moved,
//       and the smallest angle grew.
//   sodt_plugin_mesh_check --flipped INPUT.ply OUTPUT.ply
//       OUTPUT was smoothed with edge flips: the same number of vertices and
//       faces, some face references other vertices, no face repeats a vertex,
//       a closed oriented edge-manifold INPUT stays one, and the smallest
//       angle grew.
//   sodt_plugin_mesh_check --cube-denoise INPUT.ply OUTPUT.ply
//       INPUT is a noisy mesh of the cube [-1,1]^3 denoised into OUTPUT: the
//       RMS distance to the cube surface went down.
// Prints one "key: value" line per measure, then "PASS" or one "FAIL: ..."
// line per failed check. Exit status: 0 pass, 1 a check failed, 2 error.

#include <sodt_io/io.h>
#include <sodt_io/mesh.h>
#include <sodt_io/metrics.h>
#include <sodt/mesh/output.h>

#include <wrap/io_trimesh/export_ply.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

namespace {

using Mesh = sodt::MeshF;

int vertexIndex(const Mesh& m, const Mesh::VertexType* v) { return int(v - &m.vert[0]); }

/// The test's face selection: faces whose centroid x is below the median.
std::vector<char> halfFaceSelection(const Mesh& m) {
  std::vector<float> cx(m.face.size());
  for (size_t f = 0; f < m.face.size(); ++f)
    cx[f] = (m.face[f].cP(0)[0] + m.face[f].cP(1)[0] + m.face[f].cP(2)[0]) / 3.0f;
  std::vector<float> sorted = cx;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const float median = sorted.empty() ? 0.0f : sorted[sorted.size() / 2];
  std::vector<char> sel(m.face.size());
  for (size_t f = 0; f < m.face.size(); ++f) sel[f] = cx[f] < median;
  return sel;
}

/// Vertices all of whose faces are selected (what the plugin derives from a
/// face selection); vertices without faces count as unselected.
std::vector<char> strictVertexSelection(const Mesh& m, const std::vector<char>& faceSel) {
  std::vector<char> any(m.vert.size(), 0), all(m.vert.size(), 1);
  for (size_t f = 0; f < m.face.size(); ++f)
    for (int j = 0; j < 3; ++j) {
      const int v = vertexIndex(m, m.face[f].cV(j));
      any[v] = 1;
      if (!faceSel[f]) all[v] = 0;
    }
  for (size_t v = 0; v < m.vert.size(); ++v) all[v] = all[v] && any[v];
  return all;
}

/// Common checks of an input/output pair; appends failures.
void checkSameMesh(const Mesh& in, const Mesh& out, std::vector<std::string>& failures) {
  std::printf("vertices: %d -> %d\n", in.vn, out.vn);
  std::printf("faces: %d -> %d\n", in.fn, out.fn);
  if (in.vn != out.vn) failures.push_back("the vertex count changed");
  if (in.fn != out.fn) failures.push_back("the face count changed");
  if (!failures.empty()) return;
  // Both meshes are compact after loading, so index i is the same element.
  bool sameFaces = true;
  for (int f = 0; f < in.fn; ++f)
    for (int j = 0; j < 3; ++j)
      if (vertexIndex(in, in.face[f].cV(j)) != vertexIndex(out, out.face[f].cV(j))) sameFaces = false;
  if (!sameFaces) failures.push_back("the faces reference different vertices");
}

bool moved(const Mesh& in, const Mesh& out, int v) { return in.vert[v].cP() != out.vert[v].cP(); }

int report(const std::vector<std::string>& failures) {
  for (const std::string& f : failures) std::printf("FAIL: %s\n", f.c_str());
  if (failures.empty()) std::printf("PASS\n");
  return failures.empty() ? 0 : 1;
}

int checkSmoothed(const std::string& inPath, const std::string& outPath) {
  Mesh in, out;
  sodt::loadMesh(inPath, in);
  sodt::loadMesh(outPath, out);
  std::vector<std::string> failures;
  checkSameMesh(in, out, failures);
  if (failures.empty()) {
    int n = 0;
    double maxMove = 0;
    for (int v = 0; v < in.vn; ++v) {
      if (moved(in, out, v)) ++n;
      maxMove = std::max(maxMove, double((in.vert[v].cP() - out.vert[v].cP()).Norm()));
    }
    const double diag = sodt::bboxDiagonal(in);
    std::printf("moved vertices: %d of %d\n", n, in.vn);
    std::printf("max displacement / bbox diagonal: %.6g\n", diag > 0 ? maxMove / diag : 0.0);
    if (n == 0) failures.push_back("no vertex moved");
  }
  const sodt::AngleStats a = sodt::computeAngleStats(in);
  const sodt::AngleStats b = sodt::computeAngleStats(out);
  std::printf("min angle (deg): %.4f -> %.4f\n", a.minDeg, b.minDeg);
  std::printf("angles below 30 deg: %.3f%% -> %.3f%%\n", 100 * a.fracBelow30, 100 * b.fracBelow30);
  if (!(b.minDeg > a.minDeg)) failures.push_back("the minimum angle did not improve");
  return report(failures);
}

int writeHalfSelected(const std::string& inPath, const std::string& outPath) {
  Mesh m;
  sodt::loadMesh(inPath, m);
  const std::vector<char> sel = halfFaceSelection(m);
  int n = 0;
  for (size_t f = 0; f < m.face.size(); ++f) {
    m.face[f].ClearS();
    if (sel[f]) {
      m.face[f].SetS();
      ++n;
    }
  }
  const int err = vcg::tri::io::ExporterPLY<Mesh>::Save(m, outPath.c_str(),
                                                         vcg::tri::io::Mask::IOM_FACEFLAGS, true);
  if (err != 0) {
    std::fprintf(stderr, "cannot write '%s': %s\n", outPath.c_str(),
                 vcg::tri::io::ExporterPLY<Mesh>::ErrorMsg(err));
    return 2;
  }
  std::printf("selected faces: %d of %d\n", n, m.fn);
  return 0;
}

int checkSelection(const std::string& inPath, const std::string& outPath) {
  Mesh in, out;
  sodt::loadMesh(inPath, in);
  sodt::loadMesh(outPath, out);
  std::vector<std::string> failures;
  checkSameMesh(in, out, failures);
  if (failures.empty()) {
    const std::vector<char> vsel = strictVertexSelection(in, halfFaceSelection(in));
    int selected = 0, movedIn = 0, movedOut = 0;
    for (int v = 0; v < in.vn; ++v) {
      selected += vsel[size_t(v)];
      if (moved(in, out, v)) ++(vsel[size_t(v)] ? movedIn : movedOut);
    }
    std::printf("vertices with all faces selected: %d of %d\n", selected, in.vn);
    std::printf("moved inside the selection: %d\n", movedIn);
    std::printf("moved outside the selection: %d\n", movedOut);
    if (movedIn == 0) failures.push_back("no selected vertex moved");
    if (movedOut != 0) failures.push_back("vertices outside the selection moved");
  }
  return report(failures);
}

/// Options of --classes.
struct ClassCheck {
  std::string codes = "0123";  ///< allowed class codes, as digits
  int corners = -1;            ///< expected number of code-2 vertices; -1: any
  bool cubeCorners = false;    ///< the code-2 vertices are INPUT's (+-1, +-1, +-1)
  bool unmoved = false;        ///< every vertex bit-identical to INPUT
  bool selectedFeatures = false;  ///< exactly the code 1 and 2 vertices are selected
};

/// True when all three coordinates are exactly +-1.
bool isCubeCorner(const Mesh::CoordType& p) {
  return std::abs(p[0]) == 1.0f && std::abs(p[1]) == 1.0f && std::abs(p[2]) == 1.0f;
}

/// How many coordinates are exactly +-1 (1: face, 2: cube edge, 3: corner).
int unitCoordinates(const Mesh::CoordType& p) {
  return int(std::abs(p[0]) == 1.0f) + int(std::abs(p[1]) == 1.0f) + int(std::abs(p[2]) == 1.0f);
}

/// Euclidean distance from p to the surface of the cube [-1,1]^3.
double cubeDistance(const Mesh::CoordType& p) {
  const double a[3] = {std::abs(double(p[0])), std::abs(double(p[1])), std::abs(double(p[2]))};
  const double m = std::max(a[0], std::max(a[1], a[2]));
  if (m <= 1) return 1 - m;
  double s = 0;
  for (double c : a) s += std::max(c - 1, 0.0) * std::max(c - 1, 0.0);
  return std::sqrt(s);
}

double rmsCubeDistance(const Mesh& m) {
  double s = 0;
  for (int v = 0; v < m.vn; ++v) s += cubeDistance(m.vert[v].cP()) * cubeDistance(m.vert[v].cP());
  return m.vn ? std::sqrt(s / m.vn) : 0.0;
}

int checkClasses(const std::string& inPath, const std::string& outPath, const ClassCheck& opt) {
  Mesh in, out;
  sodt::LoadInfo info;
  sodt::loadMesh(inPath, in);
  sodt::loadMesh(outPath, out, &info);
  std::vector<std::string> failures;
  checkSameMesh(in, out, failures);
  if (!info.vertexQuality) failures.push_back("the output has no vertex quality (saved without -m vq?)");
  if (!info.vertexColor) failures.push_back("the output has no vertex colour (saved without -m vc?)");
  if (!failures.empty()) return report(failures);

  int count[4] = {0, 0, 0, 0};
  int badCode = 0, badColour = 0, movedCount = 0, cornersElsewhere = 0, wrongSelection = 0, selected = 0;
  for (int v = 0; v < out.vn; ++v) {
    const float q = out.vert[v].Q();
    const int code = int(q);
    if (float(code) != q || code < 0 || code > 3 ||
        opt.codes.find(char('0' + code)) == std::string::npos) {
      if (++badCode <= 5) std::printf("vertex %d: quality %.9g is not an allowed class code\n", v, double(q));
      continue;
    }
    ++count[code];
    const vcg::Color4b want = sodt::classColor(static_cast<sodt::VertexClass>(code));
    if (out.vert[v].C() != want && ++badColour <= 5)
      std::printf("vertex %d: class %d has colour (%d, %d, %d, %d)\n", v, code, out.vert[v].C()[0],
                  out.vert[v].C()[1], out.vert[v].C()[2], out.vert[v].C()[3]);
    if (moved(in, out, v)) ++movedCount;
    if (code == 2 && !isCubeCorner(in.vert[v].cP())) ++cornersElsewhere;
    const bool feature = code == 1 || code == 2;
    if (out.vert[v].IsS()) ++selected;
    if (out.vert[v].IsS() != feature) ++wrongSelection;
  }
  std::printf("class counts (0 smooth, 1 crease, 2 corner, 3 fixed): %d %d %d %d\n", count[0], count[1],
              count[2], count[3]);
  std::printf("vertices with a bad code: %d, with a wrong colour: %d, moved: %d\n", badCode, badColour,
              movedCount);
  if (badCode) failures.push_back("some vertex quality is not an allowed class code (" + opt.codes + ")");
  if (badColour) failures.push_back("some vertex colour differs from the palette colour of its class");
  if (opt.corners >= 0 && count[2] != opt.corners)
    failures.push_back("expected " + std::to_string(opt.corners) + " corner vertices, found " +
                       std::to_string(count[2]));
  if (opt.cubeCorners && cornersElsewhere)
    failures.push_back(std::to_string(cornersElsewhere) + " corner vertices are not cube corners");
  if (opt.unmoved && movedCount) failures.push_back("vertices moved");
  if (opt.selectedFeatures) {
    std::printf("selected vertices: %d, selection differing from crease/corner: %d\n", selected,
                wrongSelection);
    if (!info.vertexSelection) failures.push_back("the output has no vertex flags (saved without -m vf?)");
    else if (selected == 0) failures.push_back("no vertex is selected");
    else if (wrongSelection)
      failures.push_back("the selection is not exactly the crease and corner vertices");
  }
  return report(failures);
}

int checkCubeFeature(const std::string& inPath, const std::string& outPath) {
  Mesh in, out;
  sodt::loadMesh(inPath, in);
  sodt::loadMesh(outPath, out);
  std::vector<std::string> failures;
  checkSameMesh(in, out, failures);
  if (!failures.empty()) return report(failures);
  // "On the surface within float rounding": a few units in the last place at 1.
  const double tol = 4 * double(FLT_EPSILON);
  int corners = 0, cornersMoved = 0, edgeVertices = 0, offEdge = 0, offSurface = 0, movedCount = 0;
  double maxDev = 0;
  for (int v = 0; v < in.vn; ++v) {
    const Mesh::CoordType& a = in.vert[v].cP();
    const Mesh::CoordType& b = out.vert[v].cP();
    if (moved(in, out, v)) ++movedCount;
    const int unit = unitCoordinates(a);
    if (unit == 3) {
      ++corners;
      if (moved(in, out, v)) ++cornersMoved;
    }
    const double m =
        std::max(std::abs(double(b[0])), std::max(std::abs(double(b[1])), std::abs(double(b[2]))));
    maxDev = std::max(maxDev, std::abs(m - 1));
    if (std::abs(m - 1) > tol) ++offSurface;
    if (unit == 2) {
      ++edgeVertices;
      // The same two coordinates stay +-1 (within rounding).
      for (int k = 0; k < 3; ++k)
        if (std::abs(a[k]) == 1.0f && std::abs(double(b[k]) - double(a[k])) > tol) {
          ++offEdge;
          break;
        }
    }
  }
  std::printf("cube corners: %d, moved: %d\n", corners, cornersMoved);
  std::printf("moved vertices: %d of %d\n", movedCount, in.vn);
  std::printf("max | max|coordinate| - 1 |: %.3g (tolerance %.3g), vertices off the surface: %d\n", maxDev,
              tol, offSurface);
  std::printf("vertices on cube edges: %d, left their edge: %d\n", edgeVertices, offEdge);
  const sodt::AngleStats sa = sodt::computeAngleStats(in);
  const sodt::AngleStats sb = sodt::computeAngleStats(out);
  std::printf("min angle (deg): %.4f -> %.4f\n", sa.minDeg, sb.minDeg);
  if (corners != 8) failures.push_back("the input does not have the 8 corners of the cube [-1,1]^3");
  if (cornersMoved) failures.push_back("cube corners moved");
  if (offSurface) failures.push_back("vertices left the cube surface");
  if (offEdge) failures.push_back("vertices left their cube edge");
  if (movedCount == 0) failures.push_back("no vertex moved");
  if (!(sb.minDeg > sa.minDeg)) failures.push_back("the minimum angle did not improve");
  return report(failures);
}

int checkFlipped(const std::string& inPath, const std::string& outPath) {
  Mesh in, out;
  sodt::loadMesh(inPath, in);
  sodt::loadMesh(outPath, out);
  std::vector<std::string> failures;
  std::printf("vertices: %d -> %d\n", in.vn, out.vn);
  std::printf("faces: %d -> %d\n", in.fn, out.fn);
  if (in.vn != out.vn) failures.push_back("the vertex count changed");
  if (in.fn != out.fn) failures.push_back("the face count changed");
  if (!failures.empty()) return report(failures);
  int changed = 0, degenerate = 0;
  for (int f = 0; f < in.fn; ++f) {
    bool same = true;
    for (int j = 0; j < 3; ++j) same = same && vertexIndex(in, in.face[f].cV(j)) == vertexIndex(out, out.face[f].cV(j));
    if (!same) ++changed;
    const int a = vertexIndex(out, out.face[f].cV(0)), b = vertexIndex(out, out.face[f].cV(1)),
              c = vertexIndex(out, out.face[f].cV(2));
    if (a == b || b == c || c == a) ++degenerate;
  }
  const bool closedIn = sodt::isClosedOriented(in), closedOut = sodt::isClosedOriented(out);
  std::printf("faces with other vertices: %d of %d, repeating a vertex: %d\n", changed, in.fn, degenerate);
  std::printf("closed, oriented, edge-manifold: %s -> %s\n", closedIn ? "yes" : "no", closedOut ? "yes" : "no");
  const sodt::AngleStats a = sodt::computeAngleStats(in);
  const sodt::AngleStats b = sodt::computeAngleStats(out);
  std::printf("min angle (deg): %.4f -> %.4f\n", a.minDeg, b.minDeg);
  std::printf("angles below 30 deg: %.3f%% -> %.3f%%\n", 100 * a.fracBelow30, 100 * b.fracBelow30);
  if (changed == 0) failures.push_back("no face changed its vertices (no flip reached the output)");
  if (degenerate) failures.push_back("faces repeat a vertex");
  if (closedIn && !closedOut) failures.push_back("the closed oriented input is no longer closed and oriented");
  if (!(b.minDeg > a.minDeg)) failures.push_back("the minimum angle did not improve");
  return report(failures);
}

int checkCubeDenoise(const std::string& inPath, const std::string& outPath) {
  Mesh in, out;
  sodt::loadMesh(inPath, in);
  sodt::loadMesh(outPath, out);
  std::vector<std::string> failures;
  checkSameMesh(in, out, failures);
  if (!failures.empty()) return report(failures);
  const double a = rmsCubeDistance(in), b = rmsCubeDistance(out);
  std::printf("RMS distance to the cube surface: %.6g -> %.6g\n", a, b);
  if (!(b < a)) failures.push_back("the RMS distance to the cube did not decrease");
  return report(failures);
}

int run(int argc, char** argv) {
  if (argc == 3 && argv[1][0] != '-') return checkSmoothed(argv[1], argv[2]);
  if (argc == 4 && std::strcmp(argv[1], "--select-half") == 0) return writeHalfSelected(argv[2], argv[3]);
  if (argc == 4 && std::strcmp(argv[1], "--selection") == 0) return checkSelection(argv[2], argv[3]);
  if (argc == 4 && std::strcmp(argv[1], "--cube-feature") == 0) return checkCubeFeature(argv[2], argv[3]);
  if (argc == 4 && std::strcmp(argv[1], "--cube-denoise") == 0) return checkCubeDenoise(argv[2], argv[3]);
  if (argc == 4 && std::strcmp(argv[1], "--flipped") == 0) return checkFlipped(argv[2], argv[3]);
  if (argc >= 4 && std::strcmp(argv[1], "--classes") == 0) {
    ClassCheck opt;
    for (int i = 4; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--codes" && i + 1 < argc) opt.codes = argv[++i];
      else if (a == "--corners" && i + 1 < argc) opt.corners = std::stoi(argv[++i]);
      else if (a == "--cube-corners") opt.cubeCorners = true;
      else if (a == "--unmoved") opt.unmoved = true;
      else if (a == "--selected-features") opt.selectedFeatures = true;
      else {
        std::fprintf(stderr, "unknown --classes option '%s'\n", a.c_str());
        return 2;
      }
    }
    return checkClasses(argv[2], argv[3], opt);
  }
  std::fprintf(stderr,
               "usage: sodt_plugin_mesh_check INPUT.ply OUTPUT.ply\n"
               "       sodt_plugin_mesh_check --select-half INPUT.ply SELECTED.ply\n"
               "       sodt_plugin_mesh_check --selection INPUT.ply OUTPUT.ply\n"
               "       sodt_plugin_mesh_check --classes INPUT.ply OUTPUT.ply [--codes DIGITS] [--corners N]\n"
               "                              [--cube-corners] [--unmoved] [--selected-features]\n"
               "       sodt_plugin_mesh_check --cube-feature INPUT.ply OUTPUT.ply\n"
               "       sodt_plugin_mesh_check --cube-denoise INPUT.ply OUTPUT.ply\n"
               "       sodt_plugin_mesh_check --flipped INPUT.ply OUTPUT.ply\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
