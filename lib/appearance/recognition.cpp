#include "toolinc/appearance/recognition.hpp"

#include <stdexcept>

namespace toolinc {
namespace {

Json score_object(const std::vector<std::string>& labels, const Eigen::RowVectorXd& scores) {
  Json object = Json::object();
  for (std::size_t i = 0; i < labels.size(); ++i) object[labels[i]] = scores[static_cast<Eigen::Index>(i)];
  return object;
}

}  // namespace

Decision decide(const Eigen::RowVectorXd& scores, const std::vector<std::string>& labels,
                const DecisionConfig& config) {
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

Json classification_json(const std::vector<std::string>& labels, const Eigen::MatrixXd& scores,
                         std::vector<Json> samples, const DecisionConfig& config, const Json& context) {
  if (scores.rows() == 0 || static_cast<std::size_t>(scores.rows()) != samples.size())
    throw std::invalid_argument("classification_json: one sample description per score row");
  const Eigen::RowVectorXd mean = scores.colwise().mean();
  const Decision overall = decide(mean, labels, config);
  for (Eigen::Index i = 0; i < scores.rows(); ++i) {
    Json& sample = samples[static_cast<std::size_t>(i)];
    sample["label"] = decide(scores.row(i), labels, config).label;
    sample["scores"] = score_object(labels, scores.row(i));
  }
  Json result = {{"type", "classification"},         {"version", kClassificationVersion},
                 {"label", overall.label},           {"scores", score_object(labels, mean)},
                 {"best_score", overall.best_score}, {"margin", overall.margin},
                 {"min_score", config.min_score},    {"min_margin", config.min_margin}};
  for (const auto& [key, value] : context.items()) result[key] = value;
  result["per_sample"] = std::move(samples);
  return result;
}

}  // namespace toolinc
