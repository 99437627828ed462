// The tool frame of points made up here: a hoe-like tool (a handle along -Y from the hand, a blade
// across it at the far end), using toolinc::geometry only.
#include <cmath>
#include <cstdio>

#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"

int main() {
  toolinc::Points points;
  for (double y = -0.08; y >= -0.30; y -= 0.002)  // the handle, from beyond the hand radius
    for (int k = 0; k < 8; ++k) points.emplace_back(0.01 * std::cos(k * 0.785), y, 0.01 * std::sin(k * 0.785));
  for (double x = 0.0; x <= 0.08; x += 0.002)  // the blade, towards +X at the far end
    for (double z = -0.03; z <= 0.03; z += 0.002) points.emplace_back(x, -0.30, z);
  const toolinc::ToolFrame frame = toolinc::estimate_tool_frame(points);
  const toolinc::Tooltip tip = toolinc::find_tooltip(points, frame);
  const toolinc::Vec3 x = frame.effector_axis(), y = frame.handle_axis();
  std::printf("effector axis %.3f %.3f %.3f\nhandle axis %.3f %.3f %.3f\ntooltip %.4f %.4f %.4f\n", x.x(), x.y(), x.z(),
              y.x(), y.y(), y.z(), tip.position.x(), tip.position.y(), tip.position.z());
  // The blade points to +X and the handle to the hand (+Y): anything else is a wrong frame.
  return x.x() > 0.9 && y.y() > 0.9 ? 0 : 1;
}
