// render CLOUD... [--frame FRAME.json] [--tooltip TOOLTIP.json] [--pose POSE.json --model MODEL] -o OUT.png:
// a headless picture of clouds in the hand frame with the tool frame, the tooltip and a known tool's
// model where align-pose says it is held; render --session SESSION -o SHEET.png: a contact sheet of a
// recorded session's views.
#include "toolinc/render/render.hpp"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <ostream>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/render/contact_sheet.hpp"
#include "toolinc/results/results_json.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("render",
                           "Draw clouds (hand frame), the tool frame and the tooltip, or a session's "
                           "views, to a PNG");
  std::vector<std::string> inputs;
  std::string frame_path, tooltip_path, pose_path, model_path, session_dir;
  toolinc::RenderOptions options;
  toolinc::ContactSheetOptions sheet;
  auto& cli = command.cli();
  auto* clouds = cli.add_option("clouds", inputs, "Clouds in the hand frame (PLY or PCD)");
  auto* frame = cli.add_option("--frame", frame_path, "tool_frame JSON: draw its axes from its origin");
  auto* tooltip = cli.add_option("--tooltip", tooltip_path, "tooltip JSON: mark its position");
  auto* pose = cli.add_option("--pose", pose_path, "tool_pose JSON (align-pose): draw --model where it is held");
  auto* model = cli.add_option("--model", model_path, "The tool model (canonical pose) that --pose places");
  pose->needs(model);
  model->needs(pose);
  auto* session = cli.add_option("--session", session_dir, "A recorded session: draw a contact sheet of its views");
  for (auto* option : {clouds, frame, tooltip, pose, model}) session->excludes(option);
  // Beyond 10000 px a side an image takes gigabytes.
  const CLI::Validator kImageSide = toolinc::in_range({1, false, 10000, "px"});
  cli.add_option("--width", options.width, "Image width, pixels")->capture_default_str()->check(kImageSide);
  cli.add_option("--height", options.height, "Image height, pixels")->capture_default_str()->check(kImageSide);
  cli.add_option("--axis-length", options.axis_length, "Drawn length of the tool frame's axes, m")
      ->capture_default_str()
      ->check(toolinc::in_range({toolinc::kMinLength, false, toolinc::kMaxLength, "m"}));
  cli.add_option("--panel-width", sheet.panel_width, "With --session: width of each image on the sheet, pixels")
      ->capture_default_str()
      ->check(kImageSide);
  command.add_output("Output PNG");
  return command.run(argc, argv, [&] {
    cv::Mat image;
    if (!session_dir.empty()) {
      image = toolinc::render_contact_sheet(session_dir, sheet);
    } else {
      if (inputs.empty() && model_path.empty())
        throw std::invalid_argument("nothing to draw: give clouds, --pose with --model, or --session");
      toolinc::RenderScene scene;
      for (const auto& path : inputs) {
        auto cloud = toolinc::load_cloud(path);
        scene.clouds.push_back({std::filesystem::path(path).filename().string(), std::move(cloud.points)});
      }
      if (!model_path.empty()) {
        const Eigen::Matrix4d hand_from_model = toolinc::read_tool_pose(pose_path);
        scene.clouds.push_back({std::filesystem::path(model_path).filename().string() + " (posed)",
                                toolinc::transform_points(toolinc::load_cloud(model_path).points, hand_from_model)});
      }
      if (!frame_path.empty()) scene.frame = toolinc::read_tool_frame(frame_path);
      if (!tooltip_path.empty()) scene.tooltip = toolinc::read_tooltip_position(tooltip_path);
      image = toolinc::render_scene(scene, options);
    }
    const auto bytes = toolinc::encode_png(image);
    toolinc::write_file_atomic(
        command.output(),
        [&](std::ostream& out) { out.write(reinterpret_cast<const char*>(bytes.data()), bytes.size()); },
        /*binary=*/true);
    spdlog::info("wrote {} ({} x {})", command.output(), image.cols, image.rows);
  });
}
