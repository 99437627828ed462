// The feature extractor a classifier was trained with, as its file records it, so classification
// computes the same features: builtin, dnn, or "external" for vectors that came from elsewhere (a
// robot's feature database), which can only be classified as vectors.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "toolinc/appearance/builtin_features.hpp"
#include "toolinc/appearance/dnn_features.hpp"
#include "toolinc/io/json_file.hpp"

namespace toolinc {

class FeatureExtractor {
 public:
  static FeatureExtractor builtin(const BuiltinFeatureConfig& config = {});
  static FeatureExtractor dnn(const DnnFeatureConfig& config, const std::string& expected_sha256 = "");
  static FeatureExtractor external(Eigen::Index dimension);
  // The extractor a classifier file's "extractor" object describes; a non-empty model replaces the
  // recorded model path (its digest is still checked). Throws InputError(file, ...) on an unknown or
  // malformed description, InputError(model, ...) on a model that cannot be loaded or has another digest.
  static FeatureExtractor from_json(const Json& json, const std::string& file, const std::string& model = "");

  Json to_json() const;
  const std::string& name() const { return name_; }
  Eigen::Index dimension() const { return dimension_; }
  bool extracts_from_images() const { return name_ != "external"; }
  const BuiltinFeatureConfig& builtin_config() const { return builtin_; }  // meaningful for "builtin" only
  // Features of an 8-bit BGR crop and the blob's mask in it (empty when not recorded: the builtin
  // descriptor estimates it; a network ignores it), and the blob's 3D points (ViewCrop::points; empty
  // without depth; a network ignores them). Throws std::logic_error for an external extractor.
  Eigen::VectorXd extract(const cv::Mat& bgr, const cv::Mat& mask = cv::Mat(),
                          const std::vector<Eigen::Vector3d>& points = {}) const;

 private:
  std::string name_;
  Eigen::Index dimension_ = 0;
  BuiltinFeatureConfig builtin_;
  std::shared_ptr<DnnFeatureExtractor> dnn_;  // shared: a network is not copyable, and forward() mutates it
};

}  // namespace toolinc
