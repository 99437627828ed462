// How far one cloud lies from another, by nearest neighbours: the accuracy figures of a reconstruction
// against a reference surface.
#pragma once

#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

// Median distance from the points of `from` to their nearest points in `to` (one-sided: parts of `to`
// that `from` never covers do not count). Throws std::invalid_argument when either is empty.
double median_nearest_distance(const Points& from, const Points& to);

// Median symmetric Chamfer distance: the median over both clouds' nearest distances to the other.
double median_chamfer_distance(const Points& a, const Points& b);

}  // namespace toolinc
