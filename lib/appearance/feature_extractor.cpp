#include "toolinc/appearance/feature_extractor.hpp"

#include <stdexcept>

#include "toolinc/core/error.hpp"

namespace toolinc {

FeatureExtractor FeatureExtractor::builtin(const BuiltinFeatureConfig& config) {
  check(config);
  FeatureExtractor e;
  e.name_ = "builtin";
  e.builtin_ = config;
  e.dimension_ = static_cast<Eigen::Index>(builtin_dimension(config));
  return e;
}

FeatureExtractor FeatureExtractor::dnn(const DnnFeatureConfig& config, const std::string& expected_sha256) {
  FeatureExtractor e;
  e.name_ = "dnn";
  e.dnn_ = std::make_shared<DnnFeatureExtractor>(config, expected_sha256);
  e.dimension_ = e.dnn_->dimension();
  return e;
}

FeatureExtractor FeatureExtractor::external(Eigen::Index dimension) {
  FeatureExtractor e;
  e.name_ = "external";
  e.dimension_ = dimension;
  return e;
}

FeatureExtractor FeatureExtractor::from_json(const Json& json, const std::string& file, const std::string& model) {
  if (!json.is_object() || !json.contains("name") || !json["name"].is_string())
    throw InputError(file, "extractor: missing \"name\"");
  const std::string name = json["name"].get<std::string>();
  if (!json.contains("dimension") || !json["dimension"].is_number_unsigned() || json["dimension"].get<long>() <= 0)
    throw InputError(file, "extractor: \"dimension\" must be a positive integer");
  const auto dimension = json["dimension"].get<Eigen::Index>();
  FeatureExtractor e;
  if (name == "builtin") {
    e = builtin(builtin_config_from_json(json, file));
  } else if (name == "dnn") {
    DnnFeatureConfig config = dnn_config_from_json(json, file);
    if (!model.empty()) config.model = model;
    if (!json.contains("model_sha256") || !json["model_sha256"].is_string() ||
        json["model_sha256"].get<std::string>().empty())
      throw InputError(file, "extractor: missing \"model_sha256\"");
    e = dnn(config, json["model_sha256"].get<std::string>());
  } else if (name == "external") {
    e = external(dimension);
  } else {
    throw InputError(file, "extractor: unknown name \"" + name + "\" (builtin, dnn or external)");
  }
  if (e.dimension_ != dimension)
    throw InputError(file, "extractor: records " + std::to_string(dimension) + " features, but the " + name +
                               " extractor gives " + std::to_string(e.dimension_));
  return e;
}

Json FeatureExtractor::to_json() const {
  if (name_ == "builtin") return toolinc::to_json(builtin_);
  if (name_ == "dnn") return toolinc::to_json(*dnn_);
  return {{"name", name_}, {"dimension", dimension_}, {"note", "features computed elsewhere (a feature database)"}};
}

Eigen::VectorXd FeatureExtractor::extract(const cv::Mat& bgr, const cv::Mat& mask,
                                          const std::vector<Eigen::Vector3d>& points) const {
  if (name_ == "builtin") return builtin_features(bgr, mask, builtin_, points);
  if (name_ == "dnn") return dnn_->extract(bgr);
  throw std::logic_error("an external extractor has no images to work on");
}

}  // namespace toolinc
