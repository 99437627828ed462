// Exact 3D from the stereo module (SFM's `Rect tlx tly w h step` RPC): the box to ask for and where each
// answered point goes in the view's organised cloud.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/record/devices.hpp"

namespace toolinc {

// The blob's ROI [tlx, tly, brx, bry] (inclusive) clamped to a width x height image, as a Rect request.
// SFM does not clamp: pixels outside the image would be answered with garbage. An ROI entirely outside
// the image gives w = h = 0.
SfmRect clamp_rect(const std::array<int, 4>& roi, int width, int height, int step = 1);

// The pixels (u, v) of a Rect request in SFM's reply order: u outer, v inner, both by step.
std::vector<Eigen::Vector2i> sfm_rect_pixels(const SfmRect& rect);

// An organised width x height cloud (row-major) holding the reply at its pixels and NaN elsewhere,
// (0, 0, 0) (SFM's "no depth") included. Throws MethodError when the reply's size does not match the
// request.
Points organised_points(const SfmRect& rect, const Points& reply, int width, int height);

}  // namespace toolinc
