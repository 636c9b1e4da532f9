// SPDX-License-Identifier: GPL-3.0-or-later
// The smoother's working copy of a vcg mesh: positions in double, faces and
// one-rings as index arrays, in a cache-friendly vertex order; read from the
// mesh before a run and written back after it.
#pragma once

#include "../maths/classify.h"
#include "../maths/geometry.h"
#include "normals.h"
#include "../params.h"
#include "../maths/topology.h"

#include <vcg/complex/allocate.h>
#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/topology.h>
#include <vcg/complex/complex.h>

#include <algorithm>
#include <string>
#include <vector>

namespace sodt {

/// A mesh as the sweeps see it. The working order of the vertices is
/// breadth-first over the faces, so that a vertex's neighbours lie near it
/// in memory (meshes refined by subdivision or merged from parts store them
/// far apart); everything indexes vertices in this order.
struct WorkingMesh {
  std::vector<int> order;      ///< working index -> index in m.vert
  std::vector<int> faceOrder;  ///< working face -> index in m.face
  FaceList faces;              ///< in working vertex indices
  std::vector<Vec3> pos;
  std::vector<char> deleted, selected;
  RingTopology topo;  ///< rebuilt after edge flips
  int reorientedFaces = 0;  ///< see SodtStats::reorientedFaces
  /// Faces of m (indices in m.face) left out of faces by dropCollapsed in
  /// loadWorkingMesh: writeBack deletes them from m.
  std::vector<int> droppedFaces;
};

/// Throws InvalidInput naming how many vertices of m have a NaN or infinite
/// coordinate, and the first.
template <class MeshType>
void checkFiniteCoordinates(const MeshType& m) {
  const int nv = static_cast<int>(m.vert.size());
  int nonFinite = 0, firstNonFinite = -1;
  for (int i = 0; i < nv; ++i)
    if (!m.vert[i].IsD() && !isFinite(Vec3::Construct(m.vert[i].cP())) && nonFinite++ == 0) firstNonFinite = i;
  if (nonFinite > 0)
    throw InvalidInput(std::to_string(nonFinite) + (nonFinite > 1 ? " vertices have" : " vertex has") +
                       " a non-finite coordinate (NaN or infinite; first: vertex " +
                       std::to_string(firstNonFinite) + "); the mesh was not changed");
}

/// The working copy of m; with selectedOnly, as makeFaceList. Inconsistent
/// winding would leave the vertices where it changes fixed: each component
/// with a conflict gets one winding first (the outward one when it is
/// closed, else its majority's; see orientCoherently), written back at the
/// end and counted in reorientedFaces. With dropCollapsed (a run that may
/// change the connectivity), faces whose corners are not three distinct
/// vertices are left out (of the selection with selectedOnly): they have
/// no area and cover nothing, but make their edges non-manifold, which
/// would pin the vertices around them (droppedFaces).
/// \throw InvalidInput for a mesh outside the sizes of checkMeshSize().
template <class MeshType>
WorkingMesh loadWorkingMesh(const MeshType& m, bool selectedOnly, bool dropCollapsed = false) {
  WorkingMesh w;
  const int nv = static_cast<int>(m.vert.size());
  w.faces = makeFaceList(m, selectedOnly);
  for (std::size_t f = 0; f < w.faces.tri.size() && dropCollapsed; ++f) {
    const std::array<int, 3>& t = w.faces.tri[f];
    if (w.faces.live[f] && w.faces.flippable[f] && (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])) {
      w.faces.live[f] = 0;
      w.droppedFaces.push_back(static_cast<int>(f));
    }
  }
  w.deleted.assign(nv, 0);
  for (int i = 0; i < nv; ++i) w.deleted[i] = m.vert[i].IsD();
  w.order = breadthFirstOrder(w.faces, w.deleted);
  std::vector<int> slot(nv);  // index in m.vert -> working index
  for (int i = 0; i < nv; ++i) slot[w.order[i]] = i;
  w.pos.assign(nv, Vec3(0, 0, 0));
  w.selected.assign(nv, 0);
  for (int i = 0; i < nv; ++i) {
    const auto& v = m.vert[w.order[i]];
    w.deleted[i] = v.IsD();
    w.selected[i] = v.IsS();
    if (!w.deleted[i]) w.pos[i] = Vec3::Construct(v.cP());
  }
  for (std::size_t f = 0; f < w.faces.tri.size(); ++f)
    if (w.faces.live[f])
      for (int& v : w.faces.tri[f]) v = slot[v];
  std::vector<int>().swap(slot);
  w.faceOrder = sortFacesByVertex(w.faces, nv);
  w.topo = buildRingTopology(w.faces, w.deleted);
  if (std::find(w.topo.kind.begin(), w.topo.kind.end(), VertexKind::NonManifold) != w.topo.kind.end()) {
    w.reorientedFaces = orientCoherently(w.faces, w.pos);
    if (w.reorientedFaces > 0) w.topo = buildRingTopology(w.faces, w.deleted);
  }
  checkMeshSize(surfaceDiagonal(w.pos, w.topo));
  return w;
}

/// Writes the working copy back into m: the faces when facesChanged (and
/// any adjacency the caller had computed, which they invalidate; the
/// dropped faces are deleted then), the
/// positions of the moved vertices, the bounding box, and the unit face and
/// vertex normals when present (writeNormals).
template <class MeshType>
void writeBack(MeshType& m, const WorkingMesh& w, const std::vector<int>& moved, bool facesChanged, int threads) {
  using ScalarType = typename MeshType::ScalarType;
  using CoordType = typename MeshType::CoordType;
  if (facesChanged) {
    for (int f : w.droppedFaces) vcg::tri::Allocator<MeshType>::DeleteFace(m, m.face[f]);
    for (std::size_t f = 0; f < w.faces.tri.size(); ++f)
      if (w.faces.live[f])
        for (int j = 0; j < 3; ++j) m.face[w.faceOrder[f]].V(j) = &m.vert[w.order[w.faces.tri[f][j]]];
    if (vcg::tri::HasFFAdjacency(m)) vcg::tri::UpdateTopology<MeshType>::FaceFace(m);
    if (vcg::tri::HasVFAdjacency(m)) vcg::tri::UpdateTopology<MeshType>::VertexFace(m);
  }
  for (int i : moved)
    m.vert[w.order[i]].P() = CoordType(ScalarType(w.pos[i][0]), ScalarType(w.pos[i][1]), ScalarType(w.pos[i][2]));
  vcg::tri::UpdateBounding<MeshType>::Box(m);
  writeNormals(m, w.faces, w.topo, w.pos, w.order, w.faceOrder, threads);
}

/// Makes room in m for what a repair added to w (vertices and faces past
/// nv0 and liveBefore.size(), appended to m) and deletes from m what it
/// removed (vertices flagged deleted, faces no longer live of those live
/// before, liveBefore, or added);
/// writeBack then writes them. New vertices are selected when selected is
/// set (a run on the selection).
template <class MeshType>
void resizeForRepair(MeshType& m, WorkingMesh& w, std::size_t nv0, const std::vector<char>& liveBefore,
                     bool selected) {
  using Alloc = vcg::tri::Allocator<MeshType>;
  const std::size_t nf0 = liveBefore.size();
  const std::size_t addV = w.pos.size() - nv0, addF = w.faces.tri.size() - nf0;
  if (addV > 0) {
    const std::size_t first = m.vert.size();
    Alloc::AddVertices(m, addV);
    for (std::size_t k = 0; k < addV; ++k) {
      w.order.push_back(static_cast<int>(first + k));
      if (selected) m.vert[first + k].SetS();
    }
  }
  if (addF > 0) {
    const std::size_t first = m.face.size();
    Alloc::AddFaces(m, addF);
    for (std::size_t k = 0; k < addF; ++k) w.faceOrder.push_back(static_cast<int>(first + k));
  }
  for (std::size_t i = 0; i < w.pos.size(); ++i)  // added vertices a later collapse removed too
    if (w.deleted[i] && !m.vert[w.order[i]].IsD()) Alloc::DeleteVertex(m, m.vert[w.order[i]]);
  for (std::size_t f = 0; f < w.faces.tri.size(); ++f)  // added faces a later collapse removed too
    if ((f >= nf0 || liveBefore[f]) && !w.faces.live[f]) Alloc::DeleteFace(m, m.face[w.faceOrder[f]]);
  w.selected.resize(w.pos.size(), selected ? 1 : 0);
}

/// cls (in working order) in the mesh's vertex order.
inline Classification inMeshOrder(const Classification& cls, const std::vector<int>& order) {
  const std::size_t nv = order.size();
  Classification out = cls;
  for (std::size_t i = 0; i < nv; ++i) out.cls[order[i]] = cls.cls[i];
  if (!cls.creaseDir.empty())
    for (std::size_t i = 0; i < nv; ++i) out.creaseDir[order[i]] = cls.creaseDir[i];
  else
    out.creaseDir.assign(nv, Vec3(0, 0, 0));
  return out;
}

}  // namespace sodt
