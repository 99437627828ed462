#include "toolinc/synth/sfm_stereo.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <vector>

namespace toolinc {

cv::Mat sfm_disparity16(const cv::Mat& left, const cv::Mat& right, const SfmStereoConfig& config) {
  const int channels = left.channels(), area = config.block_size * config.block_size;
  const auto sgbm = cv::StereoSGBM::create(
      config.min_disparity, config.num_disparities, config.block_size, 8 * channels * area, 32 * channels * area,
      config.disp12_max_diff, config.pre_filter_cap, config.uniqueness_ratio, config.speckle_window_size,
      config.speckle_range, config.full_dp ? cv::StereoSGBM::MODE_HH : cv::StereoSGBM::MODE_SGBM);
  cv::Mat disparity;
  sgbm->compute(left, right, disparity);
  return disparity;
}

cv::Mat sfm_disparity8(const cv::Mat& disparity16, const SfmStereoConfig& config) {
  cv::Mat scaled;
  disparity16.convertTo(scaled, CV_8U, 255.0 / (16.0 * config.num_disparities));
  return config.bilateral ? bilateral_grid(scaled, config.bilateral_sigma_colour, config.bilateral_sigma_space)
                          : scaled;
}

cv::Mat bilateral_grid(const cv::Mat& image, double sigma_colour, double sigma_space) {
  CV_Assert(image.type() == CV_8UC1);
  constexpr int kPad = 2;  // cells around the data, so the blur never reads outside the grid
  double lo = 0, hi = 0;
  cv::minMaxLoc(image, &lo, &hi);
  const int ny = static_cast<int>((image.rows - 1) / sigma_space) + 1 + 2 * kPad;
  const int nx = static_cast<int>((image.cols - 1) / sigma_space) + 1 + 2 * kPad;
  const int nz = static_cast<int>((hi - lo) / sigma_colour) + 1 + 2 * kPad;
  const auto cell = [&](int y, int x, int z) { return (static_cast<std::size_t>(y) * nx + x) * nz + z; };
  // Per cell: the sum of the values and their count.
  std::vector<cv::Vec2d> grid(static_cast<std::size_t>(ny) * nx * nz, cv::Vec2d(0, 0)), blurred(grid.size());
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const double value = image.at<std::uint8_t>(y, x);
      grid[cell(static_cast<int>(y / sigma_space + 0.5) + kPad, static_cast<int>(x / sigma_space + 0.5) + kPad,
                static_cast<int>((value - lo) / sigma_colour + 0.5) + kPad)] += cv::Vec2d(value, 1.0);
    }
  const std::size_t strides[3] = {static_cast<std::size_t>(nx) * nz, static_cast<std::size_t>(nz), 1};
  for (const std::size_t stride : strides)
    for (int pass = 0; pass < 2; ++pass) {
      blurred = grid;
      for (int y = 1; y < ny - 1; ++y)
        for (int x = 1; x < nx - 1; ++x)
          for (int z = 1; z < nz - 1; ++z) {
            const std::size_t i = cell(y, x, z);
            grid[i] = (blurred[i - stride] + 2.0 * blurred[i] + blurred[i + stride]) * 0.25;
          }
    }
  std::vector<double> mean(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) mean[i] = grid[i][1] != 0 ? grid[i][0] / grid[i][1] : grid[i][0];
  cv::Mat out(image.size(), CV_8UC1);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const double gy = y / sigma_space + kPad, gx = x / sigma_space + kPad,
                   gz = (image.at<std::uint8_t>(y, x) - lo) / sigma_colour + kPad;
      const int y0 = static_cast<int>(gy), x0 = static_cast<int>(gx), z0 = static_cast<int>(gz);
      const double fy = gy - y0, fx = gx - x0, fz = gz - z0;
      double value = 0;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int c = 0; c < 2; ++c)
            value += (a ? fy : 1 - fy) * (b ? fx : 1 - fx) * (c ? fz : 1 - fz) *
                     mean[cell(std::min(y0 + a, ny - 1), std::min(x0 + b, nx - 1), std::min(z0 + c, nz - 1))];
      out.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(value);
    }
  return out;
}

}  // namespace toolinc
