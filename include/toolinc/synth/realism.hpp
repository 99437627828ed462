// How realistic simulated sessions are: the robot's own reconstruction of a real tool against that tool's
// model, beside the merged models of simulated sessions of the same model, by the same figures (how
// accurate the cloud is, how much of the tool it covers, how close it comes to the tooltip). A folder of
// the lab's real tools holds such pairs.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "toolinc/ann/nearest_distance.hpp"
#include "toolinc/core/point_cloud.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc {

// A cloud against the true surface and tooltip of the tool it shows (both in the cloud's frame).
struct CloudFigures {
  DistanceProfile accuracy;        // each cloud point's distance to the true surface
  double coverage_5mm = 0;         // share of the true surface's points within 5 mm of the cloud
  double coverage_10mm = 0;        // ... and within 10 mm
  double tip_gap_m = 0;            // the true tooltip's distance to the nearest cloud point
};
// The tip gap as tooltip_error measures it: for a round stick, any turn about the handle counts.
CloudFigures cloud_figures(const Points& cloud, const Points& true_surface, const ToolGroundTruth& truth);

// The tooltip a cloud's tip gap is measured to, in the canonical frame, as the evaluation defines it:
// among the effector-side points (beyond the handle plane through the centroid), the maximum of
// 0.8 x (distance in front of the effector plane through the centroid) + 0.2 x (distance from the hand);
// for a shovel, the blade's far end (the effector-side point farthest from the hand); projected onto
// the symmetry plane z = 0.
Vec3 realism_tooltip(const Points& canonical, bool shovel);

// tool_ground_truth with realism_tooltip as its (first) tooltip.
ToolGroundTruth realism_truth(const Points& canonical, ToolSymmetry symmetry, bool shovel,
                              const Eigen::Matrix4d& hand_from_canonical);

// Whether a real tool's file name says it is a shovel (the lab's prefix "sho", any case).
bool is_shovel_name(const std::string& name);

// The true model (canonical) placed on a reconstruction (hand frame): align_pose, then point-to-plane
// ICP of the model onto the reconstruction from there. Throws MethodError when no pose is found.
Eigen::Matrix4d place_model(const Points& model, const Points& reconstruction);

// The robot's reconstruction against its tool's model placed on it.
CloudFigures reconstruction_figures(const Points& model, const Points& reconstruction, bool shovel);

// Sessions of `model` (its measured symmetry, the exploration grasp of each seed drawn from `grasps`,
// the given stereo model) through the whole pipeline at its defaults (crop without the depth-edge filter,
// as the original pipeline that made the real reconstructions). Per seed, the session's errors and
// the figures of its merged model (none when the merge failed).
struct SimulatedFigures {
  SessionErrors errors;
  bool merged = false;
  CloudFigures figures;
};
std::vector<SimulatedFigures> simulated_figures(const PointCloud& model, const std::string& name, StereoModel stereo,
                                                ExplorationGrasps grasps, std::uint32_t first_seed, int seeds);

}  // namespace toolinc
