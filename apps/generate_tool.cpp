// generate-tool --family F -o TOOL.ply: a procedural tool, in the canonical pose or held in the hand
// with a random grasp, the hand's points removed and stereo-like noise added, plus its ground truth.
#include <spdlog/spdlog.h>

#include "toolinc/app/command.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/synth/ground_truth_file.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("generate-tool", "Generate a procedural tool cloud with known ground truth");
  std::string family = "hoe", truth_file;
  double handle_length = 0, handle_radius = 0, head_length = 0, head_width = 0, head_height = 0;  // 0: default
  double spacing = 0.002, hand_radius = 0.06, noise = 0.0015;
  std::uint32_t seed = 1;
  int grasp_seed = -1;
  bool ascii = false;
  auto& cli = command.cli();
  cli.add_option("--family", family, "stick, hoe, hook, rake, shovel, l-stick, t-bar, flat-top")->capture_default_str();
  cli.add_option("--handle-length", handle_length, "Handle length (m); default per family");
  cli.add_option("--handle-radius", handle_radius, "Handle radius (m); default per family");
  cli.add_option("--head-length", head_length, "Head reach along +X (m); default per family");
  cli.add_option("--head-width", head_width, "Head extent across Z (m); default per family");
  cli.add_option("--head-height", head_height, "Head extent along Y (m); default per family");
  cli.add_option("--spacing", spacing, "Surface sample spacing (m)")->capture_default_str();
  cli.add_option("--seed", seed, "Sampling seed")->capture_default_str();
  cli.add_option("--grasp-seed", grasp_seed,
                 "Hold the tool with a random grasp from this seed (rotation about the handle +/-90 deg, tilt "
                 "+/-45, roll +/-15, offsets +/-5 cm), remove the hand's points and add noise; without it the "
                 "tool stays in the canonical pose, noise-free");
  cli.add_option("--hand-radius", hand_radius, "Radius of the hand's sphere (m)")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, toolinc::kMaxLength, "m"}));
  cli.add_option("--noise", noise, "Gaussian noise sigma per coordinate (m)")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 0.1, "m"}));
  cli.add_option("--truth", truth_file, "Write the ground truth JSON here (needs --grasp-seed)");
  cli.add_flag("--ascii", ascii, "Write ASCII PLY");
  command.add_output("Output PLY");
  return command.run(argc, argv, [&] {
    toolinc::ToolShape chosen = toolinc::default_shape(toolinc::family_from_string(family));
    const auto given = [](double value, double& field) { field = value > 0 ? value : field; };
    given(handle_length, chosen.handle_length);
    given(handle_radius, chosen.handle_radius);
    given(head_length, chosen.head_length);
    given(head_width, chosen.head_width);
    given(head_height, chosen.head_height);
    chosen.spacing = spacing;
    toolinc::PointCloud cloud = toolinc::generate_tool(chosen, seed);
    if (grasp_seed >= 0) {
      toolinc::Rng rng(static_cast<std::uint32_t>(grasp_seed));
      const Eigen::Matrix4d grasp = toolinc::random_grasp({}, rng);
      const auto truth = toolinc::tool_ground_truth(cloud.points, toolinc::symmetry_of(chosen.family),
                                                    toolinc::truth_tip_of(chosen.family), grasp);
      cloud = {toolinc::observe_in_hand(cloud.points, grasp, hand_radius, noise, rng), {}, {}, "hand"};
      if (!truth_file.empty()) toolinc::write_json(truth_file, toolinc::ground_truth_json(truth, chosen));
    } else if (!truth_file.empty()) {
      throw toolinc::InputError(truth_file, "--truth needs --grasp-seed");
    }
    toolinc::write_ply(command.output(), cloud, {ascii, command.command_line()});
    spdlog::info("{} points -> {}", cloud.size(), command.output());
  });
}
