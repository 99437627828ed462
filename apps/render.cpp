// render CLOUD... [--frame FRAME.json] [--tooltip TOOLTIP.json] -o OUT.png: a headless picture of clouds
// in the hand frame with the tool frame and tooltip (issue 7).
#include <spdlog/spdlog.h>

#include <filesystem>
#include <ostream>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/results_json.hpp"
#include "toolinc/render/render.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("render", "Draw clouds (hand frame), the tool frame and the tooltip to a PNG");
  std::vector<std::string> inputs;
  std::string frame_path, tooltip_path;
  toolinc::RenderOptions options;
  command.cli().add_option("clouds", inputs, "Clouds in the hand frame (PLY or PCD)")->required();
  command.cli().add_option("--frame", frame_path, "tool_frame JSON: draw its axes from its origin");
  command.cli().add_option("--tooltip", tooltip_path, "tooltip JSON: mark its position");
  command.cli().add_option("--width", options.width, "Image width, pixels")->capture_default_str();
  command.cli().add_option("--height", options.height, "Image height, pixels")->capture_default_str();
  command.cli().add_option("--axis-length", options.axis_length, "Drawn length of the tool frame's axes, m")
      ->capture_default_str();
  command.add_output("Output PNG");
  return command.run(argc, argv, [&] {
    toolinc::RenderScene scene;
    for (const auto& path : inputs) {
      auto cloud = toolinc::load_cloud(path);
      scene.clouds.push_back({std::filesystem::path(path).filename().string(), std::move(cloud.points)});
    }
    if (!frame_path.empty()) scene.frame = toolinc::read_tool_frame(frame_path);
    if (!tooltip_path.empty()) scene.tooltip = toolinc::read_tooltip_position(tooltip_path);
    const auto bytes = toolinc::encode_png(toolinc::render_scene(scene, options));
    toolinc::write_file_atomic(
        command.output(),
        [&](std::ostream& out) { out.write(reinterpret_cast<const char*>(bytes.data()), bytes.size()); },
        /*binary=*/true);
    spdlog::info("wrote {} ({} x {})", command.output(), options.width, options.height);
  });
}
