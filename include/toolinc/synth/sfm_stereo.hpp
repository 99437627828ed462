// The iCub stereo module's disparity as robotology/stereo-vision computes it with `SFM --use_sgbm`:
// OpenCV's StereoSGBM on the rectified pair (lib/src/stereoCamera.cpp, StereoCamera::computeDisparity,
// with the values modules/SFM/SFM.cpp's configure() sets), the 16x fixed-point result scaled to 8 bits
// (value = d * 255 / numberOfDisparities) and, for the published /disp:o image, SFM's bilateral grid
// filter (modules/SFM/fastBilateral.hpp, on unless --skipBLF). The RPC's 3D points come from the
// unfiltered 16x disparity.
#pragma once

#include <opencv2/core.hpp>

namespace toolinc {

struct SfmStereoConfig {
  int num_disparities = 96;  // SFM: 96 at width <= 320, else 128
  int block_size = 7;        // SFM's SADWindowSize
  int min_disparity = 0;
  int uniqueness_ratio = 15;     // %
  int speckle_window_size = 50;  // px
  int speckle_range = 16;        // in 16x disparity units (1 px)
  int pre_filter_cap = 63;
  int disp12_max_diff = 0;               // OpenCV treats <= 0 as 1 px of left-right check
  bool full_dp = true;                   // SFM's useBestDisp: MODE_HH (8 paths) rather than MODE_SGBM (5)
  bool bilateral = true;                 // the published 8-bit disparity through the bilateral grid ...
  double bilateral_sigma_colour = 10.0;  // ... of these sigmas (disparity levels, pixels)
  double bilateral_sigma_space = 10.0;
};

// StereoSGBM on a rectified pair of 3-channel images (P1 = 8 * 3 * block^2, P2 = 32 * 3 * block^2, as
// SFM with colour images): CV_16SC1, 16 x disparity, negative where invalid.
cv::Mat sfm_disparity16(const cv::Mat& left, const cv::Mat& right, const SfmStereoConfig& config = {});

// The published 8-bit disparity: 16x disparity * 255 / (16 num_disparities), saturated (invalid -> 0),
// then the bilateral grid filter when config.bilateral.
cv::Mat sfm_disparity8(const cv::Mat& disparity16, const SfmStereoConfig& config = {});

// A bilateral filter by a downsampled (space / sigma_space, value / sigma_colour) grid, blurred by
// [1 2 1] / 4 twice along each axis and read back by trilinear interpolation (Paris and Durand's
// approximation, as SFM's cv_extend::bilateralFilter): CV_8UC1 in and out.
cv::Mat bilateral_grid(const cv::Mat& image, double sigma_colour, double sigma_space);

}  // namespace toolinc
