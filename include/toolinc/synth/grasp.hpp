// Synthetic grasps and the ground truth they imply, for tests, benchmarks and the simulator.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/synth/tool_generator.hpp"

namespace toolinc {

struct GraspRange {
  double about_handle_deg = 90.0;  // rotation about the handle, uniform in about_handle_centre_deg +/- this
  double tilt_deg = 45.0;          // about the hand's Z, uniform in tilt_centre_deg +/- this
  double roll_deg = 15.0;          // about the hand's X, uniform in roll_centre_deg +/- this
  double offset = 0.05;            // m, uniform in offset_centre +/- this along each axis
  double tilt_centre_deg = 0.0;
  double about_handle_centre_deg = 0.0;
  double roll_centre_deg = 0.0;
  Vec3 offset_centre = Vec3::Zero();
};

// hand_from_canonical = Translation(offset) * Rz(tilt) * Rx(roll) * Ry(about handle).
Eigen::Matrix4d random_grasp(const GraspRange& range, Rng& rng);

// How exploration grasps are drawn: `recorded`, as the lab held its tools in the robot's real sessions
// (measured by placing the true models on the robot's reconstructions); `any`, the earlier default,
// drawn without regard to where the effector faces (half of the turns about the handle, most of them
// away from the robot's eyes): the robustness mode, and the regression mode of the generated families.
enum class ExplorationGrasps { recorded, any };
ExplorationGrasps exploration_grasps_from_string(const std::string& name);  // "recorded" | "any"
std::string to_string(ExplorationGrasps grasps);

// Grasps as the robot gets them during exploration: the handle held in the fingers, 2-5 cm in front of
// the palm (+X, as in the original's reconstructions). recorded: as the lab's sessions held them (the
// true models placed on the robot's reconstructions: the handle leaning 31-48 degrees, tilt 33-45 and
// roll 9-16 on the five real tools, the effector turned by -90 to -180 degrees about the handle, towards
// the robot's eyes: hoes and hooks sideways, rakes and shovels back at the robot); any: leaning by 0-45
// degrees (the original's default tilt is 45), no roll centre, turned by up to +/-90 degrees about the
// handle. The tool then lies in the original's crop box.
GraspRange exploration_grasp_range(ExplorationGrasps grasps = ExplorationGrasps::recorded);
// The grasp simulate-session draws for a seed: random_grasp(exploration_grasp_range(grasps)) from Rng(seed).
Eigen::Matrix4d exploration_grasp(std::uint32_t seed, ExplorationGrasps grasps = ExplorationGrasps::recorded);

// The grasps align-pose must cope with: any rotation about the handle, tilt +/-60 deg, roll +/-15 deg,
// offsets +/-5 cm.
GraspRange any_grasp_range();

// The tool as the hand frame sees it: moved by the grasp, the points within hand_radius of the hand
// origin removed (the hand hides them), Gaussian noise of sigma metres added per coordinate.
Points observe_in_hand(const Points& canonical, const Eigen::Matrix4d& hand_from_canonical, double hand_radius,
                       double noise_sigma, Rng& rng);

// The true tooltip's rule: the paper's weighted rule, except a flat or scooped blade continuing the
// handle (a shovel, a spatula), whose tip is the blade's far end: the effector-side point farthest from
// the hand, projected onto the symmetry plane.
enum class TruthTip { weighted, far_end };
TruthTip truth_tip_of(ToolFamily family);             // shovel and blade: far_end
TruthTip truth_tip_of_kind(const std::string& kind);  // a model's kind (model_kinds.hpp): shovel, spatula

// The paper's definitions evaluated with the true frame.
struct ToolGroundTruth {
  Eigen::Matrix4d hand_from_canonical = Eigen::Matrix4d::Identity();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // true tool axes in the hand frame
  Vec3 origin = Vec3::Zero();                          // model centroid on the symmetry plane, hand frame
  std::vector<Vec3> tooltips;                          // hand frame; several when the tool's symmetry
                                                       // makes either end of its head count
  ToolSymmetry symmetry = ToolSymmetry::mirror;
  TruthTip tip = TruthTip::weighted;
};

// Tooltip: among the points beyond the handle plane (the model's centroid), the one maximising
// w * x + (1 - w) * (distance from the hand), projected onto z = 0 (and the same with -x for
// front-back symmetric tools).
ToolGroundTruth tool_ground_truth(const Points& canonical_model, ToolSymmetry symmetry, TruthTip tip,
                                  const Eigen::Matrix4d& hand_from_canonical, double effector_weight = 0.8);

// Distance from an estimated tooltip (hand frame) to the nearest equivalent true one; for axially
// symmetric tools, in cylindrical coordinates about the handle, any point from the axis to the true
// tip's radius at its height counting as right.
double tooltip_error(const ToolGroundTruth& truth, const Vec3& estimate);
// Angle between an estimated handle axis and the true one, in degrees.
double handle_axis_error_deg(const ToolGroundTruth& truth, const Vec3& handle_axis);

}  // namespace toolinc
