#include "toolinc/appearance/classifier_file.hpp"

#include <spdlog/fmt/fmt.h>

#include <cmath>
#include <set>

#include "toolinc/core/error.hpp"

namespace toolinc {
namespace {

Eigen::RowVectorXd number_row(const Json& json, Eigen::Index size, const std::string& what, const std::string& file) {
  if (!json.is_array() || static_cast<Eigen::Index>(json.size()) != size)
    throw InputError(file, fmt::format("{}: expected {} numbers", what, size));
  Eigen::RowVectorXd row(size);
  for (Eigen::Index i = 0; i < size; ++i) {
    const Json& value = json[static_cast<std::size_t>(i)];
    if (!value.is_number() || !std::isfinite(value.get<double>()))
      throw InputError(file, fmt::format("{}: expected finite numbers", what));
    row[i] = value.get<double>();
  }
  return row;
}

}  // namespace

Json classifier_json(const AppearanceClassifier& classifier, const Json& training) {
  const RlsModel& m = classifier.model;
  Json weights = Json::array();
  for (Eigen::Index c = 0; c < m.weights.cols(); ++c)
    weights.push_back(std::vector<double>(m.weights.col(c).data(), m.weights.col(c).data() + m.weights.rows()));
  Json json = {
      {"type", "classifier"},
      {"version", kClassifierVersion},
      {"method", "one-vs-all regularised least squares (targets +1/-1, unregularised bias)"},
      {"labels", m.labels},
      {"extractor", classifier.extractor.to_json()},
      {"lambda", m.lambda},
      {"lambda_selection", {{"method", "leave-one-out"}, {"error", m.loo_error}, {"accuracy", m.loo_accuracy}}},
      {"decision",
       [&] {
         Json decision = classifier.decision_summary;
         decision["min_score"] = classifier.decision.min_score;
         decision["min_margin"] = classifier.decision.min_margin;
         if (std::isfinite(classifier.decision.max_distance))
           decision["max_distance"] = classifier.decision.max_distance;
         if (std::isfinite(classifier.decision.sure_score)) decision["sure_score"] = classifier.decision.sure_score;
         return decision;
       }()},
      {"training", training},
      {"bias", std::vector<double>(m.bias.data(), m.bias.data() + m.bias.size())},
      {"weights", weights}};
  if (classifier.known) json["known_sessions"] = to_json(*classifier.known);
  return json;
}

AppearanceClassifier read_classifier(const std::string& path, const std::string& model) {
  const Json json = read_json(path);
  check_type(json, "classifier", kClassifierVersion, path);
  RlsModel m;
  const Json& labels = json.value("labels", Json());
  if (!labels.is_array() || labels.size() < 2) throw InputError(path, "\"labels\" must list at least two labels");
  for (const auto& label : labels) {
    if (!label.is_string()) throw InputError(path, "\"labels\" must be strings");
    m.labels.push_back(label.get<std::string>());
  }
  if (std::set<std::string>(m.labels.begin(), m.labels.end()).size() != m.labels.size())
    throw InputError(path, "\"labels\" repeat a label");
  if (!json.contains("extractor")) throw InputError(path, "missing \"extractor\"");
  FeatureExtractor extractor = FeatureExtractor::from_json(json["extractor"], path, model);
  const auto classes = static_cast<Eigen::Index>(m.labels.size());
  const Eigen::Index dimension = extractor.dimension();
  m.bias = number_row(json.value("bias", Json()), classes, "bias", path);
  const Json& weights = json.value("weights", Json());
  if (!weights.is_array() || static_cast<Eigen::Index>(weights.size()) != classes)
    throw InputError(path, "\"weights\" must hold one row per label");
  m.weights.resize(dimension, classes);
  for (Eigen::Index c = 0; c < classes; ++c)
    m.weights.col(c) = number_row(weights[static_cast<std::size_t>(c)], dimension, "weights", path).transpose();
  if (!json.contains("lambda") || !json["lambda"].is_number()) throw InputError(path, "missing \"lambda\"");
  m.lambda = json["lambda"].get<double>();
  DecisionConfig decision;  // files written before the thresholds were calibrated: the defaults
  Json summary = {{"min_score_from", "default"}, {"min_margin_from", "default"}};
  if (json.contains("decision")) {
    summary = json["decision"];
    const std::pair<const char*, double*> fields[] = {{"min_score", &decision.min_score},
                                                      {"min_margin", &decision.min_margin}};
    for (const auto& [key, value] : fields) {
      if (!summary.contains(key) || !summary[key].is_number() || !std::isfinite(summary[key].get<double>()))
        throw InputError(path, fmt::format("decision: \"{}\" must be a finite number", key));
      *value = summary[key].get<double>();
    }
    if (summary.contains("max_distance")) {
      if (!summary["max_distance"].is_number() || !(summary["max_distance"].get<double>() >= 0))
        throw InputError(path, "decision: \"max_distance\" must be a number >= 0");
      if (!json.contains("known_sessions"))
        throw InputError(path, "decision: \"max_distance\" without \"known_sessions\"");
      decision.max_distance = summary["max_distance"].get<double>();
    }
    if (summary.contains("sure_score")) {
      if (!summary["sure_score"].is_number() || !std::isfinite(summary["sure_score"].get<double>()))
        throw InputError(path, "decision: \"sure_score\" must be a finite number");
      decision.sure_score = summary["sure_score"].get<double>();
    }
  }
  std::optional<KnownSessions> known;
  if (json.contains("known_sessions"))
    known = known_sessions_from_json(json["known_sessions"], m.labels.size(), dimension, path);
  return {std::move(extractor), std::move(m), decision, std::move(summary), std::move(known)};
}

}  // namespace toolinc
