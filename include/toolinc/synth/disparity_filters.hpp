// The post-processing ELAS runs on a float disparity map (CV_32FC1, negative = no disparity), in its
// order: speckle removal, gap interpolation, adaptive mean.
#pragma once

#include <opencv2/core.hpp>

namespace toolinc {

// The value ELAS gives a pixel without disparity.
constexpr float kNoDisparity = -10.0f;

// Removes (sets to kNoDisparity) every 4-connected segment of fewer than `min_size` pixels whose neighbours
// differ by at most `similarity` px: isolated mismatches rather than surfaces.
void remove_speckles(cv::Mat& disparity, int min_size, double similarity);

// Fills runs of at most `max_gap` invalid pixels along each row, then each column, that have valid
// pixels on both sides away from the border: with their mean when the two differ by less than 3 px
// (one surface), else with the smaller (the background, at a depth edge).
void interpolate_gaps(cv::Mat& disparity, int max_gap);

// ELAS's approximate bilateral filter: each valid pixel becomes the mean of the 8 pixels around it
// (offsets -4..+3) along its row, then its column, weighted by max(0, 4 - |difference|) in px.
// Invalid pixels stay invalid.
void adaptive_mean(cv::Mat& disparity);

}  // namespace toolinc
