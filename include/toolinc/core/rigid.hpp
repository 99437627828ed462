// Small facts about rotations and rigid transforms.
#pragma once

#include <Eigen/Core>

namespace toolinc {

// Orthonormal with det +1, within tolerance (a reflection is not a rotation).
bool is_rotation(const Eigen::Matrix3d& matrix, double tolerance = 1e-6);
// A 4x4 with a rotation block, finite translation and bottom row 0 0 0 1.
bool is_rigid(const Eigen::Matrix4d& matrix, double tolerance = 1e-6);
// [ax, ay, az, theta] with a unit axis and theta in [0, pi] (the iCub controllers' convention).
Eigen::Vector4d axis_angle(const Eigen::Matrix3d& rotation);
// The rotation's angle in degrees.
double rotation_angle_deg(const Eigen::Matrix3d& rotation);

// The point p moved by the rigid transform: target_from_source * p.
inline Eigen::Vector3d apply(const Eigen::Matrix4d& target_from_source, const Eigen::Vector3d& p) {
  return target_from_source.topLeftCorner<3, 3>() * p + target_from_source.topRightCorner<3, 1>();
}

// The inverse of a rigid transform: source_from_target, from the rotation's transpose.
inline Eigen::Matrix4d inverse(const Eigen::Matrix4d& target_from_source) {
  const Eigen::Matrix3d r = target_from_source.topLeftCorner<3, 3>();
  Eigen::Matrix4d inverse = Eigen::Matrix4d::Identity();
  inverse.topLeftCorner<3, 3>() = r.transpose();
  inverse.topRightCorner<3, 1>() = -r.transpose() * target_from_source.topRightCorner<3, 1>();
  return inverse;
}

}  // namespace toolinc
