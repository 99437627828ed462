// The tool's mask from the left image: on drawn images whose true silhouette is known, and against the
// simulator's true tool-and-hand mask on matched-stereo sessions.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>

#include "toolinc/session/blob.hpp"
#include "toolinc/session/tool_mask.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc {
namespace {

double iou(const cv::Mat& a, const cv::Mat& b) {
  return static_cast<double>(cv::countNonZero(a & b)) / std::max(1, cv::countNonZero(a | b));
}

// A textured grey background with a green bar (the tool, 20 x 80 px) and its silhouette.
struct Scene {
  cv::Mat image, tool;
};
Scene bar_scene(const cv::Vec3b& tool_colour = {60, 160, 60}) {
  Scene s;
  s.image.create(120, 160, CV_8UC3);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> grey(90, 150), jitter(-10, 10);
  for (int v = 0; v < s.image.rows; ++v)
    for (int u = 0; u < s.image.cols; ++u) {
      const auto g = static_cast<std::uint8_t>(grey(rng));
      s.image.at<cv::Vec3b>(v, u) = {g, g, g};
    }
  s.tool = cv::Mat::zeros(s.image.size(), CV_8UC1);
  const cv::Rect bar(70, 20, 20, 80);
  s.tool(bar).setTo(255);
  for (int v = bar.y; v < bar.y + bar.height; ++v)
    for (int u = bar.x; u < bar.x + bar.width; ++u)
      for (int c = 0; c < 3; ++c)
        s.image.at<cv::Vec3b>(v, u)[c] = cv::saturate_cast<std::uint8_t>(tool_colour[c] + jitter(rng));
  return s;
}

cv::Mat dilated(const cv::Mat& mask, int px) {
  cv::Mat out;
  cv::dilate(mask, out, cv::getStructuringElement(cv::MORPH_RECT, {2 * px + 1, 2 * px + 1}));
  return out;
}

cv::Mat eroded(const cv::Mat& mask, int px) {
  cv::Mat out;
  cv::erode(mask, out, cv::getStructuringElement(cv::MORPH_RECT, {2 * px + 1, 2 * px + 1}));
  return out;
}

TEST(ToolMask, TrimsTheFatteningToTheToolsEdge) {
  const Scene s = bar_scene();
  const cv::Mat blob = dilated(s.tool, 3);  // the blob fattened by 3 px all round
  const cv::Mat mask = tool_mask(s.image, blob);
  EXPECT_LT(iou(blob, s.tool), 0.8);
  EXPECT_GT(iou(mask, s.tool), 0.97);
  EXPECT_EQ(cv::countNonZero(mask & ~blob), 0);  // never more than the blob
}

TEST(ToolMask, NeverTrimsDeeperThanTheBand) {
  // A tool the background's colour: the image cannot tell them apart, and the mask keeps the blob but
  // for its border band, however wrong the colours' verdict.
  const Scene s = bar_scene({120, 120, 120});
  const cv::Mat blob = dilated(s.tool, 3);
  const ToolMaskConfig config;
  const cv::Mat mask = tool_mask(s.image, blob, config);
  const cv::Mat core = eroded(blob, config.band_px + 1);
  EXPECT_EQ(cv::countNonZero(core & ~mask), 0);
}

TEST(ToolMask, EmptyBlobAndBadInput) {
  const Scene s = bar_scene();
  EXPECT_EQ(cv::countNonZero(tool_mask(s.image, cv::Mat::zeros(s.image.size(), CV_8UC1))), 0);
  // A blob covering the whole image leaves no background to learn: the blob is kept.
  const cv::Mat all(s.image.size(), CV_8UC1, cv::Scalar(255));
  EXPECT_EQ(cv::countNonZero(tool_mask(s.image, all)), all.total());
  EXPECT_THROW(tool_mask(s.image, cv::Mat::zeros(10, 10, CV_8UC1)), std::invalid_argument);
  cv::Mat grey;
  cv::cvtColor(s.image, grey, cv::COLOR_BGR2GRAY);
  EXPECT_THROW(tool_mask(grey, s.tool), std::invalid_argument);
}

// On the default (LIBELAS-like) stereo: the closest blob of the disparity against the simulator's true
// hand-and-tool mask, before and after the image trims it; views where the blob is a small part of the
// tool (the matcher broke it at a depth edge) are counted but cannot be mended by trimming.
// A view's mask must not depend on what drew from OpenCV's per-thread generator before it (GrabCut's
// k-means does): otherwise crop-cloud --view 3 and --all, or a batch's threads, disagree.
TEST(ToolMask, TheSameWhateverRanBeforeOnTheThread) {
  SessionSimulatorConfig config = family_session(ToolFamily::hook, 1);
  config.write_points = false;
  const SimulatedSession session = simulate_session(config);
  for (const auto& view : session.views) {
    if (cv::countNonZero(view.blob) == 0) continue;
    cv::theRNG() = cv::RNG(1);
    const cv::Mat first = tool_mask(view.left, view.blob);
    cv::theRNG() = cv::RNG(2);
    const std::uint64_t before = cv::theRNG().state;
    const cv::Mat second = tool_mask(view.left, view.blob);
    EXPECT_EQ(cv::countNonZero(first != second), 0);
    EXPECT_EQ(cv::theRNG().state, before) << "the caller's generator is left as it was";
  }
}

TEST(ToolMaskAccuracy, CloserToTheTruthThanTheBlobOnMatchedStereo) {
  std::vector<double> blob_iou, mask_iou;
  for (const auto family : all_families())
    for (std::uint32_t seed = 1; seed <= 2; ++seed) {
      SessionSimulatorConfig config = family_session(family, seed);
      config.renderer_blob = true;
      config.write_points = false;
      const SimulatedSession session = simulate_session(config);
      for (const auto& view : session.views) {
        const cv::Mat blob = closest_blob_mask(view.disparity);
        if (cv::countNonZero(blob) == 0) continue;
        blob_iou.push_back(iou(blob, view.blob));
        mask_iou.push_back(iou(tool_mask(view.left, blob), view.blob));
      }
    }
  const auto quantile = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
  };
  std::cout << blob_iou.size() << " views: IoU with the true mask, median " << quantile(blob_iou, 0.5) << " -> "
            << quantile(mask_iou, 0.5) << ", 10th percentile " << quantile(blob_iou, 0.1) << " -> "
            << quantile(mask_iou, 0.1) << '\n';
  ASSERT_GE(blob_iou.size(), 60u);
  EXPECT_GT(quantile(mask_iou, 0.5), quantile(blob_iou, 0.5) + 0.05);
  EXPECT_GE(quantile(mask_iou, 0.1), quantile(blob_iou, 0.1));
  for (std::size_t i = 0; i < blob_iou.size(); ++i) EXPECT_GE(mask_iou[i], blob_iou[i] - 0.02) << "view " << i;
}

}  // namespace
}  // namespace toolinc
