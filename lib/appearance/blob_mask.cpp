#include "toolinc/appearance/blob_mask.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace toolinc {

cv::Mat estimate_blob_mask(const cv::Mat& bgr) {
  std::vector<cv::Vec3f> border;  // about 48 samples around the crop's edge
  const int step = std::max(1, (bgr.cols + bgr.rows) / 24);
  for (int x = 0; x < bgr.cols; x += step)
    border.insert(border.end(), {cv::Vec3f(bgr.at<cv::Vec3b>(0, x)), cv::Vec3f(bgr.at<cv::Vec3b>(bgr.rows - 1, x))});
  for (int y = 0; y < bgr.rows; y += step)
    border.insert(border.end(), {cv::Vec3f(bgr.at<cv::Vec3b>(y, 0)), cv::Vec3f(bgr.at<cv::Vec3b>(y, bgr.cols - 1))});
  cv::Mat distance(bgr.size(), CV_32F);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3f p(bgr.at<cv::Vec3b>(y, x));
      float nearest = std::numeric_limits<float>::max();
      for (const auto& b : border) nearest = std::min(nearest, static_cast<float>(cv::norm(p - b, cv::NORM_L2SQR)));
      distance.at<float>(y, x) = std::sqrt(nearest);
    }
  cv::Mat scaled, mask, labels, stats, centroids;
  cv::normalize(distance, scaled, 0, 255, cv::NORM_MINMAX, CV_8U);
  cv::threshold(scaled, mask, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  const int count = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  int largest = 0;
  for (int i = 1; i < count; ++i)
    if (largest == 0 || stats.at<int>(i, cv::CC_STAT_AREA) > stats.at<int>(largest, cv::CC_STAT_AREA)) largest = i;
  if (largest == 0) return cv::Mat(bgr.size(), CV_8U, cv::Scalar(255));  // nothing stands out: the whole crop
  return labels == largest;
}

}  // namespace toolinc
