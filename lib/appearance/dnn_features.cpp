#include "toolinc/appearance/dnn_features.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "toolinc/appearance/onnx_check.hpp"
#include "toolinc/appearance/sha256.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/read_file.hpp"

namespace toolinc {
namespace {

std::array<double, 3> triple(const Json& json, const std::string& key, const std::string& file) {
  const Json& v = json.value(key, Json());
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw InputError(file, fmt::format("extractor: \"{}\" must be 3 numbers", key));
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

// OpenCV's messages run over several lines (a "> " line per nested call); a log line is one.
std::string one_line(const std::string& text) {
  std::string joined;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t start = line.find_first_not_of("> \t"), end = line.find_last_not_of(" \t\r");
    if (start == std::string::npos) continue;
    joined += (joined.empty() ? "" : "; ") + line.substr(start, end + 1 - start);
  }
  return joined;
}

}  // namespace

void check(const DnnFeatureConfig& c) {
  // Image networks take a few hundred px a side; 4096 px is already a 200 MB input tensor.
  constexpr int kMaxInputSide = 4096;
  const auto in_range = [](int side) { return side >= 1 && side <= kMaxInputSide; };
  if (!in_range(c.input_width) || !in_range(c.input_height))
    throw std::invalid_argument(fmt::format("--input-size: each side must be 1 to {} px, not {} {}", kMaxInputSide,
                                            c.input_width, c.input_height));
  for (const double m : c.mean)
    if (!std::isfinite(m)) throw std::invalid_argument("--mean: every value must be a finite number");
  for (const double s : c.std)
    if (!(s > 0) || !std::isfinite(s)) throw std::invalid_argument("--std: every value must be positive and finite");
  if (c.channel_order != "rgb" && c.channel_order != "bgr")
    throw std::invalid_argument("--channel-order: must be rgb or bgr, not \"" + c.channel_order + "\"");
}

DnnFeatureExtractor::DnnFeatureExtractor(DnnFeatureConfig config, const std::string& expected_sha256)
    : config_(std::move(config)) {
  check(config_);
  const std::string& model = config_.model;
  if (!std::filesystem::is_regular_file(model)) throw InputError(model, "no such model file");
  const std::string bytes = read_file(model);
  sha256_ = sha256_hex(bytes);
  if (!expected_sha256.empty() && sha256_ != expected_sha256)
    throw InputError(
        model, fmt::format("SHA-256 {} differs from the classifier's {}: not the model it was trained with", sha256_,
                           expected_sha256));
  check_onnx(bytes, model);
  try {
    net_ = cv::dnn::readNetFromONNX(bytes.data(), bytes.size());
  } catch (const cv::Exception& e) {
    throw InputError(model, "not an ONNX network OpenCV can load: " + one_line(e.err));
  }
  if (net_.empty()) throw InputError(model, "not an ONNX network OpenCV can load");
  if (!config_.output_layer.empty()) {
    // OpenCV 4.6 names a layer from an ONNX node "onnx_node!<node name>"; accept the ONNX name.
    for (const std::string& name : {config_.output_layer, "onnx_node!" + config_.output_layer})
      if (net_.getLayerId(name) >= 0) {
        layer_ = name;
        break;
      }
    if (layer_.empty()) throw InputError(model, "no layer called \"" + config_.output_layer + "\"");
  }
  try {  // one grey crop: the feature size, and any shape mismatch, show now rather than per crop
    dimension_ = extract(cv::Mat(config_.input_height, config_.input_width, CV_8UC3, cv::Scalar::all(128))).size();
  } catch (const cv::Exception& e) {
    throw InputError(model, fmt::format("cannot run on a {}x{} input: {}", config_.input_width, config_.input_height,
                                        one_line(e.err)));
  }
  spdlog::debug("{}: {} features from {}", model, dimension_,
                config_.output_layer.empty() ? std::string("the output") : config_.output_layer);
}

Eigen::VectorXd DnnFeatureExtractor::extract(const cv::Mat& bgr) {
  CV_Assert(bgr.type() == CV_8UC3 && !bgr.empty());
  cv::Mat resized, input;
  cv::resize(bgr, resized, cv::Size(config_.input_width, config_.input_height), 0, 0, cv::INTER_LINEAR);
  const bool rgb = config_.channel_order == "rgb";
  if (rgb) cv::cvtColor(resized, resized, cv::COLOR_BGR2RGB);
  resized.convertTo(input, CV_32FC3, 1.0 / 255.0);
  // Channel k of the input holds r, g, b (rgb) or b, g, r (bgr); mean and std are given as r, g, b.
  cv::Scalar mean, std;
  for (int k = 0; k < 3; ++k) {
    const int rgb_index = rgb ? k : 2 - k;
    mean[k] = config_.mean[rgb_index], std[k] = config_.std[rgb_index];
  }
  cv::subtract(input, mean, input);
  cv::divide(input, std, input);
  net_.setInput(cv::dnn::blobFromImage(input));  // NCHW, no further scaling, swapping or cropping
  const cv::Mat output = net_.forward(layer_);
  cv::Mat flat = output.reshape(1, 1);
  Eigen::VectorXd features(static_cast<Eigen::Index>(flat.total()));
  for (Eigen::Index i = 0; i < features.size(); ++i) features[i] = flat.at<float>(0, static_cast<int>(i));
  // NaN weights, or an overflow, would make features every score then ignores: a classifier of nulls.
  if (!features.allFinite())
    throw InputError(config_.model, fmt::format("the network's output on a {}x{} input is not finite (NaN or "
                                                "infinite weights?)",
                                                config_.input_width, config_.input_height));
  const double norm = features.norm();
  return norm > 0 ? Eigen::VectorXd(features / norm) : features;
}

Json to_json(const DnnFeatureExtractor& extractor) {
  const DnnFeatureConfig& c = extractor.config();
  return {{"name", "dnn"},
          {"model", c.model},
          {"model_sha256", extractor.model_sha256()},
          {"input_size", {c.input_width, c.input_height}},
          {"resize", "INTER_LINEAR"},
          {"mean", c.mean},
          {"std", c.std},
          {"normalisation", "input (value / 255 - mean) / std per channel; output flattened, L2"},
          {"channel_order", c.channel_order},
          {"output_layer", c.output_layer},
          {"dimension", extractor.dimension()}};
}

DnnFeatureConfig dnn_config_from_json(const Json& json, const std::string& file) {
  DnnFeatureConfig c;
  const Json& size = json.value("input_size", Json());
  if (!size.is_array() || size.size() != 2) throw InputError(file, "extractor: \"input_size\" must be [width, height]");
  constexpr int kMax = std::numeric_limits<int>::max();
  c.input_width = int_value(size[0], "input_size", file, 1, kMax);
  c.input_height = int_value(size[1], "input_size", file, 1, kMax);
  c.mean = triple(json, "mean", file);
  c.std = triple(json, "std", file);
  for (const char* key : {"model", "channel_order", "output_layer"})
    if (!json.contains(key) || !json[key].is_string())
      throw InputError(file, fmt::format("extractor: \"{}\" must be a string", key));
  c.model = json["model"].get<std::string>();
  c.channel_order = json["channel_order"].get<std::string>();
  c.output_layer = json["output_layer"].get<std::string>();
  try {
    check(c);
  } catch (const std::invalid_argument& e) {
    throw InputError(file, std::string("extractor: ") + e.what());
  }
  return c;
}

}  // namespace toolinc
