// Features from a user-supplied network (ONNX, through OpenCV's dnn module), as the robot used ResNet-50
// pool5 features (original-method.md sect. 10). No weights are downloaded: the user brings the file, and
// its SHA-256 ties a classifier to it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <string>

#include "toolinc/io/json_file.hpp"

namespace toolinc {

// Defaults: torchvision's ImageNet convention (what a ResNet-50 exported from PyTorch expects).
struct DnnFeatureConfig {
  std::string model;                                // ONNX file
  int input_width = 224, input_height = 224;        // px the crop is resized to (bilinear)
  std::array<double, 3> mean{0.485, 0.456, 0.406};  // r, g, b, on pixel values scaled to [0, 1]
  std::array<double, 3> std{0.229, 0.224, 0.225};   // r, g, b: input = (value - mean) / std
  std::string channel_order = "rgb";                // of the network's input: "rgb" or "bgr"
  std::string output_layer;  // the layer whose output is the feature; empty: the network's output
};

// Throws std::invalid_argument on a bad size, a mean that is not finite, a std that is not positive and
// finite, or an unknown channel order.
void check(const DnnFeatureConfig& config);

class DnnFeatureExtractor {
 public:
  // Loads the model; when expected_sha256 is not empty, a model whose digest differs is refused.
  // Throws InputError(model, ...) when the file is missing, fails check_onnx (onnx_check.hpp), is not a
  // network OpenCV can load, has no layer called output_layer, has the wrong digest, or gives output that
  // is not finite on a grey image.
  explicit DnnFeatureExtractor(DnnFeatureConfig config, const std::string& expected_sha256 = "");

  // The flattened output for an 8-bit BGR crop, L2-normalised; InputError(model, ...) when not finite.
  Eigen::VectorXd extract(const cv::Mat& bgr);

  const DnnFeatureConfig& config() const { return config_; }
  const std::string& model_sha256() const { return sha256_; }
  Eigen::Index dimension() const { return dimension_; }

 private:
  DnnFeatureConfig config_;
  std::string sha256_;
  cv::dnn::Net net_;
  std::string layer_;  // OpenCV's name for output_layer; empty: the network's output
  Eigen::Index dimension_ = 0;
};

// The configuration, digest and dimension, for the classifier file; and the configuration back
// (throws InputError(file, ...)).
Json to_json(const DnnFeatureExtractor& extractor);
DnnFeatureConfig dnn_config_from_json(const Json& json, const std::string& file);

}  // namespace toolinc
