#include "toolinc/synth/evaluation.hpp"

#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/frame/symmetry.hpp"

namespace toolinc {

HeldToolErrors evaluate_held_tool(const Points& canonical, ToolSymmetry symmetry, const Eigen::Matrix4d& grasp,
                                  double hand_radius, double noise_sigma, Rng& rng,
                                  const ToolFrameConfig& frame_config, const TooltipConfig& tooltip_config) {
  const Points observed = observe_in_hand(canonical, grasp, hand_radius, noise_sigma, rng);
  const ToolGroundTruth truth = tool_ground_truth(canonical, symmetry, grasp);
  HeldToolErrors errors;
  try {
    const ToolFrame frame = estimate_tool_frame(observed, frame_config);
    const Tooltip tip = find_tooltip(observed, frame, tooltip_config);
    errors.right_handed = is_rotation(frame.axes, 1e-9);
    errors.handle_axis_deg = handle_axis_error_deg(truth, frame.handle_axis());
    errors.effector_sign_right = frame.effector_axis().dot(truth.axes.col(0)) > 0;
    errors.tooltip_m = tooltip_error(truth, tip.position);
  } catch (const MethodError& e) {
    errors.failure = e.what();
  }
  return errors;
}

ToolSymmetry measure_symmetry(const Points& canonical) {
  // The same score as the frame's symmetry test, on the same resampling; mirror planes of the
  // generated tools score about 0.2 noise-free at this scale, others 0.35 and more.
  const Points cloud = voxel_downsample(canonical, 0.004);
  const SymmetryScorer scorer(cloud, 1000, 0.01);  // no free space: every image off the cloud contradicts
  Vec3 centre = Vec3::Zero();
  for (const auto& p : cloud) centre += p;
  centre /= static_cast<double>(std::max<std::size_t>(cloud.size(), 1));
  const double reference = scorer.score(Vec3::UnitZ(), centre);  // the canonical mirror plane
  const auto symmetric = [&](const Vec3& normal) { return scorer.score(normal, centre) <= reference + 0.05; };
  if (!symmetric(Vec3::UnitX())) return ToolSymmetry::mirror;
  return symmetric(Vec3(1, 0, 1).normalized()) && symmetric(Vec3(1, 0, -1).normalized()) ? ToolSymmetry::axial
                                                                                         : ToolSymmetry::front_back;
}

}  // namespace toolinc
