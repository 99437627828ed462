// The mirror-symmetry scorer and the free-space model on shapes built by hand, where the right answer is
// known by construction.
#include <gtest/gtest.h>

#include <random>
#include <utility>

#include "cloud/free_space.hpp"
#include "frame/symmetry.hpp"
#include "toolinc/ann/kdtree.hpp"
#include "toolinc/cloud/preprocessing.hpp"

namespace toolinc {
namespace {

constexpr double kStep = 0.002, kTolerance = 0.005;

// A flat T in the plane z = 0: a handle along -y from the origin and, at its far end, a bar across it
// from x = -0.05 (or from x = 0 when the bar's left half is missing) to x = 0.05.
Points flat_t(bool left_half) {
  Points points;
  for (double y = 0.0; y >= -0.2; y -= kStep) points.emplace_back(0.0, y, 0.0);
  for (double x = left_half ? -0.05 : kStep; x <= 0.05 + 1e-9; x += kStep)
    if (std::abs(x) > 1e-9) points.emplace_back(x, -0.2, 0.0);
  return points;
}

const Vec3 kAcross = Vec3::UnitX(), kFlat = Vec3::UnitZ();

TEST(SymmetryScorer, AWholeTMirrorsAboutBothOfItsPlanes) {
  const Points t = flat_t(true);
  const MirrorTarget target(t, kTolerance);
  const SymmetryScorer scorer(target, 500);
  EXPECT_LT(scorer.score(kAcross, Vec3::Zero()), 0.05);  // the bar's halves onto each other
  EXPECT_LT(scorer.score(kFlat, Vec3::Zero()), 0.05);    // a flat shape onto itself
  // Planes that keep the handle but not the bar: every bar point's image lands off the cloud (a third of
  // the points), for a plane turned 45 degrees about the handle; for a plane across the handle at 3/4
  // of its length, half of the handle's too (two thirds).
  const double handle = 101, bar = 50;
  EXPECT_NEAR(scorer.score(Vec3(1, 0, 1).normalized(), Vec3::Zero()), bar / (handle + bar), 0.05);
  EXPECT_NEAR(scorer.score(Vec3::UnitY(), Vec3(0.0, -0.15, 0.0)), (bar + handle / 2) / (handle + bar), 0.05);
}

TEST(SymmetryScorer, AMissingHalfContradictsOnlyWhereASensorSawEmptySpace) {
  const Points half_t = flat_t(false);
  const MirrorTarget target(half_t, kTolerance);
  // Without a free-space model every image off the cloud contradicts the plane across the bar: the bar's
  // 25 points of 126.
  const double blind = SymmetryScorer(target, 500).score(kAcross, Vec3::Zero());
  EXPECT_NEAR(blind, 25.0 / 126.0, 0.03);
  // Seen from above, the missing half was in view and empty: the same contradiction.
  const FreeSpace from_above(half_t, {Vec3(0.0, -0.1, 0.5)});
  EXPECT_TRUE(from_above.seen(Vec3(-0.03, -0.2, 0.0)));
  EXPECT_NEAR(SymmetryScorer(target, 500, 1.0, &from_above).score(kAcross, Vec3::Zero()), blind, 0.05);
  // Seen only edge-on from the bar's right end, the missing half lies behind the seen half: its images
  // are no evidence, and what is left (the handle, the seen half's images near the handle) matches.
  const FreeSpace edge_on(half_t, {Vec3(0.5, -0.2, 0.0)});
  EXPECT_FALSE(edge_on.seen(Vec3(-0.03, -0.2, 0.0)));
  EXPECT_LT(SymmetryScorer(target, 500, 1.0, &edge_on).score(kAcross, Vec3::Zero()), 0.03);
}

// A cloud at the grid's scale: points on a lattice a fifth of the tolerance apart (many exact ties in
// distance) and at random, a few sparse far ones (their neighbours beyond a cell: the tree's fallback), and
// queries on points, between them and off the cloud.
TEST(MirrorTarget, LookupsAreTheKdTreesWithTiesAndSparsePoints) {
  std::mt19937 random(5);
  std::uniform_int_distribution<int> lattice(-10, 10);
  std::uniform_real_distribution<double> u(-0.025, 0.025), far(-0.5, 0.5);
  // Without the far points the cells are the tolerance's size; with them, the box's share.
  for (const auto& [tolerance, far_points] : {std::pair{kTolerance, 0}, std::pair{0.013, 0}, std::pair{0.013, 10}}) {
    Points points;
    for (int i = 0; i < 800; ++i) points.emplace_back(lattice(random) * 0.001, lattice(random) * 0.001, 0.0);
    for (int i = 0; i < 800; ++i) points.emplace_back(u(random), u(random), u(random) / 5);
    for (int i = 0; i < far_points; ++i) points.emplace_back(far(random), far(random), far(random));
    const int k = 6;
    const MirrorTarget target(points, tolerance, k);
    const KdTree tree(points);
    Points queries(points.begin(), points.begin() + 200);
    for (int i = 0; i < 200; ++i) queries.emplace_back(lattice(random) * 0.0025, lattice(random) * 0.0025, 0.001);
    for (int i = 0; i < 200; ++i) queries.emplace_back(1.5 * u(random), 1.5 * u(random), u(random));
    for (int i = 0; i < far_points; ++i) queries.push_back(points[1600 + i]);
    for (const Vec3& query : queries) {
      const KdTree::Neighbor expected = tree.nearest(query, tolerance), got = target.nearest(query);
      EXPECT_EQ(got.index, expected.index);
      if (expected.index != KdTree::npos) EXPECT_EQ(got.distance2, expected.distance2);
      const auto expected_knn = tree.knn(query, k), got_knn = target.neighbours(query);
      ASSERT_EQ(got_knn.size(), expected_knn.size());
      for (std::size_t i = 0; i < got_knn.size(); ++i) {
        EXPECT_EQ(got_knn[i].index, expected_knn[i].index) << i;
        EXPECT_EQ(got_knn[i].distance2, expected_knn[i].distance2) << i;
      }
    }
    for (std::uint32_t i = 0; i < points.size(); i += 37)
      EXPECT_EQ(target.normal(i), normal_at(tree, points[i], k)) << i;
  }
}

}  // namespace
}  // namespace toolinc
