// The blob's shape in 3D, from its disparity (issue 18): what the tool's head spans across its handle
// does not change when the tool is turned about the handle, while its silhouette does (a T-bar's bar
// seen edge-on is a stick in the image, still a bar in depth).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace toolinc {

struct DepthShapeConfig {
  double unit = 0.1;         // m, the length extents are measured in (about a tool head's size)
  double head_share = 0.4;   // the head: this share of the blob's length at its top end
  int radial_bins = 8;       // histogram of the head's points' distances from the head's axis
  double radial_step = 0.02; // m per bin (the last bin takes everything beyond)
};

// Unit-norm block of 6 + radial_bins values from the blob's points in the camera frame (m): the square
// roots of the blob's three principal variances, of the head's two variances across the major axis, the
// blob's length along it (all / unit), and the head's square-rooted radial histogram about its own centre
// across the axis. The head is the end towards the image's top (smaller y: the tool is held up). Fewer
// than 3 points (no disparity, an image without depth): zeros.
Eigen::VectorXd depth_shape(const std::vector<Eigen::Vector3d>& points, const DepthShapeConfig& config);

}  // namespace toolinc
