// SPDX-License-Identifier: GPL-3.0-or-later
// The core built without the AVX2 kernel, as on processors other than x86
// (SODT_NO_LANES is defined for this whole executable): it must compile,
// report no kernel and smooth with the scalar code.
#include "test_mesh.h"

#include <sodt_io/metrics.h>
#include <sodt/smoother.h>

#include <gtest/gtest.h>

#ifndef SODT_NO_LANES
#error "this test is built with SODT_NO_LANES"
#endif

TEST(NoLanes, ScalarBuildSmoothsWithoutTheKernel) {
  EXPECT_FALSE(sodt::lanes::available());
  for (sodt::Guard g : {sodt::Guard::None, sodt::Guard::Quality}) {
    sodt::MeshD m;
    sodt_test::makeSphere(m, 3);
    sodt_test::jitterOnSphere(m, 0.45, 11);
    const sodt::AngleStats before = sodt::computeAngleStats(m);
    sodt::SodtParams p;
    p.guard = g;
    p.iterations = 10;
    const sodt::SodtStats s = sodt::SodtSmoother<sodt::MeshD>::Apply(m, p);
    EXPECT_EQ(s.laneVisits, 0);
    EXPECT_GT(s.moved, 0);
    const sodt::AngleStats after = sodt::computeAngleStats(m);
    EXPECT_LT(after.fracBelow30, before.fracBelow30 / 2);
    if (g == sodt::Guard::Quality) { EXPECT_GT(after.minDeg, before.minDeg); }
  }
}
