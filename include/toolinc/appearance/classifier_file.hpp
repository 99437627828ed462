// The classifier file (docs/formats.md "classifier"): type "classifier", version 1, the labels, the feature
// extractor with everything needed to reproduce it (for a network, the model's SHA-256), the chosen
// lambda and how it was chosen, the unknown thresholds and how they were chosen (with the training sessions' depth
// blocks they measure distances to), and per label the weights and bias of its linear score.
#pragma once

#include <optional>
#include <string>

#include "toolinc/appearance/feature_extractor.hpp"
#include "toolinc/appearance/known_sessions.hpp"
#include "toolinc/appearance/recognition.hpp"
#include "toolinc/appearance/rls.hpp"
#include "toolinc/io/json_file.hpp"

namespace toolinc {

constexpr int kClassifierVersion = 1;

struct AppearanceClassifier {
  FeatureExtractor extractor;
  RlsModel model;
  DecisionConfig decision;             // the thresholds classify uses unless told others
  Json decision_summary;               // how they were chosen (files without a "decision": the defaults)
  std::optional<KnownSessions> known;  // builtin classifiers trained on sessions: for decision.max_distance
};

// training: a summary of the training data, recorded as given.
Json classifier_json(const AppearanceClassifier& classifier, const Json& training);

// Reads and validates a classifier file and rebuilds its extractor (model replaces the recorded model
// path of a dnn extractor). Throws InputError naming the classifier file, or the model file when it is
// missing, unloadable or not the one the classifier was trained with.
AppearanceClassifier read_classifier(const std::string& path, const std::string& model = "");

}  // namespace toolinc
