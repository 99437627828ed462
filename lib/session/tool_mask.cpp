#include "toolinc/session/tool_mask.hpp"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace toolinc {

cv::Mat tool_mask(const cv::Mat& left_bgr, const cv::Mat& blob, const ToolMaskConfig& config,
                  const cv::Mat& background) {
  if (left_bgr.type() != CV_8UC3 || blob.type() != CV_8UC1 || left_bgr.size() != blob.size())
    throw std::invalid_argument("tool_mask: needs a BGR image and a one-channel seed of the same size");
  if (!background.empty() && (background.type() != CV_8UC1 || background.size() != blob.size()))
    throw std::invalid_argument("tool_mask: the background must be one-channel, the image's size");
  cv::Mat mask = cv::Mat::zeros(blob.size(), CV_8UC1);
  const cv::Rect box = cv::boundingRect(blob);
  if (box.area() == 0) return mask;
  // GrabCut on the blob's box grown by the surround only: the far background says nothing about the edge.
  const int grow = config.surround_px + 1;
  const cv::Rect roi = (box + cv::Point(-grow, -grow) + cv::Size(2 * grow, 2 * grow)) & cv::Rect({}, blob.size());
  const cv::Mat on = blob(roi) != 0;
  if (cv::countNonZero(on) == roi.area()) return blob != 0;  // no background in sight to learn
  // Distance of each blob pixel to the nearest pixel off the blob, and of each other pixel to the blob.
  cv::Mat inside, outside;
  cv::distanceTransform(on, inside, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::distanceTransform(~on, outside, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::Mat labels(roi.size(), CV_8UC1);
  for (int v = 0; v < roi.height; ++v)
    for (int u = 0; u < roi.width; ++u) {
      const bool in_blob = on.at<std::uint8_t>(v, u) != 0;
      const bool known_background = !background.empty() && background.at<std::uint8_t>(v + roi.y, u + roi.x) != 0;
      labels.at<std::uint8_t>(v, u) = in_blob ? (inside.at<float>(v, u) > config.band_px ? cv::GC_FGD : cv::GC_PR_FGD)
                                      : known_background || outside.at<float>(v, u) > config.surround_px
                                          ? cv::GC_BGD
                                          : cv::GC_PR_BGD;
    }
  cv::Mat background_model, foreground_model;
  // GrabCut seeds its colour models by k-means from OpenCV's per-thread generator: a fixed seed makes a
  // view's mask independent of whatever drew from that generator before (other views, other threads'
  // share of a batch). The caller's generator is left as it was.
  cv::RNG& generator = cv::theRNG();
  const cv::RNG callers = generator;
  generator = cv::RNG(0x746f6f6c);
  cv::grabCut(left_bgr(roi), labels, cv::Rect(), background_model, foreground_model, config.iterations,
              cv::GC_INIT_WITH_MASK);
  generator = callers;
  cv::Mat tool = (labels == cv::GC_FGD) | (labels == cv::GC_PR_FGD);
  if (!config.grow) tool &= on;
  tool.copyTo(mask(roi));
  return mask;
}

}  // namespace toolinc
