#include "toolinc/session/crop.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <queue>

#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"

namespace toolinc {

Vec3 reproject_disparity(const CameraModel& camera, const Eigen::Matrix4d& root_from_camera, int u, int v, int value) {
  if (value <= 0) return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  const double z = camera.fx * camera.baseline / camera.disparity_px(value);
  const Vec3 in_camera((u - camera.cx) * z / camera.fx, (v - camera.cy) * z / camera.fy, z);
  return apply(root_from_camera, in_camera);
}

namespace {

// The `allowed` pixels that a path of 8-neighbours, each less than `step` apart in 3D, joins to one of the
// `sources` (region growing with local continuity, as the stereo module's Flood3D); a source is in the
// result only if it is allowed.
cv::Mat grown_along_surface(const std::vector<int>& sources, const cv::Mat& allowed, const std::vector<Vec3>& points,
                            double step) {
  const int w = allowed.cols, h = allowed.rows;
  cv::Mat reached = cv::Mat::zeros(allowed.size(), CV_8UC1);
  std::queue<int> queue;
  for (const int i : sources) reached.data[i] = 255, queue.push(i);
  while (!queue.empty()) {
    const int i = queue.front();
    queue.pop();
    const int u = i % w, v = i / w;
    for (int dv = -1; dv <= 1; ++dv)
      for (int du = -1; du <= 1; ++du) {
        const int nu = u + du, nv = v + dv, j = nv * w + nu;
        if (nu < 0 || nv < 0 || nu >= w || nv >= h || reached.data[j] || !allowed.data[j]) continue;
        if ((points[j] - points[i]).norm() > step) continue;
        reached.data[j] = 255;
        queue.push(j);
      }
  }
  return reached & allowed;
}

// Keeps the mask pixels joined through 3D continuity to the one with a 3D point nearest the mask's centroid.
cv::Mat flood_3d(const cv::Mat& mask, const std::vector<Vec3>& root_points, double distance) {
  const int w = mask.cols, h = mask.rows;
  cv::Mat valid = mask.clone();
  for (int i = 0; i < w * h; ++i)
    if (!root_points[i].allFinite()) valid.data[i] = 0;
  cv::Moments m = cv::moments(mask, true);
  if (m.m00 <= 0) return mask;
  const cv::Point centre(static_cast<int>(m.m10 / m.m00), static_cast<int>(m.m01 / m.m00));
  int seed = -1;
  long best = std::numeric_limits<long>::max();
  for (int i = 0; i < w * h; ++i)
    if (valid.data[i]) {
      const long d = static_cast<long>(i % w - centre.x) * (i % w - centre.x) +
                     static_cast<long>(i / w - centre.y) * (i / w - centre.y);
      if (d < best) best = d, seed = i;
    }
  if (seed < 0) return cv::Mat::zeros(mask.size(), CV_8UC1);
  return grown_along_surface({seed}, valid, root_points, distance);
}

// Each pixel's disparity in pixels (NaN where there is none): from the exact points, as the stereo module
// triangulated them (fx b / z in the left camera), else from the 8-bit disparity.
std::vector<float> pixel_disparities(const CameraModel& camera, const Eigen::Matrix4d& root_from_camera,
                                     const ViewData& view, const std::vector<Vec3>& root_points) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> disparity(root_points.size(), nan);
  const Eigen::Matrix4d camera_from_root = inverse(root_from_camera);
  for (std::size_t i = 0; i < disparity.size(); ++i) {
    if (view.points.empty()) {
      const int value = view.disparity.data[i];
      if (value > 0) disparity[i] = static_cast<float>(camera.disparity_px(value));
    } else if (root_points[i].allFinite()) {
      disparity[i] = static_cast<float>(camera.fx * camera.baseline / apply(camera_from_root, root_points[i]).z());
    }
  }
  return disparity;
}

// Clears the mask pixels near a depth edge (CropConfig::edge_radius_px); returns how many.
int drop_depth_edges(cv::Mat& mask, const std::vector<float>& disparity, int radius, double jump) {
  const int w = mask.cols, h = mask.rows;
  std::vector<int> dropped;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const int i = v * w + u;
      if (!mask.data[i] || std::isnan(disparity[i])) continue;
      bool edge = false;
      for (int dv = -radius; dv <= radius && !edge; ++dv)
        for (int du = -radius; du <= radius && !edge; ++du) {
          const int nu = u + du, nv = v + dv;
          if (nu < 0 || nv < 0 || nu >= w || nv >= h) continue;
          const float other = disparity[nv * w + nu];
          edge = std::isnan(other) || disparity[i] - other > jump * std::max(std::abs(du), std::abs(dv));
        }
      if (edge) dropped.push_back(i);
    }
  for (const int i : dropped) mask.data[i] = 0;
  return static_cast<int>(dropped.size());
}

// Inside the crop box, mirrored for the left hand (the hands' frames are mirror images about the body's
// midplane).
bool within_box(const Vec3& p, const SessionInfo& session, const CropConfig& config) {
  const bool left = session.hand == "left";
  const double z_min = left ? -config.box_max.z() : config.box_min.z();
  const double z_max = left ? -config.box_min.z() : config.box_max.z();
  return p.x() >= config.box_min.x() && p.x() <= config.box_max.x() && p.y() >= config.box_min.y() &&
         p.y() <= config.box_max.y() && p.z() >= z_min && p.z() <= z_max;
}

}  // namespace

std::vector<Vec3> view_root_points(const CameraModel& camera, const ViewRecord& record, const ViewData& view) {
  if (!view.points.empty()) return view.points;
  const int w = camera.width, h = camera.height;
  std::vector<Vec3> points(static_cast<std::size_t>(w) * h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      points[static_cast<std::size_t>(v) * w + u] =
          reproject_disparity(camera, record.root_from_camera, u, v, view.disparity.at<std::uint8_t>(v, u));
  return points;
}

bool within_reach(const Vec3& hand_point, const CropConfig& config) {
  const double distance = hand_point.norm();
  return distance > config.hand_radius && distance <= config.reach;
}

namespace {

// A view's pixels by where their 3D points lie: on the hand (within hand_radius of it), within the tool's
// reach beyond it, and the tool followed out of the hand (the reach's pixels that a path of neighbours less
// than surface_step apart in 3D joins to the hand's own).
struct HandRegions {
  cv::Mat hand, reach, followed;
};
HandRegions hand_regions(const std::vector<Vec3>& root_points, const Eigen::Matrix4d& hand_from_root,
                         const cv::Size& size, const CropConfig& config) {
  HandRegions regions{cv::Mat::zeros(size, CV_8UC1), cv::Mat::zeros(size, CV_8UC1), {}};
  std::vector<int> hand_pixels;
  for (int i = 0; i < size.area(); ++i) {
    if (!root_points[i].allFinite()) continue;
    const Vec3 p = apply(hand_from_root, root_points[i]);
    if (p.norm() <= config.hand_radius)
      regions.hand.data[i] = 255, hand_pixels.push_back(i);
    else if (within_reach(p, config))
      regions.reach.data[i] = 255;
  }
  regions.followed = grown_along_surface(hand_pixels, regions.reach, root_points, config.surface_step);
  return regions;
}

// A held tool's blob reaches the hand. One that does not (none of its pixels' points within hand_radius of
// it) lost what joins the head to the hand, as the closest blob does when a head nearer than its handle is
// cut off from it at their depth edge, or is empty: the tool followed out of the hand joins it.
bool reaches_hand(const cv::Mat& blob, const HandRegions& regions) {
  return !blob.empty() && cv::countNonZero(blob & regions.hand) > 0;
}
cv::Mat joined_to_hand(const cv::Mat& blob, const HandRegions& regions) {
  return reaches_hand(blob, regions) ? blob : blob.empty() ? regions.followed : blob | regions.followed;
}

// view_tool_mask with the view's points (view_root_points) and hand pose already at hand.
ViewToolMask tool_mask_of(const ViewData& view, const std::vector<Vec3>& root_points,
                          const Eigen::Matrix4d& hand_from_root, const CropConfig& config) {
  const HandRegions regions = hand_regions(root_points, hand_from_root, view.left.size(), config);
  const cv::Mat seed = regions.reach & joined_to_hand(view.blob, regions);
  ToolMaskConfig grow = config.mask;
  grow.grow = true;
  ViewToolMask result;
  result.mask = tool_mask(view.left, seed, grow, regions.hand);
  result.with_depth = result.mask & seed;
  return result;
}

}  // namespace

ViewToolMask view_tool_mask(const SessionInfo& session, const ViewRecord& record, const ViewData& view,
                            const CropConfig& config) {
  return tool_mask_of(view, view_root_points(session.camera, record, view), inverse(record.root_from_hand), config);
}

CropConfig matched_stereo_crop(StereoMatcher matcher) {
  CropConfig config;
  config.edge_radius_px = matcher == StereoMatcher::sgbm ? 2 : 0;
  config.image_mask = true;
  return config;
}

CropResult crop_view(const SessionInfo& session, const ViewRecord& record, const ViewData& view,
                     const CropConfig& config) {
  CropResult result;
  const CameraModel& camera = session.camera;
  cv::Mat mask = view.blob;
  result.mask_source = "blob.png";
  if (mask.empty()) {
    mask = closest_blob_mask(view.disparity, config.blob);
    result.mask_source = "closest blob on the disparity";
  }
  const int w = camera.width, h = camera.height;
  const std::vector<Vec3> root_points = view_root_points(camera, record, view);
  const Eigen::Matrix4d hand_from_root = inverse(record.root_from_hand);
  if (cv::countNonZero(mask) == 0) {
    mask = tool_mask_of(view, root_points, hand_from_root, config).with_depth;
    result.mask_source = "no blob: the tool followed out of the hand";
  } else if (config.follow_hand) {
    const HandRegions regions = hand_regions(root_points, hand_from_root, mask.size(), config);
    if (!reaches_hand(mask, regions)) {
      const cv::Mat joined = mask | regions.followed;  // a new image: mask may share the view's blob
      mask = joined;
      result.mask_source += " short of the hand, with the tool followed out of the hand";
    }
  }
  if (config.image_mask) {
    mask = tool_mask(view.left, mask, config.mask);
    result.mask_source += ", trimmed by the left image";
  }
  result.mask_pixels = cv::countNonZero(mask);
  if (result.mask_pixels == 0) throw MethodError(fmt::format("{}: the tool's blob is empty", record.dir));

  result.points_source = view.points.empty() ? "disparity reprojection (approximate)" : "points.pcd";
  if (config.edge_radius_px > 0) {
    mask = mask.clone();  // the view's blob stays as read
    result.edge_pixels = drop_depth_edges(mask, pixel_disparities(camera, record.root_from_camera, view, root_points),
                                          config.edge_radius_px, config.edge_jump_px);
  }
  if (config.flood) mask = flood_3d(mask, root_points, config.flood_distance);

  const Eigen::Matrix3d rotation = hand_from_root.topLeftCorner<3, 3>();
  const Vec3 translation = hand_from_root.topRightCorner<3, 1>();
  PointCloud kept;
  kept.frame = "hand";
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const int i = v * w + u;
      if (!mask.data[i] || !root_points[i].allFinite()) continue;
      ++result.points_3d;
      const Vec3 p = rotation * root_points[i] + translation;
      if (!within_box(p, session, config)) continue;
      ++result.in_box;
      if (p.norm() <= config.hand_radius) continue;
      kept.points.push_back(p);
      const cv::Vec3b bgr = view.left.at<cv::Vec3b>(v, u);
      kept.colors.push_back({bgr[2], bgr[1], bgr[0]});
    }
  result.outside_hand = static_cast<int>(kept.size());

  result.cloud.frame = "hand";
  for (auto i : statistical_inliers(kept.points, config.outlier_neighbors, config.outlier_std)) {
    result.cloud.points.push_back(kept.points[i]);
    result.cloud.colors.push_back(kept.colors[i]);
  }
  result.cloud.viewpoints.push_back(rotation * record.root_from_camera.topRightCorner<3, 1>() + translation);
  result.cloud.recorded_views = static_cast<int>(session.views.size());  // a merge missing some of them knows
  if (static_cast<int>(result.cloud.size()) < config.min_points)
    throw MethodError(
        fmt::format("{}: only {} tool points left after cropping (mask {} px, 3D {}, in box {}, "
                    "outside the hand {}), at least {} needed",
                    record.dir, result.cloud.size(), result.mask_pixels, result.points_3d, result.in_box,
                    result.outside_hand, config.min_points));
  return result;
}

}  // namespace toolinc
