#include "toolinc/frame/free_space.hpp"

#include <cmath>
#include <limits>

namespace toolinc {

FreeSpace::FreeSpace(const Points& cloud, const Points& viewpoints, double pixel_deg, double tolerance, int border)
    : tolerance_(tolerance) {
  if (cloud.empty()) return;
  Vec3 centroid = Vec3::Zero();
  for (const auto& p : cloud) centroid += p;
  centroid /= static_cast<double>(cloud.size());
  for (const auto& origin : viewpoints) {
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
    view.size = 2 * (static_cast<int>(std::ceil(view.focal * extent)) + border) + 1;
    view.depth.assign(static_cast<std::size_t>(view.size) * view.size, std::numeric_limits<float>::infinity());
    for (const auto& p : cloud) {
      const Vec3 q = view.camera_from_cloud * (p - origin);
      if (q.z() <= 0) continue;
      const int u = static_cast<int>(std::lround(view.focal * q.x() / q.z())) + view.size / 2;
      const int v = static_cast<int>(std::lround(view.focal * q.y() / q.z())) + view.size / 2;
      float& d = view.depth[static_cast<std::size_t>(v) * view.size + u];
      d = std::min(d, static_cast<float>(q.z()));
    }
    views_.push_back(std::move(view));
  }
}

bool FreeSpace::seen_from(const View& view, const Vec3& p) const {
  const Vec3 q = view.camera_from_cloud * (p - view.origin);
  if (q.z() <= 0) return false;
  const int u = static_cast<int>(std::lround(view.focal * q.x() / q.z())) + view.size / 2;
  const int v = static_cast<int>(std::lround(view.focal * q.y() / q.z())) + view.size / 2;
  if (u < 1 || v < 1 || u >= view.size - 1 || v >= view.size - 1) return false;
  // The nearest surface around the pixel: points are sparse, so a single pixel may show a hole.
  float nearest = std::numeric_limits<float>::infinity();
  for (int dv = -1; dv <= 1; ++dv)
    for (int du = -1; du <= 1; ++du) nearest = std::min(nearest, view.depth[static_cast<std::size_t>(v + dv) * view.size + u + du]);
  return q.z() <= nearest + tolerance_;
}

bool FreeSpace::seen(const Vec3& p) const {
  if (views_.empty()) return true;
  for (const auto& view : views_)
    if (seen_from(view, p)) return true;
  return false;
}

}  // namespace toolinc
