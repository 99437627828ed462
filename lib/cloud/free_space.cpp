#include "cloud/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace toolinc {

FreeSpace::FreeSpace(const Points& cloud, const Points& viewpoints, double pixel_deg, double tolerance, int border,
                     double max_half_angle_deg)
    : tolerance_(tolerance) {
  if (cloud.empty()) return;
  Vec3 centroid = Vec3::Zero();
  for (const auto& p : cloud) centroid += p;
  centroid /= static_cast<double>(cloud.size());
  const double max_extent = std::tan(max_half_angle_deg * M_PI / 180.0);
  for (const auto& origin : viewpoints) {
    if (!origin.allFinite() || !((centroid - origin).norm() > 1e-9)) continue;
    View view;
    view.origin = origin;
    const Vec3 z = (centroid - origin).normalized();
    const Vec3 x = z.unitOrthogonal();
    view.camera_from_cloud.row(0) = x.transpose();
    view.camera_from_cloud.row(1) = z.cross(x).transpose();
    view.camera_from_cloud.row(2) = z.transpose();
    view.focal = 1.0 / std::tan(pixel_deg * M_PI / 180.0);
    double extent = 0.0;
    for (const auto& p : cloud) {
      const Vec3 q = view.camera_from_cloud * (p - origin);
      if (q.z() > 0) extent = std::max({extent, std::abs(q.x() / q.z()), std::abs(q.y() / q.z())});
    }
    view.size = 2 * (static_cast<int>(std::ceil(view.focal * std::min(extent, max_extent))) + border) + 1;
    view.depth.assign(static_cast<std::size_t>(view.size) * view.size, std::numeric_limits<float>::infinity());
    for (const auto& p : cloud) {
      const Vec3 q = view.camera_from_cloud * (p - origin);
      int u, v;
      if (!pixel(view, q, u, v)) continue;  // behind the sensor or outside its field of view
      float& d = view.depth[static_cast<std::size_t>(v) * view.size + u];
      d = std::min(d, static_cast<float>(q.z()));
    }
    views_.push_back(std::move(view));
  }
}

// The pixel q (camera coordinates) falls on; false behind the sensor or off the image. The bounds are
// checked on the ratios, before rounding, so that no far-off point overflows an int.
bool FreeSpace::pixel(const View& view, const Vec3& q, int& u, int& v) {
  if (!(q.z() > 0)) return false;
  const double half = view.size / 2;
  const double x = view.focal * q.x() / q.z(), y = view.focal * q.y() / q.z();
  if (!(std::abs(x) < half + 0.5 && std::abs(y) < half + 0.5)) return false;
  u = static_cast<int>(std::lround(x)) + view.size / 2;
  v = static_cast<int>(std::lround(y)) + view.size / 2;
  return u >= 0 && v >= 0 && u < view.size && v < view.size;
}

bool FreeSpace::depths(const View& view, const Vec3& p, double& depth, double& nearest) const {
  const Vec3 q = view.camera_from_cloud * (p - view.origin);
  int u, v;
  if (!pixel(view, q, u, v) || u < 1 || v < 1 || u >= view.size - 1 || v >= view.size - 1) return false;
  // The nearest surface around the pixel: points are sparse, so a single pixel may show a hole.
  float near = std::numeric_limits<float>::infinity();
  for (int dv = -1; dv <= 1; ++dv)
    for (int du = -1; du <= 1; ++du)
      near = std::min(near, view.depth[static_cast<std::size_t>(v + dv) * view.size + u + du]);
  depth = q.z();
  nearest = near;
  return true;
}

std::size_t FreeSpace::pixels() const {
  std::size_t total = 0;
  for (const auto& view : views_) total += view.depth.size();
  return total;
}

bool FreeSpace::seen(const Vec3& p) const {
  if (views_.empty()) return true;
  double depth, nearest;
  for (const auto& view : views_)
    if (depths(view, p, depth, nearest) && depth <= nearest + tolerance_) return true;
  return false;
}

bool FreeSpace::seen_through(const Vec3& p) const {
  double depth, nearest;
  for (const auto& view : views_)
    if (depths(view, p, depth, nearest) && std::isfinite(nearest) && depth < nearest - tolerance_) return true;
  return false;
}

}  // namespace toolinc
