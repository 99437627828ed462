#include "toolinc/session/blob.hpp"

#include <opencv2/imgproc.hpp>

namespace toolinc {

cv::Mat closest_blob_mask(const cv::Mat& disparity, const BlobDetectorConfig& config) {
  // dispBlobber's recipe: blur, drop the background, close small holes, blur, shrink back.
  cv::Mat smooth;
  cv::GaussianBlur(disparity, smooth, cv::Size(config.gauss_size, config.gauss_size), 1.5);
  cv::threshold(smooth, smooth, config.background_threshold, 255, cv::THRESH_TOZERO);
  cv::dilate(smooth, smooth, cv::Mat(), cv::Point(-1, -1), 4);
  cv::GaussianBlur(smooth, smooth, cv::Size(config.gauss_size, config.gauss_size), 2.0);
  cv::erode(smooth, smooth, cv::Mat(), cv::Point(-1, -1), 2);

  // Flood from the brightest (closest) pixel; blank out blobs that are too small and try the next. Block
  // matching leaves dozens of small wrong-match speckles brighter than the tool (SGBM on a plain tool:
  // 60 in one view), each blanked in turn.
  cv::Mat work = smooth.clone();
  for (int attempt = 0; attempt < 1000; ++attempt) {
    double max_value = 0;
    cv::Point brightest;
    cv::minMaxLoc(work, nullptr, &max_value, nullptr, &brightest);
    if (max_value <= 0) break;
    cv::Mat fill = cv::Mat::zeros(work.rows + 2, work.cols + 2, CV_8UC1);
    // dispBlobber floods a fixed range around the closest value, which keeps only the nearest part of
    // a tool leaning away from the camera; a floating range follows the tool's continuous disparity.
    const int flags = 8 | cv::FLOODFILL_MASK_ONLY | (255 << 8) | (config.floating ? 0 : cv::FLOODFILL_FIXED_RANGE);
    const double low = config.floating ? config.floating_step : max_value / config.low_ratio;
    const double high = config.floating ? config.floating_step : max_value / config.high_ratio;
    const int area = cv::floodFill(work, fill, brightest, 0, nullptr, cv::Scalar(low), cv::Scalar(high), flags);
    cv::Mat blob = fill(cv::Rect(1, 1, work.cols, work.rows)).clone();
    if (area < config.min_blob_size) {
      work.setTo(0, blob);
      continue;
    }
    // The largest external contour of the blob, filled, is the mask (holes closed as the robot's is).
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(blob, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    std::size_t best = 0;
    for (std::size_t i = 1; i < contours.size(); ++i)
      if (cv::contourArea(contours[i]) > cv::contourArea(contours[best])) best = i;
    const double contour_area = contours.empty() ? 0.0 : cv::contourArea(contours[best]);
    if (contour_area < config.min_blob_size || contour_area > config.max_blob_size) {
      work.setTo(0, blob);
      continue;
    }
    cv::Mat mask = cv::Mat::zeros(disparity.size(), CV_8UC1);
    cv::drawContours(mask, contours, static_cast<int>(best), cv::Scalar(255), cv::FILLED);
    return mask;
  }
  return cv::Mat::zeros(disparity.size(), CV_8UC1);
}

}  // namespace toolinc
