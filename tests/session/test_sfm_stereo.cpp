// The stereo module's matchers as the simulator runs them, SGBM and ELAS: the disparity of a known
// shift, its 8-bit publication, ELAS's filling of a textureless band and its post-processing, and the
// bilateral grid filter's edge-preserving smoothing.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "toolinc/core/random.hpp"
#include "toolinc/synth/disparity_filters.hpp"
#include "toolinc/synth/elas_stereo.hpp"
#include "toolinc/synth/sfm_stereo.hpp"

namespace toolinc {
namespace {

// A random texture smoothed to features of a few pixels, 3 channels.
cv::Mat texture(int width, int height, std::uint32_t seed) {
  Rng rng(seed);
  cv::Mat grey(height, width, CV_8UC1);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) grey.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(rng.uniform(0, 255));
  cv::GaussianBlur(grey, grey, cv::Size(5, 5), 1.0);
  cv::Mat colour;
  cv::cvtColor(grey, colour, cv::COLOR_GRAY2BGR);
  return colour;
}

TEST(SfmStereo, RecoversAKnownShiftAndPublishesItIn8Bits) {
  // The right image is the left one shifted 20 px to the left: a fronto-parallel textured plane.
  const int shift = 20;
  const cv::Mat wide = texture(320 + shift, 240, 3);
  const cv::Mat left = wide(cv::Rect(0, 0, 320, 240)).clone(), right = wide(cv::Rect(shift, 0, 320, 240)).clone();
  const SfmStereoConfig config;
  const cv::Mat d16 = sfm_disparity16(left, right, config);
  ASSERT_EQ(d16.type(), CV_16SC1);
  int valid = 0, exact = 0;
  // Columns left of num_disparities have no full search range: SGBM leaves them invalid.
  for (int v = 10; v < 230; ++v)
    for (int u = config.num_disparities + 10; u < 310; ++u) {
      const int value = d16.at<std::int16_t>(v, u);
      valid += value > 0;
      exact += std::abs(value - 16 * shift) <= 4;  // a quarter pixel
    }
  const int pixels = 220 * (300 - config.num_disparities - 10);
  EXPECT_GT(valid, 0.95 * pixels);
  EXPECT_GT(exact, 0.95 * pixels);
  EXPECT_LT(d16.at<std::int16_t>(120, 5), 0);  // no search range at the left border: invalid

  SfmStereoConfig raw = config;
  raw.bilateral = false;
  const cv::Mat d8 = sfm_disparity8(d16, raw);
  EXPECT_EQ(d8.at<std::uint8_t>(120, 200), static_cast<int>(std::lround(shift * 255.0 / config.num_disparities)));
  EXPECT_EQ(d8.at<std::uint8_t>(120, 5), 0);
}

// A fronto-parallel textured plane `shift` px away, with a band of uniform grey `band` px wide across it.
std::pair<cv::Mat, cv::Mat> shifted_pair(int shift, int band) {
  cv::Mat wide = texture(320 + shift, 240, 3);
  if (band > 0) wide(cv::Rect(200, 0, band, 240)).setTo(cv::Scalar(128, 128, 128));
  return {wide(cv::Rect(0, 0, 320, 240)).clone(), wide(cv::Rect(shift, 0, 320, 240)).clone()};
}

TEST(ElasStereo, RecoversAKnownShift) {
  const int shift = 20;
  const auto [left, right] = shifted_pair(shift, 0);
  const cv::Mat d = elas_disparity(left, right);
  ASSERT_EQ(d.type(), CV_32FC1);
  int valid = 0, exact = 0;
  for (int v = 20; v < 220; ++v)
    for (int u = 40; u < 300; ++u) {
      valid += d.at<float>(v, u) >= 0;
      exact += std::abs(d.at<float>(v, u) - shift) <= 0.5f;
    }
  EXPECT_GT(valid, 0.95 * 200 * 260);
  EXPECT_GT(exact, 0.95 * 200 * 260);
  EXPECT_LT(d.at<float>(120, 2), 0);  // outside the support points' hull: no disparity
  const cv::Mat d16 = elas_disparity16(left, right);
  ASSERT_EQ(d16.type(), CV_16SC1);
  EXPECT_EQ(d16.at<std::int16_t>(120, 150), 16 * shift);
}

TEST(ElasStereo, FillsANarrowTexturelessBandAndNotAWideOne) {
  // Unlike SGBM, which leaves a uniform face empty, ELAS interpolates gaps up to ipol_gap_width (40 px).
  const auto [left, right] = shifted_pair(20, 30);
  const cv::Mat narrow = elas_disparity(left, right);
  for (const int u : {205, 215, 225}) EXPECT_NEAR(narrow.at<float>(120, u), 20.0f, 1.0f) << u;
  const auto [wide_left, wide_right] = shifted_pair(20, 80);
  EXPECT_LT(elas_disparity(wide_left, wide_right).at<float>(120, 240), 0);
}

TEST(DisparityFilters, SpecklesGapsAndAdaptiveMean) {
  cv::Mat d(40, 60, CV_32FC1, cv::Scalar(10.0f));
  d(cv::Rect(20, 10, 3, 3)).setTo(30.0f);  // a 9-pixel island, 20 px off its surroundings
  remove_speckles(d, 20, 1.0);
  EXPECT_LT(d.at<float>(11, 21), 0);
  EXPECT_EQ(d.at<float>(30, 30), 10.0f);  // the large segment stays

  cv::Mat gaps(1, 20, CV_32FC1, cv::Scalar(-10.0f));
  gaps(cv::Rect(0, 0, 3, 1)).setTo(8.0f);  // 8 | gap of 4 | 9: one surface, the mean
  gaps(cv::Rect(7, 0, 3, 1)).setTo(9.0f);  // 9 | gap of 3 | 2: an edge, the background's
  gaps(cv::Rect(13, 0, 7, 1)).setTo(2.0f);
  interpolate_gaps(gaps, 40);
  EXPECT_FLOAT_EQ(gaps.at<float>(0, 4), 8.5f);
  EXPECT_FLOAT_EQ(gaps.at<float>(0, 11), 2.0f);

  cv::Mat step(20, 40, CV_32FC1, cv::Scalar(5.0f));
  step(cv::Rect(20, 0, 20, 20)).setTo(40.0f);
  step.at<float>(10, 10) = 6.0f;
  step.at<float>(10, 30) = -10.0f;
  adaptive_mean(step);
  EXPECT_NEAR(step.at<float>(10, 10), 5.0f, 0.3f);  // noise averaged ...
  EXPECT_FLOAT_EQ(step.at<float>(10, 19), 5.0f);    // ... but not across the edge
  EXPECT_LT(step.at<float>(10, 30), 0);             // invalid stays invalid
}

TEST(SfmStereo, BilateralGridSmoothsNoiseAndKeepsEdges) {
  // Two flat regions 100 levels apart with noise of 3 levels: the filter keeps the step and shrinks the noise.
  Rng rng(5);
  cv::Mat image(120, 160, CV_8UC1);
  for (int v = 0; v < image.rows; ++v)
    for (int u = 0; u < image.cols; ++u)
      image.at<std::uint8_t>(v, u) = cv::saturate_cast<std::uint8_t>((u < 80 ? 60 : 160) + 3 * rng.gaussian());
  const cv::Mat out = bilateral_grid(image, 10, 10);
  double noise_in = 0, noise_out = 0;
  int n = 0;
  for (int v = 20; v < 100; ++v)
    for (int u = 0; u < image.cols; ++u) {
      const double truth = u < 80 ? 60 : 160;
      EXPECT_NEAR(out.at<std::uint8_t>(v, u), truth, 5) << u << "," << v;  // no blur across the step
      noise_in += std::pow(image.at<std::uint8_t>(v, u) - truth, 2);
      noise_out += std::pow(out.at<std::uint8_t>(v, u) - truth, 2);
      ++n;
    }
  EXPECT_LT(std::sqrt(noise_out / n), 0.5 * std::sqrt(noise_in / n));
  // A constant image stays constant.
  const cv::Mat flat(50, 60, CV_8UC1, cv::Scalar(77));
  EXPECT_EQ(cv::norm(bilateral_grid(flat, 10, 10), flat, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace toolinc
