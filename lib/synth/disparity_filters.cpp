#include "toolinc/synth/disparity_filters.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace toolinc {
namespace {

constexpr float kDiscontinuity = 3.0f;  // px: neighbours farther apart lie on different surfaces
constexpr int kMeanRadius = 4;          // the adaptive mean's window: offsets -4..+3
constexpr float kMeanRange = 4.0f;      // px of difference at which a neighbour's weight reaches 0

// Fills the runs of invalid values along one line of `n` values `step` apart.
void fill_line(float* line, int n, std::ptrdiff_t step, int max_gap) {
  int count = 0;
  for (int i = 0; i < n; ++i) {
    if (line[i * step] < 0) {
      ++count;
      continue;
    }
    const int first = i - count, last = i - 1;
    if (count >= 1 && count <= max_gap && first > 0 && last < n - 1) {
      const float d1 = line[(first - 1) * step], d2 = line[(last + 1) * step];
      const float fill = std::abs(d1 - d2) < kDiscontinuity ? (d1 + d2) / 2 : std::min(d1, d2);
      for (int j = first; j <= last; ++j) line[j * step] = fill;
    }
    count = 0;
  }
}

// One pass of the adaptive mean along lines of `n` values `step` apart, from `in` to `out`.
void mean_line(const float* in, float* out, int n, std::ptrdiff_t step) {
  for (int i = kMeanRadius; i + kMeanRadius - 1 < n; ++i) {
    const float centre = in[i * step];
    if (centre < 0) continue;
    float weights = 0, sum = 0;
    for (int k = -kMeanRadius; k < kMeanRadius; ++k) {
      const float value = in[(i + k) * step];
      const float w = std::max(0.0f, kMeanRange - std::abs(value - centre));
      weights += w, sum += w * value;
    }
    out[i * step] = sum / weights;  // the centre's own weight is kMeanRange
  }
}

}  // namespace

void remove_speckles(cv::Mat& disparity, int min_size, double similarity) {
  CV_Assert(disparity.type() == CV_32FC1 && disparity.isContinuous());
  const int width = disparity.cols, height = disparity.rows;
  auto* d = disparity.ptr<float>();
  std::vector<char> done(static_cast<std::size_t>(width) * height, 0);
  std::vector<int> segment;
  for (int start = 0; start < width * height; ++start) {
    if (done[start] || d[start] < 0) continue;
    segment.assign(1, start);
    done[start] = 1;
    for (std::size_t k = 0; k < segment.size(); ++k) {
      const int i = segment[k], u = i % width, v = i / width;
      const int neighbours[4] = {u > 0 ? i - 1 : -1, u + 1 < width ? i + 1 : -1, v > 0 ? i - width : -1,
                                 v + 1 < height ? i + width : -1};
      for (const int n : neighbours)
        if (n >= 0 && !done[n] && d[n] >= 0 && std::abs(d[i] - d[n]) <= similarity) {
          done[n] = 1;
          segment.push_back(n);
        }
    }
    if (static_cast<int>(segment.size()) < min_size)
      for (const int i : segment) d[i] = kNoDisparity;
  }
}

void interpolate_gaps(cv::Mat& disparity, int max_gap) {
  CV_Assert(disparity.type() == CV_32FC1 && disparity.isContinuous());
  auto* d = disparity.ptr<float>();
  const int width = disparity.cols, height = disparity.rows;
  for (int v = 0; v < height; ++v) fill_line(d + static_cast<std::ptrdiff_t>(v) * width, width, 1, max_gap);
  for (int u = 0; u < width; ++u) fill_line(d + u, height, width, max_gap);
}

void adaptive_mean(cv::Mat& disparity) {
  CV_Assert(disparity.type() == CV_32FC1 && disparity.isContinuous());
  const int width = disparity.cols, height = disparity.rows;
  cv::Mat input = disparity.clone();
  input.setTo(kNoDisparity, input < 0);  // invalid values far below every valid one weigh nothing
  cv::Mat rows = input.clone();
  for (int v = 0; v < height; ++v) mean_line(input.ptr<float>(v), rows.ptr<float>(v), width, 1);
  cv::Mat columns = rows.clone();
  for (int u = 0; u < width; ++u) mean_line(rows.ptr<float>() + u, columns.ptr<float>() + u, height, width);
  disparity = columns;
}

}  // namespace toolinc
