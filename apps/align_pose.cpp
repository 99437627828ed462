// align-pose --model MODEL --view VIEW.ply -o POSE.json [--oriented ORIENTED.ply] [--tooltip TIP.json]:
// how a known tool is held, from one partial view (paper sect. 5).
#include "toolinc/registration/align_pose.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/results/results_json.hpp"

using namespace toolinc;

int main(int argc, char** argv) {
  Command command("align-pose", "The pose of a known tool in the hand from one partial view of it",
                  {"find-tooltip", "align-pose"});
  std::string model_file, view_file, oriented_file, tooltip_file, rule;  // add_tooltip_options sets its default
  AlignPoseConfig config;
  TooltipConfig tooltip_config;
  command.cli().add_option("--model", model_file, "The tool's model in the canonical pose (PLY or PCD)")->required();
  command.cli().add_option("--view", view_file, "One view of the held tool in the hand frame (PLY or PCD)")->required();
  command.add_output("Output tool_pose JSON (- for stdout)");
  command.cli().add_option("--oriented", oriented_file, "Also write the model moved into the hand frame (PLY)");
  command.cli().add_option("--tooltip", tooltip_file, "Also write the model's tooltip carried into the hand frame");
  add_align_pose_options(command.cli(), config);
  add_tooltip_options(command.cli(), tooltip_config, rule);
  return command.run(argc, argv, [&] {
    const auto start = std::chrono::steady_clock::now();
    const auto since = [](auto t) {
      return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
    };
    tooltip_config.rule = tooltip_rule_from_string(rule);
    tooltip_config.hand_radius = config.hand_radius;
    const PointCloud model = load_cloud(model_file);
    const PointCloud view = load_cloud(view_file);

    const auto model_start = std::chrono::steady_clock::now();
    const PoseModel pose_model = pose_model_of(model, view, config, model_file, view_file);
    const double model_ms = since(model_start);

    PoseResult result;
    try {
      result = align_pose(pose_model, view.points, config);
    } catch (const MethodError& e) {
      throw MethodError(view_file + ": " + e.what());
    }
    const Eigen::Matrix4d& pose = result.best.hand_from_model;
    const Json tooltip = tooltip_file.empty() ? Json() : [&] {
      const CarriedTooltip carried = carry_tooltip(pose_model, model.points, pose, tooltip_config);
      return tooltip_json(carried.tooltip, carried.frame, tooltip_config);
    }();
    const Feasibility& f = result.feasibility;
    spdlog::info(
        "pose: translation ({:.4f}, {:.4f}, {:.4f}) m, tilt {:.1f}, roll {:.1f}, about the handle {:.1f} "
        "deg; inliers {:.1f}% (RMSE {:.2f} mm); {} hypotheses{}",
        f.translation.x(), f.translation.y(), f.translation.z(), f.tilt_deg, f.roll_deg, f.about_handle_deg,
        100.0 * result.best.inlier_ratio, 1000.0 * result.best.inlier_rmse, result.hypotheses,
        result.ambiguous ? "; ambiguous: poses fitting equally well are listed" : "");
    write_json(command.output(), tool_pose_json(result, config, model_file, view_file, model_ms, since(start)));
    if (!f.feasible) throw MethodError("infeasible pose: " + f.reason + " (report written, \"ok\": false)");
    if (!oriented_file.empty()) write_ply(oriented_file, oriented_model(model, pose), {false, command.command_line()});
    if (!tooltip_file.empty()) write_json(tooltip_file, tooltip);
  });
}
