#include "toolinc/appearance/recognition.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace toolinc {
namespace {

Json score_object(const std::vector<std::string>& labels, const Eigen::RowVectorXd& scores) {
  Json object = Json::object();
  for (std::size_t i = 0; i < labels.size(); ++i) object[labels[i]] = scores[static_cast<Eigen::Index>(i)];
  return object;
}

}  // namespace

double separating_floor(std::vector<double> known, std::vector<double> unknown) {
  if (known.empty() || unknown.empty()) throw std::invalid_argument("separating_floor: no scores");
  std::vector<double> candidates = known;
  candidates.insert(candidates.end(), unknown.begin(), unknown.end());
  std::sort(candidates.begin(), candidates.end());
  std::sort(known.begin(), known.end());
  std::sort(unknown.begin(), unknown.end());
  // A floor just above candidates[i - 1] (i = 0: below everything) rejects the known below it and
  // accepts the unknown above it.
  double best_error = std::numeric_limits<double>::infinity(), floor = 0;
  for (std::size_t i = 0; i <= candidates.size(); ++i) {
    const double at = i == 0 ? candidates.front() - 1 : i == candidates.size() ? candidates.back() + 1
                                                                                : (candidates[i - 1] + candidates[i]) / 2;
    const auto known_rejected = std::lower_bound(known.begin(), known.end(), at) - known.begin();
    const auto unknown_accepted = unknown.end() - std::lower_bound(unknown.begin(), unknown.end(), at);
    const double error = static_cast<double>(known_rejected) / known.size() +
                         static_cast<double>(unknown_accepted) / unknown.size();
    if (error < best_error) best_error = error, floor = at;
  }
  return floor;
}

Decision decide(const Eigen::RowVectorXd& scores, const std::vector<std::string>& labels, const DecisionConfig& config) {
  if (scores.size() != static_cast<Eigen::Index>(labels.size()) || labels.size() < 2)
    throw std::invalid_argument("decide: one score per label, at least two labels");
  Eigen::Index best = 0, second = -1;
  for (Eigen::Index i = 1; i < scores.size(); ++i) {
    if (scores[i] > scores[best]) {
      second = best, best = i;
    } else if (second < 0 || scores[i] > scores[second]) {
      second = i;
    }
  }
  const Decision decision{labels[static_cast<std::size_t>(best)], scores[best], scores[best] - scores[second]};
  if (decision.best_score < config.min_score || decision.margin < config.min_margin)
    return {kUnknownLabel, decision.best_score, decision.margin};
  return decision;
}

Json classification_json(const std::vector<std::string>& labels, const Eigen::MatrixXd& scores, std::vector<Json> samples,
                         const DecisionConfig& config, const Json& context) {
  if (scores.rows() == 0 || static_cast<std::size_t>(scores.rows()) != samples.size())
    throw std::invalid_argument("classification_json: one sample description per score row");
  const Eigen::RowVectorXd mean = scores.colwise().mean();
  const Decision overall = decide(mean, labels, config);
  for (Eigen::Index i = 0; i < scores.rows(); ++i) {
    Json& sample = samples[static_cast<std::size_t>(i)];
    sample["label"] = decide(scores.row(i), labels, config).label;
    sample["scores"] = score_object(labels, scores.row(i));
  }
  Json result = {{"type", "classification"},
                 {"version", kClassificationVersion},
                 {"label", overall.label},
                 {"scores", score_object(labels, mean)},
                 {"best_score", overall.best_score},
                 {"margin", overall.margin},
                 {"min_score", config.min_score},
                 {"min_margin", config.min_margin}};
  for (const auto& [key, value] : context.items()) result[key] = value;
  result["per_sample"] = std::move(samples);
  return result;
}

}  // namespace toolinc
