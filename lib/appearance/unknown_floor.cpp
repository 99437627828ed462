#include "toolinc/appearance/unknown_floor.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>
#include <stdexcept>

#include "toolinc/core/statistics.hpp"

namespace toolinc {
namespace {

// Per group (a session's views, or a single sample), its label and the mean of its rows' scores: the
// robot decides on a session's averaged scores.
std::vector<std::pair<std::size_t, Eigen::RowVectorXd>> group_means(const Eigen::MatrixXd& scores,
                                                                    const std::vector<std::size_t>& targets,
                                                                    const std::vector<std::size_t>& groups) {
  std::map<std::size_t, std::pair<std::size_t, Eigen::RowVectorXd>> sums;
  std::map<std::size_t, int> counts;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    auto [it, fresh] = sums.try_emplace(groups[i], targets[i], Eigen::RowVectorXd::Zero(scores.cols()));
    it->second.second += scores.row(static_cast<Eigen::Index>(i));
    ++counts[groups[i]];
  }
  std::vector<std::pair<std::size_t, Eigen::RowVectorXd>> means;
  for (const auto& [group, sum] : sums) means.emplace_back(sum.first, sum.second / counts[group]);
  return means;
}

}  // namespace

DecisionConfig calibrate_decision(const Eigen::MatrixXd& x, const std::vector<std::size_t>& targets,
                                  const std::vector<std::string>& labels, const std::vector<std::size_t>& groups,
                                  bool sessions_only, const RlsModel& model, const RlsConfig& rls,
                                  const UnknownFloorConfig& floor, Json& summary) {
  if (!(floor.known_rejection >= 0 && floor.known_rejection < 1))
    throw std::invalid_argument(
        fmt::format("unknown floor: known_rejection {} is not in [0, 1)", floor.known_rejection));
  DecisionConfig decision;
  summary = {{"min_margin_from", "default: 5 % of the +-1 target range"}};
  if (labels.size() < 3 || !sessions_only) {
    summary["min_score_from"] = labels.size() < 3 ? "default: with two labels none can be left out to calibrate it"
                                                  : "default: samples not all from sessions";
    return decision;
  }
  std::vector<double> known, unknown;
  const Eigen::MatrixXd held_out = leave_group_out_scores(x, targets, labels.size(), groups, model.lambda);
  for (const auto& [target, mean] : group_means(held_out, targets, groups))
    known.push_back(mean[static_cast<Eigen::Index>(target)]);
  for (std::size_t out = 0; out < labels.size(); ++out) {
    std::vector<Eigen::Index> in_rows, out_rows;
    std::vector<std::size_t> in_targets, out_groups;
    for (std::size_t i = 0; i < targets.size(); ++i) {
      if (targets[i] == out) {
        out_rows.push_back(static_cast<Eigen::Index>(i)), out_groups.push_back(groups[i]);
      } else {
        in_rows.push_back(static_cast<Eigen::Index>(i)), in_targets.push_back(targets[i] - (targets[i] > out));
      }
    }
    std::vector<std::string> others = labels;
    others.erase(others.begin() + static_cast<std::ptrdiff_t>(out));
    const RlsModel without = train_rls(x(in_rows, Eigen::all), in_targets, others, rls);
    const Eigen::MatrixXd scores = rls_scores(without, x(out_rows, Eigen::all));
    for (const auto& [target, mean] : group_means(scores, std::vector<std::size_t>(out_rows.size(), 0), out_groups))
      unknown.push_back(mean.maxCoeff());
  }
  // Never above the default: a known tool in a new grasp differs more from the training data than one
  // training session does from the others, so floors fitted above 0 turn away known tools the default
  // answers right (and a best score above 0 is nearer its label's +1 than the others' -1).
  decision.min_score = std::min(decision.min_score, quantile(known, floor.known_rejection));
  // The other way round: no tool never seen scored above this, and a known tool in a new grasp scores
  // this much as often as not, so a session that does is its answer however far its head lies from the
  // training sessions (the distance rule, known_sessions.hpp). The highest of a few never-seen scores
  // alone is a thin bound: one more tool never seen may pass it by chance.
  decision.sure_score = std::max(*std::max_element(unknown.begin(), unknown.end()), quantile(known, 0.5));
  const auto share_below = [&](const std::vector<double>& v) {
    return static_cast<double>(std::count_if(v.begin(), v.end(), [&](double s) { return s < decision.min_score; })) /
           v.size();
  };
  summary["min_score_from"] =
      fmt::format("the {} quantile of the scores of known sessions left out of training, at most {}",
                  floor.known_rejection, DecisionConfig{}.min_score);
  summary["known_groups"] = known.size();
  summary["known_rejected"] = share_below(known);
  summary["unknown_groups"] = unknown.size();
  summary["unknown_accepted"] = 1.0 - share_below(unknown);
  summary["sure_score_from"] =
      "the highest score of a session whose label was left out of training, at least the median score of known "
      "sessions left out of training";
  spdlog::info(
      "unknown floor {:.3f} on the best score: on the training data it rejects {:.0f}% of {} known sessions "
      "(left out) and accepts {:.0f}% of {} never seen (their label left out)",
      decision.min_score, 100.0 * summary["known_rejected"].get<double>(), known.size(),
      100.0 * summary["unknown_accepted"].get<double>(), unknown.size());
  return decision;
}

}  // namespace toolinc
