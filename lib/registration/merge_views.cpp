#include "toolinc/registration/merge_views.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "cloud/free_space.hpp"
#include "toolinc/ann/kdtree.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"

namespace toolinc {
namespace {

int accepted_views(const MergeResult& result) {
  return static_cast<int>(
      std::count_if(result.views.begin(), result.views.end(), [](const ViewMerge& v) { return v.accepted; }));
}

// How much of the tool a merge holds: its accepted views' points.
long accepted_points(const MergeResult& result) {
  long points = 0;
  for (const auto& v : result.views) points += v.accepted ? v.points : 0;
  return points;
}

// The accepted views' points, less those that are smear. At a depth edge stereo strings points along
// the sensor's ray between the tool and what lies behind it. Another view, looking across that ray, sees
// the tool farther on through where those points would be, and has no point near them: its own surface
// there would have been seen by both. A point another view saw through but also saw (a thin part one
// view resolves and another misses) stays. Counts the dropped points per view; the kept points' views
// (when the views carry them) go to kept_views.
Points drop_smear(const std::vector<PointCloud>& aligned, std::vector<ViewMerge>& merges, const MergeConfig& config,
                  std::vector<std::uint32_t>& kept_views) {
  const double tolerance = config.see_through_tolerance;
  std::vector<FreeSpace> depth_images;  // each view's own; a rejected view has no points, so none
  std::vector<std::unique_ptr<KdTree>> trees;
  for (const auto& view : aligned) {
    depth_images.emplace_back(view.points, view.viewpoints, 1.0, tolerance);
    trees.push_back(std::make_unique<KdTree>(view.points));
  }
  const auto smear = [&](std::size_t a, const Vec3& p) {
    bool seen_through = false;
    for (std::size_t b = 0; b < aligned.size(); ++b) {
      if (b == a) continue;
      if (trees[b]->count_within(p, tolerance, 1) >= 1) return false;
      seen_through = seen_through || depth_images[b].seen_through(p);
    }
    return seen_through;
  };
  Points kept;
  kept_views.clear();
  for (std::size_t a = 0; a < aligned.size(); ++a) {
    if (!merges[a].accepted) continue;
    for (std::size_t i = 0; i < aligned[a].points.size(); ++i) {
      if (smear(a, aligned[a].points[i])) {
        ++merges[a].smear_dropped;
      } else {
        kept.push_back(aligned[a].points[i]);
        if (aligned[a].has_views()) kept_views.push_back(aligned[a].views[i]);
      }
    }
  }
  return kept;
}

// Every view aligned in turn onto the growing model that starts as the first view.
MergeResult merge_onto_first(const std::vector<PointCloud>& views, const MergeConfig& config) {
  if (static_cast<int>(views[0].points.size()) < config.min_points)
    throw MethodError(fmt::format("the reference view has only {} points, at least {} needed", views[0].points.size(),
                                  config.min_points));
  MergeResult result;
  result.views.resize(views.size());
  Points accumulated = views[0].points;
  std::vector<std::uint32_t> accumulated_views = views[0].views;  // the views that saw them, when labelled
  std::vector<PointCloud> aligned(views.size());  // the accepted views in the reference view's frame, the
                                                  // rejected ones empty
  aligned[0] = views[0];
  result.views[0] = {true,      "reference", Eigen::Matrix4d::Identity(),
                     {0, 0, 0}, 0.0,         1.0,
                     0.0,       0,           static_cast<int>(views[0].points.size())};
  if (config.progress) config.progress(1, views.size());
  // One view refined against the model built so far; merged into it when the correction is plausible.
  const auto merge_view = [&](std::size_t v) {
    ViewMerge& merge = result.views[v];
    merge = ViewMerge{};
    merge.points = static_cast<int>(views[v].points.size());
    if (merge.points < config.min_points) {
      merge.reason = fmt::format("too few points ({} < {})", merge.points, config.min_points);
      return;
    }
    const IcpTarget target(voxel_downsample(accumulated, config.voxel_size));
    const IcpResult icp = align_point_to_plane(voxel_downsample(views[v].points, config.registration_voxel), target,
                                               Eigen::Matrix4d::Identity(), config.icp);
    merge.correction = icp.target_from_source;
    for (int i = 0; i < 3; ++i) merge.translation_m[i] = icp.target_from_source(i, 3);
    merge.rotation_deg = rotation_angle_deg(icp.target_from_source.topLeftCorner<3, 3>());
    merge.inlier_ratio = icp.inlier_ratio;
    merge.inlier_rmse = icp.inlier_rmse;
    merge.iterations = icp.iterations;
    const double worst_axis = icp.target_from_source.topRightCorner<3, 1>().cwiseAbs().maxCoeff();
    if (worst_axis > config.max_translation) {
      merge.reason =
          fmt::format("correction of {:.3f} m along an axis exceeds {} m", worst_axis, config.max_translation);
    } else if (merge.rotation_deg > config.max_rotation_deg) {
      merge.reason =
          fmt::format("correction of {:.1f} deg exceeds {} deg", merge.rotation_deg, config.max_rotation_deg);
    } else if (icp.inlier_ratio < config.min_inlier_ratio) {
      merge.reason = fmt::format("only {:.0f}% of the view lands on the model after alignment (min {:.0f}%)",
                                 100 * icp.inlier_ratio, 100 * config.min_inlier_ratio);
    } else {
      merge.accepted = true;
      merge.reason = "aligned";
      aligned[v].points = transform_points(views[v].points, icp.target_from_source);
      aligned[v].viewpoints = transform_points(views[v].viewpoints, icp.target_from_source);
      aligned[v].views = views[v].views;
      accumulated.insert(accumulated.end(), aligned[v].points.begin(), aligned[v].points.end());
      accumulated_views.insert(accumulated_views.end(), views[v].views.begin(), views[v].views.end());
    }
  };
  // A view that does not fit the model built so far may fit it once later views have grown it (one seen
  // from behind, bridged by one from the side; a far-seeing one against short ones): with revisit_views the
  // views that failed to fit are tried again, in order, until a pass merges none of them.
  std::vector<std::size_t> pending;
  for (std::size_t v = 1; v < views.size(); ++v) {
    merge_view(v);
    if (config.progress) config.progress(v + 1, views.size());
    if (config.revisit_views && !result.views[v].accepted && result.views[v].points >= config.min_points)
      pending.push_back(v);
  }
  for (std::size_t before = 0; !pending.empty() && pending.size() != before;) {
    before = pending.size();
    std::vector<std::size_t> unfit;
    for (const std::size_t v : pending) {
      merge_view(v);
      if (!result.views[v].accepted) unfit.push_back(v);
    }
    pending = std::move(unfit);
  }
  // The reference view carries its own kinematic error; the views' errors are independent and zero-mean,
  // so the mean of the accepted views' frames is a better estimate of the hand frame than any one of them.
  Eigen::Matrix3d rotation_sum = Eigen::Matrix3d::Zero();
  Vec3 translation_sum = Vec3::Zero();
  int accepted = 0;
  for (const auto& merge : result.views)
    if (merge.accepted) {
      rotation_sum += merge.correction.topLeftCorner<3, 3>();
      translation_sum += merge.correction.topRightCorner<3, 1>();
      ++accepted;
    }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotation_sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d mean_rotation = svd.matrixU() * svd.matrixV().transpose();
  if (mean_rotation.determinant() < 0) {
    Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
    flip(2, 2) = -1;
    mean_rotation = svd.matrixU() * flip * svd.matrixV().transpose();
  }
  Eigen::Matrix4d mean_frame = Eigen::Matrix4d::Identity();
  mean_frame.topLeftCorner<3, 3>() = mean_rotation;
  mean_frame.topRightCorner<3, 1>() = translation_sum / accepted;
  result.hand_from_reference = inverse(mean_frame);
  result.model.frame = "hand";
  if (config.see_through_tolerance > 0) accumulated = drop_smear(aligned, result.views, config, accumulated_views);
  std::vector<std::uint32_t> voxel_views;
  const Points moved = transform_points(accumulated, result.hand_from_reference);
  const Points voxels = accumulated_views.empty()
                            ? voxel_downsample(moved, config.voxel_size)
                            : voxel_downsample(moved, config.voxel_size, accumulated_views, voxel_views);
  for (const auto i : non_isolated(voxels, config.clean_radius, static_cast<std::size_t>(config.clean_min_neighbors))) {
    result.model.points.push_back(voxels[i]);
    if (!voxel_views.empty()) result.model.views.push_back(voxel_views[i]);
  }
  // The views recorded: those given, or more when a view's session recorded more (views no tool was found in).
  result.model.recorded_views = static_cast<int>(result.views.size());
  for (const auto& view : views)
    result.model.recorded_views = std::max(result.model.recorded_views, view.recorded_views);
  result.model.unmerged_views = result.model.recorded_views - accepted_views(result);
  for (const auto& view : aligned) {
    const Points moved = transform_points(view.viewpoints, result.hand_from_reference);
    result.model.viewpoints.insert(result.model.viewpoints.end(), moved.begin(), moved.end());
  }
  return result;
}

}  // namespace

MergeResult merge_views(const std::vector<PointCloud>& input, const MergeConfig& config) {
  if (input.empty()) throw MethodError("no views to merge");
  // Each view's points labelled with its bit, so the model says which views saw each of its points.
  std::vector<PointCloud> views = input;
  for (std::size_t v = 0; v < views.size(); ++v)
    if (views.size() <= kMaxLabelledViews)
      views[v].views.assign(views[v].size(), std::uint32_t{1} << v);
    else
      views[v].views.clear();
  MergeResult best = merge_onto_first(views, config);
  // A reference that most views do not fit (a wrong blob, a gross pose error) loses the good views with
  // it; one that some view does not fit may see less than that view (the head beyond a blob cut at a
  // depth edge lands mostly off the rest). Then the reference is the view that the most others fit, the
  // earliest of equals (revisit_views: of equals, the merge holding the most points).
  const int all = static_cast<int>(views.size());
  if (config.revisit_views ? accepted_views(best) == all : 2 * accepted_views(best) >= all) return best;
  MergeConfig quiet = config;
  quiet.progress = nullptr;
  for (std::size_t r = 1; r < views.size(); ++r) {
    if (static_cast<int>(views[r].points.size()) < config.min_points) continue;
    std::vector<PointCloud> ordered{views[r]};
    for (std::size_t v = 0; v < views.size(); ++v)
      if (v != r) ordered.push_back(views[v]);
    MergeResult candidate = merge_onto_first(ordered, quiet);
    // revisit_views: of as many views fitting, the merge holding more of the tool (a view seeing the head,
    // which the short views' model left out, against one of those short views).
    const bool better = config.revisit_views ? std::pair{accepted_views(candidate), accepted_points(candidate)} >
                                                   std::pair{accepted_views(best), accepted_points(best)}
                                             : accepted_views(candidate) > accepted_views(best);
    if (!better) continue;
    // Back to the input's order: ordered[0] is view r, ordered[k] view k - 1 below r and k above.
    std::vector<ViewMerge> in_order(views.size());
    for (std::size_t k = 0; k < ordered.size(); ++k) in_order[k == 0 ? r : (k <= r ? k - 1 : k)] = candidate.views[k];
    candidate.views = std::move(in_order);
    best = std::move(candidate);
  }
  return best;
}

MergeConfig original_merge() {
  MergeConfig config;
  config.icp.max_iterations = 0;
  config.min_inlier_ratio = 0.0;
  config.see_through_tolerance = 0.0;
  return config;
}

}  // namespace toolinc
