#include "toolinc/registration/align_pose.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"

namespace toolinc {
namespace {

using Pose = Eigen::Matrix4d;
constexpr double kDeg = M_PI / 180.0;
constexpr double kEndShare = 0.01;  // the tool's ends along the handle: the 1% quantiles

double bbox_diagonal(const Points& points) {
  if (points.empty()) return 0.0;
  Vec3 lo = points.front(), hi = points.front();
  for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi - lo).norm();
}

double milliseconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// About `count` points spread evenly over the (voxel-ordered) input, deterministically.
Points spread_subset(const Points& points, std::size_t count) {
  if (points.size() <= count) return points;
  Points subset;
  subset.reserve(count);
  for (std::size_t i = 0; i < count; ++i) subset.push_back(points[i * points.size() / count]);
  return subset;
}

Points prepare_view(const Points& view, const AlignPoseConfig& config) {
  return voxel_downsample(remove_within(view, Vec3::Zero(), config.hand_radius), config.view_voxel);
}

// The farther a point from the hand, the more it counts (quadratically): the head decides where a long
// tool sits along its handle, which the handle's own points leave free.
std::vector<double> head_weights(const Points& view) {
  std::vector<double> weights;
  weights.reserve(view.size());
  for (const auto& p : view) weights.push_back(p.squaredNorm());
  return weights;
}

// Head-weighted fit, 0..1: each point's exp(-d^2 / 2 sigma^2), d its distance to the nearest model point.
double weighted_fit(const IcpTarget& model, const Points& view, const std::vector<double>& weights,
                    const Pose& model_from_view, double sigma) {
  const Eigen::Matrix3d r = model_from_view.topLeftCorner<3, 3>();
  const Vec3 t = model_from_view.topRightCorner<3, 1>();
  double fit = 0.0, total = 0.0;
  for (std::size_t i = 0; i < view.size(); ++i) {
    total += weights[i];
    const auto nearest = model.tree.nearest(r * view[i] + t, 3.0 * sigma);
    if (nearest.index != KdTree::npos) fit += weights[i] * std::exp(-0.5 * nearest.distance2 / (sigma * sigma));
  }
  return total > 0.0 ? fit / total : 0.0;
}

// Where the handle is: axes like a tool frame's (Y along the handle, towards the hand) and a point on
// the handle's axis line.
struct HandleGuess {
  Eigen::Matrix3d axes;
  Vec3 point;
  Vec3 axis() const { return axes.col(1); }
  // The point of the axis line at the given coordinate along it.
  Vec3 at(double coordinate) const { return point + (coordinate - axis().dot(point)) * axis(); }
};

HandleGuess from_frame(const ToolFrame& frame) { return {frame.axes, frame.handle_point}; }

// Axes with the given handle axis (Y); X and Z arbitrary (rolls are swept anyway).
Eigen::Matrix3d axes_with_handle(const Vec3& y) {
  Eigen::Matrix3d axes;
  axes.col(1) = y.normalized();
  axes.col(0) = axes.col(1).unitOrthogonal();
  axes.col(2) = axes.col(0).cross(axes.col(1));
  return axes;
}

// The coordinates along an axis below which and above which `share` of the points lie: a noisy view's
// extreme points stick out by about three sigma, quantiles do not.
std::pair<double, double> extent_along(const Points& points, const Vec3& axis, double share) {
  std::vector<double> coordinates;
  coordinates.reserve(points.size());
  for (const auto& p : points) coordinates.push_back(axis.dot(p));
  const auto k = static_cast<std::ptrdiff_t>(share * static_cast<double>(coordinates.size() - 1));
  std::nth_element(coordinates.begin(), coordinates.begin() + k, coordinates.end());
  const double lo = coordinates[k];
  std::nth_element(coordinates.begin(), coordinates.end() - 1 - k, coordinates.end());
  return {lo, coordinates[coordinates.size() - 1 - k]};
}

// The view's handle: its tool frame's when that is plausible (a handle as thick as the model's, held by
// the hand); otherwise (the handle hidden behind the head, or half seen and fitted by a much wider
// cylinder) the line from the hand through the view's centroid, which a held tool's handle follows
// within the grasp offset and the head's reach, and a cone of axes around it.
std::vector<HandleGuess> view_handle_guesses(const ToolFrame& frame, const Points& view, double model_radius,
                                             const AlignPoseConfig& config) {
  const double hand_distance = frame.handle_point.cross(frame.handle_axis()).norm();
  if (frame.handle_radius <= config.max_handle_radius_factor * model_radius &&
      hand_distance <= config.max_handle_offset)
    return {from_frame(frame)};
  Vec3 centroid = Vec3::Zero();
  for (const auto& p : view) centroid += p;
  const Vec3 axis = -(centroid / static_cast<double>(view.size())).normalized();
  const Eigen::Matrix3d around = axes_with_handle(axis);
  std::vector<HandleGuess> guesses{{around, Vec3::Zero()}};
  const int directions = 6;
  for (int k = 0; k < directions; ++k) {
    const Vec3 tilt_axis = Eigen::AngleAxisd(2.0 * M_PI * k / directions, axis) * around.col(0);
    guesses.push_back(
        {axes_with_handle(Eigen::AngleAxisd(config.fallback_cone_deg * kDeg, tilt_axis) * axis), Vec3::Zero()});
  }
  return guesses;
}

// model_from_view hypotheses: each view handle guess onto the model's handle, rolled about the handle
// axis in steps, with the handle either way. The view's far end (away from the hand) goes onto the
// model's far end, or onto its handle end when the handle is reversed, on the handle axis lines.
std::vector<Pose> frame_hypotheses(const HandleGuess& model_handle, const Points& model_points,
                                   const std::vector<HandleGuess>& view_handles, const Points& view_points,
                                   double roll_step_deg) {
  const auto [model_far, model_near] = extent_along(model_points, model_handle.axis(), kEndShare);
  const int rolls = std::max(1, static_cast<int>(std::lround(360.0 / roll_step_deg)));
  std::vector<Pose> hypotheses;
  for (const auto& view_handle : view_handles) {
    const Vec3 view_anchor = view_handle.at(extent_along(view_points, view_handle.axis(), kEndShare).first);
    for (const bool reversed : {false, true}) {
      const Eigen::Matrix3d flip =
          reversed ? Eigen::Matrix3d(Eigen::AngleAxisd(M_PI, Vec3::UnitZ())) : Eigen::Matrix3d::Identity();
      const Vec3 model_anchor = model_handle.at(reversed ? model_near : model_far);
      for (int k = 0; k < rolls; ++k) {
        const Eigen::Matrix3d roll(Eigen::AngleAxisd(2.0 * M_PI * k / rolls, Vec3::UnitY()));
        Pose pose = Pose::Identity();
        pose.topLeftCorner<3, 3>() = model_handle.axes * roll * flip * view_handle.axes.transpose();
        pose.topRightCorner<3, 1>() = model_anchor - pose.topLeftCorner<3, 3>() * view_anchor;
        hypotheses.push_back(pose);
      }
    }
  }
  return hypotheses;
}

// How far the view's far end, placed by model_from_view, falls short of the model's along the handle (m;
// negative beyond it).
double far_end_gap(const PoseModel& model, const Points& view, const Pose& model_from_view) {
  const Vec3 outwards = -model.frame.handle_axis();  // from the hand to the far end
  return extent_along(model.target.points, outwards, kEndShare).second -
         extent_along(transform_points(view, model_from_view), outwards, kEndShare).second;
}

// The head-weighted fit, discounted where the view's far end and the model's are more than slide_margin
// apart (a Gaussian of that width beyond it): the eye fixates the tool, so its far end is normally in
// view, and a pose that leaves it short slid along a handle that could not tell.
double pose_score(const PoseModel& model, const Points& view, const std::vector<double>& weights,
                  const Pose& model_from_view, const AlignPoseConfig& config) {
  const double excess =
      std::max(0.0, std::abs(far_end_gap(model, view, model_from_view)) - config.slide_margin) / config.slide_margin;
  return weighted_fit(model.target, view, weights, model_from_view, config.score_sigma) *
         std::exp(-0.5 * excess * excess);
}

bool same_pose(const Pose& a, const Pose& b, const AlignPoseConfig& config) {
  return rotation_difference_deg(a, b) < config.same_pose_deg &&
         (a.topRightCorner<3, 1>() - b.topRightCorner<3, 1>()).norm() < config.same_pose_m;
}

struct Scored {
  Pose model_from_view;
  double score;
};

void sort_by_score(std::vector<Scored>& scored) {
  std::stable_sort(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) { return a.score > b.score; });
}

// The best hypotheses, one per distinct pose: all scored as they are on a few view points, the best of
// them refined by a coarse two-stage ICP and scored again.
std::vector<Scored> best_hypotheses(const PoseModel& model, const Points& view,
                                    const std::vector<HandleGuess>& view_handles, const AlignPoseConfig& config,
                                    int& tested) {
  const Points coarse = spread_subset(view, static_cast<std::size_t>(config.coarse_points));
  const std::vector<double> weights = head_weights(coarse);
  std::vector<Scored> scored;
  for (const Pose& hypothesis :
       frame_hypotheses(from_frame(model.frame), model.target.points, view_handles, view, config.roll_step_deg))
    scored.push_back({hypothesis, weighted_fit(model.target, coarse, weights, hypothesis, config.prescore_sigma)});
  tested = static_cast<int>(scored.size());
  sort_by_score(scored);
  // The best hypotheses, and the best feasible ones too: where the shape alone cannot tell (a stick
  // either way round fits about as well) the infeasible ones could fill every place, and the hand must
  // still have a pose to decide on.
  const std::size_t keep = std::min<std::size_t>(scored.size(), static_cast<std::size_t>(config.coarse_candidates));
  const auto feasible_hypothesis = [&](const Scored& s) {
    return check_feasibility(inverse(s.model_from_view), config).feasible;
  };
  std::vector<Scored> chosen(scored.begin(), scored.begin() + static_cast<std::ptrdiff_t>(keep));
  const std::size_t feasible_wanted = keep / 2;
  std::size_t feasible_kept =
      static_cast<std::size_t>(std::count_if(chosen.begin(), chosen.end(), feasible_hypothesis));
  for (std::size_t i = keep; i < scored.size() && feasible_kept < feasible_wanted; ++i)
    if (feasible_hypothesis(scored[i])) chosen.push_back(scored[i]), ++feasible_kept;
  scored = std::move(chosen);

  IcpConfig far = config.icp, near = config.icp;
  far.max_iterations = near.max_iterations = config.coarse_iterations;
  far.max_correspondence = config.coarse_far;
  near.max_correspondence = config.coarse_near;
  // A kernel as wide as the stage lets the points still far from the surface pull.
  far.kernel_scale = far.max_correspondence / 2.0;
  near.kernel_scale = near.max_correspondence / 2.0;
  for (auto& s : scored) {
    const Pose pose = align_point_to_plane(coarse, model.target, s.model_from_view, far).target_from_source;
    s.model_from_view = align_point_to_plane(coarse, model.target, pose, near).target_from_source;
    s.score = pose_score(model, coarse, weights, s.model_from_view, config);
  }
  sort_by_score(scored);
  // Where the tool's symmetry lets poses fit about as well (a stick either way round), the hand decides:
  // feasible poses within the ambiguity margin of the best go first.
  const double equal_score = scored.front().score - config.ambiguity_margin;
  std::stable_partition(scored.begin(), scored.end(), [&](const Scored& s) {
    return s.score >= equal_score && check_feasibility(inverse(s.model_from_view), config).feasible;
  });
  std::vector<Scored> distinct;
  for (const auto& s : scored) {
    if (static_cast<int>(distinct.size()) >= config.refine_candidates) break;
    if (std::none_of(distinct.begin(), distinct.end(),
                     [&](const Scored& d) { return same_pose(d.model_from_view, s.model_from_view, config); }))
      distinct.push_back(s);
  }
  return distinct;
}

// The slide along the handle that a view of a plain handle leaves free (point-to-plane ICP feels no
// pull along a cylinder): the view's far end pins it. The view is shifted along the model's handle
// between where it is and where its far end meets the model's (and `slide_margin` beyond either); of
// the shifts fitting as well as the best (within ambiguity_margin) the one taking the view farthest out
// wins. A tool with a head fits well only where it is, so only a plain handle moves.
Pose pin_far_end(const PoseModel& model, const Points& view, const std::vector<double>& weights,
                 const Pose& model_from_view, const AlignPoseConfig& config) {
  const Vec3 outwards = -model.frame.handle_axis();  // from the hand to the far end
  const double gap = far_end_gap(model, view, model_from_view);
  const double lo = std::min(0.0, gap) - config.slide_margin, hi = std::max(0.0, gap) + config.slide_margin;
  const int steps = static_cast<int>(std::ceil((hi - lo) / config.slide_step));
  std::vector<std::pair<double, double>> fits;  // shift, fit
  double best = 0.0;
  for (int k = 0; k <= steps; ++k) {
    const double shift = lo + k * (hi - lo) / std::max(1, steps);
    Pose moved = model_from_view;
    moved.topRightCorner<3, 1>() += shift * outwards;
    fits.emplace_back(shift, weighted_fit(model.target, view, weights, moved, config.score_sigma));
    best = std::max(best, fits.back().second);
  }
  const double at_rest = weighted_fit(model.target, view, weights, model_from_view, config.score_sigma);
  if (at_rest >= best - config.ambiguity_margin && gap <= config.slide_step) return model_from_view;
  double chosen = 0.0;
  for (const auto& [shift, fit] : fits)
    if (fit >= best - config.ambiguity_margin) chosen = shift;
  Pose moved = model_from_view;
  moved.topRightCorner<3, 1>() += chosen * outwards;
  return moved;
}

}  // namespace

namespace {

// The frames the pose starts from: the rules' handle and planes, whose guesses the pose's evaluation
// (evaluate-poses) measured; the search picks a tooltip, not a pose's start. Every piece counts: one
// partial view leaves long stretches of the tool unseen (a handle behind its head), so what lies apart
// from the part nearest the hand is still the tool.
ToolFrameConfig handle_guess_frame_config(const AlignPoseConfig& config) {
  ToolFrameConfig frame_config;
  frame_config.method = FrameMethod::rules;
  frame_config.hand_radius = config.hand_radius;
  frame_config.piece_gap = 0.0;
  return frame_config;
}

}  // namespace

PoseModel::PoseModel(const Points& canonical, const AlignPoseConfig& config)
    : target(voxel_downsample(canonical, config.model_voxel)),
      frame(estimate_tool_frame(canonical, handle_guess_frame_config(config))) {}

double rotation_difference_deg(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  return rotation_angle_deg(a.topLeftCorner<3, 3>().transpose() * b.topLeftCorner<3, 3>());
}

Feasibility check_feasibility(const Eigen::Matrix4d& hand_from_model, const AlignPoseConfig& config) {
  // R = Rz(tilt) Rx(roll) Ry(about): R(2,1) = sin(roll), R(2,0) = -cos(roll) sin(about),
  // R(2,2) = cos(roll) cos(about), R(0,1) = -sin(tilt) cos(roll), R(1,1) = cos(tilt) cos(roll).
  const Eigen::Matrix3d r = hand_from_model.topLeftCorner<3, 3>();
  Feasibility f;
  f.translation = hand_from_model.topRightCorner<3, 1>();
  f.roll_deg = std::asin(std::clamp(r(2, 1), -1.0, 1.0)) / kDeg;
  f.about_handle_deg = std::atan2(-r(2, 0), r(2, 2)) / kDeg;
  f.tilt_deg = std::atan2(-r(0, 1), r(1, 1)) / kDeg;
  const char* axes = "xyz";
  for (int i = 0; i < 3 && f.reason.empty(); ++i)
    if (std::abs(f.translation[i]) > config.max_translation)
      f.reason = fmt::format("translation along {} is {:.3f} m, beyond the limit of {:.3f} m", axes[i],
                             f.translation[i], config.max_translation);
  const auto limit = [&](const char* name, double value, double max) {
    if (f.reason.empty() && std::abs(value) > max)
      f.reason = fmt::format("{} is {:.1f} deg, beyond the limit of {:.1f} deg", name, value, max);
  };
  limit("tilt", f.tilt_deg, config.max_tilt_deg);
  limit("roll", f.roll_deg, config.max_roll_deg);
  limit("rotation about the handle", f.about_handle_deg, config.max_about_handle_deg);
  f.feasible = f.reason.empty();
  return f;
}

std::string implausible_extent(const Points& points, const std::string& what) {
  constexpr double kMinExtent = 0.01, kMaxExtent = 2.0;  // m: a speck; beyond the arm's reach twice over
  const double extent = bbox_diagonal(points);
  if (extent < kMinExtent)
    return fmt::format(
        "{} spans {:.3g} m across its {} points, less than any tool ({} m): too few, or all at one "
        "place",
        what, extent, points.size(), kMinExtent);
  if (extent > kMaxExtent)
    return fmt::format(
        "{} spans {:.4g} m, more than any tool the hand holds ({} m): is it in millimetres? It must "
        "be in metres",
        what, extent, kMaxExtent);
  return {};
}

std::string unit_mismatch(const Points& model, const Points& view, double max_extent_ratio) {
  if (std::string problem = implausible_extent(view, "the view"); !problem.empty()) return problem;
  if (std::string problem = implausible_extent(model, "the model"); !problem.empty()) return problem;
  const double model_extent = bbox_diagonal(model), view_extent = bbox_diagonal(view);
  if (model_extent > max_extent_ratio * view_extent)
    return fmt::format(
        "the model is {:.0f} times larger than the view (extent {:.4g} against {:.4g}): is the "
        "model in millimetres? Both must be in metres",
        model_extent / view_extent, model_extent, view_extent);
  if (view_extent > max_extent_ratio * model_extent)
    return fmt::format(
        "the view is {:.0f} times larger than the model (extent {:.4g} against {:.4g}): is the "
        "view in millimetres? Both must be in metres",
        view_extent / model_extent, view_extent, model_extent);
  return {};
}

IcpResult refine_pose(const PoseModel& model, const Points& view, const Eigen::Matrix4d& model_from_view,
                      const AlignPoseConfig& config) {
  return align_point_to_plane(prepare_view(view, config), model.target, model_from_view, config.icp);
}

PoseResult align_pose(const PoseModel& model, const Points& view, const AlignPoseConfig& config) {
  PoseResult result;
  result.view_points_input = static_cast<int>(view.size());
  auto start = std::chrono::steady_clock::now();
  const Points points = prepare_view(view, config);
  result.view_points_used = static_cast<int>(points.size());
  if (result.view_points_used < config.min_view_points)
    throw MethodError(
        fmt::format("too few view points: {} of {} remain outside the hand ({} m) at {} m "
                    "resampling; at least {} are needed",
                    points.size(), view.size(), config.hand_radius, config.view_voxel, config.min_view_points));
  const std::vector<HandleGuess> view_handles = view_handle_guesses(
      estimate_tool_frame(points, handle_guess_frame_config(config)), points, model.frame.handle_radius, config);
  result.view_ms = milliseconds_since(start);

  start = std::chrono::steady_clock::now();
  const std::vector<Scored> hypotheses = best_hypotheses(model, points, view_handles, config, result.hypotheses);
  result.global_ms = milliseconds_since(start);

  start = std::chrono::steady_clock::now();
  const std::vector<double> weights = head_weights(points);
  const Points coarse = spread_subset(points, static_cast<std::size_t>(config.coarse_points));
  const std::vector<double> coarse_weights = head_weights(coarse);
  std::vector<PoseCandidate> refined;
  for (const auto& hypothesis : hypotheses) {
    IcpResult icp = align_point_to_plane(points, model.target, hypothesis.model_from_view, config.icp);
    const Pose pinned = pin_far_end(model, coarse, coarse_weights, icp.target_from_source, config);
    if (!pinned.isApprox(icp.target_from_source)) icp = align_point_to_plane(points, model.target, pinned, config.icp);
    PoseCandidate c;
    c.hand_from_model = inverse(icp.target_from_source);
    c.score = pose_score(model, points, weights, icp.target_from_source, config);
    c.inlier_ratio = icp.inlier_ratio;
    c.inlier_rmse = icp.inlier_rmse;
    c.iterations = icp.iterations;
    c.converged = icp.converged;
    refined.push_back(c);
  }
  result.refine_ms = milliseconds_since(start);
  std::sort(refined.begin(), refined.end(), [](const auto& a, const auto& b) { return a.score > b.score; });

  // Poses fitting as well as the best but rotated away from it: the tool's symmetry leaves the choice
  // open. The hand decides where it can: infeasible ones (a stick held by its far end) drop out.
  std::vector<PoseCandidate> equal{refined.front()};
  for (std::size_t i = 1; i < refined.size(); ++i)
    if (refined[i].score >= refined.front().score - config.ambiguity_margin &&
        std::all_of(equal.begin(), equal.end(), [&](const PoseCandidate& e) {
          return rotation_difference_deg(e.hand_from_model, refined[i].hand_from_model) > config.ambiguity_deg;
        }))
      equal.push_back(refined[i]);
  const auto feasible = [&](const PoseCandidate& c) { return check_feasibility(c.hand_from_model, config).feasible; };
  if (std::any_of(equal.begin(), equal.end(), feasible))
    equal.erase(std::stable_partition(equal.begin(), equal.end(), feasible), equal.end());
  result.best = equal.front();
  result.feasibility = check_feasibility(result.best.hand_from_model, config);
  result.ambiguous = equal.size() > 1;
  if (result.ambiguous) result.candidates = equal;
  return result;
}

PointCloud oriented_model(const PointCloud& model, const Eigen::Matrix4d& hand_from_model) {
  PointCloud oriented = model;
  oriented.points = transform_points(model.points, hand_from_model);
  const Eigen::Matrix3d r = hand_from_model.topLeftCorner<3, 3>();
  for (auto& n : oriented.normals) n = r * n;
  oriented.frame = "hand";
  return oriented;
}

CarriedTooltip carry_tooltip(const PoseModel& model, const Points& canonical, const Eigen::Matrix4d& hand_from_model,
                             const TooltipConfig& config) {
  CarriedTooltip carried{model.frame, find_tooltip(canonical, model.frame, config)};
  carried.tooltip.position = apply(hand_from_model, carried.tooltip.position);
  carried.tooltip.surface_point = apply(hand_from_model, carried.tooltip.surface_point);
  carried.frame.axes = hand_from_model.topLeftCorner<3, 3>() * carried.frame.axes;
  carried.frame.origin = apply(hand_from_model, carried.frame.origin);
  return carried;
}

}  // namespace toolinc
