// Organised clouds as the stereo module publishes them: one point per image pixel, row-major, NaN where
// nothing was triangulated. read_cloud drops non-finite points, which loses the pixel correspondence, so
// organised clouds have their own reader that keeps every point.
#pragma once

#include <string>

#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

// Binary PCD (FIELDS x y z, float32), WIDTH x HEIGHT, NaN kept, written atomically.
// Throws std::invalid_argument when points.size() != width * height.
void write_pcd(const std::string& path, const Points& points, int width, int height);

// Reads a PCD (any encoding; other fields are skipped) with the same reader as read_cloud, keeping NaN
// points. Throws InputError naming the file when it is malformed or not width x height.
Points read_organised_pcd(const std::string& path, int width, int height);

}  // namespace toolinc
