// How far one cloud lies from another, by nearest neighbours: the accuracy figures of a reconstruction
// against a reference surface.
#pragma once

#include <vector>

#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

// Median distance from the points of `from` to their nearest points in `to` (one-sided: parts of `to`
// that `from` never covers do not count). Throws std::invalid_argument when either is empty.
double median_nearest_distance(const Points& from, const Points& to);

// The distance from each point of `from` to its nearest point in `to`, in from's order.
std::vector<double> nearest_distances(const Points& from, const Points& to);

// A reconstruction's distance profile against a reference surface: the median and 90th percentile of
// its points' nearest distances and the share of points farther than `far`.
struct DistanceProfile {
  double median_m = 0, p90_m = 0, beyond = 0;
};
DistanceProfile distance_profile(const Points& from, const Points& to, double far = 0.005);

// Median symmetric Chamfer distance: the median over both clouds' nearest distances to the other.
double median_chamfer_distance(const Points& a, const Points& b);

}  // namespace toolinc
