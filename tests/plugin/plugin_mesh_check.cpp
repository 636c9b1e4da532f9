// SPDX-License-Identifier: GPL-3.0-or-later
// Compares a mesh before and after the plugin ran in meshlabserver (same
// vertices and faces, moved coordinates, larger smallest angle, selection kept).
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
// Prints one "key: value" line per measure, then "PASS" or one "FAIL: ..."
// line per failed check. Exit status: 0 pass, 1 a check failed, 2 error.

#include <sodt/io.h>
#include <sodt/mesh.h>
#include <sodt/metrics.h>

#include <wrap/io_trimesh/export_ply.h>

#include <algorithm>
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

int run(int argc, char** argv) {
  if (argc == 3 && argv[1][0] != '-') return checkSmoothed(argv[1], argv[2]);
  if (argc == 4 && std::strcmp(argv[1], "--select-half") == 0) return writeHalfSelected(argv[2], argv[3]);
  if (argc == 4 && std::strcmp(argv[1], "--selection") == 0) return checkSelection(argv[2], argv[3]);
  std::fprintf(stderr,
               "usage: sodt_plugin_mesh_check INPUT.ply OUTPUT.ply\n"
               "       sodt_plugin_mesh_check --select-half INPUT.ply SELECTED.ply\n"
               "       sodt_plugin_mesh_check --selection INPUT.ply OUTPUT.ply\n");
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
