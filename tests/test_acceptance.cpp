// SPDX-License-Identifier: GPL-3.0-or-later
// Acceptance checks on the shared real-world meshes: quality, distance,
// volume and orientation after 20 sweeps. Without ../shared they are skipped
// with a notice, or fail when SODT_REQUIRE_SHARED=1 (CI sets it: the data
// must be there). SODT_SHARED_MESH_DIR in the environment overrides the
// folder the build found.
#include "test_mesh.h"

#include <sodt_io/corners.h>
#include <sodt_io/io.h>
#include <sodt_io/metrics.h>
#include <sodt_io/prebuilt.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <vector>
#include <string>

namespace {

std::string shared(const std::string& name) {
  const char* dir = std::getenv("SODT_SHARED_MESH_DIR");
  return std::string(dir && *dir ? dir : SODT_SHARED_MESH_DIR) + "/" + name;
}

bool sharedRequired() {
  const char* v = std::getenv("SODT_REQUIRE_SHARED");
  return v && std::string(v) == "1";
}

#define REQUIRE_SHARED(name)                                                                            \
  if (!sodt_test::fileExists(shared(name))) {                                                           \
    if (sharedRequired()) FAIL() << shared(name) << " is missing and SODT_REQUIRE_SHARED=1";           \
    GTEST_SKIP() << shared(name) << " not present (the shared meshes are not next to the checkout)"; \
  }

struct Outcome {
  sodt::AngleStats before, after;
  double volBefore = 0, volAfter = 0;
  bool closed = false;
  double hausdorffToInput = 0;
  long long inverted = 0;
  sodt::SodtStats stats;
  double volRel() const { return std::abs(volAfter - volBefore) / std::abs(volBefore); }
};

Outcome run(const std::string& file, sodt::Guard guard, sodt::MeshD* out = nullptr,
            sodt::Algorithm algorithm = sodt::Algorithm::Basic, sodt::Classification* cls = nullptr,
            bool flips = false) {
  sodt::MeshD m, ref;
  sodt::loadMesh(file, m);
  sodt::loadMesh(file, ref);
  Outcome o;
  o.before = sodt::computeAngleStats(m);
  const sodt::VolumeResult v0 = sodt::enclosedVolume(m);
  sodt::SodtParams p;
  p.guard = guard;
  p.iterations = 20;
  p.algorithm = algorithm;
  p.flips = flips;
  o.stats = sodt::SodtSmoother<sodt::MeshD>::Apply(m, p, nullptr, cls);
  o.after = sodt::computeAngleStats(m);
  o.closed = v0.closed;
  o.volBefore = v0.volume;
  o.volAfter = sodt::enclosedVolume(m).volume;
  o.hausdorffToInput = sodt::hausdorffRel(m, ref);
  o.inverted = sodt::countInvertedFaces(m, ref);
  if (out) vcg::tri::Append<sodt::MeshD, sodt::MeshD>::MeshCopy(*out, m);
  return o;
}

}  // namespace

TEST(Acceptance, MarchingCubesIsosurfaceMolA) {
  REQUIRE_SHARED("mol_a.ply");
  const Outcome o = run(shared("mol_a.ply"), sodt::Guard::Quality);
  ASSERT_TRUE(o.closed);
  EXPECT_LT(o.before.minDeg, 0.01);
  EXPECT_GE(o.after.minDeg, 15.0);
  EXPECT_LE(o.hausdorffToInput, 0.0015);
  EXPECT_LE(o.volRel(), 1e-5);
  EXPECT_EQ(o.inverted, 0);
  RecordProperty("min_angle_after", std::to_string(o.after.minDeg));
}

TEST(Acceptance, LiteralPaperUpdateFoldsMolA) {
  // Why the guards exist: the unguarded update inverts faces on this mesh.
  REQUIRE_SHARED("mol_a.ply");
  const Outcome o = run(shared("mol_a.ply"), sodt::Guard::None);
  EXPECT_GT(o.inverted, 0);
  EXPECT_LT(o.after.minDeg, 1.0);
}

TEST(Acceptance, SliveredSpotImprovesAndApproachesTheCleanMesh) {
  REQUIRE_SHARED("spot_badquality.ply");
  REQUIRE_SHARED("spot.ply");
  sodt::MeshD out, input, clean;
  const Outcome o = run(shared("spot_badquality.ply"), sodt::Guard::Quality, &out);
  sodt::loadMesh(shared("spot_badquality.ply"), input);
  sodt::loadMesh(shared("spot.ply"), clean);
  EXPECT_EQ(o.inverted, 0);
  EXPECT_GT(o.after.minDeg, o.before.minDeg + 10);
  EXPECT_LE(sodt::hausdorffRel(out, clean), sodt::hausdorffRel(input, clean));
}

TEST(Acceptance, FandiskMinimumAngleDoesNotDrop) {
  REQUIRE_SHARED("fandisk.ply");
  const Outcome o = run(shared("fandisk.ply"), sodt::Guard::Quality);
  EXPECT_GE(o.after.minDeg, o.before.minDeg);
  EXPECT_EQ(o.inverted, 0);
}

TEST(Acceptance, OpenAneurysmKeepsItsBoundary) {
  REQUIRE_SHARED("aneurysm_open.ply");
  sodt::MeshD in, out;
  sodt::loadMesh(shared("aneurysm_open.ply"), in);
  const Outcome o = run(shared("aneurysm_open.ply"), sodt::Guard::Quality, &out);
  EXPECT_FALSE(o.closed);
  EXPECT_GT(o.stats.fixedBoundary, 0);
  const sodt::RingTopology t = sodt::buildRingTopology(in);
  for (std::size_t i = 0; i < in.vert.size(); ++i)
    if (t.kind[i] == sodt::VertexKind::Boundary) { EXPECT_EQ(out.vert[i].cP(), in.vert[i].cP()) << i; }
  EXPECT_EQ(o.inverted, 0);
  EXPECT_GE(o.after.minDeg, o.before.minDeg);
}


TEST(Acceptance, FandiskAlgorithm2KeepsCornersAndShape) {
  REQUIRE_SHARED("fandisk.ply");
  sodt::MeshD out, in;
  sodt::loadMesh(shared("fandisk.ply"), in);
  sodt::Classification cls;
  const Outcome o = run(shared("fandisk.ply"), sodt::Guard::Quality, &out, sodt::Algorithm::Feature, &cls);
  EXPECT_GT(cls.corner(), 0);
  for (std::size_t i = 0; i < in.vert.size(); ++i)
    if (cls.cls[i] == sodt::VertexClass::Corner) { EXPECT_EQ(out.vert[i].cP(), in.vert[i].cP()) << i; }
  EXPECT_LE(o.hausdorffToInput, 0.003);
  EXPECT_EQ(o.inverted, 0);
  EXPECT_GE(o.after.minDeg, 25.0);
}

TEST(Acceptance, NoisyFandiskAlgorithm3RemovesNoiseKeepsCreases) {
  REQUIRE_SHARED("fandisk_noise0.2.ply");
  REQUIRE_SHARED("fandisk.ply");
  sodt::MeshD out, noisy, clean;
  sodt::loadMesh(shared("fandisk_noise0.2.ply"), noisy);
  sodt::loadMesh(shared("fandisk.ply"), clean);
  const Outcome o = run(shared("fandisk_noise0.2.ply"), sodt::Guard::Quality, &out, sodt::Algorithm::Denoise);
  const double before = sodt::surfaceDistance(noisy, clean).meanRel;
  const double after = sodt::surfaceDistance(out, clean).meanRel;
  EXPECT_LE(after, 0.6 * before);
  EXPECT_GE(o.after.minDeg, 18.4);
  EXPECT_EQ(o.inverted, 0);
  // Creases stay sharp: the edges that are sharp (> 60 deg) in the clean mesh
  // are still sharp, and closer to their clean angle than in the noisy input.
  const auto dc = sodt_test::dihedralAngles(clean), dn = sodt_test::dihedralAngles(noisy), dm = sodt_test::dihedralAngles(out);
  int sharp = 0, kept = 0;
  double errNoisy = 0, errOut = 0;
  for (const auto& kv : dc) {
    if (kv.second <= 60) continue;
    ++sharp;
    kept += dm.at(kv.first) > 60;
    errNoisy += std::abs(dn.at(kv.first) - kv.second);
    errOut += std::abs(dm.at(kv.first) - kv.second);
  }
  ASSERT_GT(sharp, 0);
  EXPECT_GE(double(kept) / sharp, 0.85);
  EXPECT_LT(errOut, 0.8 * errNoisy);
}

TEST(Acceptance, HingeAlgorithm2StaysOnTheCadSurface) {
  REQUIRE_SHARED("hinge.ply");
  const Outcome o = run(shared("hinge.ply"), sodt::Guard::Quality, nullptr, sodt::Algorithm::Feature);
  EXPECT_EQ(o.inverted, 0);
  EXPECT_LE(o.hausdorffToInput, 0.005);
  EXPECT_GE(o.after.minDeg, o.before.minDeg);
}

TEST(Acceptance, MolAWithFlips) {
  REQUIRE_SHARED("mol_a.ply");
  const Outcome o = run(shared("mol_a.ply"), sodt::Guard::Quality, nullptr, sodt::Algorithm::Basic, nullptr, true);
  EXPECT_GT(o.stats.flips, 0);
  EXPECT_GE(o.after.minDeg, 28.0);
  EXPECT_LE(o.after.fracBelow30, 0.001);
  EXPECT_LE(o.hausdorffToInput, 0.0015);
  EXPECT_LE(o.volRel(), 1e-4);
}

TEST(Acceptance, FandiskAlgorithm2WithFlipsNeverFlipsACrease) {
  REQUIRE_SHARED("fandisk.ply");
  sodt::MeshD out, in;
  sodt::loadMesh(shared("fandisk.ply"), in);
  sodt::Classification cls;
  const Outcome o =
      run(shared("fandisk.ply"), sodt::Guard::Quality, &out, sodt::Algorithm::Feature, &cls, true);
  EXPECT_GT(o.stats.flips, 0);
  EXPECT_GE(o.after.minDeg, 28.0);
  EXPECT_LE(o.hausdorffToInput, 0.003);
  for (std::size_t i = 0; i < in.vert.size(); ++i)
    if (cls.cls[i] == sodt::VertexClass::Corner) { EXPECT_EQ(out.vert[i].cP(), in.vert[i].cP()) << i; }
  const auto after = sodt_test::dihedralAngles(out);
  int creases = 0;
  for (const auto& kv : sodt_test::dihedralAngles(in)) {
    if (kv.second <= 30) continue;
    ++creases;
    EXPECT_TRUE(after.count(kv.first)) << "crease edge " << kv.first.first << "-" << kv.first.second << " flipped";
  }
  EXPECT_GT(creases, 0);
}

TEST(Acceptance, SliveredSpotWithFlips) {
  REQUIRE_SHARED("spot_badquality.ply");
  REQUIRE_SHARED("spot.ply");
  sodt::MeshD out, input, clean;
  const Outcome o = run(shared("spot_badquality.ply"), sodt::Guard::Quality, &out, sodt::Algorithm::Basic, nullptr, true);
  sodt::loadMesh(shared("spot_badquality.ply"), input);
  sodt::loadMesh(shared("spot.ply"), clean);
  EXPECT_GE(o.after.minDeg, 15.0);
  EXPECT_LE(sodt::hausdorffRel(out, clean), sodt::hausdorffRel(input, clean));
  // Flips obey the deviation guard as moves do: the output stays within the
  // order of the 0.1% bound of the input (flipping across the dents the
  // damage left would lift the surface about 0.3% off it).
  const double toInput = sodt::hausdorffRel(out, input);
  std::printf("spot_badquality + flips: %.2f deg, Hausdorff to input %.3f%%, to spot.ply %.3f%%\n", o.after.minDeg,
              100 * toInput, 100 * sodt::hausdorffRel(out, clean));
  EXPECT_LT(toInput, 0.0025);
}

TEST(Acceptance, RepairKeepsTheBoundBothWays) {
  // The repair's changes keep the input near the faces they replace
  // covered, as the sweeps' cover does: the sampled two-way distance stays
  // within 1.5 bounds (spot_badquality reached 1.62 when only the point a
  // change removed was checked), and no face ends facing away from the
  // input under it.
  REQUIRE_SHARED("spot_badquality.ply");
  REQUIRE_SHARED("hinge.ply");
  for (const auto& c : {std::make_pair("spot_badquality.ply", sodt::Algorithm::Basic),
                        std::make_pair("hinge.ply", sodt::Algorithm::Feature)}) {
    sodt::MeshD m, input;
    sodt::loadMesh(shared(c.first), m);
    sodt::loadMesh(shared(c.first), input);
    sodt::SodtParams p;
    p.algorithm = c.second;
    p.flips = true;
    p.repair = true;
    const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
    const double d = sodt::hausdorffRel(m, input);
    std::printf("%s --flips --repair: %d vertices added, %d removed, Hausdorff %.4f%% (bound %.2f%%)\n", c.first,
                s.verticesAdded, s.verticesRemoved, 100 * d, 100 * p.maxDeviationRel);
    EXPECT_GT(s.verticesAdded + s.verticesRemoved, 0) << c.first;
    EXPECT_LE(d, 1.5 * p.maxDeviationRel) << c.first;
    EXPECT_EQ(sodt::countInvertedFaces(m, input), 0) << c.first;
  }
}

TEST(Acceptance, SpotBasicMakesNoSharpEdgesBeyondTheFaceTurn) {
  // Basic has no feature handling: near spot's ridges its guarded moves
  // turned faces by up to 76 degrees from their input orientation when
  // only folds were refused (a 90-degree bound), making edges sharper than
  // 60 degrees where the input's were below 30. The default bound keeps
  // every face within it (the reported largest turn), makes no such edge,
  // and costs no smallest angle here.
  REQUIRE_SHARED("spot.ply");
  double minDeg[2] = {0, 0};
  for (int bounded = 0; bounded < 2; ++bounded) {
    sodt::MeshD m;
    sodt::loadMesh(shared("spot.ply"), m);
    const auto before = sodt_test::dihedralAngles(m);
    sodt::SodtParams p;
    p.algorithm = sodt::Algorithm::Basic;
    if (!bounded) p.maxFaceTurnDeg = 90;
    const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
    int sharpened = 0;
    for (const auto& kv : sodt_test::dihedralAngles(m)) sharpened += kv.second > 60 && before.at(kv.first) <= 30;
    minDeg[bounded] = sodt::computeAngleStats(m).minDeg;
    if (bounded) {
      EXPECT_LT(p.maxFaceTurnDeg, 60);
      EXPECT_LE(s.maxFaceTurnDeg, p.maxFaceTurnDeg + 1e-9);
      EXPECT_EQ(sharpened, 0);
    } else {  // the fixture shows what the bound is for
      EXPECT_GT(s.maxFaceTurnDeg, 70);
      EXPECT_GT(sharpened, 0);
    }
  }
  EXPECT_GE(minDeg[1], minDeg[0] - 1e-9);
}

TEST(Acceptance, OpenAneurysmBorderSlidesAndKeepsItsLength) {
  REQUIRE_SHARED("aneurysm_open.ply");
  sodt::MeshD in, fixed, sliding;
  sodt::loadMesh(shared("aneurysm_open.ply"), in);
  sodt::loadMesh(shared("aneurysm_open.ply"), fixed);
  sodt::loadMesh(shared("aneurysm_open.ply"), sliding);
  sodt::SodtParams p;  // `sodt smooth --flips`: basic, 20 sweeps, the default guard and bound
  p.flips = true;
  sodt::SodtSmoother<sodt::MeshD>::Apply(fixed, p);
  p.slideBoundary = true;
  const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(sliding, p);
  EXPECT_GT(s.movedBoundary, s.slidingBoundary / 2);
  const double length = sodt::borderLength(in);
  EXPECT_LE(std::abs(sodt::borderLength(sliding) - length), 1e-3 * length);
  // The rim's smallest angle grows; the mesh's (far from the rim) does not drop.
  const sodt::RingTopology t = sodt::buildRingTopology(in);
  const auto rimMin = [&](const sodt::MeshD& m) {
    double lo = 180;
    for (const auto& f : m.face) {
      bool rim = false;
      for (int j = 0; j < 3; ++j) rim = rim || t.kind[f.cV(j) - &m.vert[0]] == sodt::VertexKind::Boundary;
      if (!rim) continue;
      const auto P = [&](int j) { return sodt::Vec3(f.cP(j)[0], f.cP(j)[1], f.cP(j)[2]); };
      lo = std::min(lo, sodt::triangleMinAngle(P(0), P(1), P(2)) * sodt::kRadToDeg);
    }
    return lo;
  };
  EXPECT_GT(rimMin(sliding), rimMin(fixed) + 1);
  EXPECT_GE(sodt::computeAngleStats(sliding).minDeg, sodt::computeAngleStats(fixed).minDeg);
}

TEST(Acceptance, SharedMeshesStayNearTheInputBothWays) {
  // The deviation bound held one way only (output near input) until the
  // cover: basic rounded fandisk's rims (0.21% of the diagonal both ways)
  // and bunny_closed's ears (0.21%), feature slid hinge's faces (0.20%).
  // With the input's sample points kept near the output the sampled
  // symmetric distance stays within 1.5 times the default bound of 0.1%.
  struct Run {
    const char* file;
    sodt::Algorithm algorithm;
    bool flips;
  };
  for (const Run& r : {Run{"fandisk.ply", sodt::Algorithm::Basic, false},
                       Run{"bunny_closed.ply", sodt::Algorithm::Basic, false},
                       Run{"hinge.ply", sodt::Algorithm::Feature, true}}) {
    REQUIRE_SHARED(r.file);
    sodt::MeshD in, out;
    sodt::loadMesh(shared(r.file), in);
    sodt::loadMesh(shared(r.file), out);
    sodt::SodtParams p;
    p.algorithm = r.algorithm;
    p.flips = r.flips;
    sodt::SodtSmoother<sodt::MeshD>::Apply(out, p);
    EXPECT_LE(sodt::surfaceDistance(in, out).maxRel, 1.5 * p.maxDeviationRel) << r.file;
  }
}

TEST(Acceptance, HingeRepairRisesWithItsBudget) {
  // hinge's coarse cylinders need nearly all of the default budget to lift
  // their slivers (`sodt smooth --algorithm feature --flips --repair
  // --repair-budget B`): measured 12.0 degrees at 100%, 18.9 at 200% and
  // the target, 30.1, at 300%, the default (254% more vertices; 25.05 with
  // a target of 25; 18.6 before the feature lines could coarsen). Plain rounds and the tide
  // both run and the better is kept; at 200% plain rounds alone spent the
  // budget in two rounds and ended at 5.0 degrees.
  REQUIRE_SHARED("hinge.ply");
  double last = 0;
  for (const auto& b : {std::make_pair(100.0, 11.5), std::make_pair(200.0, 18.0), std::make_pair(300.0, 30.0)}) {
    sodt::MeshD m;
    sodt::loadMesh(shared("hinge.ply"), m);
    const int nv = m.VN();
    sodt::SodtParams p;
    p.algorithm = sodt::Algorithm::Feature;
    p.flips = true;
    p.repair = true;
    p.repairBudgetPct = b.first;
    const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
    const double a = sodt::computeAngleStats(m).minDeg;
    EXPECT_GE(a, b.second) << "budget " << b.first;
    EXPECT_GT(a, last) << "budget " << b.first;
    EXPECT_LE(s.verticesAdded, b.first / 100 * nv) << "budget " << b.first;
    last = a;
  }
}

TEST(Acceptance, BunnyClosedRepairReachesTwentyFiveDegreesOutsideItsCorners) {
  // `sodt smooth --flips --repair`: caps on feature edges that no flip nor
  // split could open (the hole fill's) lose their short edge last, which
  // lifts the smallest angle outside the protected corners from 21.3 to
  // 25.0 degrees; the corners themselves (19.5) stay.
  REQUIRE_SHARED("bunny_closed.ply");
  sodt::MeshD m, input;
  sodt::loadMesh(shared("bunny_closed.ply"), m);
  sodt::loadMesh(shared("bunny_closed.ply"), input);
  sodt::SodtParams p;
  p.flips = true;
  p.repair = true;
  const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
  const sodt::ProtectedAngles c = sodt::protectedAngles(m, p.featureAngleDeg, p.repairAngleDeg);
  EXPECT_GE(c.minAngleElsewhereDeg, 25.0);
  EXPECT_LE(sodt::hausdorffRel(m, input), 1.5 * p.maxDeviationRel);
  EXPECT_EQ(sodt::countInvertedFaces(m, input), 0);
  EXPECT_EQ(m.VN(), input.VN() + s.verticesAdded - s.verticesRemoved);
}

TEST(Acceptance, SpotBadqualityRepairReachesItsTargetAngle) {
  // `sodt smooth --flips --repair`: after the sweeps one triangle stayed at
  // 19 degrees because splitting its long edge left the bound; splitting
  // its middle edge instead lifts it, and no triangle stays below 25
  // degrees, with at most 2% of the vertices added or removed.
  REQUIRE_SHARED("spot_badquality.ply");
  sodt::MeshD m;
  sodt::loadMesh(shared("spot_badquality.ply"), m);
  const int nv = m.VN();
  sodt::SodtParams p;
  p.flips = true;
  p.repair = true;
  p.repairAngleDeg = 25;
  const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
  EXPECT_GE(sodt::computeAngleStats(m).minDeg, p.repairAngleDeg);
  EXPECT_TRUE(s.belowTarget.empty());
  EXPECT_LE(s.verticesAdded + s.verticesRemoved, 0.02 * nv);
  EXPECT_EQ(m.VN(), nv + s.verticesAdded - s.verticesRemoved);
}

TEST(Acceptance, SpotBadqualityKeepsTheFirstStageWhereTheSecondRaisesNothing) {
  // With the default target of 30 degrees the repair works to 25 first,
  // then to 30. On spot_badquality the second stage leaves the smallest
  // angle at 25.2 degrees (the bound holds it) but took the Hausdorff
  // distance from 0.132% to 0.152% of the diagonal; it is not kept, so the
  // result is the 25-degree repair's, bit for bit.
  REQUIRE_SHARED("spot_badquality.ply");
  sodt::MeshD at25, at30, input;
  sodt::loadMesh(shared("spot_badquality.ply"), at25);
  sodt::loadMesh(shared("spot_badquality.ply"), at30);
  sodt::loadMesh(shared("spot_badquality.ply"), input);
  sodt::SodtParams p;
  p.flips = true;
  p.repair = true;
  ASSERT_GT(p.repairAngleDeg, 25.0);
  const sodt::SodtStats s30 = sodt::SodtSmoother<sodt::MeshD>::Apply(at30, p);
  p.repairAngleDeg = 25;
  sodt::SodtSmoother<sodt::MeshD>::Apply(at25, p);
  ASSERT_EQ(at25.VN(), at30.VN());
  ASSERT_EQ(at25.FN(), at30.FN());
  for (int v = 0; v < at25.VN(); ++v) EXPECT_EQ(at25.vert[v].cP(), at30.vert[v].cP()) << "vertex " << v;
  for (int f = 0; f < at25.FN(); ++f)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(at25.face[f].cV(j) - &at25.vert[0], at30.face[f].cV(j) - &at30.vert[0]);
  EXPECT_LE(sodt::hausdorffRel(at30, input), 1.5 * p.maxDeviationRel);
  // The faces between 25 and 30 degrees are listed as left below the target.
  EXPECT_FALSE(s30.belowTarget.empty());
}

TEST(Acceptance, HingeRepairReachesThirtyDegreesWithoutFolds) {
  // Issue 44's target for hinge (`sodt smooth --algorithm feature --flips
  // --repair`, the default target of 30 degrees): 30.1 degrees outside the
  // protected corners, within 1.5 times the bound both ways, no face
  // facing away and no edge folded sharper than 150 degrees (the input has
  // none). In one stage to 30 it ended at 11.5 degrees.
  REQUIRE_SHARED("hinge.ply");
  sodt::MeshD m, input;
  sodt::loadMesh(shared("hinge.ply"), m);
  sodt::loadMesh(shared("hinge.ply"), input);
  sodt::SodtParams p;
  p.algorithm = sodt::Algorithm::Feature;
  p.flips = true;
  p.repair = true;
  sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
  EXPECT_GE(sodt::protectedAngles(m, p.featureAngleDeg, p.repairAngleDeg).minAngleElsewhereDeg, 30.0);
  EXPECT_LE(sodt::hausdorffRel(m, input), 1.5 * p.maxDeviationRel);
  EXPECT_EQ(sodt::countInvertedFaces(m, input), 0);
  const auto sharpest = [](const sodt::MeshD& x) {
    double worst = 0;
    for (const auto& e : sodt_test::dihedralAngles(x)) worst = std::max(worst, e.second);
    return worst;
  };
  ASSERT_LT(sharpest(input), 150.0);
  EXPECT_LE(sharpest(m), 150.0);
}

TEST(Acceptance, SharedMeshesEndWithNoFaceFacingAway) {
  // Issue 42: the repair used to turn faces over and hide it. Each face of
  // the result against the input face under it, as the report counts
  // (after a repair the input face nearest its centroid, else its own; a
  // face over an input face folded onto its neighbours counts only when it
  // faces away from the surface there too): none faces away after
  // `--flips --repair`, `--repair` or `filtered`. bunny_closed kept one over its
  // hole fill's fold until the fold was undone before the repair.
  struct Run {
    const char* file;
    sodt::Algorithm algorithm;
  };
  for (const Run& r : {Run{"bunny_closed.ply", sodt::Algorithm::Basic}, Run{"spot_badquality.ply", sodt::Algorithm::Basic},
                       Run{"spot.ply", sodt::Algorithm::Basic}, Run{"mol_a.ply", sodt::Algorithm::Basic},
                       Run{"aneurysm_open.ply", sodt::Algorithm::Basic},
                       Run{"fandisk_noise0.2.ply", sodt::Algorithm::Basic},
                       Run{"fandisk.ply", sodt::Algorithm::Feature}, Run{"hinge.ply", sodt::Algorithm::Feature}}) {
    REQUIRE_SHARED(r.file);
    sodt::MeshD in;
    sodt::loadMesh(shared(r.file), in);
    for (int run = 0; run < 3; ++run) {
      if (run == 2 && std::string(r.file) != "bunny_closed.ply") continue;
      sodt::MeshD out;
      sodt::loadMesh(shared(r.file), out);
      sodt::SodtParams p;
      p.algorithm = run == 1 ? sodt::Algorithm::Filtered : r.algorithm;
      p.flips = run == 0;
      p.repair = run != 1;  // run 2: --repair alone
      const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(out, p);
      EXPECT_EQ(sodt::countInvertedFaces(out, in), 0) << r.file << " run " << run;
      EXPECT_EQ(s.facingAwayLeft, 0) << r.file << " run " << run;
    }
  }
}
