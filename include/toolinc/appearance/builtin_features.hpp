// The builtin appearance descriptor, which needs no model file. It looks at the tool's shape first, since
// tools are often the same colour as one another:
//  - the blob (the tool and the hand holding it) is put upright: its principal axis vertical, the end
//    towards the image's top up (the camera looks at a tool held up, the hand below it), the head's side
//    with the larger third moment across to the right (so a tool and its mirror image look alike);
//  - two square windows of that frame, `size` px: the whole blob, and its head (the top end, a square
//    of head_share of the blob's length, centred across on the head's pixels);
//  - "mask_hog", "head_mask_hog": HOG of the silhouette in each window, "grey_hog", "head_grey_hog": of
//    the blob's grey image there (background set to 0: the table's texture is no part of the tool), each
//    at two scales (size and coarse_size px, `cell` px cells, `block` x `block` blocks L2-normalised,
//    `orientation_bins` unsigned orientations, square-rooted);
//  - "silhouette": the blob's rotation-invariant shape: the histogram of its pixels' distances from the
//    centroid (in units of the farthest, square-rooted shares) and its seven Hu moments (-sign log10 |h|,
//    divided by 10 to the histogram's range);
//  - "depth": the tool's head about its handle's axis in 3D, from the blob's disparity in the hand frame
//    (depth_shape.hpp), which a turn of the tool about its handle does not change; it counts as much as
//    the five image shape blocks together (scaled by sqrt(5)), and is zero for an image without disparity;
//  - "colour": a joint hue x saturation histogram of the blob's pixels in HSV, square-rooted shares.
// Each block has unit norm (depth sqrt(5)) and the whole vector is divided by sqrt(11). How much colour
// counts is left to the training data (learn-appearance weighs the block by leave-one-session-out).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "toolinc/appearance/depth_shape.hpp"
#include "toolinc/io/json_file.hpp"

namespace toolinc {

// Which descriptor a classifier file's "builtin" extractor is: files without it predate the shape
// descriptor (colour HOG and a hue histogram), earlier versions have other blocks (3: a depth block in
// the camera frame) or other crops (6 and before: the disparity blob, hand included, where 7 has the tool's
// mask); both are refused with a request to retrain.
constexpr int kBuiltinDescriptorVersion = 7;

struct BuiltinFeatureConfig {
  int size = 64;             // px side of the normalised window; a multiple of cell
  int coarse_size = 32;      // px side of the second HOG scale; a multiple of cell
  double head_share = 0.4;   // the head window's side, as a share of the blob's length
  int cell = 8;              // px
  int block = 2;             // cells per block side
  int orientation_bins = 9;  // over 0-180 deg
  int radial_bins = 16;      // silhouette distance histogram, over 0 to the farthest blob pixel
  int hue_bins = 16;         // over OpenCV's 0-180 hue
  int saturation_bins = 4;   // over 0-255
  DepthShapeConfig depth;
};

// A named part of the vector, for ablations: mask_hog, head_mask_hog, grey_hog, head_grey_hog, silhouette,
// depth, colour, in that order (colour last).
struct FeatureBlock {
  std::string name;
  Eigen::Index start = 0, size = 0;
};
std::vector<FeatureBlock> builtin_blocks(const BuiltinFeatureConfig& config);

std::size_t builtin_dimension(const BuiltinFeatureConfig& config);

// Throws std::invalid_argument when the sizes do not fit together.
void check(const BuiltinFeatureConfig& config);

// Features of an 8-bit BGR crop and the blob's mask in it (CV_8UC1, non-zero on the blob, the crop's
// size); an empty mask is estimated with estimate_blob_mask (blob_mask.hpp). points: the blob's pixels
// with a disparity, in the hand frame (m; ViewCrop::points), empty when there is no depth.
Eigen::VectorXd builtin_features(const cv::Mat& bgr, const cv::Mat& mask, const BuiltinFeatureConfig& config,
                                 const std::vector<Eigen::Vector3d>& points = {});

// Every parameter, for the classifier file; and back (throws InputError(file, ...)).
Json to_json(const BuiltinFeatureConfig& config);
BuiltinFeatureConfig builtin_config_from_json(const Json& json, const std::string& file);

}  // namespace toolinc
