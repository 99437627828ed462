#include "toolinc/record/gaze.hpp"

#include "toolinc/core/rigid.hpp"

namespace toolinc {

Vec3 first_fixation(const Eigen::Matrix4d& root_from_hand, const GazeConfig& config) {
  return apply(root_from_hand, config.first_guess);
}

std::optional<Eigen::Vector2d> project(const CameraModel& camera, const Eigen::Matrix4d& root_from_camera,
                                       const Vec3& root_point) {
  const Eigen::Matrix3d r = root_from_camera.topLeftCorner<3, 3>();
  const Vec3 q = r.transpose() * (root_point - root_from_camera.topRightCorner<3, 1>());
  if (q.z() <= 1e-6) return std::nullopt;
  return Eigen::Vector2d(camera.fx * q.x() / q.z() + camera.cx, camera.fy * q.y() / q.z() + camera.cy);
}

std::optional<Eigen::Vector2d> blob_target(const cv::Mat& mask, const Eigen::Vector2d& hand_pixel, double fraction) {
  std::optional<Eigen::Vector2d> farthest;
  double best = -1;
  for (int v = 0; v < mask.rows; ++v) {
    const uchar* row = mask.ptr<uchar>(v);
    for (int u = 0; u < mask.cols; ++u) {
      if (row[u] == 0) continue;
      const double d = (Eigen::Vector2d(u, v) - hand_pixel).squaredNorm();
      if (d > best) best = d, farthest = Eigen::Vector2d(u, v);
    }
  }
  if (!farthest) return std::nullopt;
  return Eigen::Vector2d(hand_pixel + fraction * (*farthest - hand_pixel));
}

Vec3 point_at_pixel(const CameraModel& camera, const Eigen::Matrix4d& root_from_camera, const Eigen::Vector2d& pixel,
                    double depth) {
  const Vec3 ray((pixel.x() - camera.cx) / camera.fx, (pixel.y() - camera.cy) / camera.fy, 1.0);
  return apply(root_from_camera, depth * ray);
}

}  // namespace toolinc
