// The tool's shape in 3D, from the blob's disparity, in the hand frame: what the tool's head
// spans about its handle does not change when the tool is turned about the handle, while its silhouette
// does (a T-bar's bar seen edge-on is a stick in the image, still a bar in depth). The hand frame tells
// which points are the hand (its known extent) and which end of the tool is the far one (away from it).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace toolinc {

struct DepthShapeConfig {
  // The hand (palm and closed fingers) as a box in the hand frame, m: the iCub hand's extent, 9 cm across
  // the palm, 7 cm along the handle, 4 cm thick (the simulator's hand), grown by hand_margin for the
  // kinematic error (a few mm) and the disparity's blur at the hand's edges.
  Eigen::Vector3d hand_min{-0.045, -0.05, -0.02};
  Eigen::Vector3d hand_max{0.045, 0.02, 0.02};
  double hand_margin = 0.01;
  // The handle: the points between handle_near and handle_far from the tool's far end, beyond a head
  // (tool heads reach up to about 10 cm along the handle) and short of the hand (tools are 25-30 cm
  // long, the hand holds the last 5-10 cm).
  double handle_near = 0.10;  // m
  double handle_far = 0.16;   // m
  // After a first estimate, the band keeps only its points this close to the axis: a handle is 1-3 cm
  // thick, and what lies farther (a shovel's 10 cm blade reaching into the band, fingers, a view that
  // sees the head's face and only a sliver of the handle) is not handle and would tilt it (set 0's
  // shovels' axes 12-44 degrees off without it).
  double handle_trim = 0.02;  // m
  // The handle's line passes this close to the hand's origin: the fingers hold it, and the original's
  // grasp check accepts the tool 10 cm from the hand at most along each axis.
  double grasp_reach = 0.10;  // m
  // The head: the points within head_length of the far end, binned along the handle in head_bins and
  // across it in steps of across_step.
  double head_length = 0.12;     // m
  int head_bins = 4;             // along the handle
  double across_step = 0.02;     // m (2 handle diameters: a tooth, a bar)
  int radial_bins = 6;           // distance from the handle's axis, the last bin takes everything beyond
  int footprint_bins = 12;       // across the head's main direction, signed: half each side, 12 cm, so that
                                 // what reaches farthest (a hook's return 11 cm out) has bins of its own
  int footprint_depth_bins = 4;  // across the head's second direction, unsigned
  double unit = 0.1;             // m, the extents are measured in (about a tool head's size)
};

// Length of the block: 6 extents, head_bins x radial_bins, head_bins x footprint_bins x footprint_depth_bins.
int depth_shape_dimension(const DepthShapeConfig& config);

// Unit-norm block from the blob's points in the hand frame (m; the hand's points are dropped):
//  - the handle's axis: the principal axis of the points between handle_near and handle_far from the far
//    end (the end away from the hand), found from the whole tool's principal axis and refined 5 times,
//    from the second time on only from the band's points within handle_trim of the previous axis; a
//    line passing farther than grasp_reach from the hand is the head's, and the line from the hand
//    through the tool's centroid replaces it;
//  - the head, the points within head_length of the far end, in cylindrical coordinates about that axis:
//    6 extents (/ unit): the head centroid's distance from the axis, the head's two standard deviations
//    across the axis and its one along it, its farthest point from the axis, the tool's length / 3;
//  - a histogram of the head's points over (distance from the far end, distance from the axis);
//  - the head's footprint across the axis: over (distance from the far end, coordinate along the head's
//    main direction across the axis, signed so that its third moment is positive, |coordinate along the
//    second|): what sticks out on one side (an L, a hook) or both (a T, a rake's bar);
//  histograms as square-rooted shares. A turn about the handle changes none of it. Fewer than 20 points
// (no disparity, an image without depth, no hand pose): zeros.
Eigen::VectorXd depth_shape(const std::vector<Eigen::Vector3d>& points, const DepthShapeConfig& config);

// The handle's axis that block is described about (unit, towards the far end); none with fewer than 20
// points outside the hand.
std::optional<Eigen::Vector3d> depth_shape_axis(const std::vector<Eigen::Vector3d>& points,
                                                const DepthShapeConfig& config);

}  // namespace toolinc
