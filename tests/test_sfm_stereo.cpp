// The stereo module's SGBM as the simulator runs it: the disparity of a known shift, its 8-bit
// publication, and the bilateral grid filter's edge-preserving smoothing.
#include "toolinc/synth/sfm_stereo.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "toolinc/core/random.hpp"

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
