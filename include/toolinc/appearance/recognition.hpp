// From scores to an answer (docs/formats.md "classification"): per sample the best-scoring label, and over
// all samples the label of the averaged scores (the robot averaged over a buffer of frames); "unknown"
// when the best score is below min_score or within min_margin of the second best.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "toolinc/io/json_file.hpp"

namespace toolinc {

constexpr const char* kUnknownLabel = "unknown";
constexpr int kClassificationVersion = 1;

// Defaults: RLS scores are fitted to +1 for the label and -1 for the others, so a sample whose best
// score is below 0 looks more like "none of these" than like its best label; a margin of 0.1 (5% of
// that range) leaves near-ties undecided.
// max_distance: a whole session is also unknown when its depth block lies farther than this from every
// training session of its answer (known_sessions.hpp; infinite: not checked), unless its best score is
// above sure_score (higher than any tool never seen scored in training; infinite: never).
struct DecisionConfig {
  double min_score = 0.0;
  double min_margin = 0.1;
  double max_distance = std::numeric_limits<double>::infinity();
  double sure_score = std::numeric_limits<double>::infinity();
};

struct Decision {
  std::string label;  // or kUnknownLabel
  double best_score = 0, margin = 0;
};

// Throws std::invalid_argument unless there are as many scores as labels and at least two.
Decision decide(const Eigen::RowVectorXd& scores, const std::vector<std::string>& labels, const DecisionConfig& config);

// scores: one row per sample; samples: what each row came from ({"view": 2, "box": [...]}, {"row": 0}, ...),
// to which the sample's label and scores are added; context: fields recorded before the samples (the
// classifier, the input).
Json classification_json(const std::vector<std::string>& labels, const Eigen::MatrixXd& scores,
                         std::vector<Json> samples, const DecisionConfig& config, const Json& context = Json::object());

}  // namespace toolinc
