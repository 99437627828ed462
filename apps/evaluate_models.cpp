// evaluate-models MODEL|FOLDER... [--kinds MAP.json] : accuracy of estimate-frame and find-tooltip on
// canonical tool models (e.g. CAD models), each held with random grasps, the hand's points removed and
// stereo-like noise added; per model and per kind of tool, each rate with its 95 % (Wilson) interval.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/model_kinds.hpp"

namespace {

// The chosen tooltip's probability is tallied in these bins, each with how many of its tooltips lie within
// 15 mm: the confidence's calibration on the cases.
constexpr std::array<double, 7> kProbabilityEdges{0.0, 0.5, 0.7, 0.8, 0.9, 0.95, 1.0};
constexpr std::size_t kProbabilityBins = kProbabilityEdges.size() - 1;

struct Tally {
  int cases = 0, failed = 0, within_10 = 0, handle_within_3 = 0, left_handed = 0, salient = 0, sign_right = 0;
  int confident = 0, confident_within_15 = 0;
  std::array<int, kProbabilityBins> bin_cases{}, bin_within_15{};
  std::vector<double> tips;
  double worst_handle = 0.0;

  void add(const toolinc::HeldToolErrors& e, bool mirror) {
    ++cases;
    if (!e.failure.empty()) {
      ++failed;
      return;
    }
    tips.push_back(e.tooltip_m);
    within_10 += e.tooltip_m <= 0.010;
    handle_within_3 += e.handle_axis_deg <= 3.0;
    left_handed += !e.right_handed;
    confident += e.confident;
    confident_within_15 += e.confident && e.tooltip_m <= 0.015;
    const auto upper =
        std::upper_bound(kProbabilityEdges.begin() + 1, kProbabilityEdges.end() - 1, e.tooltip_probability);
    const auto bin = static_cast<std::size_t>(upper - kProbabilityEdges.begin() - 1);
    ++bin_cases[bin];
    bin_within_15[bin] += e.tooltip_m <= 0.015;
    worst_handle = std::max(worst_handle, e.handle_axis_deg);
    if (mirror) ++salient, sign_right += e.effector_sign_right;
  }
};

void print_row(std::FILE* out, const std::string& name, const std::string& detail, const Tally& t) {
  const double worst = t.tips.empty() ? NAN : *std::max_element(t.tips.begin(), t.tips.end());
  std::fprintf(out, "%-16s %-10s %6d %24s %24s %7.1fmm %7.1fmm %7s %5d %24s\n", name.c_str(), detail.c_str(), t.cases,
               toolinc::rate_text(t.within_10, t.cases).c_str(), toolinc::rate_text(t.handle_within_3, t.cases).c_str(),
               1000 * toolinc::median(t.tips), 1000 * worst,
               t.salient ? (std::to_string(t.sign_right) + "/" + std::to_string(t.salient)).c_str() : "-", t.confident,
               toolinc::rate_text(t.confident_within_15, t.confident).c_str());
}

toolinc::Json tally_json(const std::string& key, const std::string& name, const Tally& t) {
  toolinc::Json bins = toolinc::Json::array();
  for (std::size_t b = 0; b < kProbabilityBins; ++b)
    bins.push_back({{"probability", {kProbabilityEdges[b], kProbabilityEdges[b + 1]}},
                    {"cases", t.bin_cases[b]},
                    {"tooltip_within_15mm", t.bin_within_15[b]}});
  return {{key, name},
          {"cases", t.cases},
          {"failed", t.failed},
          {"tooltip_within_10mm", toolinc::rate_json(name, t.within_10, t.cases)},
          {"handle_axis_within_3deg", toolinc::rate_json(name, t.handle_within_3, t.cases)},
          {"left_handed", t.left_handed},
          {"worst_handle_axis_deg", t.worst_handle},
          {"median_tooltip_m", toolinc::median(t.tips)},
          {"worst_tooltip_m", t.tips.empty() ? NAN : *std::max_element(t.tips.begin(), t.tips.end())},
          {"effector_sign_right", t.sign_right},
          {"salient_cases", t.salient},
          {"confident", t.confident},
          {"confident_tooltip_within_15mm", toolinc::rate_json(name, t.confident_within_15, t.confident)},
          {"probability_bins", bins}};
}

}  // namespace

int main(int argc, char** argv) {
  toolinc::Command command("evaluate-models", "Frame and tooltip accuracy on canonical models under random grasps",
                           {"estimate-frame", "find-tooltip", "evaluate-models"});
  std::vector<std::string> inputs;
  std::string kinds_file;
  int grasps = 20;
  std::uint32_t seed = 1;
  double hand_radius = 0.06, noise = 0.0015;
  toolinc::ToolFrameConfig frame_config;
  toolinc::TooltipConfig tooltip_config;
  std::string rule;  // add_tooltip_options sets its default
  auto& cli = command.cli();
  cli.add_option("models", inputs,
                 "Canonical models (handle from the origin along -Y, effector +X), or folders of them")
      ->required();
  cli.add_option("--kinds", kinds_file,
                 "JSON {\"file stem or prefix\": \"kind\"}; default: the stem's leading letters (hok -> hook, ...)");
  cli.add_option("--grasps", grasps, "Random grasps per model")
      ->capture_default_str()
      ->check(toolinc::in_range({1, false, 10000, ""}));
  cli.add_option("--seed", seed, "Seed of the grasps and noise")->capture_default_str();
  cli.add_option("--noise", noise, "Gaussian noise sigma per coordinate (m)")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 0.1, "m"}));
  command.add_output("Per-model and per-kind results JSON (- for stdout)", false);
  toolinc::add_tool_frame_options(cli, frame_config);
  toolinc::add_tooltip_options(cli, tooltip_config, rule);
  return command.run(argc, argv, [&] {
    tooltip_config.rule = toolinc::tooltip_rule_from_string(rule);
    toolinc::share_hand_settings(frame_config, tooltip_config);
    hand_radius = frame_config.hand_radius;
    const toolinc::KindMap kinds = kinds_file.empty() ? toolinc::KindMap{} : toolinc::read_kind_map(kinds_file);
    const std::vector<std::string> models = toolinc::expand_model_paths(inputs);
    // The table goes to standard output, unless the JSON does.
    std::FILE* table = command.output() == "-" ? stderr : stdout;
    const auto header = [&](const char* first, const char* second) {
      std::fprintf(table, "%-16s %-10s %6s %24s %24s %9s %9s %7s %5s %24s\n", first, second, "cases",
                   "tip<=10mm (95% int.)", "handle<=3deg (95% int.)", "tip med", "tip max", "sign", "conf.",
                   "confident: tip<=15mm");
    };
    header("model", "symmetry");
    toolinc::Json per_model = toolinc::Json::array(), per_kind = toolinc::Json::array();
    std::map<std::string, Tally> by_kind;
    Tally all;
    for (const auto& path : models) {
      const auto model = toolinc::load_cloud(path);
      const auto symmetry = toolinc::measure_symmetry(model.points);
      const bool mirror = symmetry == toolinc::ToolSymmetry::mirror;
      const std::string kind = toolinc::model_kind(path, kinds);
      toolinc::Rng rng(seed);
      Tally tally;
      for (int g = 0; g < grasps; ++g) {
        const Eigen::Matrix4d grasp = toolinc::random_grasp({}, rng);
        const auto e = toolinc::evaluate_held_tool(model.points, symmetry, toolinc::truth_tip_of_kind(kind), grasp,
                                                   hand_radius, noise, rng, frame_config, tooltip_config);
        if (!e.failure.empty()) spdlog::warn("{} grasp {}: {}", path, g, e.failure);
        tally.add(e, mirror), by_kind[kind].add(e, mirror), all.add(e, mirror);
      }
      const std::string base = path.substr(path.find_last_of('/') + 1);
      print_row(table, base, toolinc::to_string(symmetry), tally);
      toolinc::Json row = tally_json("model", path, tally);
      row["kind"] = kind;
      row["symmetry"] = toolinc::to_string(symmetry);
      per_model.push_back(row);
    }
    std::fprintf(table, "\n");
    header("kind", "");
    for (const auto& [kind, tally] : by_kind) {
      print_row(table, kind, "", tally);
      per_kind.push_back(tally_json("kind", kind, tally));
    }
    print_row(table, "all", "", all);
    std::fprintf(table,
                 "\nall: %d cases, %d failed; right-handed %d/%d; tooltip within 10 mm %s; handle axis within "
                 "3 deg %s; effector sign right %d of %d salient; confident %d, of which tooltip within 15 mm %s\n",
                 all.cases, all.failed, all.cases - all.failed - all.left_handed, all.cases - all.failed,
                 toolinc::rate_text(all.within_10, all.cases).c_str(),
                 toolinc::rate_text(all.handle_within_3, all.cases).c_str(), all.sign_right, all.salient, all.confident,
                 toolinc::rate_text(all.confident_within_15, all.confident).c_str());
    if (!command.output().empty())
      toolinc::write_json(command.output(), {{"type", "model_evaluation"},
                                             {"version", 2},
                                             {"grasps", grasps},
                                             {"seed", seed},
                                             {"noise_m", noise},
                                             {"hand_radius_m", hand_radius},
                                             {"models", per_model},
                                             {"kinds", per_kind},
                                             {"all", tally_json("kind", "all", all)}});
  });
}
