// toolinc/pcl.hpp: PointXYZ and PointXYZRGB clouds to and from toolinc clouds (colours, the sensor origin
// as the viewpoint, non-finite points dropped), and the tool frame and tooltip of a PCL cloud equal to
// those of the same points as a toolinc cloud. Prints what fails and exits 1.
#include <cmath>
#include <cstdio>
#include <limits>

#include "toolinc/pcl.hpp"

namespace {

int failures = 0;
void expect(bool ok, const char* what) {
  if (!ok) std::printf("FAILED: %s\n", what), ++failures;
}

}  // namespace

int main() {
  // A hoe in the hand frame, in float coordinates so that PCL's floats carry it exactly.
  toolinc::PointCloud cloud;
  cloud.frame = "hand";
  for (int i = 0; i <= 110; ++i)
    for (int k = 0; k < 8; ++k)
      cloud.points.emplace_back(float(0.01 * std::cos(k * 0.785)), float(-0.08 - 0.002 * i),
                                float(0.01 * std::sin(k * 0.785)));
  for (int i = 0; i <= 40; ++i)
    for (int j = -15; j <= 15; ++j) cloud.points.emplace_back(float(0.002 * i), float(-0.30), float(0.002 * j));
  for (std::size_t i = 0; i < cloud.size(); ++i)
    cloud.colors.push_back({std::uint8_t(i % 256), std::uint8_t(i / 7 % 256), 200});
  cloud.viewpoints = {{0.25, 0.1, -0.3}, {0.3, -0.1, 0.2}};

  std::size_t dropped = 99;
  auto rgb = toolinc::to_pcl<pcl::PointXYZRGB>(cloud, &dropped);
  expect(rgb.size() == cloud.size() && rgb.is_dense, "to_pcl keeps every point");
  expect(dropped == 1, "to_pcl says it drops the second viewpoint");
  expect((rgb.sensor_origin_.head<3>().cast<double>() - cloud.viewpoints[0]).norm() < 1e-6,
         "sensor origin = first viewpoint");
  expect(rgb[5].r == 5 && rgb[5].g == 0 && rgb[5].b == 200, "colours carried");

  // A hole of an organised cloud (NaN) is dropped on the way back.
  pcl::PointXYZRGB hole;
  hole.x = hole.y = hole.z = std::numeric_limits<float>::quiet_NaN();
  rgb.push_back(hole);
  const toolinc::PointCloud back = toolinc::from_pcl(rgb);
  expect(back.size() == cloud.size() && back.colors.size() == cloud.size(), "from_pcl drops the NaN point only");
  expect(back.colors[5] == cloud.colors[5], "colours back");
  expect(back.viewpoints.size() == 1 && (back.viewpoints[0] - cloud.viewpoints[0]).norm() < 1e-6, "viewpoint back");
  expect(back.frame == "hand", "frame named");
  bool same = true;
  for (std::size_t i = 0; i < cloud.size(); ++i) same = same && back.points[i] == cloud.points[i];
  expect(same, "points back exactly (float coordinates)");

  // PointXYZ: no colours; PCL's default sensor origin (zero) is no viewpoint.
  pcl::PointCloud<pcl::PointXYZ> xyz =
      toolinc::to_pcl<pcl::PointXYZ>(toolinc::PointCloud{cloud.points, {}, {}, "hand", {}});
  expect(xyz.sensor_origin_.isZero(), "no viewpoint, zero sensor origin");
  const toolinc::PointCloud plain = toolinc::from_pcl(xyz);
  expect(!plain.has_colors() && plain.viewpoints.empty() && plain.size() == cloud.size(),
         "PointXYZ back: no colours, no viewpoint");

  // The frame and tooltip of the PCL cloud are those of the toolinc cloud with the same viewpoint.
  const auto single =
      toolinc::to_pcl<pcl::PointXYZ>(toolinc::PointCloud{cloud.points, {}, {}, "hand", {cloud.viewpoints[0]}});
  const toolinc::ToolFrame frame = toolinc::estimate_tool_frame(single);
  const toolinc::ToolFrame direct = toolinc::estimate_tool_frame(cloud.points, {}, {cloud.viewpoints[0]});
  expect((frame.hand_from_tool() - direct.hand_from_tool()).cwiseAbs().maxCoeff() < 1e-9, "PCL frame = toolinc frame");
  const double tip_difference =
      (toolinc::find_tooltip(single, frame).position - toolinc::find_tooltip(cloud.points, direct).position).norm();
  expect(tip_difference < 1e-9, "PCL tooltip = toolinc tooltip");
  expect(frame.effector_axis().x() > 0.9 && frame.handle_axis().y() > 0.9, "the hoe's frame: effector +X, handle +Y");
  std::printf("%s\n", failures == 0 ? "pcl.hpp: all checks passed" : "pcl.hpp: checks failed");
  return failures == 0 ? 0 : 1;
}
