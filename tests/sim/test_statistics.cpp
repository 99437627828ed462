// Order statistics, the interval of a measured rate and a cloud's distance profile, against values
// worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "toolinc/ann/nearest_distance.hpp"
#include "toolinc/core/statistics.hpp"

namespace toolinc {
namespace {

TEST(Statistics, QuantileAndMedianPickElementsOfTheSortedValues) {
  const std::vector<double> values{5, 1, 4, 2, 3};
  EXPECT_EQ(quantile(values, 0.0), 1);
  EXPECT_EQ(quantile(values, 1.0), 5);
  EXPECT_EQ(quantile(values, 0.5), 3);
  EXPECT_EQ(quantile(values, 0.3), 2);   // element floor(0.3 x 4) = 1
  EXPECT_EQ(quantile(values, -1.0), 1);  // clamped
  EXPECT_EQ(quantile({}, 0.5), 0.0);
  EXPECT_EQ(median(values), 3);
  EXPECT_EQ(median({4, 1, 3, 2}), 3);  // the upper middle of an even count
  EXPECT_TRUE(std::isnan(median({})));
}

TEST(Statistics, WilsonIntervalOfARate) {
  // All or nothing: the closed forms n / (n + z^2) and z^2 / (n + z^2).
  const double z2 = 1.96 * 1.96;
  const auto [none_lo, none_hi] = wilson_interval(0, 10);
  EXPECT_DOUBLE_EQ(none_lo, 0.0);
  EXPECT_NEAR(none_hi, z2 / (10 + z2), 1e-12);
  const auto [all_lo, all_hi] = wilson_interval(10, 10);
  EXPECT_NEAR(all_lo, 10 / (10 + z2), 1e-12);
  EXPECT_DOUBLE_EQ(all_hi, 1.0);
  // Symmetric under swapping successes and failures.
  const auto [lo, hi] = wilson_interval(2435, 2560);
  const auto [failures_lo, failures_hi] = wilson_interval(2560 - 2435, 2560);
  EXPECT_NEAR(lo, 1.0 - failures_hi, 1e-12);
  EXPECT_NEAR(hi, 1.0 - failures_lo, 1e-12);
  // 95.1 % of 2560: about +/- 0.85 % (1.96 standard errors), slightly pulled towards one half.
  EXPECT_NEAR(lo, 0.9421, 1e-4);
  EXPECT_NEAR(hi, 0.9589, 1e-4);
  // More trials, a narrower interval around the same rate.
  const auto [small_lo, small_hi] = wilson_interval(95, 100);
  EXPECT_LT(small_lo, 0.95 - 0.03);
  EXPECT_GT(small_hi - small_lo, 2 * (hi - lo));
  const auto [empty_lo, empty_hi] = wilson_interval(0, 0);
  EXPECT_EQ(empty_lo, 0.0);
  EXPECT_EQ(empty_hi, 1.0);
}

}  // namespace
}  // namespace toolinc

namespace toolinc {
namespace {

TEST(Statistics, DistanceProfileOfACloudToASurface) {
  // Ten points 1..10 mm above a single surface point: median the 6th (upper middle), p90 the 9th
  // (floor(0.9 * 9) = 8th index), and 5 of 10 farther than 5 mm.
  const Points surface{Vec3::Zero()};
  Points cloud;
  for (int k = 1; k <= 10; ++k) cloud.push_back(Vec3(0, 0, 0.001 * k));
  const DistanceProfile profile = distance_profile(cloud, surface);
  EXPECT_NEAR(profile.median_m, 0.006, 1e-12);
  EXPECT_NEAR(profile.p90_m, 0.009, 1e-12);
  EXPECT_DOUBLE_EQ(profile.beyond, 0.5);
  EXPECT_DOUBLE_EQ(distance_profile(cloud, surface, 0.0095).beyond, 0.1);
  EXPECT_EQ(nearest_distances(cloud, surface).size(), 10u);
  EXPECT_THROW(distance_profile({}, surface), std::invalid_argument);
}

}  // namespace
}  // namespace toolinc
