// evaluate --truth GROUND_TRUTH.json [--frame FRAME.json] [--tooltip TOOLTIP.json] -o -: errors of the
// results against a synthetic ground truth, as JSON (for demos, experiments and summaries).
#include <spdlog/spdlog.h>

#include "toolinc/app/command.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/results/results_json.hpp"
#include "toolinc/synth/ground_truth_file.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("evaluate", "Compare tool frame and tooltip results with a ground truth");
  std::string truth_file, frame_file, tooltip_file;
  command.cli().add_option("--truth", truth_file, "tool_ground_truth JSON")->required();
  command.cli().add_option("--frame", frame_file, "tool_frame JSON");
  command.cli().add_option("--tooltip", tooltip_file, "tooltip JSON");
  command.add_output("Output evaluation JSON (- for stdout)", false)->default_str("-");
  return command.run(argc, argv, [&] {
    const auto truth = toolinc::read_ground_truth(truth_file);
    toolinc::Json result = {{"type", "evaluation"}, {"version", 1}, {"truth", truth_file}};
    if (!frame_file.empty()) {
      const auto frame = toolinc::read_tool_frame(frame_file);
      const double effector = std::acos(std::clamp(frame.effector_axis().dot(truth.axes.col(0)), -1.0, 1.0));
      result["frame"] = {{"file", frame_file},
                         {"handle_axis_error_deg", toolinc::handle_axis_error_deg(truth, frame.handle_axis())},
                         {"effector_axis_error_deg", effector * 180.0 / M_PI},
                         {"right_handed", frame.axes.determinant() > 0},
                         {"origin_error_m", (frame.origin - truth.origin).norm()}};
    }
    if (!tooltip_file.empty()) {
      const double error = toolinc::tooltip_error(truth, toolinc::read_tooltip_position(tooltip_file));
      result["tooltip"] = {{"file", tooltip_file}, {"error_m", error}};
      spdlog::info("tooltip error {:.1f} mm", 1000.0 * error);
    }
    toolinc::write_json(command.output().empty() ? "-" : command.output(), result);
  });
}
