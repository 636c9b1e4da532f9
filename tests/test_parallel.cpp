// SPDX-License-Identifier: GPL-3.0-or-later
// The coloured sweep: a valid colouring, results independent of the thread
// count, and skipped visits that change nothing.
#include "full_fixture.h"
#include "test_mesh.h"

#include <sodt_io/io.h>
#include <sodt_io/metrics.h>
#include <sodt_io/prebuilt.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

namespace {

using sodt::MeshD;

void loadBundled(MeshD& m, const std::string& name) {
  const std::string path = std::string(SODT_MESH_DIR) + "/" + name;
  ASSERT_TRUE(sodt_test::fileExists(path)) << path;
  sodt::loadMesh(path, m);
}

using sodt_test::positions;

std::vector<std::array<int, 3>> faces(const MeshD& m) { return sodt_test::faceIndices(m); }

/// Every counter of the run (threads aside).
std::vector<long long> counters(const sodt::SodtStats& s) {
  return {s.iterations,   s.moved,        s.backtracked,   s.rejected,     s.failedSolves, s.unchanged,
          s.fallbackMoves, s.activeVertices, s.flips,       s.returnedSweep, s.skipped,     s.smoothVertices,
          s.creaseVertices, s.cornerVertices};
}

}  // namespace

TEST(Colouring, NeighboursNeverShareAPhaseAndEveryVertexAppearsOnce) {
  MeshD m;
  loadBundled(m, "blobs_mc.ply");
  const sodt::RingTopology topo = sodt::buildRingTopology(m);
  std::vector<int> active;
  for (int i = 0; i < static_cast<int>(m.vert.size()); ++i)
    if (topo.kind[i] == sodt::VertexKind::Interior) active.push_back(i);
  int maxValence = 0;
  for (int v : active) maxValence = std::max(maxValence, topo.ringSize(v));
  // Phase of every vertex in the plan without tiles: its colour.
  std::vector<int> colour(m.vert.size(), -1);
  for (int tile : {0, 7, 500, 2048}) {
    const sodt::SweepPlan plan = sodt::colourVertices(topo, active, tile);
    const std::string what = "tile " + std::to_string(tile);
    ASSERT_EQ(plan.order.size(), active.size()) << what;
    EXPECT_EQ(std::set<int>(plan.order.begin(), plan.order.end()), std::set<int>(active.begin(), active.end()))
        << what;
    ASSERT_EQ(plan.phaseBegin.front(), 0) << what;
    ASSERT_EQ(plan.phaseBegin.back(), static_cast<int>(plan.order.size())) << what;
    std::vector<int> phase(m.vert.size(), -1);
    const int phases = static_cast<int>(plan.phaseBegin.size()) - 1;
    for (int c = 0; c < phases; ++c) {
      EXPECT_LT(plan.phaseBegin[c], plan.phaseBegin[c + 1]) << what << ": empty phase " << c;
      for (int j = plan.phaseBegin[c]; j < plan.phaseBegin[c + 1]; ++j) phase[plan.order[j]] = c;
    }
    int conflicts = 0;
    for (int v : active)
      for (int k = topo.ringBegin[v]; k < topo.ringBegin[v + 1]; ++k) conflicts += phase[topo.ringIdx[k]] == phase[v];
    EXPECT_EQ(conflicts, 0) << what;
    if (tile == 0) {
      colour = phase;
      EXPECT_GE(phases, 3);  // a triangle mesh needs at least three
      EXPECT_LE(phases, maxValence + 1);
      std::printf("blobs_mc: %zu vertices in %d colours (max valence %d)\n", active.size(), phases, maxValence);
      continue;
    }
    // One colour of one tile per phase, ascending within it; a tile's
    // phases in a row (tileBegin), each tile once.
    ASSERT_FALSE(plan.tileBegin.empty()) << what;
    ASSERT_EQ(plan.tileBegin.front(), 0) << what;
    ASSERT_EQ(plan.tileBegin.back(), phases) << what;
    int mixedPhases = 0, unsorted = 0, mixedTiles = 0;
    std::vector<int> tileOf(m.vert.size(), -1);  // plan tile of each vertex
    std::set<int> tilesSeen;
    const int planTiles = static_cast<int>(plan.tileBegin.size()) - 1;
    for (int t = 0; t < planTiles; ++t) {
      const int id = plan.order[plan.phaseBegin[plan.tileBegin[t]]] / tile;
      EXPECT_TRUE(tilesSeen.insert(id).second) << what << ": tile " << id << " twice";
      for (int c = plan.tileBegin[t]; c < plan.tileBegin[t + 1]; ++c) {
        const int first = plan.order[plan.phaseBegin[c]];
        for (int j = plan.phaseBegin[c]; j < plan.phaseBegin[c + 1]; ++j) {
          const int v = plan.order[j];
          tileOf[v] = t;
          mixedTiles += v / tile != id;
          mixedPhases += colour[v] != colour[first];
          unsorted += j > plan.phaseBegin[c] && v < plan.order[j - 1];
        }
      }
    }
    EXPECT_EQ(mixedPhases, 0) << what;
    EXPECT_EQ(unsorted, 0) << what;
    EXPECT_EQ(mixedTiles, 0) << what;
    // Groups of tiles: ascending tile index within a group, and no vertex
    // with a ring neighbour in another tile of its group.
    ASSERT_GE(plan.groupBegin.size(), 2u) << what;
    ASSERT_EQ(plan.groupBegin.front(), 0) << what;
    ASSERT_EQ(plan.groupBegin.back(), planTiles) << what;
    std::vector<int> groupOf(planTiles, -1);
    int groupOrder = 0;
    for (std::size_t g = 0; g + 1 < plan.groupBegin.size(); ++g)
      for (int t = plan.groupBegin[g]; t < plan.groupBegin[g + 1]; ++t) {
        groupOf[t] = static_cast<int>(g);
        groupOrder += t > plan.groupBegin[g] &&
                      plan.order[plan.phaseBegin[plan.tileBegin[t]]] / tile <
                          plan.order[plan.phaseBegin[plan.tileBegin[t - 1]]] / tile;
      }
    EXPECT_EQ(groupOrder, 0) << what;
    int touching = 0;
    for (int v : active)
      for (int k = topo.ringBegin[v]; k < topo.ringBegin[v + 1]; ++k) {
        const int u = topo.ringIdx[k];
        if (tileOf[u] < 0 || tileOf[u] == tileOf[v]) continue;
        touching += groupOf[tileOf[u]] == groupOf[tileOf[v]];
      }
    EXPECT_EQ(touching, 0) << what;
    const int colours = *std::max_element(colour.begin(), colour.end()) + 1;
    const int tiles = (active.back() / tile) - (active.front() / tile) + 1;
    EXPECT_LE(phases, tiles * colours) << what;
    EXPECT_LE(static_cast<int>(plan.groupBegin.size()) - 1, planTiles) << what;
    std::printf("%s: %d tiles in %zu groups\n", what.c_str(), planTiles, plan.groupBegin.size() - 1);
    EXPECT_GT(phases, tile < static_cast<int>(active.size()) / 2 ? colours : 0) << what;
  }
}

SODT_FULL_FIXTURE_TEST(Parallel, ResultsAreBitIdenticalForEveryThreadCount) {
  // blobs_mc's colours hold ~1000 vertices each, enough to be split between
  // threads; the guarded runs' phases (one colour of a tile of 2048) a few
  // hundred, split from 128 on. The small fixture takes every path too (the
  // sphere stays above the tile count), with fewer sweeps.
  const int sweeps = sodt_test::fullFixture() ? 10 : 3;
  MeshD input;
  loadBundled(input, "blobs_mc.ply");
  MeshD noisy;
  loadBundled(noisy, "cube_noisy.ply");
  // 40962 vertices: the guarded runs' plan has 20 tiles of 2048, enough for
  // every thread count here to sweep the tiles of a group at once (with
  // kMinParallelTiles = 4 per thread) instead of splitting each phase.
  MeshD sphere;
  sodt_test::makeSphere(sphere, 6);
  sodt_test::jitterOnSphere(sphere, 0.4, 5);
  {
    const sodt::RingTopology topo = sodt::buildRingTopology(sphere);
    std::vector<int> all(sphere.vert.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    const sodt::SweepPlan plan = sodt::colourVertices(topo, all, 2048);
    ASSERT_GE(plan.tileBegin.size(), 4u * 4 + 1);
    ASSERT_GE(plan.groupBegin.size(), 3u);
  }
  struct Case {
    MeshD* mesh;
    sodt::Algorithm algorithm;
    sodt::Guard guard;
    bool flips;
  };
  const std::vector<Case> cases = {
      {&input, sodt::Algorithm::Basic, sodt::Guard::Quality, false},
      {&input, sodt::Algorithm::Basic, sodt::Guard::None, false},
      {&input, sodt::Algorithm::Basic, sodt::Guard::Fold, true},
      {&input, sodt::Algorithm::Feature, sodt::Guard::Quality, false},
      {&input, sodt::Algorithm::Odt, sodt::Guard::Quality, false},
      {&noisy, sodt::Algorithm::Denoise, sodt::Guard::Quality, false},
      {&sphere, sodt::Algorithm::Basic, sodt::Guard::Quality, false},
      {&sphere, sodt::Algorithm::Feature, sodt::Guard::Fold, true},
  };
  for (const Case& c : cases) {
    std::vector<vcg::Point3d> refPos;
    std::vector<std::array<int, 3>> refFaces;
    std::vector<long long> refCounters;
    for (int threads : {1, 2, 3, 4}) {
      MeshD m;
      vcg::tri::Append<MeshD, MeshD>::MeshCopy(m, *c.mesh);
      sodt::SodtParams p;
      p.algorithm = c.algorithm;
      p.guard = c.guard;
      p.flips = c.flips;
      p.iterations = sweeps;
      p.threads = threads;
      const sodt::SodtStats s = sodt::SodtSmoother<MeshD>::Apply(m, p);
      const std::string what = std::string(sodt::toString(c.algorithm)) + "/" + sodt::toString(c.guard) +
                               (c.flips ? "/flips" : "") + " threads " + std::to_string(threads);
      if (threads == 1) {
        EXPECT_GT(s.moved + s.backtracked + s.fallbackMoves, 0) << what;
        refPos = positions(m);
        refFaces = faces(m);
        refCounters = counters(s);
        continue;
      }
#ifdef _OPENMP
      EXPECT_EQ(s.threads, threads) << what;
#endif
      EXPECT_TRUE(positions(m) == refPos) << what;  // exact, not approximate
      EXPECT_TRUE(faces(m) == refFaces) << what;
      EXPECT_EQ(counters(s), refCounters) << what;
    }
  }
}

TEST(Parallel, TwoThreadsKeepTheVolumeOfAClosedMesh) {
  MeshD m;
  sodt_test::makeSphere(m, 5);  // 10k vertices: colours large enough to split
  sodt_test::jitterOnSphere(m, 0.4, 7);
  const double v0 = sodt::enclosedVolume(m).volume;
  sodt::SodtParams p;
  p.guard = sodt::Guard::None;
  p.threads = 2;
  const sodt::SodtStats s = sodt::SodtSmoother<MeshD>::Apply(m, p);
  EXPECT_GT(s.moved, 10 * m.vn);
  EXPECT_LT(std::abs(sodt::enclosedVolume(m).volume - v0) / v0, 1e-12);
}

TEST(Parallel, SkippedVisitsChangeNothing) {
  // One call of K sweeps (which skips vertices whose stars did not change
  // since they last stayed put) must equal K calls of one sweep each (which
  // start without any memory and so visit everything). The deviation guard
  // is off: its reference, the input of the call, would differ between them.
  // So do the fold guard's input orientation of the faces and the reach box
  // (the input's bounding box), but on this flat grid no face turns far
  // enough, and no vertex comes near enough to the fixed border, for them
  // to matter.
  MeshD input;
  loadBundled(input, "plane_grid_open.ply");
  for (sodt::Guard g : {sodt::Guard::Quality}) {
    sodt::SodtParams p;
    p.guard = g;
    p.maxDeviationRel = 0;
    p.iterations = 12;
    MeshD once;
    vcg::tri::Append<MeshD, MeshD>::MeshCopy(once, input);
    const sodt::SodtStats s = sodt::SodtSmoother<MeshD>::Apply(once, p);
    EXPECT_GT(s.skipped, 0) << "the fixture should have vertices to skip";
    MeshD stepwise;
    vcg::tri::Append<MeshD, MeshD>::MeshCopy(stepwise, input);
    p.iterations = 1;
    long long rejected = 0, unchanged = 0;
    for (int k = 0; k < 12; ++k) {
      const sodt::SodtStats t = sodt::SodtSmoother<MeshD>::Apply(stepwise, p);
      EXPECT_EQ(t.skipped, 0);
      rejected += t.rejected;
      unchanged += t.unchanged;
    }
    EXPECT_TRUE(positions(once) == positions(stepwise)) << sodt::toString(g);
    EXPECT_EQ(s.rejected, rejected) << "skipped visits count under the outcome they repeat";
    EXPECT_EQ(s.unchanged, unchanged);
  }
}
