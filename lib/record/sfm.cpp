#include "toolinc/record/sfm.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <limits>

#include "toolinc/core/error.hpp"

namespace toolinc {

SfmRect clamp_rect(const std::array<int, 4>& roi, int width, int height, int step) {
  const int x0 = std::max(0, std::min(roi[0], roi[2])), x1 = std::min(width - 1, std::max(roi[0], roi[2]));
  const int y0 = std::max(0, std::min(roi[1], roi[3])), y1 = std::min(height - 1, std::max(roi[1], roi[3]));
  SfmRect rect{x0, y0, std::max(0, x1 - x0 + 1), std::max(0, y1 - y0 + 1), std::max(1, step)};
  if (rect.w == 0 || rect.h == 0) rect.w = rect.h = 0;
  return rect;
}

std::vector<Eigen::Vector2i> sfm_rect_pixels(const SfmRect& rect) {
  std::vector<Eigen::Vector2i> pixels;
  for (int u = rect.tlx; u < rect.tlx + rect.w; u += rect.step)
    for (int v = rect.tly; v < rect.tly + rect.h; v += rect.step) pixels.emplace_back(u, v);
  return pixels;
}

Points organised_points(const SfmRect& rect, const Points& reply, int width, int height) {
  const auto pixels = sfm_rect_pixels(rect);
  if (reply.size() != pixels.size())
    throw MethodError(fmt::format("the stereo module answered {} points for Rect {} {} {} {} {} ({} pixels)",
                                  reply.size(), rect.tlx, rect.tly, rect.w, rect.h, rect.step, pixels.size()));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Points points(static_cast<std::size_t>(width) * height, Vec3::Constant(nan));
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const int u = pixels[i].x(), v = pixels[i].y();
    if (u < 0 || v < 0 || u >= width || v >= height) continue;
    if (reply[i].allFinite() && !reply[i].isZero()) points[static_cast<std::size_t>(v) * width + u] = reply[i];
  }
  return points;
}

}  // namespace toolinc
