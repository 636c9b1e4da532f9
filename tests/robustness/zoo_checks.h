// SPDX-License-Identifier: GPL-3.0-or-later
// Measures shared by the robustness tests and the zoo tool: bitwise vertex
// comparison, edge-manifoldness counts, smallest angle over chosen faces.
#pragma once

#include "defect_zoo.h"

#include <sodt/maths/geometry.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

namespace sodt_zoo {

/// True when the two coordinates have the same bits (NaN payloads included).
inline bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
inline bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

template <class M>
bool sameBits(const typename M::CoordType& a, const typename M::CoordType& b) {
  return sameBits(a[0], b[0]) && sameBits(a[1], b[1]) && sameBits(a[2], b[2]);
}

/// True when every coordinate of every non-deleted vertex is finite.
template <class M>
bool allFinite(const M& m) {
  for (const auto& v : m.vert)
    if (!v.IsD() && !(std::isfinite(double(v.cP()[0])) && std::isfinite(double(v.cP()[1])) &&
                      std::isfinite(double(v.cP()[2]))))
      return false;
  return true;
}

/// Edge counts of the live faces (each undirected edge once).
struct EdgeReport {
  long long border = 0;        ///< edges with one face
  long long nonManifold = 0;   ///< edges with more than two faces
  long long misoriented = 0;   ///< two-face edges traversed in the same direction by both
  long long faces = 0;
  long long degenerateIndex = 0;  ///< faces with a repeated vertex
  bool notWorseThan(const EdgeReport& o) const {
    return border <= o.border && nonManifold <= o.nonManifold && misoriented <= o.misoriented &&
           faces == o.faces && degenerateIndex == o.degenerateIndex;
  }
};

template <class M>
EdgeReport edgeReport(const M& m) {
  EdgeReport r;
  std::vector<std::pair<std::pair<int, int>, int>> e;  // (min, max), +1 if min->max else -1
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    ++r.faces;
    int v[3];
    for (int j = 0; j < 3; ++j) v[j] = int(f.cV(j) - &m.vert[0]);
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      ++r.degenerateIndex;
      continue;
    }
    for (int j = 0; j < 3; ++j) {
      const int a = v[j], b = v[(j + 1) % 3];
      e.push_back({{std::min(a, b), std::max(a, b)}, a < b ? 1 : -1});
    }
  }
  std::sort(e.begin(), e.end());
  for (std::size_t i = 0; i < e.size();) {
    std::size_t j = i;
    int sum = 0;
    while (j < e.size() && e[j].first == e[i].first) sum += e[j++].second;
    const std::size_t n = j - i;
    if (n == 1) ++r.border;
    if (n > 2) ++r.nonManifold;
    if (n == 2 && sum != 0) ++r.misoriented;
    i = j;
  }
  return r;
}

/// Smallest angle (degrees) over the live faces whose flag in `use` is set
/// (all when `use` is empty); 180 when there is none.
template <class M>
double minAngleDeg(const M& m, const std::vector<char>& use) {
  double lo = 180;
  for (std::size_t f = 0; f < m.face.size(); ++f) {
    if (m.face[f].IsD() || (!use.empty() && !use[f])) continue;
    const auto p = [&](int j) { return sodt::Vec3::Construct(m.face[f].cP(j)); };
    lo = std::min(lo, sodt::triangleMinAngle(p(0), p(1), p(2)) * sodt::kRadToDeg);
  }
  return lo;
}

}  // namespace sodt_zoo
