#include "toolinc/synth/elas_stereo.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

#include "toolinc/synth/disparity_filters.hpp"

namespace toolinc {
namespace {

constexpr int kDescriptorBytes = 16;
constexpr int kSupportStep = 2;       // the support cost reads the descriptors at (u +/- 2, v +/- 2)
constexpr int kSupportBorder = 5;     // px a support candidate keeps from the image's border
constexpr int kMinSupportRange = 10;  // disparities a support candidate must be able to try
constexpr int kDenseBorder = 2;       // px the dense match keeps from the border
constexpr double kMaxSlant = 0.7;     // a plane steeper than this (px of disparity per px) gives no prior

// Per pixel, 16 bytes of its 5x5 neighbourhood's Sobel responses (12 horizontal, 4 vertical, the centre
// twice), each response / 4 + 128: ELAS's descriptor. Pixels within 3 px of the border have none (128s).
class Descriptors {
 public:
  explicit Descriptors(const cv::Mat& grey) : width_(grey.cols), height_(grey.rows) {
    cv::Mat du, dv;
    cv::Sobel(grey, du, CV_16S, 1, 0, 3);
    cv::Sobel(grey, dv, CV_16S, 0, 1, 3);
    const auto byte = [](const cv::Mat& m, int v, int u) {
      return static_cast<std::uint8_t>(std::clamp(m.at<std::int16_t>(v, u) >> 2, -128, 127) + 128);
    };
    data_.assign(static_cast<std::size_t>(width_) * height_ * kDescriptorBytes, 128);
    for (int v = 3; v < height_ - 3; ++v)
      for (int u = 3; u < width_ - 3; ++u) {
        std::uint8_t* d = data_.data() + (static_cast<std::size_t>(v) * width_ + u) * kDescriptorBytes;
        const std::array<std::uint8_t, kDescriptorBytes> bytes = {
            byte(du, v - 2, u),     byte(du, v - 1, u - 2), byte(du, v - 1, u),     byte(du, v - 1, u + 2),
            byte(du, v, u - 1),     byte(du, v, u),         byte(du, v, u),         byte(du, v, u + 1),
            byte(du, v + 1, u - 2), byte(du, v + 1, u),     byte(du, v + 1, u + 2), byte(du, v + 2, u),
            byte(dv, v - 1, u),     byte(dv, v, u - 1),     byte(dv, v, u + 1),     byte(dv, v + 1, u)};
        std::copy(bytes.begin(), bytes.end(), d);
      }
  }
  const std::uint8_t* at(int u, int v) const {
    return data_.data() + (static_cast<std::size_t>(v) * width_ + u) * kDescriptorBytes;
  }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_, height_;
  std::vector<std::uint8_t> data_;
};

int sad(const std::uint8_t* a, const std::uint8_t* b) {
  int sum = 0;
  for (int i = 0; i < kDescriptorBytes; ++i) sum += std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
  return sum;
}

int texture(const std::uint8_t* d) {
  int sum = 0;
  for (int i = 0; i < kDescriptorBytes; ++i) sum += std::abs(static_cast<int>(d[i]) - 128);
  return sum;
}

// The pair as seen from one of its images: `self` is matched against `other`, whose matching pixel
// lies at u + direction * d (direction -1 for the left image, +1 for the right).
struct View {
  const Descriptors& self;
  const Descriptors& other;
  int direction;
};

// A support candidate's disparity: the best of all disparities by the summed cost of the four
// descriptors around it, kept when its texture suffices and it is unique (best below
// support_threshold x second best); else -1.
int support_disparity(const View& view, int u, int v, const ElasConfig& config) {
  const int width = view.self.width(), height = view.self.height();
  if (u < kSupportBorder || u > width - 1 - kSupportBorder || v < kSupportBorder || v > height - 1 - kSupportBorder)
    return -1;
  if (texture(view.self.at(u, v)) < config.support_texture) return -1;
  const int reach = view.direction < 0 ? u - kSupportBorder : width - 1 - u - kSupportBorder;
  const int d_max = std::min(config.disp_max, reach);
  if (d_max < kMinSupportRange) return -1;
  int best = 1 << 30, second = 1 << 30, best_d = -1;
  for (int d = 0; d <= d_max; ++d) {
    const int w = u + view.direction * d;
    int cost = 0;
    for (const int dv : {-kSupportStep, kSupportStep})
      for (const int du : {-kSupportStep, kSupportStep})
        cost += sad(view.self.at(u + du, v + dv), view.other.at(w + du, v + dv));
    if (cost < best)
      second = best, best = cost, best_d = d;
    else if (cost < second)
      second = cost;
  }
  return second < (1 << 30) && best < config.support_threshold * second ? best_d : -1;
}

struct SupportPoint {
  int u, v, d;
};

// Invalidates (in place, as ELAS) each candidate that fewer than incon_min_support candidates within
// incon_window_size cells agree with (within incon_threshold px).
void remove_inconsistent(cv::Mat& grid, const ElasConfig& config) {
  const int r = config.incon_window_size;
  for (int x = 0; x < grid.cols; ++x)
    for (int y = 0; y < grid.rows; ++y) {
      const int d = grid.at<int>(y, x);
      if (d < 0) continue;
      int support = 0;
      for (int x2 = std::max(0, x - r); x2 <= std::min(grid.cols - 1, x + r); ++x2)
        for (int y2 = std::max(0, y - r); y2 <= std::min(grid.rows - 1, y + r); ++y2) {
          const int d2 = grid.at<int>(y2, x2);
          support += d2 >= 0 && std::abs(d - d2) <= config.incon_threshold;
        }
      if (support < config.incon_min_support) grid.at<int>(y, x) = -1;
    }
}

// Invalidates the candidates that lie between two agreeing ones (within 1 px, at most 5 cells away on
// both sides) along the axis (dx, dy): a plane through the others carries them anyway.
void remove_redundant(cv::Mat& grid, int dx, int dy) {
  constexpr int kReach = 5, kAgree = 1;
  for (int x = 0; x < grid.cols; ++x)
    for (int y = 0; y < grid.rows; ++y) {
      const int d = grid.at<int>(y, x);
      if (d < 0) continue;
      bool redundant = true;
      for (const int sign : {-1, 1}) {
        bool found = false;
        for (int k = 1; k <= kReach && !found; ++k) {
          const int x2 = x + sign * k * dx, y2 = y + sign * k * dy;
          if (x2 < 0 || y2 < 0 || x2 >= grid.cols || y2 >= grid.rows) break;
          const int d2 = grid.at<int>(y2, x2);
          found = d2 >= 0 && std::abs(d - d2) <= kAgree;
        }
        redundant = redundant && found;
      }
      if (redundant) grid.at<int>(y, x) = -1;
    }
}

std::vector<SupportPoint> support_points(const Descriptors& left, const Descriptors& right, const ElasConfig& config) {
  const int step = config.candidate_stepsize;
  cv::Mat grid((left.height() + step - 1) / step, (left.width() + step - 1) / step, CV_32S, cv::Scalar(-1));
  const View from_left{left, right, -1}, from_right{right, left, +1};
  for (int x = 1; x < grid.cols; ++x)
    for (int y = 1; y < grid.rows; ++y) {
      const int u = x * step, v = y * step, d = support_disparity(from_left, u, v, config);
      if (d < 0) continue;
      const int back = support_disparity(from_right, u - d, v, config);
      if (back >= 0 && std::abs(d - back) <= config.lr_threshold) grid.at<int>(y, x) = d;
    }
  remove_inconsistent(grid, config);
  remove_redundant(grid, 0, 1);
  remove_redundant(grid, 1, 0);
  std::vector<SupportPoint> points;
  for (int x = 1; x < grid.cols; ++x)
    for (int y = 1; y < grid.rows; ++y)
      if (grid.at<int>(y, x) >= 0) points.push_back({x * step, y * step, grid.at<int>(y, x)});
  return points;
}

// A triangle of support points in one image's coordinates and the disparity plane d = a u + b v + c
// through them in that image; `valid` when neither it nor its image in the other view is steeper than
// kMaxSlant.
struct Triangle {
  std::array<cv::Point2f, 3> corners;
  double a, b, c;
  bool valid;
};

Eigen::Vector3d plane(const std::array<Eigen::Vector3d, 3>& uvd) {
  Eigen::Matrix3d m;
  Eigen::Vector3d d;
  for (int k = 0; k < 3; ++k) m.row(k) << uvd[k].x(), uvd[k].y(), 1.0, d[k] = uvd[k].z();
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(m);
  return lu.isInvertible() ? Eigen::Vector3d(lu.solve(d)) : Eigen::Vector3d::Zero();
}

// The Delaunay triangulation of the support points at their positions in one image (the left: u; the
// right: u - d).
std::vector<Triangle> triangulate(const std::vector<SupportPoint>& support, bool right_image, cv::Size size) {
  cv::Subdiv2D subdiv(cv::Rect(0, 0, size.width, size.height));
  std::map<std::pair<float, float>, std::size_t> index;
  for (std::size_t i = 0; i < support.size(); ++i) {
    const cv::Point2f p(static_cast<float>(right_image ? support[i].u - support[i].d : support[i].u),
                        static_cast<float>(support[i].v));
    if (index.emplace(std::make_pair(p.x, p.y), i).second) subdiv.insert(p);
  }
  std::vector<cv::Vec6f> list;
  subdiv.getTriangleList(list);
  std::vector<Triangle> triangles;
  for (const auto& t : list) {
    std::array<std::size_t, 3> ids{};
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) {
      const auto found = index.find({t[2 * k], t[2 * k + 1]});  // the outer virtual vertices are not there
      inside = found != index.end();
      if (inside) ids[k] = found->second;
    }
    if (!inside) continue;
    std::array<Eigen::Vector3d, 3> in_left, in_right;
    Triangle triangle{};
    for (int k = 0; k < 3; ++k) {
      const SupportPoint& p = support[ids[k]];
      in_left[k] = Eigen::Vector3d(p.u, p.v, p.d);
      in_right[k] = Eigen::Vector3d(p.u - p.d, p.v, p.d);
      triangle.corners[k] = cv::Point2f(t[2 * k], t[2 * k + 1]);
    }
    const Eigen::Vector3d own = plane(right_image ? in_right : in_left),
                          other = plane(right_image ? in_left : in_right);
    triangle.a = own[0], triangle.b = own[1], triangle.c = own[2];
    triangle.valid = std::abs(own[0]) < kMaxSlant && std::abs(other[0]) < kMaxSlant;
    triangles.push_back(triangle);
  }
  return triangles;
}

// Per grid cell, the disparities of the support points in it and in the 8 cells around it, +/- 1: the
// candidates every pixel of the cell tries besides its plane's window.
std::vector<std::vector<int>> candidate_grid(const std::vector<SupportPoint>& support, bool right_image, cv::Size size,
                                             const ElasConfig& config) {
  const int gw = (size.width + config.grid_size - 1) / config.grid_size;
  const int gh = (size.height + config.grid_size - 1) / config.grid_size;
  const int nd = config.disp_max + 1;
  std::vector<char> seen(static_cast<std::size_t>(gw) * gh * nd, 0);
  for (const auto& p : support) {
    const int cx = (right_image ? p.u - p.d : p.u) / config.grid_size, cy = p.v / config.grid_size;
    for (int x = std::max(0, cx - 1); x <= std::min(gw - 1, cx + 1); ++x)
      for (int y = std::max(0, cy - 1); y <= std::min(gh - 1, cy + 1); ++y)
        for (int d = std::max(0, p.d - 1); d <= std::min(config.disp_max, p.d + 1); ++d)
          seen[(static_cast<std::size_t>(y) * gw + x) * nd + d] = 1;
  }
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(gw) * gh);
  for (std::size_t cell = 0; cell < grid.size(); ++cell)
    for (int d = 0; d < nd; ++d)
      if (seen[cell * nd + d]) grid[cell].push_back(d);
  return grid;
}

// The dense match of one image: each pixel inside a triangle takes the disparity of least cost among
// its cell's candidates (descriptor SAD) and the window of sigma x sradius around its plane (SAD plus
// the prior -log(gamma + exp(-delta^2 / 2 sigma^2)) / beta, relative to its value far away).
cv::Mat dense_match(const View& view, const std::vector<SupportPoint>& support, const ElasConfig& config) {
  const int width = view.self.width(), height = view.self.height();
  const cv::Size size(width, height);
  const bool right_image = view.direction > 0;
  const std::vector<Triangle> triangles = triangulate(support, right_image, size);
  const auto grid = candidate_grid(support, right_image, size, config);
  const int gw = (width + config.grid_size - 1) / config.grid_size;
  const int radius = std::max(2, static_cast<int>(std::ceil(config.sigma * config.sradius)));
  std::vector<int> prior(radius + 1);
  for (int delta = 0; delta <= radius; ++delta)
    prior[delta] =
        static_cast<int>((std::log(config.gamma) -
                          std::log(config.gamma + std::exp(-delta * delta / (2 * config.sigma * config.sigma)))) /
                         config.beta);
  cv::Mat disparity(size, CV_32FC1, cv::Scalar(kNoDisparity));
  const auto match = [&](int u, int v, const Triangle& t) {
    const int line = std::clamp(v, 2, height - 3);
    const std::uint8_t* self = view.self.at(u, line);
    if (texture(self) < config.match_texture) return;
    const int plane_d = static_cast<int>(t.a * u + t.b * v + t.c);
    const int lo = std::max(plane_d - radius, 0), hi = std::min(plane_d + radius, config.disp_max);
    int best = 1 << 30, best_d = -1;
    const auto offer = [&](int d, int extra) {
      const int w = u + view.direction * d;
      if (w < kDenseBorder || w >= width - kDenseBorder) return;
      const int cost = sad(self, view.other.at(w, line)) + extra;
      if (cost < best) best = cost, best_d = d;
    };
    for (const int d : grid[static_cast<std::size_t>(v / config.grid_size) * gw + u / config.grid_size])
      if (d < lo || d > hi) offer(d, 0);
    for (int d = lo; d <= hi; ++d) offer(d, t.valid ? prior[std::abs(d - plane_d)] : 0);
    disparity.at<float>(v, u) = static_cast<float>(best_d);  // -1: nothing to match
  };
  for (const Triangle& t : triangles) {
    const auto& [p0, p1, p2] = t.corners;
    const double area = (p1.x - p0.x) * (p2.y - p0.y) - (p2.x - p0.x) * (p1.y - p0.y);
    if (area == 0) continue;
    const int u0 = std::max(kDenseBorder, static_cast<int>(std::floor(std::min({p0.x, p1.x, p2.x}))));
    const int u1 = std::min(width - kDenseBorder - 1, static_cast<int>(std::ceil(std::max({p0.x, p1.x, p2.x}))));
    const int v0 = std::max(0, static_cast<int>(std::floor(std::min({p0.y, p1.y, p2.y}))));
    const int v1 = std::min(height - 1, static_cast<int>(std::ceil(std::max({p0.y, p1.y, p2.y}))));
    const auto edge = [area](const cv::Point2f& a, const cv::Point2f& b, double u, double v) {
      return ((b.x - a.x) * (v - a.y) - (u - a.x) * (b.y - a.y)) / area;
    };
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u)
        if (edge(p0, p1, u, v) >= 0 && edge(p1, p2, u, v) >= 0 && edge(p2, p0, u, v) >= 0) match(u, v, t);
  }
  return disparity;
}

// Keeps a left disparity only where the right image's disparity at its match agrees within lr_threshold.
void left_right_check(cv::Mat& left, const cv::Mat& right, int threshold) {
  for (int v = 0; v < left.rows; ++v)
    for (int u = 0; u < left.cols; ++u) {
      float& d = left.at<float>(v, u);
      const int w = static_cast<int>(u - d);
      if (d < 0 || w < 0 || w >= left.cols || std::abs(right.at<float>(v, w) - d) > threshold) d = kNoDisparity;
    }
}

cv::Mat grey(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat out;
  cv::cvtColor(image, out, cv::COLOR_BGR2GRAY);
  return out;
}

}  // namespace

cv::Mat elas_disparity(const cv::Mat& left, const cv::Mat& right, const ElasConfig& config) {
  CV_Assert(left.size() == right.size() && left.type() == right.type() && left.depth() == CV_8U);
  const Descriptors dl(grey(left)), dr(grey(right));
  const std::vector<SupportPoint> support = support_points(dl, dr, config);
  if (support.size() < 3) return cv::Mat(left.size(), CV_32FC1, cv::Scalar(kNoDisparity));
  cv::Mat disparity = dense_match({dl, dr, -1}, support, config);
  left_right_check(disparity, dense_match({dr, dl, +1}, support, config), config.lr_threshold);
  remove_speckles(disparity, config.speckle_size, config.speckle_sim_threshold);
  interpolate_gaps(disparity, config.ipol_gap_width);
  if (config.filter_adaptive_mean) adaptive_mean(disparity);
  return disparity;
}

cv::Mat elas_disparity16(const cv::Mat& left, const cv::Mat& right, const ElasConfig& config) {
  cv::Mat disparity16;
  elas_disparity(left, right, config).convertTo(disparity16, CV_16SC1, 16.0);
  return disparity16;
}

}  // namespace toolinc
