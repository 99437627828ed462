// fit-frame-score [--families F...] [--first-seed S] [--grasps N] [--stereo M] [-j J] -o SCORE.json: fits the
// frame search's score (frame_search.hpp) on simulated sessions of the generated families: every frame
// hypothesis on each session's merged model is labelled right when its tooltip lies within --tip-tolerance
// of the truth carried by the true model aligned onto the merge, and a logistic model of the hypotheses'
// features is fitted to those labels. The real tools, the CAD models and the robot's reconstructions are
// never fitted on: they are the exam. The output is configs/frame-score.json's contents.
#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/progress.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/logistic.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/evaluation.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("fit-frame-score", "Fit the frame search's score on simulated sessions of the families",
                           {"estimate-frame", "find-tooltip", "fit-frame-score"});
  std::vector<std::string> family_names;
  std::uint32_t first_seed = 1000;
  int grasps = 16;
  double tip_tolerance = 0.010, ridge = 0.01;
  unsigned jobs = 1;
  toolinc::PipelineConfig pipeline;
  std::string rule, stereo = "elas", compare;
  auto& cli = command.cli();
  cli.add_option("--families", family_names, "Tool families (default: all)");
  cli.add_option("--first-seed", first_seed, "Seed of the first grasp (away from evaluate-sessions' 100 and 200)")
      ->capture_default_str();
  cli.add_option("--grasps", grasps, "Sessions per family")->capture_default_str()->check(CLI::Range(1, 10000));
  cli.add_option("--tip-tolerance", tip_tolerance, "m: a hypothesis whose tooltip lies this close is right")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 0.1));
  cli.add_option("--ridge", ridge, "L2 penalty on the weights (features are of order 1)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  cli.add_option("--stereo", stereo, "The sessions' stereo model, as simulate-session --stereo")
      ->check(CLI::IsMember({"ideal", "sgbm", "elas"}))
      ->capture_default_str();
  cli.add_option("-j,--jobs", jobs, "Sessions simulated in parallel (the fit does not depend on it)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64u));
  cli.add_option("--compare", compare,
                 "A score JSON (configs/frame-score.json) whose mean log-likelihood on the same hypotheses is "
                 "reported beside the fit's (compared_mean_log_likelihood)");
  command.add_output("The fitted score JSON (- for stdout)");
  toolinc::add_tool_frame_options(cli, pipeline.frame);
  toolinc::add_tooltip_options(cli, pipeline.tooltip, rule);
  return command.run(argc, argv, [&] {
    if (stereo != "ideal") pipeline.crop = toolinc::matched_stereo_crop();
    pipeline.tooltip.rule = toolinc::tooltip_rule_from_string(rule);
    // The score to compare with, read before the long run so that a bad file fails at once.
    std::optional<toolinc::FrameScoreModel> other;
    if (!compare.empty()) {
      const toolinc::Json file = toolinc::read_json(compare);
      other.emplace();
      try {
        for (int f = 0; f < toolinc::kFrameFeatures; ++f) other->weights[f] = file.at("weights").at(f).get<double>();
        other->bias = file.at("bias").get<double>();
      } catch (const toolinc::Json::exception& e) {
        throw toolinc::InputError(compare, std::string("not a frame score: ") + e.what());
      }
    }
    std::vector<toolinc::ToolFamily> families;
    for (const auto& name : family_names) families.push_back(toolinc::family_from_string(name));
    if (families.empty()) families = toolinc::all_families();
    struct Case {
      toolinc::ToolFamily family;
      std::uint32_t seed;
      std::vector<toolinc::LabelledHypothesis> hypotheses;
    };
    std::vector<Case> cases;
    for (const auto family : families)
      for (int g = 0; g < grasps; ++g) cases.push_back({family, first_seed + static_cast<std::uint32_t>(g), {}});
    // Each case writes only its own slot: the fit is the same for any -j.
    toolinc::run_in_parallel(cases.size(), jobs, toolinc::Progress("labelling frame hypotheses"), [&](std::size_t i) {
      toolinc::SessionSimulatorConfig session = toolinc::family_session(cases[i].family, cases[i].seed);
      session.stereo = toolinc::stereo_model_from_string(stereo);
      cases[i].hypotheses = toolinc::labelled_frame_hypotheses(session, pipeline);
    });

    std::vector<std::array<double, toolinc::kFrameFeatures>> rows;
    std::vector<int> labels;
    for (const auto& c : cases)
      for (const auto& h : c.hypotheses) rows.push_back(h.features), labels.push_back(h.tooltip_m <= tip_tolerance);
    if (rows.empty()) throw toolinc::MethodError("no session gave a hypothesis to fit on");
    Eigen::MatrixXd x(static_cast<Eigen::Index>(rows.size()), toolinc::kFrameFeatures);
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (int f = 0; f < toolinc::kFrameFeatures; ++f) x(static_cast<Eigen::Index>(i), f) = rows[i][f];
    const toolinc::LogisticFit fit = toolinc::fit_logistic(x, labels, ridge);
    toolinc::FrameScoreModel model;
    for (int f = 0; f < toolinc::kFrameFeatures; ++f) model.weights[f] = fit.weights[f];
    model.bias = fit.bias;
    // Mean log-likelihood per hypothesis of a model on these labels: how well it explains them.
    const auto mean_log_likelihood = [&](const toolinc::FrameScoreModel& m) {
      double sum = 0.0;
      for (std::size_t i = 0; i < rows.size(); ++i) {
        const double z = m.log_odds(rows[i]);
        sum += labels[i] * z - std::log1p(std::exp(-std::abs(z))) - std::max(z, 0.0);
      }
      return sum / static_cast<double>(rows.size());
    };
    toolinc::Json compared;
    if (other) compared = {{"file", compare}, {"mean_log_likelihood", mean_log_likelihood(*other)}};

    // What the search would choose on the sessions it was fitted on, beside the rules' hypothesis (the
    // first: the rules' side about the whole tool's fitted axis is not always the rules' handle, so this
    // is a check of the fit, not the exam: evaluate-sessions --method search is).
    int sessions = 0, chosen_right = 0, any_right = 0;
    for (const auto& c : cases) {
      if (c.hypotheses.empty()) continue;
      ++sessions;
      const auto best = std::max_element(c.hypotheses.begin(), c.hypotheses.end(), [&](const auto& a, const auto& b) {
        return model.log_odds(a.features) < model.log_odds(b.features);
      });
      chosen_right += best->tooltip_m <= tip_tolerance;
      any_right += std::any_of(c.hypotheses.begin(), c.hypotheses.end(),
                               [&](const auto& h) { return h.tooltip_m <= tip_tolerance; });
    }
    int positives = 0;
    for (const int label : labels) positives += label;
    std::printf(
        "fitted on %zu hypotheses of %d sessions (%d right); the search's choice right on %d sessions, "
        "some hypothesis right on %d\n",
        rows.size(), sessions, positives, chosen_right, any_right);
    toolinc::Json features = toolinc::Json::array(), weights = toolinc::Json::array();
    for (int f = 0; f < toolinc::kFrameFeatures; ++f) {
      features.push_back(toolinc::frame_feature_names()[f]);
      weights.push_back(model.weights[f]);
      std::printf("%-36s %+9.4f\n", toolinc::frame_feature_names()[f], model.weights[f]);
    }
    std::printf("%-36s %+9.4f\n", "bias", model.bias);
    std::vector<std::string> names;
    for (const auto family : families) names.push_back(toolinc::to_string(family));
    toolinc::write_json(command.output(), {{"type", "frame_score"},
                                           {"version", 1},
                                           {"fitted_on",
                                            {{"families", names},
                                             {"first_seed", first_seed},
                                             {"grasps", grasps},
                                             {"stereo", stereo},
                                             {"tip_tolerance_m", tip_tolerance},
                                             {"ridge", ridge}}},
                                           {"hypotheses", rows.size()},
                                           {"right", positives},
                                           {"features", features},
                                           {"weights", weights},
                                           {"bias", model.bias},
                                           {"mean_log_likelihood", mean_log_likelihood(model)},
                                           {"compared", compared}});
  });
}
