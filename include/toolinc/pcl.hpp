// PCL interop, header-only (the library itself does not depend on PCL): toolinc clouds to and from
// pcl::PointCloud<pcl::PointXYZ> / <pcl::PointXYZRGB>, and the tool frame and tooltip of a PCL cloud.
//
// A PCL cloud has one sensor origin (sensor_origin_), a toolinc cloud a list of viewpoints (a merged
// model carries every view's). from_pcl takes a non-zero sensor origin as the viewpoint (the default,
// zero, is PCL's "unknown": no camera sits at the hand origin); to_pcl sets the first viewpoint as the
// sensor origin and says how many it could not carry. Non-finite points (an organised cloud's holes)
// are dropped, as the cloud readers do.
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>
#include <string>
#include <type_traits>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"

namespace toolinc {

template <typename PointT>
PointCloud from_pcl(const pcl::PointCloud<PointT>& in, const std::string& frame = "hand") {
  constexpr bool has_rgb = std::is_same_v<PointT, pcl::PointXYZRGB>;
  static_assert(has_rgb || std::is_same_v<PointT, pcl::PointXYZ>, "toolinc::from_pcl: PointXYZ or PointXYZRGB");
  PointCloud out;
  out.frame = frame;
  out.points.reserve(in.size());
  for (const auto& p : in) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    out.points.emplace_back(p.x, p.y, p.z);
    if constexpr (has_rgb) out.colors.push_back({p.r, p.g, p.b});
  }
  const Eigen::Vector3f origin = in.sensor_origin_.template head<3>();
  if (!origin.isZero(0.0f)) out.viewpoints.push_back(origin.cast<double>());
  return out;
}

// `dropped_viewpoints`, when given, receives how many viewpoints PCL's single sensor origin could not carry.
template <typename PointT>
pcl::PointCloud<PointT> to_pcl(const PointCloud& in, std::size_t* dropped_viewpoints = nullptr) {
  constexpr bool has_rgb = std::is_same_v<PointT, pcl::PointXYZRGB>;
  static_assert(has_rgb || std::is_same_v<PointT, pcl::PointXYZ>, "toolinc::to_pcl: PointXYZ or PointXYZRGB");
  pcl::PointCloud<PointT> out;
  out.reserve(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    PointT p;
    p.x = static_cast<float>(in.points[i].x());
    p.y = static_cast<float>(in.points[i].y());
    p.z = static_cast<float>(in.points[i].z());
    if constexpr (has_rgb) {
      const Rgb c = in.has_colors() ? in.colors[i] : Rgb{255, 255, 255};
      p.r = c[0], p.g = c[1], p.b = c[2], p.a = 255;
    }
    out.push_back(p);
  }
  out.is_dense = true;
  if (!in.viewpoints.empty())
    out.sensor_origin_ =
        Eigen::Vector4f(static_cast<float>(in.viewpoints[0].x()), static_cast<float>(in.viewpoints[0].y()),
                        static_cast<float>(in.viewpoints[0].z()), 0.0f);
  if (dropped_viewpoints) *dropped_viewpoints = in.viewpoints.empty() ? 0 : in.viewpoints.size() - 1;
  return out;
}

// The tool frame of a PCL cloud in the hand frame; its sensor origin, when set, is the viewpoint the
// symmetry test uses.
template <typename PointT>
ToolFrame estimate_tool_frame(const pcl::PointCloud<PointT>& cloud, const ToolFrameConfig& config = {}) {
  const PointCloud c = from_pcl(cloud);
  return estimate_tool_frame(c.points, config, c.viewpoints);
}

template <typename PointT>
Tooltip find_tooltip(const pcl::PointCloud<PointT>& cloud, const ToolFrame& frame, const TooltipConfig& config = {}) {
  return find_tooltip(from_pcl(cloud).points, frame, config);
}

}  // namespace toolinc
