// SPDX-License-Identifier: GPL-3.0-or-later
// The sweep plan regrouped for the 4-lane kernel of lanes.h: which vertices
// are solved four at once and which one by one.
#pragma once

#include "../maths/lanes.h"
#include "../maths/topology.h"

#include <array>
#include <cstddef>
#include <vector>

namespace sodt {

/// Per phase of a SweepPlan, groups of lanes::kWidth vertices of equal
/// valence (3 to lanes::kMaxValence), each group complete where its last
/// member comes in the phase's order, then the vertices left over.
struct LanePlan {
  std::vector<int> vertex;      ///< lanes::kWidth per group
  std::vector<int> valence;     ///< per group
  std::vector<int> table;       ///< the groups' index tables (lanes::packGroup)
  std::vector<std::size_t> tableBegin;  ///< per group, into table
  std::vector<int> groupBegin;  ///< per phase, first group (phases + 1 entries)
  std::vector<int> rest;        ///< visited one by one
  std::vector<int> restBegin;   ///< per phase, into rest (phases + 1 entries)
};

/// Groups ahead whose centre and ring positions a lane visit asks the
/// cache for: on a mesh larger than the cache the kernel waits on its
/// gathers otherwise (a fifth of an unguarded sweep at 1M vertices).
constexpr int kPrefetchGroups = 4;

/// Only the vertices marked laneable go into groups (those whose update
/// the kernel computes). withFaces: the tables get the face rows of the
/// full-step test.
inline LanePlan planLanes(const SweepPlan& plan, const RingTopology& topo, const std::vector<char>& laneable,
                          bool withFaces) {
  LanePlan lp;
  const std::size_t phases = plan.phaseBegin.size() - 1;
  lp.vertex.reserve(plan.order.size());
  lp.table.reserve(plan.order.size() + (withFaces ? 2 : 1) * topo.ringIdx.size());
  lp.rest.reserve(plan.order.size() / 8);
  lp.groupBegin.push_back(0);
  lp.restBegin.push_back(0);
  std::array<std::vector<int>, lanes::kMaxValence + 1> open;  // per valence, a group being filled
  for (std::size_t c = 0; c < phases; ++c) {
    for (int j = plan.phaseBegin[c]; j < plan.phaseBegin[c + 1]; ++j) {
      const int v = plan.order[j], n = topo.ringSize(v);
      if (n < 3 || n > lanes::kMaxValence || !laneable[v]) {
        lp.rest.push_back(v);
        continue;
      }
      open[n].push_back(v);
      if (static_cast<int>(open[n].size()) == lanes::kWidth) {
        int begin[lanes::kWidth];
        for (int l = 0; l < lanes::kWidth; ++l) begin[l] = topo.ringBegin[open[n][l]];
        lp.tableBegin.push_back(lp.table.size());
        lp.table.resize(lp.table.size() + lanes::kWidth * (withFaces ? 2 * n + 1 : n + 1));
        lanes::packGroup(open[n].data(), topo.ringIdx.data(), begin, n, lp.table.data() + lp.tableBegin.back(),
                         withFaces ? topo.ringFace.data() : nullptr);
        lp.vertex.insert(lp.vertex.end(), open[n].begin(), open[n].end());
        lp.valence.push_back(n);
        open[n].clear();
      }
    }
    for (std::vector<int>& g : open) {
      lp.rest.insert(lp.rest.end(), g.begin(), g.end());
      g.clear();
    }
    lp.groupBegin.push_back(static_cast<int>(lp.valence.size()));
    lp.restBegin.push_back(static_cast<int>(lp.rest.size()));
  }
  return lp;
}

}  // namespace sodt
