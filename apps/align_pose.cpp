// align-pose --model MODEL --view VIEW.ply -o POSE.json [--oriented ORIENTED.ply] [--tooltip TIP.json]:
// how a known tool is held, from one partial view (paper sect. 5).
#include <spdlog/spdlog.h>

#include <chrono>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/results_json.hpp"
#include "toolinc/registration/align_pose.hpp"

namespace {

using namespace toolinc;

void add_align_pose_options(CLI::App& cli, AlignPoseConfig& c) {
  const auto group = "Alignment";
  const auto positive = CLI::PositiveNumber;
  cli.add_option("--hand-radius", c.hand_radius, "View points this close to the hand origin are the hand's (m)")
      ->capture_default_str()->group(group)->check(CLI::NonNegativeNumber);
  cli.add_option("--min-view-points", c.min_view_points, "Fewer resampled view points cannot fix a pose")
      ->capture_default_str()->group(group)->check(positive);
  cli.add_option("--max-extent-ratio", c.max_extent_ratio, "Model and view extents further apart: different units")
      ->capture_default_str()->group(group)->check(CLI::Range(1.0, 1e6));
  cli.add_option("--model-voxel", c.model_voxel, "Resampling of the model (m)")
      ->capture_default_str()->group(group)->check(positive);
  cli.add_option("--view-voxel", c.view_voxel, "Resampling of the view (m)")
      ->capture_default_str()->group(group)->check(positive);
  cli.add_option("--roll-step-deg", c.roll_step_deg, "Step of the rolls about the handle tried as hypotheses (deg)")
      ->capture_default_str()->group(group)->check(CLI::Range(1.0, 180.0));
  cli.add_option("--refine-candidates", c.refine_candidates, "Distinct hypotheses refined fully")
      ->capture_default_str()->group(group)->check(positive);
  cli.add_option("--max-iterations", c.icp.max_iterations, "Iterations of the final ICP")
      ->capture_default_str()->group(group)->check(positive);
  cli.add_option("--max-correspondence", c.icp.max_correspondence, "Correspondence distance of the final ICP (m)")
      ->capture_default_str()->group(group)->check(positive);
  cli.add_option("--inlier-distance", c.icp.inlier_distance, "View points this close to the model are inliers (m)")
      ->capture_default_str()->group(group)->check(positive);
  cli.add_option("--max-translation", c.max_translation, "Feasible translation of the tool per axis (m)")
      ->capture_default_str()->group(group)->check(CLI::NonNegativeNumber);
  cli.add_option("--max-tilt-deg", c.max_tilt_deg, "Feasible tilt about the hand's Z (deg)")
      ->capture_default_str()->group(group)->check(CLI::Range(0.0, 180.0));
  cli.add_option("--max-roll-deg", c.max_roll_deg, "Feasible roll about the hand's X (deg)")
      ->capture_default_str()->group(group)->check(CLI::Range(0.0, 90.0));
  cli.add_option("--max-about-handle-deg", c.max_about_handle_deg, "Feasible rotation about the handle (deg)")
      ->capture_default_str()->group(group)->check(CLI::Range(0.0, 180.0));
  cli.add_option("--ambiguity-margin", c.ambiguity_margin, "Poses scoring within this of the best fit as well")
      ->capture_default_str()->group(group)->check(CLI::NonNegativeNumber);
}

}  // namespace

int main(int argc, char** argv) {
  Command command("align-pose", "The pose of a known tool in the hand from one partial view of it",
                  {"find-tooltip", "align-pose"});
  std::string model_file, view_file, oriented_file, tooltip_file, rule = toolinc::to_string(toolinc::TooltipConfig{}.rule);
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
    const auto since = [](auto t) { return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count(); };
    tooltip_config.rule = tooltip_rule_from_string(rule);
    tooltip_config.hand_radius = config.hand_radius;
    const PointCloud model = load_cloud(model_file);
    const PointCloud view = load_cloud(view_file);

    if (const std::string mismatch = unit_mismatch(model.points, view.points, config.max_extent_ratio);
        !mismatch.empty())
      throw InputError(mismatch.rfind("the model", 0) == 0 ? model_file : view_file, mismatch);
    const auto model_start = std::chrono::steady_clock::now();
    const PoseModel pose_model = [&]() -> PoseModel {
      try {
        return PoseModel(model.points, config);
      } catch (const MethodError& e) {
        throw InputError(model_file, std::string("not usable as a tool model: ") + e.what());
      }
    }();
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
    spdlog::info("pose: translation ({:.4f}, {:.4f}, {:.4f}) m, tilt {:.1f}, roll {:.1f}, about the handle {:.1f} "
                 "deg; inliers {:.1f}% (RMSE {:.2f} mm); {} hypotheses{}",
                 f.translation.x(), f.translation.y(), f.translation.z(), f.tilt_deg, f.roll_deg,
                 f.about_handle_deg, 100.0 * result.best.inlier_ratio, 1000.0 * result.best.inlier_rmse,
                 result.hypotheses, result.ambiguous ? "; ambiguous: poses fitting equally well are listed" : "");
    write_json(command.output(), tool_pose_json(result, config, model_file, view_file, model_ms, since(start)));
    if (!f.feasible) throw MethodError("infeasible pose: " + f.reason + " (report written, \"ok\": false)");
    if (!oriented_file.empty())
      write_ply(oriented_file, oriented_model(model, pose), {false, command.command_line()});
    if (!tooltip_file.empty()) write_json(tooltip_file, tooltip);
  });
}
