// SPDX-License-Identifier: GPL-3.0-or-later
// The last step of a guarded run: faces facing away from the input under
// them are mended by putting vertices back towards their input positions.
#include <sodt/guards/facing.h>
#include <sodt/guards/guarded_move.h>

#include <gtest/gtest.h>

#include <vector>

namespace {

using sodt::FaceList;
using sodt::Vec3;

/// Two sheets of n x n vertices a distance h apart, like the two sides of
/// a thin plate: the top one (vertices 0 .. n^2 - 1) at z = h facing +z,
/// the bottom one at z = 0 facing -z.
struct Plate {
  std::vector<Vec3> pos;
  FaceList faces;
  explicit Plate(int n = 5, double h = 0.05) {
    for (int sheet = 0; sheet < 2; ++sheet)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) pos.push_back(Vec3(i, j, sheet == 0 ? h : 0.0));
    for (int sheet = 0; sheet < 2; ++sheet)
      for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
          const int o = sheet * n * n, a = o + j * n + i, b = a + 1, c = a + n, d = c + 1;
          if (sheet == 0) {
            faces.tri.push_back({a, b, d});
            faces.tri.push_back({a, d, c});
          } else {
            faces.tri.push_back({a, d, b});
            faces.tri.push_back({a, c, d});
          }
        }
    faces.live.assign(faces.tri.size(), 1);
    faces.flippable.assign(faces.tri.size(), 1);
  }
  int away(const sodt::FacingInput& in) const {
    int n = 0;
    for (const auto& t : faces.tri) n += in.test(pos[t[0]], pos[t[1]], pos[t[2]]).away;
    return n;
  }
};

const double kTurn40 = sodt::faceTurnCos2(40.0);

/// The top sheet's centre vertex, and where the tests push it: through
/// the plate to below its bottom sheet.
const int kCentre = 12;
const Vec3 kThrough(2.1, 1.9, -0.1);

/// input with kCentre at kThrough.
Plate pushedThrough(const Plate& input) {
  Plate out = input;
  out.pos[kCentre] = kThrough;
  return out;
}

}  // namespace

TEST(Facing, MendsFacesThatCrossedAThinPlate) {
  const Plate input;
  const sodt::FacingInput in(input.pos, input.faces);
  EXPECT_EQ(input.away(in), 0);  // the input faces nowhere away from itself
  Plate out = pushedThrough(input);
  const int v = kCentre;
  const int before = out.away(in);
  ASSERT_GT(before, 0);  // its faces' centroids lie on the bottom sheet, facing up
  std::vector<int> moved;
  const std::vector<char> deleted(out.pos.size(), 0);
  const sodt::UnfoldResult r = sodt::unfoldFacingAway(out.pos, out.faces, {}, deleted, input.pos, in, kTurn40, 0.0, 1, &moved);
  EXPECT_EQ(r.found, before);
  EXPECT_EQ(r.left, 0);
  EXPECT_EQ(out.away(in), 0);
  ASSERT_EQ(moved, std::vector<int>{v});
  EXPECT_EQ(r.moves, 1);
  // Only as far back as it needed (half of the way: its faces' centroids
  // then lie halfway between the sheets), and nothing else moved.
  EXPECT_NEAR(out.pos[v].Z(), -0.025, 1e-12);
  for (std::size_t k = 0; k < out.pos.size(); ++k) {
    if (static_cast<int>(k) != v) {
      EXPECT_EQ(out.pos[k], input.pos[k]);
    }
  }
}

TEST(Facing, LeavesVerticesWithoutAnInputPositionAndSaysSo) {
  const Plate input;
  const sodt::FacingInput in(input.pos, input.faces);
  Plate out = pushedThrough(input);
  const int v = kCentre;
  // Vertex 12 and every later one count as added (a repair's): none has
  // an input position to go back to.
  const std::vector<Vec3> known(input.pos.begin(), input.pos.begin() + v);
  const std::vector<char> deleted(out.pos.size(), 0);
  const sodt::UnfoldResult r = sodt::unfoldFacingAway(out.pos, out.faces, {}, deleted, known, in, kTurn40, 0.0);
  EXPECT_GT(r.found, 0);
  EXPECT_EQ(r.left, r.found);
  EXPECT_EQ(r.moves, 0);
  EXPECT_EQ(out.pos[v], kThrough);
}

TEST(Facing, KeepsTheDeviationBoundAndTheSmallestAngle) {
  const Plate input;
  const sodt::FacingInput in(input.pos, input.faces);
  Plate out = pushedThrough(input);
  const int v = kCentre;
  const std::vector<char> deleted(out.pos.size(), 0);
  // Within a bound of 0.001, half of the way leaves its faces 0.025
  // below the bottom sheet: it goes all the way back.
  Plate bounded = out;
  const sodt::UnfoldResult r = sodt::unfoldFacingAway(bounded.pos, bounded.faces, {}, deleted, input.pos, in, kTurn40, 1e-3);
  EXPECT_EQ(r.left, 0);
  EXPECT_EQ(bounded.pos[v], input.pos[v]);
  // A mesh whose smallest angle is above what the mended faces would
  // have: no mend lowers it.
  Plate sharp = out;
  sharp.pos[v] = Vec3(2.0, 2.0, -0.1);
  const std::vector<Vec3> inputSliver = [&] {
    std::vector<Vec3> p = input.pos;
    p[v] = Vec3(2.98, 2.98, 0.05);  // its input position makes needles
    return p;
  }();
  const sodt::UnfoldResult kept =
      sodt::unfoldFacingAway(sharp.pos, sharp.faces, {}, deleted, inputSliver, in, kTurn40, 0.0);
  EXPECT_GT(kept.found, 0);
  EXPECT_EQ(kept.left, kept.found);  // every way back makes needles
  double smallest = sodt::kPi;
  for (const auto& t : sharp.faces.tri)
    smallest = std::min(smallest, sodt::triangleMinAngle(sharp.pos[t[0]], sharp.pos[t[1]], sharp.pos[t[2]]));
  EXPECT_EQ(sharp.pos[v], Vec3(2.0, 2.0, -0.1));
  EXPECT_GT(smallest, 0.7);  // about 45 degrees, as before
}

namespace {

/// The top sheet of a Plate alone (flat, facing +z), with vertex 25 added
/// just above the middle of edge 12-13: face (12, 13, 18) is split into
/// the sliver (12, 13, 25) along that edge and two faces to vertex 18.
struct SplitSheet : Plate {
  static constexpr int kAdded = 25;
  explicit SplitSheet(double y) : Plate(5, 0.0) {
    pos.resize(25);
    faces.tri.resize(32);
    for (auto& t : faces.tri)
      if (t == std::array<int, 3>{12, 13, 18}) t = {12, 13, kAdded};
    faces.tri.push_back({13, 18, kAdded});
    faces.tri.push_back({18, 12, kAdded});
    pos.push_back(Vec3(2.5, y, 0.0));
    faces.live.assign(faces.tri.size(), 1);
    faces.flippable.assign(faces.tri.size(), 1);
  }
};

}  // namespace

TEST(Facing, FlipsAnEdgeWhereASliverFoldedOverItsNeighbour) {
  const SplitSheet input(2.0005);
  const sodt::FacingInput in(input.pos, input.faces);
  ASSERT_EQ(input.away(in), 0);
  // The added vertex crossed edge 12-13: the sliver now lies over face
  // (7, 13, 12), upside down. It has no input position to go back to.
  SplitSheet out(1.9995);
  const std::vector<Vec3> known(input.pos.begin(), input.pos.begin() + SplitSheet::kAdded);
  const std::vector<char> deleted(out.pos.size(), 0);
  ASSERT_EQ(out.away(in), 1);
  SplitSheet still = out;
  const sodt::UnfoldResult none = sodt::unfoldFacingAway(still.pos, still.faces, {}, deleted, known, in, kTurn40, 1e-3);
  EXPECT_EQ(none.left, 1);  // no move can mend it
  sodt::UnfoldFreedom may;
  may.flip = true;
  const sodt::UnfoldResult r = sodt::unfoldFacingAway(out.pos, out.faces, may, deleted, known, in, kTurn40, 1e-3);
  EXPECT_EQ(r.found, 1);
  EXPECT_EQ(r.flips, 1);
  EXPECT_EQ(r.moves, 0);
  EXPECT_EQ(r.left, 0);
  EXPECT_EQ(out.away(in), 0);
  // Edge 12-13 became 25-7: the two faces cover the part of (7, 13, 12)
  // the sliver did not, the right way up; the strip between the sliver
  // and edge 12-13 they leave is within the bound.
  int with7and25 = 0;
  for (const auto& t : out.faces.tri) {
    const bool has12 = std::count(t.begin(), t.end(), 12), has13 = std::count(t.begin(), t.end(), 13);
    EXPECT_FALSE(has12 && has13);
    with7and25 += std::count(t.begin(), t.end(), 7) && std::count(t.begin(), t.end(), 25);
    EXPECT_GT(sodt::doubleAreaVector(out.pos[t[0]], out.pos[t[1]], out.pos[t[2]]).Z(), 0);
  }
  EXPECT_EQ(with7and25, 2);
  EXPECT_EQ(out.pos, still.pos);  // no vertex moved
}

TEST(Facing, MovesAVertexPushedOutOfItsRingBackIntoIt) {
  const Plate flat(5, 0.0);
  Plate input = flat;  // the flat top sheet alone
  input.pos.resize(25);
  input.faces.tri.resize(32);
  input.faces.live.assign(32, 1);
  input.faces.flippable.assign(32, 1);
  const sodt::FacingInput in(input.pos, input.faces);
  // Vertex 12, one the repair added (no input position), slid out of its
  // ring of six within the plane: three of its faces turned over.
  Plate out = input;
  out.pos[kCentre] = Vec3(3.4, 2.6, 0.0);
  const std::vector<Vec3> known(input.pos.begin(), input.pos.begin() + kCentre);
  const std::vector<char> deleted(out.pos.size(), 0);
  const int before = out.away(in);
  ASSERT_GT(before, 0);
  std::vector<char> centre(out.pos.size(), 0);
  sodt::UnfoldFreedom may;
  may.centre = &centre;  // no vertex may: nothing mends
  Plate still = out;
  EXPECT_EQ(sodt::unfoldFacingAway(still.pos, still.faces, may, deleted, known, in, kTurn40, 1e-3).left, before);
  centre[kCentre] = 1;
  std::vector<int> moved;
  const sodt::UnfoldResult r = sodt::unfoldFacingAway(out.pos, out.faces, may, deleted, known, in, kTurn40, 1e-3, 1, &moved);
  EXPECT_EQ(r.found, before);
  EXPECT_EQ(r.left, 0);
  EXPECT_EQ(out.away(in), 0);
  EXPECT_EQ(moved, std::vector<int>{kCentre});
  // The middle of its ring (1, 1), (2, 1), (3, 2), (3, 3), (2, 3), (1, 2).
  EXPECT_NEAR(out.pos[kCentre].X(), 2.0, 1e-12);
  EXPECT_NEAR(out.pos[kCentre].Y(), 2.0, 1e-12);
  EXPECT_NEAR(out.pos[kCentre].Z(), 0.0, 1e-12);
}
