// How realistic simulated sessions are: the robot's own reconstruction of a real tool against that tool's
// model, beside the merged models of simulated sessions of the same model, by the same figures (how
// accurate the cloud is, how much of the tool it covers, how close it comes to the tooltip). A folder of
// the lab's real tools holds such pairs; the same figures of simulated sessions alone describe any
// model or generated family.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "toolinc/ann/nearest_distance.hpp"
#include "toolinc/core/point_cloud.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc {

// A cloud against the true surface and tooltip of the tool it shows (both in the cloud's frame).
struct CloudFigures {
  DistanceProfile accuracy;  // each cloud point's distance to the true surface
  double coverage_5mm = 0;   // share of the true surface's points within 5 mm of the cloud
  double coverage_10mm = 0;  // ... and within 10 mm
  double tip_gap_m = 0;      // the true tooltip's distance to the nearest cloud point
};
// The tip gap as tooltip_error measures it: for a round stick, any turn about the handle counts.
CloudFigures cloud_figures(const Points& cloud, const Points& true_surface, const ToolGroundTruth& truth);

// The true model (canonical) placed on a reconstruction (hand frame): align_pose, then point-to-plane
// ICP of the model onto the reconstruction from there. Throws MethodError when no pose is found.
Eigen::Matrix4d place_model(const Points& model, const Points& reconstruction);

// The robot's reconstruction against its tool's model placed on it; the truth is tool_ground_truth's
// with the model's measured symmetry and the tooltip rule `tip` (truth_tip_of_kind of the model's kind).
CloudFigures reconstruction_figures(const Points& model, const Points& reconstruction, TruthTip tip);

// Sessions of the tool `session` configures (family_session or model_session, with its stereo model):
// seeds session.seed, session.seed + 1, ..., each held with exploration_grasp(seed, grasps), through the
// whole pipeline at its defaults (crop without the depth-edge filter, as the original pipeline that made
// the real reconstructions). Per seed, the session's errors and the figures of its merged model (none
// when the merge failed) against the simulator's own truth: true_surface and tool_ground_truth with
// tool_symmetry and tool_truth_tip, placed by the grasp.
struct SimulatedFigures {
  SessionErrors errors;
  bool merged = false;
  CloudFigures figures;
};
std::vector<SimulatedFigures> simulated_figures(SessionSimulatorConfig session, ExplorationGrasps grasps, int seeds);

}  // namespace toolinc
