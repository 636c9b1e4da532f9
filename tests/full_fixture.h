// SPDX-License-Identifier: GPL-3.0-or-later
// Tests with a small fixture for everyday runs and a full one for CI: the slow
// equivalence tests, which compare two code paths bit for bit.
#pragma once

#include <gtest/gtest.h>

namespace sodt_test {
namespace detail {
/// In a SODT_FULL_FIXTURE_TEST: 1 in the full run, 0 in the small one; -1 elsewhere.
inline int& fixtureRun() {
  static int run = -1;
  return run;
}
struct FixtureRun {
  explicit FixtureRun(bool full) { fixtureRun() = full ? 1 : 0; }
  ~FixtureRun() { fixtureRun() = -1; }
  FixtureRun(const FixtureRun&) = delete;
  FixtureRun& operator=(const FixtureRun&) = delete;
};
}  // namespace detail

/// Whether the SODT_FULL_FIXTURE_TEST running now is its full run.
/// Called anywhere else, it fails the test: that test would have no full run.
inline bool fullFixture() {
  if (detail::fixtureRun() < 0) ADD_FAILURE() << "fullFixture() outside a SODT_FULL_FIXTURE_TEST";
  return detail::fixtureRun() == 1;
}

}  // namespace sodt_test

/// A test that runs twice: as Suite.Name on its small fixture and as
/// SuiteFull.Name on its full one; sodt_test::fullFixture() tells the body
/// which. tests/CMakeLists.txt gives the *Full tests the ctest label "slow",
/// which `ctest -LE slow` leaves out and CI (scripts/run-tests.sh) runs.
/// The small fixture must still take the paths the test compares.
#define SODT_FULL_FIXTURE_TEST(Suite, Name)                  \
  static void sodtFixtureBody_##Suite##_##Name();            \
  TEST(Suite, Name) {                                        \
    const sodt_test::detail::FixtureRun run(false);          \
    sodtFixtureBody_##Suite##_##Name();                      \
  }                                                          \
  TEST(Suite##Full, Name) {                                  \
    const sodt_test::detail::FixtureRun run(true);           \
    sodtFixtureBody_##Suite##_##Name();                      \
  }                                                          \
  static void sodtFixtureBody_##Suite##_##Name()
