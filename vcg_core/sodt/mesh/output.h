// SPDX-License-Identifier: GPL-3.0-or-later
// Writes a vertex classification into a mesh: class codes as vertex quality,
// a fixed colour palette, and the selection of feature vertices.
#pragma once

#include "../maths/classify.h"

#include <vcg/complex/complex.h>

namespace sodt {

/// Colour of each class (RGB): smooth light grey, crease blue, corner red,
/// fixed (border, non-manifold) yellow. Fixed, so colours never depend on
/// which classes happen to be present.
inline vcg::Color4b classColor(VertexClass c) {
  switch (c) {
    case VertexClass::Smooth: return vcg::Color4b(200, 200, 200, 255);
    case VertexClass::Crease: return vcg::Color4b(30, 90, 230, 255);
    case VertexClass::Corner: return vcg::Color4b(230, 30, 30, 255);
    case VertexClass::Fixed: return vcg::Color4b(240, 200, 0, 255);
  }
  return vcg::Color4b(0, 0, 0, 255);
}

/// Writes the class code (0 smooth, 1 crease, 2 corner, 3 fixed) to the
/// quality of every live vertex.
/// \pre c was computed on m (same vertex vector). \throw vcg::MissingComponentException
///      when m has no per-vertex quality.
template <class MeshType>
void writeClassToQuality(MeshType& m, const Classification& c) {
  vcg::tri::RequirePerVertexQuality(m);
  for (std::size_t i = 0; i < m.vert.size() && i < c.cls.size(); ++i)
    if (!m.vert[i].IsD()) m.vert[i].Q() = static_cast<typename MeshType::VertexType::QualityType>(c.cls[i]);
}

/// Paints every live vertex with the colour of its class (classColor).
/// \throw vcg::MissingComponentException when m has no per-vertex colour.
template <class MeshType>
void colorizeByClass(MeshType& m, const Classification& c) {
  vcg::tri::RequirePerVertexColor(m);
  for (std::size_t i = 0; i < m.vert.size() && i < c.cls.size(); ++i)
    if (!m.vert[i].IsD()) m.vert[i].C() = classColor(c.cls[i]);
}

/// Selects exactly the crease and corner vertices (clears the others).
/// \return the number of selected vertices.
template <class MeshType>
int selectFeatureVertices(MeshType& m, const Classification& c) {
  int n = 0;
  for (std::size_t i = 0; i < m.vert.size() && i < c.cls.size(); ++i) {
    auto& v = m.vert[i];
    if (v.IsD()) continue;
    if (c.cls[i] == VertexClass::Crease || c.cls[i] == VertexClass::Corner) {
      v.SetS();
      ++n;
    } else {
      v.ClearS();
    }
  }
  return n;
}

}  // namespace sodt
