#include "toolinc/appearance/builtin_features.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "toolinc/appearance/blob_mask.hpp"
#include "toolinc/core/error.hpp"

namespace toolinc {
namespace {

constexpr double kEpsilon = 1e-6;  // keeps empty blocks and histograms finite

void normalise(Eigen::Ref<Eigen::VectorXd> v) { v /= std::sqrt(v.squaredNorm() + kEpsilon * kEpsilon); }

std::size_t hog_dimension(int side, const BuiltinFeatureConfig& c) {
  const auto blocks = static_cast<std::size_t>(side / c.cell - c.block + 1);
  return blocks * blocks * c.block * c.block * c.orientation_bins;
}

// Per-cell orientation histograms of a square single-channel float image, row-major cells, bins
// innermost: central differences, unsigned orientation voted into the two nearest bins.
Eigen::VectorXd cell_histograms(const cv::Mat& image, const BuiltinFeatureConfig& c) {
  cv::Mat dx, dy;
  cv::Sobel(image, dx, CV_32F, 1, 0, 1);  // ksize 1: the central difference [-1 0 1]
  cv::Sobel(image, dy, CV_32F, 0, 1, 1);
  const int cells = image.cols / c.cell, bins = c.orientation_bins;
  Eigen::VectorXd histograms = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(cells) * cells * bins);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const float gx = dx.at<float>(y, x), gy = dy.at<float>(y, x);
      const double magnitude = std::sqrt(gx * gx + gy * gy);
      if (magnitude == 0) continue;
      double angle = std::atan2(gy, gx);  // unsigned: fold into [0, pi)
      if (angle < 0) angle += M_PI;
      const double position = angle / M_PI * bins - 0.5;  // bin centres at (i + 0.5) * pi / bins
      const int lower = static_cast<int>(std::floor(position));
      const double upper_share = position - lower;
      const Eigen::Index base = (static_cast<Eigen::Index>(y / c.cell) * cells + x / c.cell) * bins;
      histograms[base + (lower + bins) % bins] += magnitude * (1 - upper_share);
      histograms[base + (lower + 1) % bins] += magnitude * upper_share;
    }
  return histograms;
}

// Dalal & Triggs blocks of `block` x `block` cells, stride one cell, each L2-normalised.
Eigen::VectorXd hog(const cv::Mat& image, const BuiltinFeatureConfig& c) {
  const Eigen::VectorXd cells = cell_histograms(image, c);
  const int cells_x = image.cols / c.cell, bins = c.orientation_bins, blocks = cells_x - c.block + 1;
  const int block_size = c.block * c.block * bins;
  Eigen::VectorXd features(static_cast<Eigen::Index>(blocks) * blocks * block_size);
  Eigen::Index out = 0;
  for (int by = 0; by < blocks; ++by)
    for (int bx = 0; bx < blocks; ++bx) {
      const Eigen::Index start = out;
      for (int cy = by; cy < by + c.block; ++cy)
        for (int cx = bx; cx < bx + c.block; ++cx, out += bins)
          features.segment(out, bins) = cells.segment((static_cast<Eigen::Index>(cy) * cells_x + cx) * bins, bins);
      normalise(features.segment(start, block_size));
    }
  return features;
}

// HOG of the window and of its coarser copy, one unit-norm block.
Eigen::VectorXd two_scale_hog(const cv::Mat& window, const BuiltinFeatureConfig& c) {
  cv::Mat coarse;
  cv::resize(window, coarse, cv::Size(c.coarse_size, c.coarse_size), 0, 0, cv::INTER_AREA);
  const Eigen::VectorXd fine = hog(window, c), rough = hog(coarse, c);
  Eigen::VectorXd both(fine.size() + rough.size());
  both << fine.cwiseSqrt(), rough.cwiseSqrt();  // Hellinger: a linear classifier on it compares histograms better
  normalise(both);
  return both;
}

// The blob in its principal-axis frame: a along the major axis, b along the minor, both signed so that
// the end towards the image's top (the camera looks at a tool held up, the hand below it) has the
// smaller a, and the head's side with the larger third moment (where a hook or an L sticks out) the
// larger b.
struct BlobFrame {
  cv::Point2d centroid;
  double angle = 0;  // of the major axis, from the image's x
  double sign_a = 1, sign_b = 1;
  std::vector<cv::Point2d> ab;  // every pixel's signed (a, b), about the centroid
};

BlobFrame blob_frame(const cv::Mat& mask) {
  const cv::Moments m = cv::moments(mask, true);
  BlobFrame f;
  f.centroid = {m.m10 / m.m00, m.m01 / m.m00};
  f.angle = 0.5 * std::atan2(2 * m.mu11, m.mu20 - m.mu02);
  const double ca = std::cos(f.angle), sa = std::sin(f.angle);
  f.sign_a = sa > 0 ? 1 : -1;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) {
      if (!mask.at<uchar>(y, x)) continue;
      const double dx = x - f.centroid.x, dy = y - f.centroid.y;
      f.ab.emplace_back(f.sign_a * (ca * dx + sa * dy), -sa * dx + ca * dy);
    }
  return f;
}

// A square of the (a, b) plane: its centre and half side.
struct Region {
  double a = 0, b = 0, half = 1;
};

// The whole blob, and its head: the square on the blob's top end whose side is head_share of the blob's
// length, centred across on the pixels of that band. The band's third moment across sets sign_b.
std::pair<Region, Region> regions(BlobFrame& f, double head_share) {
  double a_lo = 0, a_hi = 0, extent = 1;
  for (const auto& p : f.ab)
    a_lo = std::min(a_lo, p.x), a_hi = std::max(a_hi, p.x), extent = std::max({extent, std::abs(p.x), std::abs(p.y)});
  const double half = std::max(1.0, head_share * (a_hi - a_lo) / 2);
  double sum = 0, count = 0;
  for (const auto& p : f.ab)
    if (p.x <= a_lo + 2 * half) sum += p.y, count += 1;
  const double centre = sum / count;
  double b3 = 0;
  for (const auto& p : f.ab)
    if (p.x <= a_lo + 2 * half) b3 += std::pow(p.y - centre, 3);
  f.sign_b = b3 >= 0 ? 1 : -1;
  return {Region{0, 0, extent}, Region{a_lo + half, f.sign_b * centre, half}};
}

// Crop pixels -> window pixels: the region's b along x, a along y, filling the window.
cv::Matx23d window_from_crop(const BlobFrame& f, const Region& r, int size) {
  const double s = (size / 2.0 - 1) / r.half, ca = std::cos(f.angle), sa = std::sin(f.angle);
  const cv::Vec2d row_x = s * f.sign_b * cv::Vec2d(-sa, ca), row_y = s * f.sign_a * cv::Vec2d(ca, sa);
  const double half = size / 2.0;
  return {row_x[0], row_x[1], half - s * r.b - row_x[0] * f.centroid.x - row_x[1] * f.centroid.y,
          row_y[0], row_y[1], half - s * r.a - row_y[0] * f.centroid.x - row_y[1] * f.centroid.y};
}

// Float image warped into the window, low-passed first where the window shrinks it (against aliasing).
cv::Mat warp(const cv::Mat& image, const cv::Matx23d& transform, double scale, int size) {
  cv::Mat source = image;
  if (scale < 1) cv::GaussianBlur(image, source, cv::Size(), 0.5 / scale);
  cv::Mat window;
  cv::warpAffine(source, window, transform, cv::Size(size, size), cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  return window;
}

Eigen::VectorXd silhouette(const cv::Mat& mask, const BlobFrame& f, const BuiltinFeatureConfig& c) {
  Eigen::VectorXd block = Eigen::VectorXd::Zero(c.radial_bins + 7);
  double farthest = kEpsilon;
  for (const auto& p : f.ab) farthest = std::max(farthest, std::hypot(p.x, p.y) + kEpsilon);
  for (const auto& p : f.ab)
    block[std::min(c.radial_bins - 1, static_cast<int>(std::hypot(p.x, p.y) / farthest * c.radial_bins))] += 1;
  block.head(c.radial_bins) = (block.head(c.radial_bins) / static_cast<double>(f.ab.size())).cwiseSqrt();
  double hu[7];
  cv::HuMoments(cv::moments(mask, true), hu);
  for (int i = 0; i < 7; ++i)
    block[c.radial_bins + i] = hu[i] == 0 ? 0 : -std::copysign(1.0, hu[i]) * std::log10(std::abs(hu[i])) / 10;
  normalise(block);
  return block;
}

Eigen::VectorXd colour_histogram(const cv::Mat& bgr, const cv::Mat& mask, const BuiltinFeatureConfig& c) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  Eigen::VectorXd histogram = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(c.hue_bins) * c.saturation_bins);
  double count = 0;
  for (int y = 0; y < hsv.rows; ++y)
    for (int x = 0; x < hsv.cols; ++x) {
      if (!mask.at<uchar>(y, x)) continue;
      const auto& p = hsv.at<cv::Vec3b>(y, x);
      const int h = std::min(c.hue_bins - 1, p[0] * c.hue_bins / 180);
      const int s = p[1] * c.saturation_bins / 256;
      histogram[static_cast<Eigen::Index>(h) * c.saturation_bins + s] += 1, count += 1;
    }
  return (histogram / count).cwiseSqrt();  // unit norm: the shares sum to 1
}

int positive_int(const Json& json, const std::string& key, const std::string& file) {
  return int_field(json, key, file, 1, std::numeric_limits<int>::max());
}

}  // namespace

void check(const BuiltinFeatureConfig& c) {
  const DepthShapeConfig& d = c.depth;
  if (c.cell <= 0 || c.block <= 0 || c.orientation_bins <= 0 || c.radial_bins <= 0 || c.hue_bins <= 0 ||
      c.saturation_bins <= 0 || c.size % c.cell != 0 || c.coarse_size % c.cell != 0 ||
      c.coarse_size / c.cell < c.block || c.coarse_size > c.size || !(c.head_share > 0 && c.head_share <= 1) ||
      d.head_bins <= 0 || d.radial_bins <= 0 || d.footprint_bins <= 0 || d.footprint_depth_bins <= 0 || !(d.unit > 0) ||
      !(d.across_step > 0) || !(d.head_length > 0) || !(d.hand_margin >= 0) || !(d.handle_trim > 0) ||
      !(d.grasp_reach > 0) || !(d.handle_near >= 0 && d.handle_far > d.handle_near) ||
      !(d.hand_min.array() < d.hand_max.array()).all())
    throw std::invalid_argument(
        fmt::format("builtin features: {} and {} px windows do not hold {}-cell blocks of {} px "
                    "cells, or the head share {} is not in (0, 1] (or the depth block's parameters "
                    "are not positive, its handle band or hand box empty)",
                    c.size, c.coarse_size, c.block, c.cell, c.head_share));
}

std::vector<FeatureBlock> builtin_blocks(const BuiltinFeatureConfig& c) {
  const auto hog = static_cast<Eigen::Index>(hog_dimension(c.size, c) + hog_dimension(c.coarse_size, c));
  std::vector<FeatureBlock> blocks;
  Eigen::Index at = 0;
  for (const auto& [name, size] : std::vector<std::pair<std::string, Eigen::Index>>{
           {"mask_hog", hog},
           {"head_mask_hog", hog},
           {"grey_hog", hog},
           {"head_grey_hog", hog},
           {"silhouette", c.radial_bins + 7},
           {"depth", depth_shape_dimension(c.depth)},
           {"colour", static_cast<Eigen::Index>(c.hue_bins) * c.saturation_bins}})
    blocks.push_back({name, at, size}), at += size;
  return blocks;
}

std::size_t builtin_dimension(const BuiltinFeatureConfig& c) {
  const FeatureBlock last = builtin_blocks(c).back();
  return static_cast<std::size_t>(last.start + last.size);
}

Eigen::VectorXd builtin_features(const cv::Mat& bgr, const cv::Mat& given_mask, const BuiltinFeatureConfig& c,
                                 const std::vector<Eigen::Vector3d>& points) {
  CV_Assert(bgr.type() == CV_8UC3 && !bgr.empty());
  CV_Assert(given_mask.empty() || (given_mask.type() == CV_8UC1 && given_mask.size() == bgr.size()));
  cv::Mat mask = given_mask.empty() ? estimate_blob_mask(bgr) : given_mask;
  if (cv::countNonZero(mask) == 0) mask = cv::Mat(bgr.size(), CV_8U, cv::Scalar(255));
  BlobFrame frame = blob_frame(mask);
  const auto [whole, head] = regions(frame, c.head_share);
  cv::Mat grey, grey_f, mask_f;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  grey.convertTo(grey_f, CV_32F);
  mask.convertTo(mask_f, CV_32F, 1.0 / 255);
  const cv::Mat blob_grey = grey_f.mul(mask_f);  // the background's texture is no part of the tool
  const cv::Matx23d to_whole = window_from_crop(frame, whole, c.size), to_head = window_from_crop(frame, head, c.size);
  const double whole_scale = (c.size / 2.0 - 1) / whole.half, head_scale = (c.size / 2.0 - 1) / head.half;
  const Eigen::VectorXd blocks[] = {two_scale_hog(warp(mask_f, to_whole, whole_scale, c.size), c),
                                    two_scale_hog(warp(mask_f, to_head, head_scale, c.size), c),
                                    two_scale_hog(warp(blob_grey, to_whole, whole_scale, c.size), c),
                                    two_scale_hog(warp(blob_grey, to_head, head_scale, c.size), c),
                                    silhouette(mask, frame, c),
                                    std::sqrt(5.0) * depth_shape(points, c.depth),
                                    colour_histogram(bgr, mask, c)};
  Eigen::VectorXd features(static_cast<Eigen::Index>(builtin_dimension(c)));
  Eigen::Index at = 0;
  for (const auto& block : blocks) features.segment(at, block.size()) = block, at += block.size();
  return features / std::sqrt(11.0);  // six unit blocks and depth's sqrt(5)
}

Json to_json(const BuiltinFeatureConfig& c) {
  return {{"name", "builtin"},
          {"descriptor_version", kBuiltinDescriptorVersion},
          {"window",
           {{"size", c.size},
            {"coarse_size", c.coarse_size},
            {"head_share", c.head_share},
            {"alignment", "blob principal axis, top end up, head's third moment across"}}},
          {"hog",
           {{"cell", c.cell},
            {"block", c.block},
            {"orientation_bins", c.orientation_bins},
            {"gradient", "central differences"},
            {"block_normalisation", "L2"},
            {"of", "blob mask, grey image"}}},
          {"silhouette", {{"radial_bins", c.radial_bins}, {"hu_moments", 7}}},
          {"depth",
           {{"frame", "hand"},
            {"hand_min_m", {c.depth.hand_min.x(), c.depth.hand_min.y(), c.depth.hand_min.z()}},
            {"hand_max_m", {c.depth.hand_max.x(), c.depth.hand_max.y(), c.depth.hand_max.z()}},
            {"hand_margin_m", c.depth.hand_margin},
            {"handle_near_m", c.depth.handle_near},
            {"handle_far_m", c.depth.handle_far},
            {"handle_trim_m", c.depth.handle_trim},
            {"grasp_reach_m", c.depth.grasp_reach},
            {"head_length_m", c.depth.head_length},
            {"head_bins", c.depth.head_bins},
            {"across_step_m", c.depth.across_step},
            {"radial_bins", c.depth.radial_bins},
            {"footprint_bins", c.depth.footprint_bins},
            {"footprint_depth_bins", c.depth.footprint_depth_bins},
            {"unit_m", c.depth.unit},
            {"of",
             "blob pixels with a disparity, in the hand frame, the hand's dropped; about the handle's axis; weight "
             "sqrt(5)"}}},
          {"colour",
           {{"space", "HSV"}, {"hue_bins", c.hue_bins}, {"saturation_bins", c.saturation_bins}, {"of", "blob pixels"}}},
          {"normalisation", "each block L2 (depth times sqrt(5)), all divided by sqrt(11)"},
          {"dimension", builtin_dimension(c)}};
}

BuiltinFeatureConfig builtin_config_from_json(const Json& json, const std::string& file) {
  if (!json.is_object()) throw InputError(file, "extractor: expected an object");
  const Json version = json.value("descriptor_version", Json(1));
  if (!version.is_number_integer() || version.get<long long>() != kBuiltinDescriptorVersion)
    throw InputError(file,
                     fmt::format("extractor: a builtin descriptor of version {} (this toolinc computes version {}, "
                                 "which sees shape): retrain the classifier with learn-appearance train",
                                 version.dump(), kBuiltinDescriptorVersion));
  if (!json.contains("window") || !json.contains("hog") || !json.contains("silhouette") || !json.contains("depth") ||
      !json.contains("colour"))
    throw InputError(file, "extractor: missing \"window\", \"hog\", \"silhouette\", \"depth\" or \"colour\"");
  BuiltinFeatureConfig c;
  c.size = positive_int(json["window"], "size", file);
  c.coarse_size = positive_int(json["window"], "coarse_size", file);
  const Json& share = json["window"].value("head_share", Json());
  if (!share.is_number()) throw InputError(file, "extractor: \"head_share\" must be a number");
  c.head_share = share.get<double>();
  c.cell = positive_int(json["hog"], "cell", file);
  c.block = positive_int(json["hog"], "block", file);
  c.orientation_bins = positive_int(json["hog"], "orientation_bins", file);
  c.radial_bins = positive_int(json["silhouette"], "radial_bins", file);
  const Json& depth = json["depth"];
  for (const auto& [key, value] : {std::pair<const char*, int*>{"head_bins", &c.depth.head_bins},
                                   {"radial_bins", &c.depth.radial_bins},
                                   {"footprint_bins", &c.depth.footprint_bins},
                                   {"footprint_depth_bins", &c.depth.footprint_depth_bins}})
    *value = positive_int(depth, key, file);
  for (const auto& [key, value] : {std::pair<const char*, double*>{"hand_margin_m", &c.depth.hand_margin},
                                   {"handle_near_m", &c.depth.handle_near},
                                   {"handle_far_m", &c.depth.handle_far},
                                   {"handle_trim_m", &c.depth.handle_trim},
                                   {"grasp_reach_m", &c.depth.grasp_reach},
                                   {"head_length_m", &c.depth.head_length},
                                   {"across_step_m", &c.depth.across_step},
                                   {"unit_m", &c.depth.unit}}) {
    const Json& number = depth.value(key, Json());
    if (!number.is_number()) throw InputError(file, fmt::format("extractor: depth \"{}\" must be a number", key));
    *value = number.get<double>();
  }
  for (const auto& [key, value] :
       {std::pair<const char*, Eigen::Vector3d*>{"hand_min_m", &c.depth.hand_min}, {"hand_max_m", &c.depth.hand_max}}) {
    const Json& corner = depth.value(key, Json());
    const auto number = [](const Json& v) { return v.is_number(); };
    if (!corner.is_array() || corner.size() != 3 || !std::all_of(corner.begin(), corner.end(), number))
      throw InputError(file, fmt::format("extractor: depth \"{}\" must be 3 numbers", key));
    *value = {corner[0].get<double>(), corner[1].get<double>(), corner[2].get<double>()};
  }
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
