// The exploration plan (original-method.md sect. 3-4, turnHand and exploreTool): the hand holding the tool
// is turned through a few wrist poses in front of the eyes, the tool pointing up. Shared by the recorder,
// which moves the real arm there, and the session simulator, which renders the same poses.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace toolinc {

// The original's exploration poses, (wrist X, wrist Y) in degrees: (0,0), (-40,-20), (30,-20), (0,-20), (0,30).
std::vector<Eigen::Vector2d> paper_exploration_poses();

struct ExplorationConfig {
  std::vector<Eigen::Vector2d> poses = paper_exploration_poses();  // wrist (X, Y) degrees, in this order
  // The hand's position in the root frame for the right hand (25 cm in front, 15 cm to the side, 10 cm up);
  // y is mirrored for the left hand.
  Eigen::Vector3d hand_position{-0.25, 0.15, 0.10};
  // turnHand refuses larger wrist rotations (the wrist's range).
  double max_x_deg = 90.0, max_y_deg = 70.0;
  // The other arm is first moved here (right-hand y, mirrored like hand_position), keeping its
  // orientation, so it stays out of the cameras' view.
  bool move_other_arm = true;
  Eigen::Vector3d other_arm_position{-0.20, 0.35, 0.15};
};

// turnHand's target: the hand at `right_hand_position` (y mirrored for the left hand) in the root frame,
// rotation Rh * Rx(X) * Ry(Y) with Rh putting the tool (hand -Y) up; the rotations' signs are negated for the
// left hand, as in the original. Throws std::invalid_argument on a hand other than "left"/"right".
Eigen::Matrix4d exploration_hand_pose(const std::string& hand, const Eigen::Vector2d& wrist_deg,
                                      const Eigen::Vector3d& right_hand_position = {-0.25, 0.15, 0.10});

// A root-frame position given for the right hand, mirrored (y -> -y) for the left one.
Eigen::Vector3d for_hand(const std::string& hand, const Eigen::Vector3d& right_hand_position);

// The hand poses of the plan, one per wrist pose. Checks the whole plan before anything moves: throws
// std::invalid_argument naming the first pose beyond max_x_deg / max_y_deg, or on an empty plan.
std::vector<Eigen::Matrix4d> plan_exploration(const ExplorationConfig& config, const std::string& hand);

}  // namespace toolinc
