// evaluate-sessions [--families F...] [--first-seed S] [--grasps N] [--tip-tolerance M] [-j J] [-o RESULTS.json]:
// accuracy of the whole offline pipeline on simulated sessions, every family x N grasps (seeds S, S+1, ...),
// as simulate-session draws them. The figures of the sessions issue, reproducible from the repository, with
// the 95 % interval of each rate: a rate measured on a few hundred sessions is uncertain by a few percent,
// and beside it the rate with the true frame on the same merged models (what the frame costs).
#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/progress.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/model_kinds.hpp"

namespace {

// One session: of a generated family, or of a canonical model (model >= 0); group is the row it counts in.
struct Case {
  std::string group;
  toolinc::ToolFamily family;
  int model;
  std::uint32_t seed;
  toolinc::SessionErrors errors;
};

}  // namespace

int main(int argc, char** argv) {
  toolinc::Command command("evaluate-sessions", "Whole-pipeline accuracy on simulated sessions of every tool family",
                           {"estimate-frame", "find-tooltip", "evaluate-sessions"});
  std::vector<std::string> family_names, model_inputs;
  std::string kinds_file;
  std::uint32_t first_seed = 100;
  int grasps = 10;
  double tip_tolerance = 0.010;
  unsigned jobs = 1;
  bool follow_hand = false;
  toolinc::PipelineConfig pipeline;
  std::string rule, stereo = "elas", grasp = "recorded", reconstruction = "registered";  // add_tooltip_options
                                                                                         // sets rule's default
  double kinematic_mm = toolinc::SessionSimulatorConfig{}.kinematic_error_m * 1000.0;
  double kinematic_deg = toolinc::SessionSimulatorConfig{}.kinematic_error_deg;
  auto& cli = command.cli();
  cli.add_option("--families", family_names, "Tool families (default: all, unless --models)");
  cli.add_option("--models", model_inputs,
                 "Canonical models or folders of them, simulated as simulate-session --model (symmetry "
                 "measured); reported per kind of tool");
  cli.add_option("--kinds", kinds_file,
                 "With --models: JSON {\"file stem or prefix\": \"kind\"}; default: the stem's leading letters");
  cli.add_option("--first-seed", first_seed, "Seed of the first grasp; grasp g uses first-seed + g")
      ->capture_default_str();
  cli.add_option("--grasps", grasps, "Sessions per family")
      ->capture_default_str()
      ->check(toolinc::in_range({1, false, 10000, ""}));
  cli.add_option("--tip-tolerance", tip_tolerance, "m: a tooltip this close to the truth counts as right")
      ->capture_default_str()
      ->check(toolinc::in_range({toolinc::kMinLength, false, toolinc::kMaxLength, "m"}));
  cli.add_option("--stereo", stereo,
                 "The sessions' stereo model, as simulate-session --stereo (elas: crop trims the blob by the image, "
                 "crop-cloud --image-mask; sgbm: it also drops depth edges, --edge-radius 2)")
      ->check(CLI::IsMember({"ideal", "sgbm", "elas"}))
      ->capture_default_str();
  cli.add_option("--grasp", grasp, "The sessions' grasps, as simulate-session --grasp")
      ->check(CLI::IsMember({"recorded", "any"}))
      ->capture_default_str();
  cli.add_option("--reconstruction", reconstruction,
                 "registered: merge-views as it runs; original: the views merged as the original exploreTool made "
                 "the robot's reconstructions (at their recorded poses, no smear check) and kept as bare points")
      ->check(CLI::IsMember({"registered", "original"}))
      ->capture_default_str();
  cli.add_flag("--follow-hand", follow_hand,
               "As crop-cloud --follow-hand: a blob short of the hand is joined by the tool followed out of it");
  cli.add_flag("--revisit-views", pipeline.merge.revisit_views,
               "As merge-views --revisit-views: a view that does not fit is tried again, then as the reference");
  cli.add_option("--kinematic-error-mm", kinematic_mm, "As simulate-session --kinematic-error-mm")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 100, "mm"}));
  cli.add_option("--kinematic-error-deg", kinematic_deg, "As simulate-session --kinematic-error-deg")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 90, "deg"}));
  cli.add_option("-j,--jobs", jobs, "Sessions evaluated in parallel (the results do not depend on it)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64u));
  command.add_output("Per-session results JSON (- for stdout)", false);
  toolinc::add_tool_frame_options(cli, pipeline.frame);
  toolinc::add_tooltip_options(cli, pipeline.tooltip, rule);
  return command.run(argc, argv, [&] {
    pipeline.crop = toolinc::session_crop(toolinc::stereo_model_from_string(stereo));
    pipeline.crop.follow_hand = follow_hand;
    if (reconstruction == "original") pipeline = toolinc::as_original_reconstruction(pipeline);
    pipeline.tooltip.rule = toolinc::tooltip_rule_from_string(rule);
    toolinc::share_hand_settings(pipeline.frame, pipeline.tooltip);
    const toolinc::ExplorationGrasps drawn = toolinc::exploration_grasps_from_string(grasp);
    std::vector<toolinc::ToolFamily> families;
    for (const auto& name : family_names) families.push_back(toolinc::family_from_string(name));
    if (families.empty() && model_inputs.empty()) families = toolinc::all_families();
    const toolinc::KindMap kinds = kinds_file.empty() ? toolinc::KindMap{} : toolinc::read_kind_map(kinds_file);
    struct Model {
      std::string path, kind;
      toolinc::PointCloud cloud;
      toolinc::ToolSymmetry symmetry;
    };
    std::vector<Model> models;
    for (const auto& path : toolinc::expand_model_paths(model_inputs)) {
      toolinc::PointCloud cloud = toolinc::load_cloud(path);
      const auto symmetry = toolinc::measure_symmetry(cloud.points);
      models.push_back({path, toolinc::model_kind(path, kinds), std::move(cloud), symmetry});
    }
    std::vector<Case> cases;
    std::vector<std::string> groups;  // in the order of the table
    const auto add_group = [&](const std::string& g) {
      if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
    };
    for (const auto family : families) {
      add_group(toolinc::to_string(family));
      for (int g = 0; g < grasps; ++g)
        cases.push_back({toolinc::to_string(family), family, -1, first_seed + static_cast<std::uint32_t>(g), {}});
    }
    for (std::size_t m = 0; m < models.size(); ++m) {
      add_group(models[m].kind);
      for (int g = 0; g < grasps; ++g)
        cases.push_back({models[m].kind, {}, static_cast<int>(m), first_seed + static_cast<std::uint32_t>(g), {}});
    }

    // Each case is independent and writes only its own slot, so the output is the same for any -j.
    toolinc::run_in_parallel(cases.size(), jobs, toolinc::Progress("evaluating sessions"), [&](std::size_t i) {
      const Case& c = cases[i];
      toolinc::SessionSimulatorConfig session =
          c.model < 0 ? toolinc::family_session(c.family, c.seed, drawn)
                      : toolinc::model_session(models[c.model].cloud, models[c.model].path, models[c.model].symmetry,
                                               c.seed, drawn);
      session.stereo = toolinc::stereo_model_from_string(stereo);
      session.kinematic_error_m = kinematic_mm / 1000.0;
      session.kinematic_error_deg = kinematic_deg;
      cases[i].errors = toolinc::evaluate_simulated_session(session, pipeline);
    });

    // The table goes to standard output, unless the JSON does.
    std::FILE* table = command.output() == "-" ? stderr : stdout;
    const double tolerance_mm = 1000 * tip_tolerance;
    const std::string within_header = fmt::format("tip<={:g}mm", tolerance_mm);
    // "true frame": the tooltip rule on the same merged model with the true frame, so that a miss the
    // frame causes tells itself from one the cloud causes (the tip not seen, points off the tool before it).
    // "confident": sessions whose tooltip said confident, and of those the share within 15 mm (a wrong
    // tip said confident is the harmful kind).
    std::fprintf(table, "%-9s %8s %10s %13s %9s %9s %9s %8s %10s %9s %9s %24s\n", models.empty() ? "family" : "kind",
                 "sessions", within_header.c_str(), "95% interval", "tip med", "tip max", "model med", "failed",
                 "true frame", "relative", "confident", "confident: tip<=15mm");
    toolinc::Json results = toolinc::Json::array(), summary = toolinc::Json::array();
    int total = 0, total_within = 0, total_true_frame = 0, total_relative = 0, total_confident = 0,
        total_confident_within_15 = 0;
    // Failed sessions count as sessions whose tooltip is wrong.
    const auto rate = [&](const std::string& name, int within, int sessions, int within_true_frame, int within_relative,
                          int confident, int confident_within_15) {
      const auto [lo, hi] = toolinc::wilson_interval(within, sessions);
      summary.push_back({{"family", name},
                         {"sessions", sessions},
                         {"tooltip_within_tolerance", within},
                         {"rate", static_cast<double>(within) / sessions},
                         {"rate_interval_95", {lo, hi}},
                         {"tooltip_within_tolerance_true_frame", within_true_frame},
                         {"tooltip_within_tolerance_relative", toolinc::rate_json(name, within_relative, sessions)},
                         {"confident", confident},
                         {"confident_tooltip_within_15mm", toolinc::rate_json(name, confident_within_15, confident)}});
      return fmt::format("{:.1f}-{:.1f}%", 100 * lo, 100 * hi);
    };
    for (const auto& group : groups) {
      std::vector<double> tips, model_medians;
      int within = 0, within_true_frame = 0, within_relative = 0, failed = 0, sessions = 0, confident = 0,
          confident_within_15 = 0;
      for (const auto& c : cases) {
        if (c.group != group) continue;
        ++sessions;
        const auto& e = c.errors;
        const toolinc::Json tooltip_error = e.tool.failure.empty() ? toolinc::Json(e.tool.tooltip_m) : toolinc::Json();
        results.push_back(
            {{"family", group},
             {"model", c.model < 0 ? toolinc::Json() : toolinc::Json(models[c.model].path)},
             {"seed", c.seed},
             {"tooltip_error_m", tooltip_error},
             {"tooltip_error_true_frame_m", std::isfinite(e.tool.tooltip_true_frame_m) && e.tool.failure.empty()
                                                ? toolinc::Json(e.tool.tooltip_true_frame_m)
                                                : toolinc::Json()},
             {"tooltip_error_relative_m",
              e.tool.failure.empty() ? toolinc::Json(e.tool.tooltip_relative_m) : toolinc::Json()},
             {"handle_axis_error_deg", e.tool.handle_axis_deg},
             {"symmetry_plane_error_deg", e.tool.symmetry_plane_deg},
             {"effector_sign_right", e.tool.effector_sign_right},
             {"confident", e.tool.confident},
             {"tooltip_probability", e.tool.tooltip_probability},
             {"model_median_m", e.model_median_m},
             {"views_rejected", e.views_rejected},
             {"failure", e.tool.failure}});
        if (!e.tool.failure.empty()) {
          ++failed;
          spdlog::warn("{} seed {}: {}", c.model < 0 ? group : models[c.model].path, c.seed, e.tool.failure);
          continue;
        }
        tips.push_back(e.tool.tooltip_m);
        model_medians.push_back(e.model_median_m);
        within += e.tool.tooltip_m <= tip_tolerance;
        within_true_frame += e.tool.tooltip_true_frame_m <= tip_tolerance;
        within_relative += e.tool.tooltip_relative_m <= tip_tolerance;
        confident += e.tool.confident;
        confident_within_15 += e.tool.confident && e.tool.tooltip_m <= 0.015;
      }
      total += sessions;
      total_within += within;
      total_true_frame += within_true_frame;
      total_relative += within_relative;
      total_confident += confident;
      total_confident_within_15 += confident_within_15;
      const double worst = tips.empty() ? NAN : *std::max_element(tips.begin(), tips.end());
      const std::string interval =
          rate(group, within, sessions, within_true_frame, within_relative, confident, confident_within_15);
      std::fprintf(table, "%-9s %8d %9.1f%% %13s %7.1fmm %7.1fmm %7.2fmm %8d %9.1f%% %8.1f%% %9d %24s\n", group.c_str(),
                   sessions, 100.0 * within / sessions, interval.c_str(), 1000 * toolinc::median(tips), 1000 * worst,
                   1000 * toolinc::median(model_medians), failed, 100.0 * within_true_frame / sessions,
                   100.0 * within_relative / sessions, confident,
                   toolinc::rate_text(confident_within_15, confident).c_str());
    }
    const std::string interval =
        rate("all", total_within, total, total_true_frame, total_relative, total_confident, total_confident_within_15);
    std::fprintf(table, "all: tooltip within %g mm in %d of %d sessions (%.1f%%, 95%% interval %s)\n", tolerance_mm,
                 total_within, total, 100.0 * total_within / total, interval.c_str());
    std::fprintf(table, "with the true frame: within %g mm in %d of %d sessions (%.1f%%)\n", tolerance_mm,
                 total_true_frame, total, 100.0 * total_true_frame / total);
    std::fprintf(table,
                 "relative to the true model aligned onto the merged model: within %g mm in %d of %d sessions (%s)\n",
                 tolerance_mm, total_relative, total, toolinc::rate_text(total_relative, total).c_str());
    std::fprintf(table, "confident: %d of %d sessions, of which tooltip within 15 mm %s\n", total_confident, total,
                 toolinc::rate_text(total_confident_within_15, total_confident).c_str());
    if (!command.output().empty())
      toolinc::write_json(command.output(), {{"type", "session_evaluation"},
                                             {"version", 1},
                                             {"first_seed", first_seed},
                                             {"grasps", grasps},
                                             {"tooltip_tolerance_m", tip_tolerance},
                                             {"summary", summary},
                                             {"sessions", results}});
  });
}
