#include "toolinc/appearance/builtin_features.hpp"

#include <spdlog/fmt/fmt.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "toolinc/core/error.hpp"

namespace toolinc {
namespace {

constexpr double kEpsilon = 1e-6;  // keeps empty blocks and histograms finite

void normalise(Eigen::Ref<Eigen::VectorXd> v) { v /= std::sqrt(v.squaredNorm() + kEpsilon * kEpsilon); }

// Per-cell orientation histograms, row-major cells, bins innermost.
Eigen::VectorXd cell_histograms(const cv::Mat& image, const BuiltinFeatureConfig& c) {
  cv::Mat colour, dx, dy;
  image.convertTo(colour, CV_32FC3);
  cv::Sobel(colour, dx, CV_32F, 1, 0, 1);  // ksize 1: the central difference [-1 0 1]
  cv::Sobel(colour, dy, CV_32F, 0, 1, 1);
  const int cells_x = c.width / c.cell, bins = c.orientation_bins;
  Eigen::VectorXd histograms = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(cells_x) * (c.height / c.cell) * bins);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const auto &gx = dx.at<cv::Vec3f>(y, x), &gy = dy.at<cv::Vec3f>(y, x);
      int strongest = 0;
      float best = -1;
      for (int k = 0; k < 3; ++k)
        if (const float m = gx[k] * gx[k] + gy[k] * gy[k]; m > best) best = m, strongest = k;
      const double magnitude = std::sqrt(best);
      double angle = std::atan2(gy[strongest], gx[strongest]);  // unsigned: fold into [0, pi)
      if (angle < 0) angle += M_PI;
      const double position = angle / M_PI * bins - 0.5;  // bin centres at (i + 0.5) * pi / bins
      const int lower = static_cast<int>(std::floor(position));
      const double upper_share = position - lower;
      const Eigen::Index base = (static_cast<Eigen::Index>(y / c.cell) * cells_x + x / c.cell) * bins;
      histograms[base + (lower + bins) % bins] += magnitude * (1 - upper_share);
      histograms[base + (lower + 1) % bins] += magnitude * upper_share;
    }
  return histograms;
}

Eigen::VectorXd hog(const cv::Mat& image, const BuiltinFeatureConfig& c) {
  const Eigen::VectorXd cells = cell_histograms(image, c);
  const int cells_x = c.width / c.cell, cells_y = c.height / c.cell, bins = c.orientation_bins;
  const int blocks_x = cells_x - c.block + 1, blocks_y = cells_y - c.block + 1;
  const int block_size = c.block * c.block * bins;
  Eigen::VectorXd features(static_cast<Eigen::Index>(blocks_x) * blocks_y * block_size);
  Eigen::Index out = 0;
  for (int by = 0; by < blocks_y; ++by)
    for (int bx = 0; bx < blocks_x; ++bx) {
      const Eigen::Index start = out;
      for (int cy = by; cy < by + c.block; ++cy)
        for (int cx = bx; cx < bx + c.block; ++cx, out += bins)
          features.segment(out, bins) = cells.segment((static_cast<Eigen::Index>(cy) * cells_x + cx) * bins, bins);
      normalise(features.segment(start, block_size));
    }
  return features;
}

Eigen::VectorXd colour_histogram(const cv::Mat& image, const BuiltinFeatureConfig& c) {
  cv::Mat hsv;
  cv::cvtColor(image, hsv, cv::COLOR_BGR2HSV);
  Eigen::VectorXd histogram = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(c.hue_bins) * c.saturation_bins);
  for (int y = 0; y < hsv.rows; ++y)
    for (int x = 0; x < hsv.cols; ++x) {
      const auto& p = hsv.at<cv::Vec3b>(y, x);
      const int h = std::min(c.hue_bins - 1, p[0] * c.hue_bins / 180);
      const int s = p[1] * c.saturation_bins / 256;
      histogram[static_cast<Eigen::Index>(h) * c.saturation_bins + s] += 1;
    }
  return (histogram / static_cast<double>(hsv.total())).cwiseSqrt();  // unit norm: the shares sum to 1
}

int positive_int(const Json& json, const std::string& key, const std::string& file) {
  if (!json.contains(key) || !json[key].is_number_integer() || json[key].get<int>() <= 0)
    throw InputError(file, fmt::format("extractor: \"{}\" must be a positive integer", key));
  return json[key].get<int>();
}

}  // namespace

void check(const BuiltinFeatureConfig& c) {
  if (c.cell <= 0 || c.block <= 0 || c.orientation_bins <= 0 || c.hue_bins <= 0 || c.saturation_bins <= 0 ||
      c.width % c.cell != 0 || c.height % c.cell != 0 || c.width / c.cell < c.block || c.height / c.cell < c.block)
    throw std::invalid_argument(fmt::format("builtin features: a {}x{} crop does not hold {}-cell blocks of {} px cells",
                                            c.width, c.height, c.block, c.cell));
}

std::size_t builtin_dimension(const BuiltinFeatureConfig& c) {
  const std::size_t blocks = static_cast<std::size_t>(c.width / c.cell - c.block + 1) * (c.height / c.cell - c.block + 1);
  return blocks * c.block * c.block * c.orientation_bins + static_cast<std::size_t>(c.hue_bins) * c.saturation_bins;
}

Eigen::VectorXd builtin_features(const cv::Mat& bgr, const BuiltinFeatureConfig& config) {
  CV_Assert(bgr.type() == CV_8UC3 && !bgr.empty());
  cv::Mat resized;
  cv::resize(bgr, resized, cv::Size(config.width, config.height), 0, 0, cv::INTER_AREA);
  Eigen::VectorXd shape = hog(resized, config), colour = colour_histogram(resized, config);
  normalise(shape);
  Eigen::VectorXd features(shape.size() + colour.size());
  features << shape, colour;
  return features / std::sqrt(2.0);
}

Json to_json(const BuiltinFeatureConfig& c) {
  return {{"name", "builtin"},
          {"input_size", {c.width, c.height}},
          {"resize", "INTER_AREA"},
          {"hog",
           {{"cell", c.cell},
            {"block", c.block},
            {"orientation_bins", c.orientation_bins},
            {"gradient", "central differences, strongest colour channel"},
            {"block_normalisation", "L2"}}},
          {"colour", {{"space", "HSV"}, {"hue_bins", c.hue_bins}, {"saturation_bins", c.saturation_bins}}},
          {"normalisation", "HOG L2, sqrt(colour shares), both scaled by 1/sqrt(2)"},
          {"dimension", builtin_dimension(c)}};
}

BuiltinFeatureConfig builtin_config_from_json(const Json& json, const std::string& file) {
  BuiltinFeatureConfig c;
  const Json& size = json.value("input_size", Json());
  if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() || !size[1].is_number_integer())
    throw InputError(file, "extractor: \"input_size\" must be [width, height]");
  c.width = size[0].get<int>(), c.height = size[1].get<int>();
  if (!json.contains("hog") || !json.contains("colour")) throw InputError(file, "extractor: missing \"hog\" or \"colour\"");
  c.cell = positive_int(json["hog"], "cell", file);
  c.block = positive_int(json["hog"], "block", file);
  c.orientation_bins = positive_int(json["hog"], "orientation_bins", file);
  c.hue_bins = positive_int(json["colour"], "hue_bins", file);
  c.saturation_bins = positive_int(json["colour"], "saturation_bins", file);
  try {
    check(c);
  } catch (const std::invalid_argument& e) {
    throw InputError(file, e.what());
  }
  return c;
}

}  // namespace toolinc
