// find-tooltip CLOUD [--frame FRAME.json] -o TOOLTIP.json: the tooltip (paper sect. 4.3).
#include <spdlog/spdlog.h>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/results/results_json.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("find-tooltip", "Find a held tool's tooltip from its cloud in the hand frame",
                           {"estimate-frame", "find-tooltip"});
  std::string input, frame_file, rule;  // add_tooltip_options sets its default
  toolinc::ToolFrameConfig frame_config;
  toolinc::TooltipConfig config;
  command.cli().add_option("cloud", input, "Tool cloud in the hand frame (PLY or PCD)")->required();
  command.cli().add_option("--frame", frame_file, "tool_frame JSON; estimated from the cloud when absent");
  command.add_output("Output tooltip JSON (- for stdout)");
  toolinc::add_tool_frame_options(command.cli(), frame_config);
  toolinc::add_tooltip_options(command.cli(), config, rule);
  return command.run(argc, argv, [&] {
    config.rule = toolinc::tooltip_rule_from_string(rule);
    toolinc::share_hand_settings(frame_config, config);
    const auto frame = frame_file.empty() ? toolinc::ToolFrame{} : toolinc::read_tool_frame(frame_file);
    const auto cloud = toolinc::load_cloud(input);
    const auto [used, tooltip] = frame_file.empty()
                                     ? toolinc::estimate_frame_and_tooltip(cloud, frame_config, config)
                                     : toolinc::FrameAndTooltip{frame, toolinc::find_tooltip(cloud, frame, config)};
    spdlog::info("tooltip at ({:.4f}, {:.4f}, {:.4f}) m in the hand frame", tooltip.position.x(), tooltip.position.y(),
                 tooltip.position.z());
    toolinc::write_json(command.output(), toolinc::tooltip_json(tooltip, used, config));
  });
}
