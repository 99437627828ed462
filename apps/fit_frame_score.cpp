// fit-frame-score [--families F...] [--first-seed S] [--grasps N] [--calibration-first-seed S]
// [--calibration-grasps N] [--calibration-reconstructions R...] [--stereo M] [-j J] -o SCORE.json: fits the frame
// search's score (frame_search.hpp) on simulated sessions of the generated families. Every frame hypothesis on each
// session's merged model is labelled right when its tooltip lies within --tip-tolerance of the truth carried by the
// true model aligned onto the merge, on a tool with a salient effector its effector points the true way, and its handle
// lies within --handle-tolerance of its session's best candidate's; a choice model of the hypotheses' features is
// fitted so that each session's right ones are the likely ones. On sessions of other seeds, never fitted on, the chosen
// hypotheses' probabilities are compared with how often their tooltips were right (the calibration table),
// and the probability from which 98 % of the chosen tooltips that find-tooltip's other checks pass (only those
// can be called confident) lie within 15 mm becomes the confidence threshold.
// The real tools, the CAD models and the robot's reconstructions are never fitted on: they are the exam.
// The output is configs/frame-score.json's contents.
#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/progress.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/core/choice_model.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/evaluation.hpp"

namespace {

using Hypotheses = std::vector<toolinc::LabelledHypothesis>;

// A hypothesis is right when its tooltip lies within `tolerance` of the truth, its effector points the
// true way (on a tool with a salient effector; a scoop's tip alone does not tell its side) and its handle
// lies within `handle_deg` of the best of its session's candidate handles (a stick's tip does not tell its
// handle either; the choice can do no better than the best candidate, and a session whose candidates all
// miss by more, a scoop whose belly tilts them, still teaches the rest).
struct Rightness {
  double tip_m, handle_deg;
  bool operator()(const toolinc::LabelledHypothesis& h, const Hypotheses& session) const {
    double best = h.handle_deg;
    for (const auto& other : session) best = std::min(best, other.handle_deg);
    return h.tooltip_m <= tip_m && h.effector_right && h.handle_deg <= best + handle_deg;
  }
};

// The hypothesis a model chooses on one session, and its tooltip's probability among that session's.
struct Choice {
  const toolinc::LabelledHypothesis* chosen;
  double probability;
};
// As estimate-frame chooses: the likeliest tip within radius, its probability the model's, within its
// confident tolerance.
Choice choose(const toolinc::FrameScoreModel& model, const Hypotheses& hypotheses, double radius) {
  std::vector<double> scores;
  std::vector<std::optional<toolinc::Vec3>> tooltips, other_ends;
  std::vector<toolinc::Vec3> sides;
  for (const auto& h : hypotheses) {
    scores.push_back(model.log_odds(h.features)), tooltips.push_back(h.tooltip), other_ends.push_back(h.other_end);
    sides.push_back(h.effector_side);
  }
  const std::size_t best = toolinc::most_probable_tooltip(scores, tooltips, sides, radius);
  return {&hypotheses[best],
          toolinc::tooltip_probability(scores, tooltips, best, model.confident_tolerance, other_ends)};
}

// Mean log-probability the model gives a session's right hypotheses (shared equally among them), over the
// sessions with right and wrong ones: how well it explains the labels.
double mean_log_likelihood(const toolinc::FrameScoreModel& model, const std::vector<Hypotheses>& sessions,
                           const Rightness& is_right) {
  double sum = 0.0;
  int counted = 0;
  for (const auto& hypotheses : sessions) {
    std::vector<double> scores;
    int right = 0;
    for (const auto& h : hypotheses) scores.push_back(model.log_odds(h.features)), right += is_right(h, hypotheses);
    if (right == 0 || right == static_cast<int>(hypotheses.size())) continue;
    const double top = *std::max_element(scores.begin(), scores.end());
    double total = 0.0;
    for (const double z : scores) total += std::exp(z - top);
    for (std::size_t i = 0; i < hypotheses.size(); ++i)
      if (is_right(hypotheses[i], hypotheses)) sum += (scores[i] - top - std::log(total)) / right;
    ++counted;
  }
  return sum / std::max(counted, 1);
}

// The lowest probability from which the chosen tooltips within `tolerance` are at least `precision` of
// those chosen (the longest run, from the most probable down, that keeps it); 1 when none does.
double confident_probability(std::vector<std::pair<double, bool>> chosen, double precision) {
  std::sort(chosen.begin(), chosen.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  double threshold = 1.0;
  int right = 0;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    right += chosen[i].second;
    const bool tie_follows = i + 1 < chosen.size() && chosen[i + 1].first == chosen[i].first;
    if (!tie_follows && right >= precision * static_cast<double>(i + 1)) threshold = chosen[i].first;
  }
  return threshold;
}

}  // namespace

int main(int argc, char** argv) {
  toolinc::Command command("fit-frame-score", "Fit the frame search's score on simulated sessions of the families",
                           {"estimate-frame", "find-tooltip", "fit-frame-score"});
  std::vector<std::string> family_names;
  std::uint32_t first_seed = 1000, calibration_first_seed = 2000;
  int grasps = 16, calibration_grasps = 32;
  double tip_tolerance = 0.010, handle_tolerance = 3.0, confident_tolerance = 0.015, precision = 0.98, ridge = 0.01;
  bool belly_behind = true;
  unsigned jobs = 1;
  toolinc::PipelineConfig pipeline;
  std::string rule, stereo = "elas", compare, hypotheses_csv;
  std::vector<std::string> reconstructions{"registered"}, calibration_reconstructions{"registered", "original"};
  auto& cli = command.cli();
  cli.add_option("--families", family_names, "Tool families (default: all)");
  cli.add_option("--first-seed", first_seed,
                 "Seed of the first grasp fitted on (away from evaluate-sessions' 100 and 200)")
      ->capture_default_str();
  cli.add_option("--grasps", grasps, "Sessions per family fitted on")
      ->capture_default_str()
      ->check(toolinc::in_range({1, false, 10000, ""}));
  cli.add_option("--calibration-first-seed", calibration_first_seed,
                 "Seed of the first grasp the confidence is calibrated on (never fitted on)")
      ->capture_default_str();
  cli.add_option("--calibration-grasps", calibration_grasps, "Sessions per family the confidence is calibrated on")
      ->capture_default_str()
      ->check(toolinc::in_range({1, false, 10000, ""}));
  cli.add_option("--tip-tolerance", tip_tolerance, "m: a hypothesis whose tooltip lies this close is right")
      ->capture_default_str()
      ->check(toolinc::in_range({0.001, false, 0.1, "m"}));
  cli.add_option("--handle-tolerance", handle_tolerance,
                 "deg: ... and whose handle axis lies this close to the best of its session's candidates' (180: the "
                 "handle is not asked)")
      ->capture_default_str()
      ->check(toolinc::in_range({0.1, false, 180.0, "deg"}));
  cli.add_flag("--belly-behind,!--no-belly-behind", belly_behind,
               "Every other shovel session's scoop lowered behind the handle's axis (belly_behind), as many real "
               "scoops are held (default; --no-belly-behind: none)");
  cli.add_option("--confident-tolerance", confident_tolerance,
                 "m: a confident tooltip must lie this close to the truth ...")
      ->capture_default_str()
      ->check(toolinc::in_range({0.001, false, 0.1, "m"}));
  cli.add_option("--precision", precision, "... in this share of the calibration sessions called confident")
      ->capture_default_str()
      ->check(toolinc::in_range({0.5, false, 1.0, ""}));
  cli.add_option("--ridge", ridge, "L2 penalty on the weights (features are of order 1)")
      ->capture_default_str()
      ->check(toolinc::in_range({0.0, false, 100.0, ""}));
  cli.add_option("--stereo", stereo, "The sessions' stereo model, as simulate-session --stereo")
      ->check(CLI::IsMember({"ideal", "sgbm", "elas"}))
      ->capture_default_str();
  cli.add_option("--reconstructions", reconstructions,
                 "Each session fitted on as each of these models (evaluate-sessions --reconstruction)")
      ->check(CLI::IsMember({"registered", "original"}))
      ->capture_default_str();
  cli.add_option("--calibration-reconstructions", calibration_reconstructions,
                 "Each session calibrated on as each of these models: the confidence must hold on merges made as the "
                 "robot's were (original) as well as registered ones")
      ->check(CLI::IsMember({"registered", "original"}))
      ->capture_default_str();
  cli.add_option("-j,--jobs", jobs, "Sessions simulated in parallel (the fit does not depend on it)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64u));
  cli.add_option("--compare", compare,
                 "A score JSON (configs/frame-score.json) whose mean log-likelihood on the same hypotheses is "
                 "reported beside the fit's (compared.mean_log_likelihood)");
  cli.add_option("--hypotheses", hypotheses_csv,
                 "CSV of every labelled hypothesis (set, family, seed, reconstruction, handle, side reversed, "
                 "tooltip error, features), to study the features");
  command.add_output("The fitted score JSON (- for stdout)");
  toolinc::add_tool_frame_options(cli, pipeline.frame);
  toolinc::add_tooltip_options(cli, pipeline.tooltip, rule);
  return command.run(argc, argv, [&] {
    pipeline.crop = toolinc::session_crop(toolinc::stereo_model_from_string(stereo));
    pipeline.tooltip.rule = toolinc::tooltip_rule_from_string(rule);
    toolinc::share_hand_settings(pipeline.frame, pipeline.tooltip);
    // The score to compare with, read before the long run so that a bad file fails at once.
    std::optional<toolinc::FrameScoreModel> other;
    if (!compare.empty()) {
      const toolinc::Json file = toolinc::read_json(compare);
      other.emplace();
      try {
        for (int f = 0; f < toolinc::kFrameFeatures; ++f) other->weights[f] = file.at("weights").at(f).get<double>();
      } catch (const toolinc::Json::exception& e) {
        throw toolinc::InputError(compare, std::string("not a frame score: ") + e.what());
      }
    }
    std::vector<toolinc::ToolFamily> families;
    for (const auto& name : family_names) families.push_back(toolinc::family_from_string(name));
    if (families.empty()) families = toolinc::all_families();
    // The sessions fitted on, then those calibrated on; each writes only its own slot, so any -j gives the
    // same fit.
    struct Case {
      toolinc::ToolFamily family;
      std::uint32_t seed;
      const toolinc::PipelineConfig* pipeline;
    };
    const toolinc::PipelineConfig original = toolinc::as_original_reconstruction(pipeline);
    const Rightness is_right{tip_tolerance, handle_tolerance};
    std::vector<Case> cases;
    const auto add_cases = [&](std::uint32_t first, int count, const std::vector<std::string>& as) {
      for (const auto family : families)
        for (int g = 0; g < count; ++g)
          for (const auto& r : as)
            cases.push_back({family, first + static_cast<std::uint32_t>(g), r == "original" ? &original : &pipeline});
    };
    add_cases(first_seed, grasps, reconstructions);
    const std::size_t fitted = cases.size();
    add_cases(calibration_first_seed, calibration_grasps, calibration_reconstructions);
    std::vector<Hypotheses> labelled(cases.size());
    toolinc::run_in_parallel(cases.size(), jobs, toolinc::Progress("labelling frame hypotheses"), [&](std::size_t i) {
      toolinc::SessionSimulatorConfig session = toolinc::family_session(cases[i].family, cases[i].seed);
      // Real scoops are held with their belly on either side of the handle's axis: with --belly-behind
      // every other shovel's is behind it, so that the fit sees the head's curl, not its reach, tell a
      // scoop's side.
      if (belly_behind && cases[i].family == toolinc::ToolFamily::shovel && cases[i].seed % 2 == 1)
        session.shape = toolinc::belly_behind(session.shape);
      session.stereo = toolinc::stereo_model_from_string(stereo);
      labelled[i] = toolinc::labelled_frame_hypotheses(session, *cases[i].pipeline);
    });
    if (!hypotheses_csv.empty()) {
      std::string csv =
          "set,family,seed,reconstruction,handle,side_reversed,tooltip_m,effector_right,handle_deg,backed";
      for (const char* name : toolinc::frame_feature_names()) csv += std::string(",") + name;
      csv += "\n";
      for (std::size_t i = 0; i < cases.size(); ++i)
        for (const auto& h : labelled[i]) {
          csv += fmt::format("{},{},{},{},\"{}\",{},{},{},{},{}", i < fitted ? "fit" : "calibration",
                             toolinc::to_string(cases[i].family), cases[i].seed,
                             cases[i].pipeline == &original ? "original" : "registered", h.handle_source,
                             int{h.side_reversed}, h.tooltip_m, int{h.effector_right}, h.handle_deg, int{h.backed});
          for (const double f : h.features) csv += fmt::format(",{}", f);
          csv += "\n";
        }
      toolinc::write_file_atomic(hypotheses_csv, [&](std::ostream& out) { out << csv; });
    }
    const std::vector<Hypotheses> fit_on(labelled.begin(), labelled.begin() + static_cast<std::ptrdiff_t>(fitted)),
        calibrate_on(labelled.begin() + static_cast<std::ptrdiff_t>(fitted), labelled.end());

    std::vector<std::array<double, toolinc::kFrameFeatures>> rows;
    std::vector<int> labels, groups;
    for (std::size_t i = 0; i < fit_on.size(); ++i)
      for (const auto& h : fit_on[i]) {
        rows.push_back(h.features);
        labels.push_back(is_right(h, fit_on[i]));
        groups.push_back(static_cast<int>(i));
      }
    if (rows.empty()) throw toolinc::MethodError("no session gave a hypothesis to fit on");
    Eigen::MatrixXd x(static_cast<Eigen::Index>(rows.size()), toolinc::kFrameFeatures);
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (int f = 0; f < toolinc::kFrameFeatures; ++f) x(static_cast<Eigen::Index>(i), f) = rows[i][f];
    const toolinc::ChoiceFit fit = toolinc::fit_choice_model(x, labels, groups, ridge);
    toolinc::FrameScoreModel model;
    for (int f = 0; f < toolinc::kFrameFeatures; ++f) model.weights[f] = fit.weights[f];
    model.confident_tolerance = confident_tolerance;

    // On the sessions never fitted on: the chosen hypotheses' probabilities against their tooltips' errors;
    // the threshold on those whose other checks pass, as it is applied.
    std::vector<std::pair<double, bool>> chosen, backed;
    int chosen_right = 0, any_right = 0;
    for (const auto& hypotheses : calibrate_on) {
      if (hypotheses.empty()) continue;
      const Choice c = choose(model, hypotheses, pipeline.tooltip.ambiguity_distance);
      chosen.emplace_back(c.probability, c.chosen->tooltip_m <= confident_tolerance);
      if (c.chosen->backed) backed.push_back(chosen.back());
      chosen_right += is_right(*c.chosen, hypotheses);
      any_right +=
          std::any_of(hypotheses.begin(), hypotheses.end(), [&](const auto& h) { return is_right(h, hypotheses); });
    }
    model.confident_probability = confident_probability(backed, precision);
    toolinc::Json calibration = toolinc::Json::array();
    for (int bin = 0; bin < 5; ++bin) {
      const double lo = 0.2 * bin, hi = 0.2 * (bin + 1);
      int n = 0, right = 0;
      double predicted = 0.0;
      for (const auto& [p, ok] : chosen)
        if (p >= lo && (p < hi || bin == 4)) ++n, right += ok, predicted += p;
      if (n > 0)
        calibration.push_back({{"probability", {lo, hi}},
                               {"sessions", n},
                               {"mean_probability", predicted / n},
                               {"within_confident_tolerance", static_cast<double>(right) / n}});
    }
    int confident = 0, confident_right = 0;
    for (const auto& [p, ok] : backed)
      confident += p >= model.confident_probability, confident_right += ok && p >= model.confident_probability;
    int positives = 0;
    for (const int label : labels) positives += label;
    std::printf(
        "fitted on %zu hypotheses of %zu sessions (%d right); on %zu calibration sessions the choice is right on %d, "
        "some hypothesis on %d, the other checks pass on %zu; confident from probability %.3f: %d sessions, %d of "
        "them within %.0f mm\n",
        rows.size(), fit_on.size(), positives, chosen.size(), chosen_right, any_right, backed.size(),
        model.confident_probability, confident, confident_right, 1000 * confident_tolerance);
    toolinc::Json features = toolinc::Json::array(), weights = toolinc::Json::array();
    for (int f = 0; f < toolinc::kFrameFeatures; ++f) {
      features.push_back(toolinc::frame_feature_names()[f]);
      weights.push_back(model.weights[f]);
      std::printf("%-36s %+9.4f\n", toolinc::frame_feature_names()[f], model.weights[f]);
    }
    std::vector<std::string> names;
    for (const auto family : families) names.push_back(toolinc::to_string(family));
    toolinc::Json compared;
    if (other) compared = {{"file", compare}, {"mean_log_likelihood", mean_log_likelihood(*other, fit_on, is_right)}};
    toolinc::write_json(
        command.output(),
        {{"type", "frame_score"},
         {"version", 2},
         {"fitted_on",
          {{"families", names},
           {"first_seed", first_seed},
           {"grasps", grasps},
           {"stereo", stereo},
           {"reconstructions", reconstructions},
           {"tip_tolerance_m", tip_tolerance},
           {"handle_tolerance_deg", handle_tolerance},
           {"belly_behind", belly_behind},
           {"right",
            "tooltip within tip_tolerance_m, where the effector is salient the "
            "effector the true way, and the handle within handle_tolerance_deg of the session's best candidate's"},
           {"ridge", ridge}}},
         {"calibrated_on",
          {{"first_seed", calibration_first_seed},
           {"grasps", calibration_grasps},
           {"reconstructions", calibration_reconstructions},
           {"confident_tolerance_m", confident_tolerance},
           {"precision", precision}}},
         {"hypotheses", rows.size()},
         {"right", positives},
         {"features", features},
         {"weights", weights},
         {"confident_probability", model.confident_probability},
         {"calibration",
          {{"sessions", chosen.size()},
           {"chosen_right", chosen_right},
           {"some_hypothesis_right", any_right},
           {"other_checks_pass", backed.size()},
           {"confident", confident},
           {"confident_within_tolerance", confident_right},
           {"table", calibration}}},
         {"mean_log_likelihood", mean_log_likelihood(model, fit_on, is_right)},
         {"compared", compared}});
  });
}
