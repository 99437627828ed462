#include "toolinc/synth/evaluation.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "frame/symmetry.hpp"
#include "toolinc/ann/nearest_distance.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/core/statistics.hpp"

namespace toolinc {

namespace {

// estimate-frame and find-tooltip on `cloud`, compared with the truth.
HeldToolErrors frame_and_tooltip_errors(const Points& cloud, const Points& viewpoints, const ToolGroundTruth& truth,
                                        const ToolFrameConfig& frame_config, const TooltipConfig& tooltip_config) {
  HeldToolErrors errors;
  try {
    const ToolFrame frame = estimate_tool_frame(cloud, frame_config, viewpoints);
    const Tooltip tip = find_tooltip(cloud, frame, tooltip_config);
    errors.right_handed = is_rotation(frame.axes, 1e-9);
    errors.handle_axis_deg = handle_axis_error_deg(truth, frame.handle_axis());
    errors.effector_sign_right = frame.effector_axis().dot(truth.axes.col(0)) > 0;
    errors.tooltip_m = tooltip_error(truth, tip.position);
    errors.confident = tip.confidence.confident;
    errors.symmetry_plane_deg =
        std::acos(std::min(1.0, std::abs(frame.symmetry_axis().dot(truth.axes.col(2))))) * 180.0 / M_PI;
    // The true axes and origin; whether the tool is a stick (no head) is the tool's, as the estimate saw it.
    ToolFrame true_frame;
    true_frame.axes = truth.axes;
    true_frame.origin = truth.origin;
    true_frame.stick = frame.stick;
    true_frame.head_kind = frame.head_kind;
    try {
      errors.tooltip_true_frame_m = tooltip_error(truth, find_tooltip(cloud, true_frame, tooltip_config).position);
    } catch (const MethodError&) {  // no dense point on the true effector side: as far as can be
      errors.tooltip_true_frame_m = std::numeric_limits<double>::infinity();
    }
  } catch (const MethodError& e) {
    errors.failure = e.what();
  }
  return errors;
}

}  // namespace

HeldToolErrors evaluate_held_tool(const Points& canonical, ToolSymmetry symmetry, TruthTip tip,
                                  const Eigen::Matrix4d& grasp, double hand_radius, double noise_sigma, Rng& rng,
                                  const ToolFrameConfig& frame_config, const TooltipConfig& tooltip_config) {
  const Points observed = observe_in_hand(canonical, grasp, hand_radius, noise_sigma, rng);
  return frame_and_tooltip_errors(observed, {}, tool_ground_truth(canonical, symmetry, tip, grasp), frame_config,
                                  tooltip_config);
}

Points true_surface(const SessionSimulatorConfig& session) {
  if (!session.model.points.empty()) return session.model.points;
  ToolShape dense = session.shape;
  dense.spacing = 0.001;
  return generate_tool(dense, 1).points;
}

SessionErrors evaluate_simulated_session(const SessionSimulatorConfig& config, const PipelineConfig& pipeline) {
  const SimulatedSession session = simulate_session(config);
  const Points canonical = true_surface(config);
  const ToolGroundTruth truth =
      tool_ground_truth(canonical, tool_symmetry(config), tool_truth_tip(config), config.hand_from_canonical);
  SessionErrors errors;
  std::vector<PointCloud> views;
  for (std::size_t v = 0; v < session.views.size(); ++v) {
    try {
      views.push_back(crop_view(session.info, session.info.views[v], session.views[v], pipeline.crop).cloud);
    } catch (const MethodError&) {
      ++errors.views_rejected;  // as crop-cloud --all: one bad view does not lose the others
    }
  }
  MergeResult merged;
  try {
    if (views.empty()) throw MethodError("no view could be cropped");
    merged = merge_views(views, pipeline.merge);
  } catch (const MethodError& e) {
    errors.tool.failure = e.what();
    return errors;
  }
  for (const auto& view : merged.views) errors.views_rejected += !view.accepted;
  errors.model = distance_profile(merged.model.points, transform_points(canonical, config.hand_from_canonical));
  errors.model_median_m = errors.model.median_m;
  errors.tool =
      frame_and_tooltip_errors(merged.model.points, merged.model.viewpoints, truth, pipeline.frame, pipeline.tooltip);
  errors.merged = std::move(merged.model.points);
  return errors;
}

std::string rate_text(int successes, int trials) {
  const auto [lo, hi] = wilson_interval(successes, trials);
  return fmt::format("{:5.1f}% ({:.1f}-{:.1f}%)", 100.0 * successes / std::max(trials, 1), 100 * lo, 100 * hi);
}

nlohmann::ordered_json rate_json(const std::string& name, int successes, int trials) {
  const auto [lo, hi] = wilson_interval(successes, trials);
  return {{"name", name},
          {"trials", trials},
          {"successes", successes},
          {"rate", static_cast<double>(successes) / std::max(trials, 1)},
          {"rate_interval_95", {lo, hi}}};
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
  if (!symmetric(Vec3(1, 0, 1).normalized()) || !symmetric(Vec3(1, 0, -1).normalized()))
    return ToolSymmetry::front_back;
  // Mirror planes every 45 degrees: a square or a cross, unless planes in between are mirrors too (round).
  const double a = M_PI / 8;
  return symmetric(Vec3(std::cos(a), 0, std::sin(a))) && symmetric(Vec3(std::cos(3 * a), 0, -std::sin(3 * a)))
             ? ToolSymmetry::axial
             : ToolSymmetry::fourfold;
}

}  // namespace toolinc
