// tooltip_of_cloud CLOUD: the tool frame and tooltip of a cloud in the hand frame (PLY or PCD), as
// find-tooltip computes them with its default options.
#include <cstdio>
#include <exception>

#include "toolinc/toolinc.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: tooltip_of_cloud CLOUD\n");
    return 2;
  }
  try {
    const toolinc::PointCloud cloud = toolinc::read_cloud(argv[1]);
    // Both steps on one kd-tree and held piece, as find-tooltip.
    const auto [frame, tip] = toolinc::estimate_frame_and_tooltip(cloud.points, {}, {}, cloud.viewpoints, cloud.views);
    std::printf("tooltip %.17g %.17g %.17g\n", tip.position.x(), tip.position.y(), tip.position.z());
    std::printf("confident %s\n", tip.confidence.confident ? "yes" : "no");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tooltip_of_cloud: %s\n", e.what());
    return 2;
  }
}
