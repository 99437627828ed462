#include "toolinc/synth/realism.hpp"

#include <algorithm>
#include <cctype>
#include <limits>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/registration/align_pose.hpp"
#include "toolinc/registration/icp.hpp"

namespace toolinc {
namespace {

constexpr double kNear = 0.005, kFar = 0.010;  // m: the coverage radii
constexpr double kEffectorWeight = 0.8;

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

Vec3 realism_tooltip(const Points& canonical, bool shovel) {
  Vec3 centroid = Vec3::Zero();
  for (const auto& p : canonical) centroid += p;
  centroid /= static_cast<double>(std::max<std::size_t>(canonical.size(), 1));
  double best = -std::numeric_limits<double>::infinity();
  Vec3 tip = Vec3::Zero();
  for (const auto& p : canonical) {
    if (p.y() >= centroid.y()) continue;
    const double score =
        shovel ? p.norm() : kEffectorWeight * (p.x() - centroid.x()) + (1.0 - kEffectorWeight) * p.norm();
    if (score > best) best = score, tip = Vec3(p.x(), p.y(), 0.0);
  }
  return tip;
}

bool is_shovel_name(const std::string& name) {
  std::string prefix = name.substr(0, 3);
  std::transform(prefix.begin(), prefix.end(), prefix.begin(), [](unsigned char c) { return std::tolower(c); });
  return prefix == "sho";
}

Eigen::Matrix4d place_model(const Points& model, const Points& reconstruction) {
  const PoseModel pose_model(model);
  const PoseResult pose = align_pose(pose_model, reconstruction);
  const IcpTarget target(reconstruction);
  return align_point_to_plane(voxel_downsample(model, 0.003), target, pose.best.hand_from_model).target_from_source;
}

ToolGroundTruth realism_truth(const Points& canonical, ToolSymmetry symmetry, bool shovel,
                              const Eigen::Matrix4d& hand_from_canonical) {
  ToolGroundTruth truth = tool_ground_truth(canonical, symmetry, shovel ? TruthTip::far_end : TruthTip::weighted,
                                            hand_from_canonical);
  truth.tooltips.front() = apply(hand_from_canonical, realism_tooltip(canonical, shovel));
  return truth;
}

CloudFigures reconstruction_figures(const Points& model, const Points& reconstruction, bool shovel) {
  const Eigen::Matrix4d hand_from_model = place_model(model, reconstruction);
  return cloud_figures(reconstruction, transform_points(model, hand_from_model),
                       realism_truth(model, measure_symmetry(model), shovel, hand_from_model));
}

std::vector<SimulatedFigures> simulated_figures(const PointCloud& model, const std::string& name, StereoModel stereo,
                                                ExplorationGrasps grasps, std::uint32_t first_seed, int seeds) {
  SessionSimulatorConfig config = model_session(model, name, measure_symmetry(model.points), first_seed);
  config.stereo = stereo;
  std::vector<SimulatedFigures> sessions;
  for (int s = 0; s < seeds; ++s) {
    config.seed = first_seed + static_cast<std::uint32_t>(s);
    config.hand_from_canonical = exploration_grasp(config.seed, grasps);
    SimulatedFigures simulated;
    simulated.errors = evaluate_simulated_session(config);
    simulated.merged = !simulated.errors.merged.empty();
    if (simulated.merged)
      simulated.figures = cloud_figures(
          simulated.errors.merged, transform_points(model.points, config.hand_from_canonical),
          realism_truth(model.points, config.model_symmetry, is_shovel_name(name), config.hand_from_canonical));
    sessions.push_back(std::move(simulated));
  }
  return sessions;
}

}  // namespace toolinc
