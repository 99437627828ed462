#include "toolinc/synth/realism.hpp"

#include <algorithm>
#include <limits>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/registration/align_pose.hpp"
#include "toolinc/registration/icp.hpp"

namespace toolinc {
namespace {

constexpr double kNear = 0.005, kFar = 0.010;  // m: the coverage radii

double share_within(const std::vector<double>& distances, double radius) {
  const auto n = std::count_if(distances.begin(), distances.end(), [&](double d) { return d <= radius; });
  return distances.empty() ? 0.0 : static_cast<double>(n) / static_cast<double>(distances.size());
}

}  // namespace

CloudFigures cloud_figures(const Points& cloud, const Points& true_surface, const ToolGroundTruth& truth) {
  CloudFigures figures;
  figures.accuracy = distance_profile(cloud, true_surface, kNear);
  const std::vector<double> covered = nearest_distances(true_surface, cloud);
  figures.coverage_5mm = share_within(covered, kNear);
  figures.coverage_10mm = share_within(covered, kFar);
  figures.tip_gap_m = std::numeric_limits<double>::infinity();
  for (const auto& p : cloud) figures.tip_gap_m = std::min(figures.tip_gap_m, tooltip_error(truth, p));
  return figures;
}

Eigen::Matrix4d place_model(const Points& model, const Points& reconstruction) {
  const PoseModel pose_model(model);
  const PoseResult pose = align_pose(pose_model, reconstruction);
  const IcpTarget target(reconstruction);
  return align_point_to_plane(voxel_downsample(model, 0.003), target, pose.best.hand_from_model).target_from_source;
}

CloudFigures reconstruction_figures(const Points& model, const Points& reconstruction, TruthTip tip) {
  const Eigen::Matrix4d hand_from_model = place_model(model, reconstruction);
  return cloud_figures(reconstruction, transform_points(model, hand_from_model),
                       tool_ground_truth(model, measure_symmetry(model), tip, hand_from_model));
}

std::vector<SimulatedFigures> simulated_figures(SessionSimulatorConfig session, ExplorationGrasps grasps, int seeds) {
  const Points canonical = true_surface(session);
  const std::uint32_t first_seed = session.seed;
  std::vector<SimulatedFigures> sessions;
  for (int s = 0; s < seeds; ++s) {
    session.seed = first_seed + static_cast<std::uint32_t>(s);
    session.hand_from_canonical = exploration_grasp(session.seed, grasps);
    SimulatedFigures simulated;
    simulated.errors = evaluate_simulated_session(session);
    simulated.merged = !simulated.errors.merged.empty();
    if (simulated.merged)
      simulated.figures = cloud_figures(
          simulated.errors.merged, transform_points(canonical, session.hand_from_canonical),
          tool_ground_truth(canonical, tool_symmetry(session), tool_truth_tip(session), session.hand_from_canonical));
    sessions.push_back(std::move(simulated));
  }
  return sessions;
}

}  // namespace toolinc
