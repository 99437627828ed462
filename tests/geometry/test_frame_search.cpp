// The frame as a search over hypotheses: what it enumerates, that it keeps the best-scored one, that the
// shipped weights are the shipped file's and that fit-frame-score reproduces that file; and the choice
// model it rests on, against choices drawn from known weights.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "support/synthetic_cases.hpp"
#include "toolinc/core/choice_model.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/frame/frame_search.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/results/results_json.hpp"

using namespace toolinc;
using namespace toolinc::testing;

namespace {

// A feature's index by its name (frame_feature_names() when absent).
std::size_t feature_index(const std::string& name) {
  const auto& names = frame_feature_names();
  return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
}

}  // namespace

TEST(ChoiceModel, RecoversTheWeightsItsChoicesWereDrawnFrom) {
  // 4,000 choices among 5 candidates, each drawn with probability exp(2 a - b) / sum: the weights' standard
  // errors are about 0.03, so 0.15 is five of them.
  Rng rng(3);
  const int choices = 4000, candidates = 5;
  Eigen::MatrixXd rows(choices * candidates, 2);
  std::vector<int> labels(rows.rows(), 0), groups(rows.rows());
  for (int c = 0; c < choices; ++c) {
    std::vector<double> p(candidates);
    double total = 0.0;
    for (int k = 0; k < candidates; ++k) {
      const int i = c * candidates + k;
      rows(i, 0) = rng.gaussian();
      rows(i, 1) = rng.gaussian();
      groups[i] = c;
      total += p[k] = std::exp(2.0 * rows(i, 0) - rows(i, 1));
    }
    double u = rng.uniform() * total;
    int k = 0;
    while (k + 1 < candidates && (u -= p[k]) > 0) ++k;
    labels[c * candidates + k] = 1;
  }
  const ChoiceFit fit = fit_choice_model(rows, labels, groups, 0.0);
  EXPECT_EQ(fit.groups, choices);
  EXPECT_NEAR(fit.weights[0], 2.0, 0.15);
  EXPECT_NEAR(fit.weights[1], -1.0, 0.15);
}

TEST(ChoiceModel, SeparableDataGivesFiniteWeightsAndGroupsWithoutAChoiceSayNothing) {
  Eigen::MatrixXd rows(6, 1);
  rows << -2, 1, -1, 2, 5, 7;
  // The right candidate is always the larger; the last group is all right and is left out.
  const ChoiceFit fit = fit_choice_model(rows, {0, 1, 0, 1, 1, 1}, {0, 0, 1, 1, 2, 2}, 0.01);
  EXPECT_EQ(fit.groups, 2);
  EXPECT_TRUE(std::isfinite(fit.weights[0]));
  EXPECT_GT(fit.weights[0], 1.0);
  EXPECT_THROW(fit_choice_model(rows, {0, 1}, {0, 0}, 0.01), std::invalid_argument);
}

TEST(FrameSearch, HypothesesAreCandidateHandlesAndPlanesWithEitherSide) {
  const std::size_t asymmetry = feature_index("effector_reach_asymmetry");
  const std::vector<std::size_t> handle_features{feature_index("hand_to_handle_per_grasp_reach"),
                                                 feature_index("beyond_grasp_hold")};
  for (const std::size_t f : handle_features) ASSERT_LT(f, frame_feature_names().size());
  ASSERT_LT(asymmetry, frame_feature_names().size());
  int alternatives = 0;
  for (const ToolFamily family : {ToolFamily::hook, ToolFamily::hoe, ToolFamily::rake, ToolFamily::t_bar}) {
    const HeldToolCase held = make_held_tool(family, 5);
    const auto hypotheses = frame_hypotheses(held.observed);
    ASSERT_GE(hypotheses.size(), 4u) << to_string(family);
    ASSERT_EQ(hypotheses.size() % 2, 0u);
    std::set<std::string> sources;
    for (std::size_t i = 0; i < hypotheses.size(); i += 2) {
      const ToolFrame &rules_side = hypotheses[i].frame, &other = hypotheses[i + 1].frame;
      EXPECT_FALSE(hypotheses[i].side_reversed);
      EXPECT_TRUE(hypotheses[i + 1].side_reversed);
      EXPECT_EQ(hypotheses[i].handle_source, hypotheses[i + 1].handle_source);
      EXPECT_EQ(hypotheses[i].rules_plane, hypotheses[i + 1].rules_plane);
      // Each handle first with the rules' plane, then its alternatives, which turn the plane about it.
      if (hypotheses[i].rules_plane) {
        EXPECT_TRUE(sources.insert(hypotheses[i].handle_source).second) << "a handle listed twice";
      } else {
        ++alternatives;
        ASSERT_GE(i, 2u);
        EXPECT_EQ(hypotheses[i].handle_source, hypotheses[i - 2].handle_source);
        EXPECT_TRUE(rules_side.handle_axis().isApprox(hypotheses[i - 2].frame.handle_axis()));
        EXPECT_LT(std::abs(rules_side.symmetry_axis().dot(hypotheses[i - 2].frame.symmetry_axis())),
                  std::cos(M_PI / 180.0 * 10.0))
            << "an alternative plane within 10 degrees of another";
      }
      // The same handle and plane, the effector turned: still right-handed.
      EXPECT_TRUE(rules_side.handle_axis().isApprox(other.handle_axis()));
      EXPECT_TRUE(rules_side.effector_axis().isApprox(-other.effector_axis()));
      EXPECT_TRUE(is_rotation(other.axes, 1e-9));
      // The side's features change sign with the side; the handle's do not.
      EXPECT_DOUBLE_EQ(hypotheses[i].features[asymmetry], -hypotheses[i + 1].features[asymmetry]);
      for (const std::size_t f : handle_features)
        EXPECT_DOUBLE_EQ(hypotheses[i].features[f], hypotheses[i + 1].features[f]);
      for (const double f : hypotheses[i].features) EXPECT_TRUE(std::isfinite(f));
    }
  }
  EXPECT_GT(alternatives, 0) << "no handle had an alternative plane (at least its quarter turn)";
}

TEST(FrameSearch, TheWholeJobOnOneTreeIsTheTwoStepsApart) {
  // estimate_frame_and_tooltip shares the kd-tree and held piece; the frame and tooltip are those of the
  // two steps run apart, to the bit, with either method; a cache whose hand settings are not the frame's
  // is refused (its held piece would not be the frame's).
  const HeldToolCase held = make_held_tool(ToolFamily::hook, 4);
  for (const FrameMethod method : {FrameMethod::search, FrameMethod::rules}) {
    ToolFrameConfig config;
    config.method = method;
    const auto [frame, tip] = estimate_frame_and_tooltip(held.observed, config, TooltipConfig{});
    const ToolFrame apart = estimate_tool_frame(held.observed, config);
    EXPECT_EQ(frame.axes, apart.axes) << to_string(method);
    EXPECT_EQ(frame.origin, apart.origin) << to_string(method);
    EXPECT_EQ(tip.position, find_tooltip(held.observed, apart).position) << to_string(method);
  }
  const KdTree tree(held.observed);
  TooltipConfig wider;
  wider.hand_radius = 0.08;
  EXPECT_THROW(estimate_tool_frame(TooltipCache(held.observed, tree, wider), ToolFrameConfig{}), std::invalid_argument);
}

TEST(FrameSearch, EachHypothesissTooltipIsFindTooltipsPosition) {
  // tooltip_position skips what find_tooltip measures around its tip, not the tip: the same position to
  // the bit, on every hypothesis (either side, every plane), and none where find_tooltip throws.
  for (const ToolFamily family : {ToolFamily::hoe, ToolFamily::shovel, ToolFamily::stick}) {
    const HeldToolCase held = make_held_tool(family, 3);
    const KdTree tree(held.observed);
    const TooltipCache cache(held.observed, tree, TooltipConfig{});
    for (const auto& h : frame_hypotheses(held.observed)) {
      const std::optional<Vec3> position = tooltip_position(cache, h.frame);
      ASSERT_TRUE(position.has_value()) << to_string(family);
      EXPECT_EQ(*position, find_tooltip(cache, h.frame).position) << to_string(family);
    }
    ToolFrame away = frame_hypotheses(held.observed).front().frame;
    away.origin -= 10.0 * away.handle_axis();  // nothing lies beyond the origin along the handle: no tooltip
    EXPECT_FALSE(tooltip_position(cache, away).has_value());
    EXPECT_THROW(find_tooltip(cache, away), MethodError);
  }
}

TEST(FrameSearch, TheTooltipsProbabilityIsTheShareOfTheHypothesesAgreeingOnIt) {
  // Two hypotheses 5 mm apart (the same tip at 10 mm) and a third, twice as likely, 10 cm away.
  const std::vector<double> scores{0.0, 0.0, std::log(2.0)};
  const std::vector<std::optional<Vec3>> tips{Vec3(0.1, 0, 0), Vec3(0.105, 0, 0), Vec3(0.2, 0, 0)};
  EXPECT_NEAR(tooltip_probability(scores, tips, 0, 0.01), 0.5, 1e-12);
  EXPECT_NEAR(tooltip_probability(scores, tips, 2, 0.01), 0.5, 1e-12);
  EXPECT_NEAR(tooltip_probability(scores, tips, 0, 0.001), 0.25, 1e-12);
  EXPECT_NEAR(tooltip_probability(scores, tips, 0, 1.0), 1.0, 1e-12);
  // A hypothesis without a tooltip has none to be sure of, and adds to no other's.
  const std::vector<std::optional<Vec3>> one_missing{std::nullopt, Vec3(0.105, 0, 0), Vec3(0.2, 0, 0)};
  EXPECT_EQ(tooltip_probability(scores, one_missing, 0, 0.01), 0.0);
  EXPECT_NEAR(tooltip_probability(scores, one_missing, 1, 0.01), 0.25, 1e-12);
}

// Either end of a T is its tip: a hypothesis at the chosen one's other end agrees with it, one elsewhere does not.
TEST(FrameSearch, HypothesesAtTheOtherEndOfATwoEndedToolAgreeOnItsTip) {
  const std::vector<double> scores{std::log(3.0), std::log(2.0), std::log(2.0), 0.0};
  const std::vector<std::optional<Vec3>> tips{Vec3(0.1, -0.2, 0), Vec3(-0.1, -0.2, 0), Vec3(0.1, -0.2, 0.003),
                                              Vec3(0.0, -0.25, 0)};
  // Each end's other end is the tip mirrored across x = 0; the last hypothesis's tool has one end.
  const std::vector<std::optional<Vec3>> ends{Vec3(-0.1, -0.2, 0), Vec3(0.1, -0.2, 0), Vec3(-0.1, -0.2, 0.003),
                                              std::nullopt};
  EXPECT_NEAR(tooltip_probability(scores, tips, 0, 0.01), 5.0 / 8.0, 1e-12);
  EXPECT_NEAR(tooltip_probability(scores, tips, 0, 0.01, ends), 7.0 / 8.0, 1e-12);
  EXPECT_NEAR(tooltip_probability(scores, tips, 1, 0.01, ends), 7.0 / 8.0, 1e-12);
  EXPECT_NEAR(tooltip_probability(scores, tips, 3, 0.01, ends), 1.0 / 8.0, 1e-12);
  EXPECT_THROW(tooltip_probability(scores, tips, 0, 0.01, {std::nullopt}), std::invalid_argument);
}

// On held T-bars and flat tops the search finds the other end where the truth has its second tip; on tools
// with one end (hoes, hooks, rakes) it finds none. The noise (1.5 mm) and the plane's refinement (within a
// degree) move a mirrored tip by a few millimetres; 10 mm is the tooltip tolerance.
TEST(FrameSearch, FindsTheOtherEndOfTwoEndedToolsOnly) {
  for (const ToolFamily family :
       {ToolFamily::t_bar, ToolFamily::flat_top, ToolFamily::hoe, ToolFamily::hook, ToolFamily::rake})
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
      const HeldToolCase held = make_held_tool(family, seed);
      const auto hypotheses = frame_hypotheses(held.observed);
      int with_end = 0, right = 0;
      for (const auto& h : hypotheses) {
        if (!h.other_end) continue;
        ++with_end;
        const double to_tip = (*h.tooltip - held.truth.tooltips.front()).norm();
        if (held.truth.tooltips.size() == 2 && to_tip <= 0.01)
          right += (*h.other_end - held.truth.tooltips.back()).norm() <= 0.01;
        else if (held.truth.tooltips.size() == 2 && (*h.tooltip - held.truth.tooltips.back()).norm() <= 0.01)
          right += (*h.other_end - held.truth.tooltips.front()).norm() <= 0.01;
      }
      if (held.truth.tooltips.size() == 1) {
        EXPECT_EQ(with_end, 0) << to_string(family) << " seed " << seed;
      } else {
        EXPECT_GT(right, 0) << to_string(family) << " seed " << seed;
      }
    }
  // The frame's record keeps each hypothesis's other end, through its JSON.
  ToolFrameConfig search;
  search.method = FrameMethod::search;
  const ToolFrame frame = estimate_tool_frame(make_held_tool(ToolFamily::t_bar, 1).observed, search);
  const ToolFrame read = tool_frame_from_json(tool_frame_json(frame, search), "t-bar.json");
  ASSERT_EQ(read.diagnostics.hypotheses.size(), frame.diagnostics.hypotheses.size());
  int ends = 0;
  for (std::size_t i = 0; i < read.diagnostics.hypotheses.size(); ++i) {
    const auto& end = frame.diagnostics.hypotheses[i].other_end;
    ASSERT_EQ(read.diagnostics.hypotheses[i].other_end.has_value(), end.has_value());
    if (!end) continue;
    ++ends;
    EXPECT_TRUE(read.diagnostics.hypotheses[i].other_end->isApprox(*end, 1e-12));
  }
  EXPECT_GT(ends, 0);
}

TEST(FrameSearch, TheChoiceIsTheTipWithTheMostProbabilityThenItsLikeliestHypothesis) {
  // The likeliest hypothesis alone 10 cm away, against two less likely ones 5 mm apart whose sum outweighs
  // it: the two's tip, and of them the likelier.
  const std::vector<double> scores{std::log(2.0), 0.0, 0.1};
  const std::vector<std::optional<Vec3>> tips{Vec3(0.2, 0, 0), Vec3(0.1, 0, 0), Vec3(0.105, 0, 0)};
  const std::vector<Vec3> one_side(3, Vec3::UnitX());
  EXPECT_EQ(most_probable_tooltip(scores, tips, one_side, 0.01), 2u);
  // Apart (a 1 mm radius), each stands alone and the likeliest wins.
  EXPECT_EQ(most_probable_tooltip(scores, tips, one_side, 0.001), 0u);
  // A hypothesis without a tooltip is not chosen while another has one.
  EXPECT_EQ(most_probable_tooltip({5.0, 0.0}, {std::nullopt, Vec3(0.1, 0, 0)}, {Vec3::UnitX(), Vec3::UnitX()}, 0.01),
            1u);
  EXPECT_THROW(most_probable_tooltip(scores, tips, {Vec3::UnitX()}, 0.01), std::invalid_argument);
}

// Hypotheses on either side of a scoop's plane agree on its far end. The side is then the one with the most
// probability among them: three hypotheses along +X (about different handles, their axes a few degrees
// apart) outweigh the likeliest one, along -X.
TEST(FrameSearch, AmongHypothesesAgreeingOnTheTipTheSideWithTheMostProbabilityIsChosen) {
  const std::vector<double> scores{std::log(3.0), std::log(2.0), std::log(1.5), std::log(1.5), 0.0};
  const std::vector<std::optional<Vec3>> tips{Vec3(0.2, 0, 0), Vec3(0.201, 0, 0), Vec3(0.2, 0.001, 0),
                                              Vec3(0.2, 0, 0.001), Vec3(0.5, 0, 0)};
  const std::vector<Vec3> axes{-Vec3::UnitX(), Vec3(1, 0.05, 0).normalized(), Vec3::UnitX(),
                               Vec3(1, 0, -0.05).normalized(), -Vec3::UnitX()};
  EXPECT_EQ(most_probable_tooltip(scores, tips, axes, 0.01), 1u);  // +X: 2 + 1.5 + 1.5 against 3; its likeliest
  // With the -X side likelier than the others together, it stays.
  const std::vector<double> bold{std::log(6.0), std::log(2.0), std::log(1.5), std::log(1.5), 0.0};
  EXPECT_EQ(most_probable_tooltip(bold, tips, axes, 0.01), 0u);
  // A stick has no side: it agrees with either, and among sticks alone the likeliest is chosen.
  const std::vector<Vec3> sticks(5, Vec3::Zero());
  EXPECT_EQ(most_probable_tooltip(scores, tips, sticks, 0.01), 0u);
  ToolFrame stick;
  stick.stick = true;
  EXPECT_EQ(effector_side(stick), Vec3::Zero());
  stick.stick = false;
  EXPECT_EQ(effector_side(stick), stick.effector_axis());
}

TEST(FrameSearch, KeepsTheHypothesisWhoseTooltipIsLikeliest) {
  const HeldToolCase held = make_held_tool(ToolFamily::l_stick, 2);
  ToolFrameConfig config;
  config.method = FrameMethod::search;
  const auto hypotheses = frame_hypotheses(held.observed, config);
  std::vector<double> scores;
  std::vector<std::optional<Vec3>> tips;
  std::vector<Vec3> axes;
  for (const auto& h : hypotheses)
    scores.push_back(h.log_odds), tips.push_back(h.tooltip), axes.push_back(effector_side(h.frame));
  const std::size_t chosen = most_probable_tooltip(scores, tips, axes, TooltipConfig{}.ambiguity_distance);
  const ToolFrame frame = estimate_tool_frame(held.observed, config);
  EXPECT_TRUE(frame.axes.isApprox(hypotheses[chosen].frame.axes));
  // The tip chosen for the 10 mm a tool's use needs; its probability, that of lying within the 15 mm a
  // confident tooltip claims.
  EXPECT_NEAR(frame.diagnostics.tooltip_probability,
              tooltip_probability(scores, tips, chosen, fitted_frame_score().confident_tolerance), 1e-12);
  // A model that scores only the effector's salience, against it: the least salient side wins.
  const std::size_t salience = feature_index("effector_reach_asymmetry");
  ASSERT_LT(salience, frame_feature_names().size());
  FrameScoreModel against_salience;
  against_salience.weights[salience] = -1.0;
  const auto scored = frame_hypotheses(held.observed, config, {}, against_salience);
  double least = scored.front().features[salience];
  for (const auto& h : scored) least = std::min(least, h.features[salience]);
  for (const auto& h : scored) EXPECT_DOUBLE_EQ(h.log_odds, -h.features[salience]);
  EXPECT_LT(least, 0.0) << "some hypothesis has its effector on its less salient side";
}

TEST(FrameSearch, ShippedWeightsAreTheShippedFilesAndTheMethodIsRecorded) {
  const Json file = read_json(std::string(kSourceDir) + "/configs/frame-score.json");
  const FrameScoreModel& model = fitted_frame_score();
  ASSERT_EQ(file.at("features").size(), static_cast<std::size_t>(kFrameFeatures));
  for (int f = 0; f < kFrameFeatures; ++f) {
    EXPECT_EQ(file.at("features")[f].get<std::string>(), frame_feature_names()[f]);
    EXPECT_DOUBLE_EQ(file.at("weights")[f].get<double>(), model.weights[f]) << frame_feature_names()[f];
  }
  EXPECT_DOUBLE_EQ(file.at("confident_probability").get<double>(), model.confident_probability);
  EXPECT_DOUBLE_EQ(file.at("calibrated_on").at("confident_tolerance_m").get<double>(), model.confident_tolerance);
  const std::string cloud = std::string(kSourceDir) + "/data/held/hook.ply";
  const ToolRun run = run_tool("estimate-frame", "-q " + cloud + " --method search -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("\"method\": \"search\""), std::string::npos);
  EXPECT_EQ(run_tool("estimate-frame", "-q " + cloud + " --method guess -o -").exit_code, 2);
}

TEST(FrameSearchAccuracy, FitFrameScoreReproducesTheShippedFile) {
  // The fit is rerun as the file says it was made, and the shipped model must explain the refit's labels
  // as well as the refit does. Not the weights themselves: the labels are tooltips within 10 mm, a few
  // hypotheses lie within a millimetre of that, and the compilers' rounding of the simulated disparities
  // decides those (a Clang build's refit moved the mirror score's weight from -9.5 to -11.1), while the
  // likelihood barely moves: the shipped model's mean log-likelihood per hypothesis fell short of the
  // refit's by 0 in a GCC build and 0.001 in a Clang build; the bound is 0.005. A change to the features,
  // the frame or the simulator without a refit moves it further. The likelihood is the fitted sessions'
  // alone, so one calibration grasp of one merge (not the file's) spares the calibration sessions' time.
  const std::string shipped = std::string(kSourceDir) + "/configs/frame-score.json";
  const Json file = read_json(shipped);
  const Json &on = file.at("fitted_on"), &calibrated = file.at("calibrated_on");
  std::string families, reconstructions;
  for (const auto& f : on.at("families")) families += " " + f.get<std::string>();
  for (const auto& r : on.at("reconstructions")) reconstructions += " " + r.get<std::string>();
  const auto dir = scratch_dir("fit-frame-score");
  const ToolRun run = run_tool(
      "fit-frame-score",
      "-q -j 2 --families" + families + " --first-seed " + std::to_string(on.at("first_seed").get<int>()) +
          " --grasps " + std::to_string(on.at("grasps").get<int>()) + " --reconstructions" + reconstructions +
          " --calibration-first-seed " + std::to_string(calibrated.at("first_seed").get<int>()) +
          " --calibration-grasps 1 --calibration-reconstructions registered --stereo " +
          on.at("stereo").get<std::string>() + " --tip-tolerance " +
          std::to_string(on.at("tip_tolerance_m").get<double>()) + " --handle-tolerance " +
          std::to_string(on.at("handle_tolerance_deg").get<double>()) +
          (on.at("belly_behind").get<bool>() ? " --belly-behind" : " --no-belly-behind") + " --compare " + shipped +
          " --hypotheses " + (dir / "hypotheses.csv").string() + " -o " + (dir / "score.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json refit = read_json((dir / "score.json").string());
  const double best = refit.at("mean_log_likelihood").get<double>();
  const double of_shipped = refit.at("compared").at("mean_log_likelihood").get<double>();
  EXPECT_LE(of_shipped, best + 1e-12);
  EXPECT_GT(of_shipped, best - 0.005) << "the shipped weights no longer fit what the command labels";
  // What each set was merged as is recorded: in the file, and per hypothesis in the CSV.
  EXPECT_EQ(refit.at("calibrated_on").at("reconstructions"), Json::array({"registered"}));
  EXPECT_EQ(refit.at("fitted_on").at("reconstructions"), on.at("reconstructions"));
  std::ifstream csv(dir / "hypotheses.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line.rfind("set,family,seed,reconstruction,", 0), 0u) << line;
  std::set<std::string> merges;
  while (std::getline(csv, line)) {
    std::vector<std::string> fields;
    std::stringstream row(line);
    for (std::string field; fields.size() < 4 && std::getline(row, field, ',');) fields.push_back(field);
    ASSERT_EQ(fields.size(), 4u) << line;
    if (fields[0] == "calibration") {
      EXPECT_EQ(fields[3], "registered") << line;
    } else {
      merges.insert(fields[3]);
    }
  }
  std::set<std::string> fitted;
  for (const auto& r : on.at("reconstructions")) fitted.insert(r.get<std::string>());
  EXPECT_EQ(merges, fitted);
}
