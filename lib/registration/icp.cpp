#include "toolinc/registration/icp.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/rigid.hpp"

namespace toolinc {

IcpTarget::IcpTarget(Points target_points, int normal_neighbors)
    : points(std::move(target_points)), normals(estimate_normals(points, normal_neighbors)), tree(points) {}

namespace {

Eigen::Matrix4d exp_se3(const Eigen::Matrix<double, 6, 1>& delta) {
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  const Vec3 omega = delta.head<3>();
  const double angle = omega.norm();
  if (angle > 1e-12) t.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
  t.topRightCorner<3, 1>() = delta.tail<3>();
  return t;
}

}  // namespace

IcpResult align_point_to_plane(const Points& source, const IcpTarget& target, const Eigen::Matrix4d& initial,
                               const IcpConfig& config) {
  IcpResult result;
  result.target_from_source = initial;
  const double k2 = config.kernel_scale * config.kernel_scale;
  for (int iteration = 0; iteration < config.max_iterations; ++iteration) {
    const Eigen::Matrix3d rotation = result.target_from_source.topLeftCorner<3, 3>();
    const Vec3 translation = result.target_from_source.topRightCorner<3, 1>();
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    int pairs = 0;
    for (const auto& s : source) {
      const Vec3 p = rotation * s + translation;
      const auto nearest = target.tree.nearest(p, config.max_correspondence);
      if (nearest.index == KdTree::npos) continue;
      const Vec3& n = target.normals[nearest.index];
      const double r = n.dot(p - target.points[nearest.index]);
      Eigen::Matrix<double, 6, 1> J;
      J << p.cross(n), n;
      const double w = k2 / ((k2 + r * r) * (k2 + r * r)) * k2;  // Geman-McClure, 1 at r = 0
      H.noalias() += w * J * J.transpose();
      g.noalias() += w * J * r;
      ++pairs;
    }
    result.iterations = iteration + 1;
    if (pairs < 6) break;
    // A weak prior towards the initial pose keeps directions the geometry does not constrain (the roll
    // of a stick about its axis) where they started instead of letting noise turn them freely, and,
    // unlike per-step damping, lets every step shrink to zero so the iteration converges.
    // Rotation (rad) and translation (m) blocks each get their own scale: one shared scale, dominated
    // by the translation terms, made the prior outweigh the data on rotation for clouds a few cm from
    // the origin (a 5-degree error was left at 3.3).
    Eigen::Matrix<double, 6, 1> prior;
    prior.head<3>().setConstant(config.damping * H.topLeftCorner<3, 3>().trace() / 3.0);
    prior.tail<3>().setConstant(config.damping * H.bottomRightCorner<3, 3>().trace() / 3.0);
    const Eigen::Matrix4d moved = result.target_from_source * inverse(initial);
    const Eigen::AngleAxisd turned(Eigen::Matrix3d(moved.topLeftCorner<3, 3>()));
    Eigen::Matrix<double, 6, 1> offset;
    offset << turned.angle() * turned.axis(), moved.topRightCorner<3, 1>();
    H.diagonal() += prior;
    g += prior.cwiseProduct(offset);
    const Eigen::Matrix<double, 6, 1> delta = H.ldlt().solve(-g);
    if (!delta.allFinite()) break;
    result.target_from_source = exp_se3(delta) * result.target_from_source;
    if (delta.head<3>().norm() < config.min_step && delta.tail<3>().norm() < config.min_step) {
      result.converged = true;
      break;
    }
  }
  // Fitness figures at the final pose.
  const Eigen::Matrix3d rotation = result.target_from_source.topLeftCorner<3, 3>();
  const Vec3 translation = result.target_from_source.topRightCorner<3, 1>();
  int inliers = 0;
  double sum2 = 0.0;
  for (const auto& s : source) {
    const Vec3 p = rotation * s + translation;
    const auto nearest = target.tree.nearest(p, config.inlier_distance);
    if (nearest.index == KdTree::npos) continue;
    const double r = target.normals[nearest.index].dot(p - target.points[nearest.index]);
    sum2 += r * r;
    ++inliers;
  }
  result.inlier_ratio = source.empty() ? 0.0 : static_cast<double>(inliers) / static_cast<double>(source.size());
  result.inlier_rmse = inliers > 0 ? std::sqrt(sum2 / inliers) : 0.0;
  return result;
}

}  // namespace toolinc
