// estimate-frame CLOUD -o FRAME.json: the tool's intrinsic frame (paper sect. 4.1-4.2).
#include <spdlog/spdlog.h>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/results/results_json.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("estimate-frame", "Estimate a held tool's intrinsic frame from its cloud in the hand frame");
  std::string input;
  toolinc::ToolFrameConfig config;
  command.cli().add_option("cloud", input, "Tool cloud in the hand frame (PLY or PCD)")->required();
  command.add_output("Output tool_frame JSON (- for stdout)");
  toolinc::add_tool_frame_options(command.cli(), config);
  return command.run(argc, argv, [&] {
    const auto cloud = toolinc::load_cloud(input);
    const auto frame = toolinc::estimate_tool_frame(cloud.points, config, cloud.viewpoints, cloud.views);
    spdlog::info("handle axis refined by {:.1f} deg from the major axis; symmetry score {:.3f}; {}",
                 frame.diagnostics.handle_refinement_deg, frame.symmetry_score,
                 frame.diagnostics.salient_effector ? "salient effector" : "no salient effector");
    toolinc::write_json(command.output(), toolinc::tool_frame_json(frame, config));
  });
}
