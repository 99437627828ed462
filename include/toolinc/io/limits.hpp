// What the readers accept (docs/formats.md "Limits"): bounds far beyond anything the robot or the
// simulator produces, so that a hostile or corrupt file is one clear error (exit 2) rather than
// gigabytes of memory, a hang or an arithmetic overflow downstream.
#pragma once

#include <cstddef>

namespace toolinc {

// Any file read: a 640x480 session view's PNGs and points.pcd weigh a few MB, a 5M-point ASCII PLY with
// colours and normals about 500 MB.
constexpr std::size_t kMaxFileBytes = std::size_t{1} << 30;
// Points per cloud (about 80 bytes each once read: 800 MB): 30 whole 640x480 views, 30 times a merged model.
constexpr std::size_t kMaxCloudPoints = 10'000'000;
// |coordinate| in a cloud, metres in the hand frame: the arm reaches under 1 m and the stereo sees a few;
// 1000 m leaves room for clouds in millimetres (rejected later as the wrong unit, with a message) while
// keeping every voxel index of a 1 um grid far inside 64-bit integers.
constexpr double kMaxCoordinate = 1000.0;
// Width or height of an image, px: libpng's own default limit, beyond which it prints warnings of its own.
constexpr std::size_t kMaxImageSide = 1'000'000;

}  // namespace toolinc
