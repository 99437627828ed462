// evaluate-poses MODEL... [--grasps N] [--seed S] [-j J] [-o RESULTS.json]: accuracy of align-pose on
// canonical tool models (e.g. CAD models), each held with random grasps (any turn about the handle) and
// seen in one rendered partial view; a table per model and per kind of tool, each rate with its 95 %
// Wilson interval, and every case in the JSON.
#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <map>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/model_kinds.hpp"
#include "toolinc/synth/pose_evaluation.hpp"

using namespace toolinc;

namespace {

struct Tally {
  int cases = 0, right = 0, pose_right = 0, tooltip_right = 0, failed = 0;
  std::vector<double> rotation, translation, tooltip;
  void add(const PoseCaseResult& r) {
    ++cases, right += r.right, pose_right += r.pose_right, tooltip_right += r.tooltip_right;
    if (!r.failure.empty()) return void(++failed);
    rotation.push_back(r.errors.rotation_deg), translation.push_back(r.errors.translation_m),
        tooltip.push_back(r.errors.tooltip_m);
  }
  std::string interval() const {
    const auto [lo, hi] = wilson_interval(right, cases);
    return fmt::format("{:.0f}-{:.0f}%", 100 * lo, 100 * hi);
  }
  Json json(const std::string& key, const std::string& name) const {
    const auto [lo, hi] = wilson_interval(right, cases);
    return {{key, name},
            {"cases", cases},
            {"right", right},
            {"pose_right", pose_right},
            {"tooltip_right", tooltip_right},
            {"failed", failed},
            {"rate", static_cast<double>(right) / cases},
            {"rate_interval_95", {lo, hi}},
            {"median_tooltip_m", median(tooltip)},
            {"median_translation_m", median(translation)}};
  }
};

void print_row(std::FILE* table, const std::string& name, const std::string& extra, const Tally& t) {
  const auto max_of = [](const std::vector<double>& v) {
    return v.empty() ? NAN : *std::max_element(v.begin(), v.end());
  };
  std::fprintf(table, "%-16s %-10s %5d %5d %5d %5d %9s %7.1f %7.1f %8.1f %8.1f\n", name.c_str(), extra.c_str(), t.cases,
               t.right, t.pose_right, t.tooltip_right, t.interval().c_str(), median(t.rotation),
               1000 * median(t.translation), 1000 * median(t.tooltip), 1000 * max_of(t.tooltip));
}

}  // namespace

int main(int argc, char** argv) {
  Command command("evaluate-poses",
                  "align-pose accuracy on canonical models under random grasps, one partial view each",
                  {"align-pose", "evaluate-poses"});
  std::vector<std::string> inputs;
  std::string kinds_file;
  PoseEvaluationConfig config;
  auto& cli = command.cli();
  cli.add_option("models", inputs,
                 "Canonical models (handle from the origin along -Y, effector +X), or folders of them")
      ->required();
  cli.add_option("--kinds", kinds_file,
                 "JSON {\"file stem or prefix\": \"kind\"}; default: the stem's leading letters (hok -> hook, ...)");
  cli.add_option("--grasps", config.grasps, "Random grasps per model")
      ->capture_default_str()
      ->check(toolinc::in_range({1, false, 10000, ""}));
  cli.add_option("--seed", config.seed, "Seed of the grasps, views and noise")->capture_default_str();
  cli.add_option("-j,--jobs", config.jobs, "Cases evaluated in parallel (the results do not depend on it)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64u));
  command.add_output("Per-case results JSON (- for stdout)", false);
  add_align_pose_options(cli, config.align);
  return command.run(argc, argv, [&] {
    const KindMap kinds_map = kinds_file.empty() ? KindMap{} : read_kind_map(kinds_file);
    std::vector<PoseEvaluationModel> models;
    for (const auto& file : expand_model_paths(inputs)) {
      PointCloud cloud = load_cloud(file);
      const ToolSymmetry symmetry = measure_symmetry(cloud.points);
      models.push_back({file, model_kind(file, kinds_map), std::move(cloud), symmetry});
    }
    const std::vector<PoseCaseResult> results = evaluate_poses(models, config);

    // The table goes to standard output, unless the JSON does.
    std::FILE* table = command.output() == "-" ? stderr : stdout;
    const char* header = "%-16s %-10s %5s %5s %5s %5s %9s %7s %7s %8s %8s\n";
    std::fprintf(table, header, "model", "symmetry", "cases", "right", "pose", "tip", "95%", "rot med", "t mm",
                 "tip med", "tip max");
    std::map<std::string, Tally> kinds;
    Tally all;
    Json cases = Json::array(), per_model = Json::array(), per_kind = Json::array();
    for (std::size_t m = 0; m < models.size(); ++m) {
      Tally tally;
      for (const auto& r : results) {
        if (r.model != static_cast<int>(m)) continue;
        tally.add(r), kinds[models[m].kind].add(r), all.add(r);
        if (!r.failure.empty()) spdlog::warn("{} grasp {}: {}", models[m].name, r.grasp, r.failure);
        cases.push_back({{"model", models[m].name},
                         {"kind", models[m].kind},
                         {"grasp", r.grasp},
                         {"right", r.right},
                         {"pose_right", r.pose_right},
                         {"tooltip_right", r.tooltip_right},
                         {"rotation_deg", r.errors.rotation_deg},
                         {"translation_m", r.errors.translation_m},
                         {"tooltip_m", r.errors.tooltip_m},
                         {"ambiguous", r.ambiguous},
                         {"feasible", r.feasible},
                         {"view_points", r.view_points},
                         {"failure", r.failure}});
      }
      const std::string base = models[m].name.substr(models[m].name.find_last_of('/') + 1);
      print_row(table, base, to_string(models[m].symmetry), tally);
      per_model.push_back(tally.json("model", models[m].name));
      per_model.back()["symmetry"] = to_string(models[m].symmetry);
    }
    std::fprintf(table, "\n");
    std::fprintf(table, header, "kind", "", "cases", "right", "pose", "tip", "95%", "rot med", "t mm", "tip med",
                 "tip max");
    for (const auto& [kind, tally] : kinds) {
      print_row(table, kind, "", tally);
      per_kind.push_back(tally.json("kind", kind));
    }
    print_row(table, "all", "", all);
    std::fprintf(table,
                 "\nright: rotation <= %g deg and translation <= %g mm (pose), or tooltip <= %g mm (tip), "
                 "modulo symmetry; %d failed\n",
                 config.max_rotation_deg, 1000 * config.max_translation_m, 1000 * config.max_tooltip_m, all.failed);
    if (!command.output().empty())
      write_json(command.output(), {{"type", "pose_evaluation"},
                                    {"version", 1},
                                    {"grasps", config.grasps},
                                    {"seed", config.seed},
                                    {"all", all.json("kind", "all")},
                                    {"kinds", per_kind},
                                    {"models", per_model},
                                    {"cases", cases}});
  });
}
