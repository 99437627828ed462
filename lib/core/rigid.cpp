#include "toolinc/core/rigid.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace toolinc {

bool is_rotation(const Eigen::Matrix3d& m, double tolerance) {
  return m.allFinite() && (m.transpose() * m - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= tolerance &&
         std::abs(m.determinant() - 1.0) <= tolerance;
}

bool is_rigid(const Eigen::Matrix4d& m, double tolerance) {
  return m.allFinite() && is_rotation(m.topLeftCorner<3, 3>(), tolerance) &&
         (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() <= tolerance;
}

Eigen::Vector4d axis_angle(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  return {aa.axis().x(), aa.axis().y(), aa.axis().z(), aa.angle()};
}

double rotation_angle_deg(const Eigen::Matrix3d& rotation) {
  const double c = std::clamp((rotation.trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

}  // namespace toolinc
