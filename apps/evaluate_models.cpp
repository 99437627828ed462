// evaluate-models MODEL... : accuracy of estimate-frame and find-tooltip on canonical tool models (e.g.
// CAD models), each held with random grasps, the hand's points removed and stereo-like noise added.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/evaluation.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("evaluate-models", "Frame and tooltip accuracy on canonical models under random grasps",
                           {"estimate-frame", "find-tooltip", "evaluate-models"});
  std::vector<std::string> models;
  int grasps = 20;
  std::uint32_t seed = 1;
  double hand_radius = 0.06, noise = 0.0015;
  toolinc::ToolFrameConfig frame_config;
  toolinc::TooltipConfig tooltip_config;
  std::string rule;  // add_tooltip_options sets its default
  auto& cli = command.cli();
  cli.add_option("models", models, "Canonical models (handle from the origin along -Y, effector +X)")->required();
  cli.add_option("--grasps", grasps, "Random grasps per model")->capture_default_str()->check(CLI::PositiveNumber);
  cli.add_option("--seed", seed, "Seed of the grasps and noise")->capture_default_str();
  cli.add_option("--noise", noise, "Gaussian noise sigma per coordinate (m)")->capture_default_str();
  command.add_output("Per-model results JSON (- for stdout)", false);
  toolinc::add_tool_frame_options(cli, frame_config);
  toolinc::add_tooltip_options(cli, tooltip_config, rule);
  return command.run(argc, argv, [&] {
    tooltip_config.rule = toolinc::tooltip_rule_from_string(rule);
    hand_radius = tooltip_config.hand_radius = frame_config.hand_radius;
    toolinc::Json results = toolinc::Json::array();
    int cases = 0, within_10 = 0, beyond_20 = 0, left_handed = 0, handle_over_3 = 0, sign_wrong = 0, salient = 0,
        failed = 0;
    // The table goes to standard output, unless the JSON does.
    std::FILE* table = command.output() == "-" ? stderr : stdout;
    std::fprintf(table, "%-16s %-10s %7s %9s %9s %9s %6s\n", "model", "symmetry", "cases", "handle<=", "tip med", "tip max",
                "sign");
    for (const auto& path : models) {
      const auto model = toolinc::load_cloud(path);
      const auto symmetry = toolinc::measure_symmetry(model.points);
      const std::string name = toolinc::to_string(symmetry);
      toolinc::Rng rng(seed);
      std::vector<double> tips;
      double worst_handle = 0.0;
      int signs = 0, model_failed = 0;
      for (int g = 0; g < grasps; ++g) {
        const Eigen::Matrix4d grasp = toolinc::random_grasp({}, rng);
        const auto e = toolinc::evaluate_held_tool(model.points, symmetry, grasp, hand_radius, noise, rng,
                                                   frame_config, tooltip_config);
        ++cases;
        if (!e.failure.empty()) {
          ++failed, ++model_failed;
          spdlog::warn("{} grasp {}: {}", path, g, e.failure);
          continue;
        }
        tips.push_back(e.tooltip_m);
        worst_handle = std::max(worst_handle, e.handle_axis_deg);
        left_handed += !e.right_handed;
        handle_over_3 += e.handle_axis_deg > 3.0;
        within_10 += e.tooltip_m <= 0.010;
        beyond_20 += e.tooltip_m > 0.020;
        signs += e.effector_sign_right;
      }
      if (symmetry == toolinc::ToolSymmetry::mirror) salient += static_cast<int>(tips.size()), sign_wrong += static_cast<int>(tips.size()) - signs;
      const double median = toolinc::median(tips);
      const double worst = tips.empty() ? NAN : *std::max_element(tips.begin(), tips.end());
      const std::string base = path.substr(path.find_last_of('/') + 1);
      std::fprintf(table, "%-16s %-10s %7d %7.2f° %7.1fmm %7.1fmm %6s\n", base.c_str(), name.c_str(), grasps, worst_handle, 1000 * median,
                  1000 * worst, symmetry == toolinc::ToolSymmetry::mirror ? (std::to_string(signs) + "/" + std::to_string(tips.size())).c_str() : "-");
      results.push_back({{"model", path}, {"symmetry", name}, {"cases", grasps}, {"failed", model_failed},
                         {"worst_handle_axis_deg", worst_handle}, {"median_tooltip_m", median}, {"worst_tooltip_m", worst},
                         {"effector_sign_right", signs}});
    }
    std::fprintf(table, "\nall: %d cases, %d failed; right-handed %d/%d; handle axis > 3 deg: %d; effector sign wrong: %d of %d "
                "salient; tooltip within 10 mm: %.1f%%, beyond 20 mm: %d\n",
                cases, failed, cases - failed - left_handed, cases - failed, handle_over_3, sign_wrong, salient,
                100.0 * within_10 / std::max(1, cases), beyond_20);
    if (!command.output().empty())
      toolinc::write_json(command.output(), {{"type", "model_evaluation"}, {"version", 1}, {"models", results}});
  });
}
