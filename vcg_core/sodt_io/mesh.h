// SPDX-License-Identifier: GPL-3.0-or-later
// The project's own vcg mesh types (float and double), used by the CLI, the
// tests and the benchmarks. The plugin uses MeshLab's CMeshO instead.
#pragma once

#include <vcg/complex/complex.h>

namespace sodt {

/// Triangle mesh with the components the core and the metrics need, with the
/// coordinate/normal precision chosen by the component templates, and
/// per-vertex texture coordinates (single precision, as in MeshLab's CMeshO
/// and in PLY files) that the loaders and writers carry with each vertex.
template <template <typename> class VertCoord, template <typename> class VertNormal,
          template <typename> class FaceNormal>
struct MeshTypes {
  class Vertex;
  class Face;
  struct UsedTypes : public vcg::UsedTypes<vcg::Use<Vertex>::template AsVertexType,
                                           vcg::Use<Face>::template AsFaceType> {};
  class Vertex : public vcg::Vertex<UsedTypes, VertCoord, VertNormal, vcg::vertex::Qualityf,
                                    vcg::vertex::Color4b, vcg::vertex::VFAdj, vcg::vertex::Mark,
                                    vcg::vertex::BitFlags, vcg::vertex::TexCoord2f> {};
  // TexCoord2f last: it then fills padding, 8 bytes a vertex where 16 elsewhere.
  class Face : public vcg::Face<UsedTypes, vcg::face::VertexRef, FaceNormal, vcg::face::FFAdj,
                                vcg::face::VFAdj, vcg::face::Mark, vcg::face::BitFlags> {};
  class Mesh : public vcg::tri::TriMesh<std::vector<Vertex>, std::vector<Face>> {};
};

/// Single precision, like MeshLab's CMeshO.
using MeshF = MeshTypes<vcg::vertex::Coord3f, vcg::vertex::Normal3f, vcg::face::Normal3f>::Mesh;
/// Double precision, used by the CLI.
using MeshD = MeshTypes<vcg::vertex::Coord3d, vcg::vertex::Normal3d, vcg::face::Normal3d>::Mesh;

}  // namespace sodt
