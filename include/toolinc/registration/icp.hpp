// Robust point-to-plane ICP: aligns a source point set onto a target surface (points with normals).
#pragma once

#include <Eigen/Core>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

struct IcpConfig {
  int max_iterations = 50;
  double max_correspondence = 0.02;  // m: farther pairs are not correspondences
  double kernel_scale = 0.003;       // m: Geman-McClure scale (about 2 sigma of stereo noise)
  double inlier_distance = 0.005;    // m: pairs this close count as inliers in the fitness figures
  double min_step = 1e-5;            // stop when an update moves less than this (m, rad)
  double damping = 1e-3;             // weight of a prior towards the initial pose, relative to the
                                     //    problem's mean curvature: holds still what the geometry leaves free
};

struct IcpResult {
  Eigen::Matrix4d target_from_source = Eigen::Matrix4d::Identity();
  double inlier_ratio = 0.0;  // share of source points within inlier_distance of the target
  double inlier_rmse = 0.0;   // m, RMS point-to-plane distance of those inliers
  int iterations = 0;
  bool converged = false;
};

// A target surface prepared once for many alignments. The tree refers to this object's own points, so
// the target is neither copyable nor movable (a copy's tree would still search the original's points),
// and its members are const (new points under an old tree would be searched wrongly).
struct IcpTarget {
  IcpTarget(Points points, int normal_neighbors = 10);
  IcpTarget(const IcpTarget&) = delete;
  IcpTarget& operator=(const IcpTarget&) = delete;
  const Points points;
  const Points normals;
  const KdTree tree;
};

IcpResult align_point_to_plane(const Points& source, const IcpTarget& target, const Eigen::Matrix4d& initial,
                               const IcpConfig& config = {});

}  // namespace toolinc
