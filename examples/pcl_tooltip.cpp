// pcl_tooltip CLOUD: a PCL user's view. The cloud arrives as a pcl::PointCloud<pcl::PointXYZRGB> with
// its sensor origin (here made from a file; in a YARP module from the stereo module); toolinc finds the
// tool frame and tooltip on it directly, and the result goes back to PCL as a cloud in the tool frame.
// Exits 1 when the PCL route disagrees with toolinc's own (beyond PCL's float coordinates) or loses
// the sensor origin.
#include <pcl/common/transforms.h>

#include <cstdio>
#include <exception>

#include "toolinc/io/cloud_io.hpp"
#include "toolinc/pcl.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: pcl_tooltip CLOUD\n");
    return 2;
  }
  try {
    toolinc::PointCloud original = toolinc::read_cloud(argv[1]);
    if (original.viewpoints.empty()) original.viewpoints.push_back({0.05, 0.3, -0.2});  // a camera, for the example
    const auto cloud = toolinc::to_pcl<pcl::PointXYZRGB>(original);
    const toolinc::ToolFrame frame = toolinc::estimate_tool_frame(cloud);
    const toolinc::Tooltip tip = toolinc::find_tooltip(cloud, frame);
    pcl::PointCloud<pcl::PointXYZRGB> in_tool_frame;
    pcl::transformPointCloud(cloud, in_tool_frame, Eigen::Matrix4f(frame.hand_from_tool().inverse().cast<float>()));
    std::printf("%zu PCL points; sensor origin %.3f %.3f %.3f\n", cloud.size(), cloud.sensor_origin_.x(),
                cloud.sensor_origin_.y(), cloud.sensor_origin_.z());
    std::printf("tooltip %.6f %.6f %.6f\n", tip.position.x(), tip.position.y(), tip.position.z());
    std::printf("in the tool frame, the first point is at %.4f %.4f %.4f\n", in_tool_frame[0].x, in_tool_frame[0].y,
                in_tool_frame[0].z);

    const toolinc::PointCloud back = toolinc::from_pcl(cloud);
    const toolinc::ToolFrame direct_frame = toolinc::estimate_tool_frame(original.points, {}, original.viewpoints);
    const toolinc::Tooltip direct = toolinc::find_tooltip(original.points, direct_frame);
    const double difference = (direct.position - tip.position).norm();
    std::printf("toolinc's own cloud: tooltip %.6f %.6f %.6f (%.1e m apart)\n", direct.position.x(),
                direct.position.y(), direct.position.z(), difference);
    const bool same_origin = back.viewpoints.size() == 1 && (back.viewpoints[0] - original.viewpoints[0]).norm() < 1e-7;
    return difference < 1e-5 && same_origin && back.size() == original.size() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_tooltip: %s\n", e.what());
    return 2;
  }
}
