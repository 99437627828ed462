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
#include "toolinc/frame/frame_search.hpp"
#include "toolinc/registration/icp.hpp"

namespace toolinc {

namespace {

// estimate-frame and find-tooltip on `cloud`, compared with the truth (the tooltip also with the truth
// as the cloud has the tool, `relative`).
HeldToolErrors frame_and_tooltip_errors(const PointCloud& observed, const ToolGroundTruth& truth,
                                        const ToolGroundTruth& relative, const ToolFrameConfig& frame_config,
                                        const TooltipConfig& tooltip_config) {
  HeldToolErrors errors;
  const Points& cloud = observed.points;
  try {
    const auto [frame, tip] = estimate_frame_and_tooltip(observed, frame_config, tooltip_config);
    errors.right_handed = is_rotation(frame.axes, 1e-9);
    errors.handle_axis_deg = handle_axis_error_deg(truth, frame.handle_axis());
    errors.effector_sign_right = frame.effector_axis().dot(truth.axes.col(0)) > 0;
    errors.tooltip_m = tooltip_error(truth, tip.position);
    errors.tooltip_relative_m = tooltip_error(relative, tip.position);
    errors.confident = tip.confidence.confident;
    errors.tooltip_probability = frame.diagnostics.tooltip_probability;
    errors.symmetry_plane_deg =
        std::acos(std::min(1.0, std::abs(frame.symmetry_axis().dot(truth.axes.col(2))))) * 180.0 / M_PI;
    // The true axes and origin; whether the tool is a stick (no head) is the tool's, as the estimate saw it.
    ToolFrame true_frame;
    true_frame.axes = truth.axes;
    true_frame.origin = truth.origin;
    true_frame.handle_point = truth.hand_from_canonical.topRightCorner<3, 1>();  // the handle's end, on its axis
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
  const ToolGroundTruth truth = tool_ground_truth(canonical, symmetry, tip, grasp);
  return frame_and_tooltip_errors({observed, {}, {}, "hand", {}, {}}, truth, truth, frame_config, tooltip_config);
}

Points true_surface(const SessionSimulatorConfig& session) {
  if (!session.model.points.empty()) return session.model.points;
  ToolShape dense = session.shape;
  dense.spacing = 0.001;
  return generate_tool(dense, 1).points;
}

namespace {

// A simulated session cropped (every view; one bad view does not lose the others, as crop-cloud --all)
// and merged, with the truth: at the true grasp, and carried by the true model aligned onto the merge.
struct MergedSession {
  Points canonical;
  ToolGroundTruth truth, relative;
  int views_rejected = 0;
  MergeResult merged;
  std::string failure;  // why the merge failed, else empty
};
MergedSession simulate_and_merge(const SessionSimulatorConfig& config, const PipelineConfig& pipeline) {
  const SimulatedSession session = simulate_session(config);
  MergedSession m;
  m.canonical = true_surface(config);
  m.truth = tool_ground_truth(m.canonical, tool_symmetry(config), tool_truth_tip(config), config.hand_from_canonical);
  std::vector<PointCloud> views;
  for (std::size_t v = 0; v < session.views.size(); ++v) {
    try {
      views.push_back(crop_view(session.info, session.info.views[v], session.views[v], pipeline.crop).cloud);
    } catch (const MethodError&) {
      ++m.views_rejected;
    }
  }
  try {
    if (views.empty()) throw MethodError("no view could be cropped");
    m.merged = merge_views(views, pipeline.merge);
  } catch (const MethodError& e) {
    m.failure = e.what();
    return m;
  }
  m.views_rejected = m.merged.model.unmerged_views;  // those the crop found no tool in among them
  if (pipeline.bare_model) {
    PointCloud& model = m.merged.model;
    model.views.clear(), model.viewpoints.clear(), model.recorded_views = 0, model.unmerged_views = 0;
  }
  m.relative = tool_ground_truth(m.canonical, tool_symmetry(config), tool_truth_tip(config),
                                 pose_on_merged_model(m.merged.model.points, m.canonical, config.hand_from_canonical));
  return m;
}

}  // namespace

CropConfig session_crop(StereoModel stereo) {
  if (stereo == StereoModel::ideal) return {};
  return matched_stereo_crop(stereo == StereoModel::sgbm ? StereoMatcher::sgbm : StereoMatcher::libelas);
}

PipelineConfig as_original_reconstruction(PipelineConfig pipeline) {
  pipeline.merge = original_merge();
  pipeline.bare_model = true;
  return pipeline;
}

SessionErrors evaluate_simulated_session(const SessionSimulatorConfig& config, const PipelineConfig& pipeline) {
  MergedSession m = simulate_and_merge(config, pipeline);
  SessionErrors errors;
  errors.views_rejected = m.views_rejected;
  if (!m.failure.empty()) {
    errors.tool.failure = m.failure;
    return errors;
  }
  errors.model = distance_profile(m.merged.model.points, transform_points(m.canonical, config.hand_from_canonical));
  errors.model_median_m = errors.model.median_m;
  errors.tool = frame_and_tooltip_errors(m.merged.model, m.truth, m.relative, pipeline.frame, pipeline.tooltip);
  errors.merged = std::move(m.merged.model.points);
  return errors;
}

std::vector<LabelledHypothesis> labelled_frame_hypotheses(const SessionSimulatorConfig& config,
                                                          const PipelineConfig& pipeline) {
  const MergedSession m = simulate_and_merge(config, pipeline);
  std::vector<LabelledHypothesis> labelled;
  if (!m.failure.empty()) return labelled;
  const bool salient = tool_symmetry(config) == ToolSymmetry::mirror;
  try {
    const PointCloud& model = m.merged.model;
    // One tree and cache for every hypothesis's tooltip (find-tooltip's, with the pipeline's settings).
    const KdTree tree(model.points);
    const TooltipCache tooltips(model.points, tree, pipeline.tooltip, model.views);
    for (const auto& h : frame_hypotheses(tooltips, pipeline.frame, model.viewpoints)) {
      double error = std::numeric_limits<double>::infinity();
      bool backed = false;
      try {
        Tooltip tip = find_tooltip(tooltips, h.frame);
        check_unmerged_views(tip.confidence, model.unmerged_views);
        error = tooltip_error(m.relative, tip.position);
        backed = tip.confidence.confident;
      } catch (const MethodError&) {  // no tip on this hypothesis's effector side: as wrong as can be
      }
      const bool effector_right = !salient || h.frame.effector_axis().dot(m.relative.axes.col(0)) > 0;
      labelled.push_back({h.features, h.handle_source, h.side_reversed, h.tooltip, h.other_end, effector_side(h.frame),
                          error, effector_right, handle_axis_error_deg(m.relative, h.frame.handle_axis()), backed});
    }
  } catch (const MethodError&) {  // a degenerate merged model: nothing to learn from
    labelled.clear();
  }
  return labelled;
}

Eigen::Matrix4d pose_on_merged_model(const Points& merged, const Points& canonical,
                                     const Eigen::Matrix4d& hand_from_canonical) {
  // The merged model onto the true surface (every point it holds has a true counterpart; much of the
  // true surface was never seen), at the merge's 2 mm grid; the inverse carries the surface onto the model.
  const IcpTarget surface(transform_points(voxel_downsample(canonical, 0.002), hand_from_canonical));
  const IcpResult fit = align_point_to_plane(merged, surface, Eigen::Matrix4d::Identity());
  return toolinc::inverse(fit.target_from_source) * hand_from_canonical;
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
  const MirrorTarget target(cloud, 0.01);
  const SymmetryScorer scorer(target, 1000);  // no free space: every image off the cloud contradicts
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
