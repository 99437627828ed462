// The tool's mask from the left image: on drawn images whose true silhouette is known, and against the
// simulator's true tool-and-hand mask on matched-stereo sessions.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>

#include "toolinc/session/blob.hpp"
#include "toolinc/session/crop.hpp"
#include "toolinc/session/tool_mask.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc {
namespace {

double iou(const cv::Mat& a, const cv::Mat& b) {
  return static_cast<double>(cv::countNonZero(a & b)) / std::max(1, cv::countNonZero(a | b));
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

// The median and 10th percentile of two masks' IoU with the truth, over the same views.
void print_iou(const char* what, const std::vector<double>& before, const std::vector<double>& after) {
  std::cout << before.size() << " views: IoU with " << what << ": median " << quantile(before, 0.5) << " -> "
            << quantile(after, 0.5) << ", 10th percentile " << quantile(before, 0.1) << " -> " << quantile(after, 0.1)
            << '\n';
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

// Growing, the image adds what the seed missed (a face with no disparity) up to the surround, and never a
// pixel held as background.
TEST(ToolMask, GrowsOverWhatTheSeedMissedButNotTheBackground) {
  const Scene s = bar_scene();
  cv::Mat seed = s.tool.clone();
  seed(cv::Rect(70, 20, 20, 15)).setTo(0);  // the bar's top 15 px unmatched
  ToolMaskConfig config;
  config.grow = true;
  EXPECT_GT(iou(tool_mask(s.image, seed, config), s.tool), 0.97);
  EXPECT_EQ(cv::countNonZero(tool_mask(s.image, seed) & ~seed), 0);  // without grow: never beyond the seed
  cv::Mat held = cv::Mat::zeros(s.image.size(), CV_8UC1);
  held(cv::Rect(60, 20, 40, 8)).setTo(255);
  const cv::Mat grown = tool_mask(s.image, seed, config, held);
  EXPECT_EQ(cv::countNonZero(grown & held), 0);
  EXPECT_GT(cv::countNonZero(grown & ~seed & ~held), 100);
  EXPECT_THROW(tool_mask(s.image, seed, config, cv::Mat::zeros(10, 10, CV_8UC1)), std::invalid_argument);
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

// Each view of two sessions of every family on the default stereo, with its session.
template <class Visit>
void for_each_view(bool renderer_blob, Visit&& visit) {
  for (const auto family : all_families())
    for (std::uint32_t seed = 1; seed <= 2; ++seed) {
      SessionSimulatorConfig config = family_session(family, seed);
      config.renderer_blob = renderer_blob;
      config.write_points = false;
      const SimulatedSession session = simulate_session(config);
      for (std::size_t v = 0; v < session.views.size(); ++v) visit(session, v);
    }
}

TEST(ToolMaskAccuracy, CloserToTheTruthThanTheBlobOnMatchedStereo) {
  std::vector<double> blob_iou, mask_iou;
  for_each_view(true, [&](const SimulatedSession& session, std::size_t v) {
    const ViewData& view = session.views[v];
    const cv::Mat blob = closest_blob_mask(view.disparity);
    if (cv::countNonZero(blob) == 0) return;
    blob_iou.push_back(iou(blob, view.blob));
    mask_iou.push_back(iou(tool_mask(view.left, blob), view.blob));
  });
  print_iou("the true hand-and-tool mask, blob -> trimmed blob", blob_iou, mask_iou);
  ASSERT_GE(blob_iou.size(), 60u);
  EXPECT_GT(quantile(mask_iou, 0.5), quantile(blob_iou, 0.5) + 0.05);
  EXPECT_GE(quantile(mask_iou, 0.1), quantile(blob_iou, 0.1));
  for (std::size_t i = 0; i < blob_iou.size(); ++i) EXPECT_GE(mask_iou[i], blob_iou[i] - 0.02) << "view " << i;
}

// The tool's silhouette for recognition (view_tool_mask) on the default (LIBELAS-like) stereo, against the
// renderer's own tool pixels (the hand's not): the disparity's blob holds the hand and, where the blob
// detector finds nothing, is empty (IoU 0); the mask follows the tool out of the hand and the image trims it.
TEST(ToolMaskAccuracy, ViewToolMaskCloserToTheToolThanTheBlob) {
  std::vector<double> blob_iou, mask_iou;
  for_each_view(false, [&](const SimulatedSession& session, std::size_t v) {
    const ViewData& view = session.views[v];
    const cv::Mat& truth = session.true_tool_masks[v];
    blob_iou.push_back(view.blob.empty() ? 0.0 : iou(view.blob, truth));
    mask_iou.push_back(iou(view_tool_mask(session.info, session.info.views[v], view).mask, truth));
  });
  print_iou("the tool's true mask, blob -> tool mask", blob_iou, mask_iou);
  ASSERT_EQ(blob_iou.size(), all_families().size() * 2 * 5);
  EXPECT_GT(quantile(mask_iou, 0.5), quantile(blob_iou, 0.5) + 0.1);
  EXPECT_GT(quantile(mask_iou, 0.1), quantile(blob_iou, 0.1));
}

}  // namespace
}  // namespace toolinc
