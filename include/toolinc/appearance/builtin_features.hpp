// The builtin appearance descriptor, which needs no model file: the crop resized to a fixed size, then
//  - HOG (Dalal & Triggs): per pixel the gradient of the colour channel where it is strongest (central
//    differences), its unsigned orientation voted into `orientation_bins` bins per `cell` x `cell` cell
//    with linear interpolation between neighbouring bins, and blocks of `block` x `block` cells (stride
//    one cell) each L2-normalised: the tool's outline and parts;
//  - a joint hue x saturation histogram in HSV, square-rooted (Hellinger) so that it is L2-normalised:
//    the tool's colour, which the outline alone cannot give at table-top resolutions.
// Each part is L2-normalised and both are scaled by 1/sqrt(2), so the whole vector has unit norm.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <opencv2/core.hpp>

#include "toolinc/io/json_file.hpp"

namespace toolinc {

struct BuiltinFeatureConfig {
  int width = 64, height = 64;  // px the crop is resized to; multiples of cell
  int cell = 8;                 // px
  int block = 2;                // cells per block side
  int orientation_bins = 9;     // over 0-180 deg
  int hue_bins = 16;            // over OpenCV's 0-180 hue
  int saturation_bins = 4;      // over 0-255
};

std::size_t builtin_dimension(const BuiltinFeatureConfig& config);

// Throws std::invalid_argument when the sizes do not fit together.
void check(const BuiltinFeatureConfig& config);

// Features of an 8-bit BGR crop.
Eigen::VectorXd builtin_features(const cv::Mat& bgr, const BuiltinFeatureConfig& config);

// Every parameter, for the classifier file; and back (throws InputError(file, ...)).
Json to_json(const BuiltinFeatureConfig& config);
BuiltinFeatureConfig builtin_config_from_json(const Json& json, const std::string& file);

}  // namespace toolinc
