#include "toolinc/record/exploration.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace toolinc {

std::vector<Eigen::Vector2d> paper_exploration_poses() { return {{0, 0}, {-40, -20}, {30, -20}, {0, -20}, {0, 30}}; }

Eigen::Vector3d for_hand(const std::string& hand, const Eigen::Vector3d& right_hand_position) {
  if (hand != "left" && hand != "right")
    throw std::invalid_argument("hand must be left or right, not \"" + hand + "\"");
  return hand == "left" ? Eigen::Vector3d(right_hand_position.x(), -right_hand_position.y(), right_hand_position.z())
                        : right_hand_position;
}

Eigen::Matrix4d exploration_hand_pose(const std::string& hand, const Eigen::Vector2d& wrist_deg,
                                      const Eigen::Vector3d& right_hand_position) {
  const Eigen::Vector3d position = for_hand(hand, right_hand_position);
  const double sign = hand == "left" ? -1.0 : 1.0;
  const double deg = M_PI / 180.0;
  Eigen::Matrix3d base;  // columns: hand x = -root x, hand y = -root z, hand z = -root y (det +1)
  base.col(0) = Eigen::Vector3d(-1, 0, 0);
  base.col(1) = Eigen::Vector3d(0, 0, -1);
  base.col(2) = Eigen::Vector3d(0, -1, 0);
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  pose.topLeftCorner<3, 3>() = base * Eigen::AngleAxisd(sign * wrist_deg.x() * deg, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(sign * wrist_deg.y() * deg, Eigen::Vector3d::UnitY());
  pose.topRightCorner<3, 1>() = position;
  return pose;
}

std::vector<Eigen::Matrix4d> plan_exploration(const ExplorationConfig& config, const std::string& hand) {
  if (config.poses.empty()) throw std::invalid_argument("no exploration poses");
  std::vector<Eigen::Matrix4d> plan;
  for (const auto& wrist : config.poses) {
    if (!(std::abs(wrist.x()) <= config.max_x_deg) || !(std::abs(wrist.y()) <= config.max_y_deg))
      throw std::invalid_argument(fmt::format("wrist pose ({}, {}) refused: |X| must be <= {} and |Y| <= {} degrees",
                                              wrist.x(), wrist.y(), config.max_x_deg, config.max_y_deg));
    plan.push_back(exploration_hand_pose(hand, wrist, config.hand_position));
  }
  return plan;
}

}  // namespace toolinc
