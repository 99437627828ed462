#include "toolinc/frame/symmetry.hpp"

#include <algorithm>
#include <cmath>

namespace toolinc {

SymmetryScorer::SymmetryScorer(const Points& points, std::size_t samples, double tolerance,
                               const FreeSpace* free_space, const Points* normals)
    : points_(points), tree_(points), tolerance_(tolerance), free_space_(free_space), normals_(normals) {
  const std::size_t n = points.size();
  const std::size_t count = std::min(n, std::max<std::size_t>(samples, 1));
  samples_.reserve(count);
  for (std::size_t i = 0; i < count; ++i) samples_.push_back(static_cast<std::uint32_t>(i * n / count));
}

double SymmetryScorer::score(const Vec3& normal, const Vec3& point_on_plane, const MirrorWeights& weights) const {
  if (samples_.empty()) return 1.0;
  double sum = 0.0;
  for (std::uint32_t index : samples_) {
    const Vec3& p = points_[index];
    const Vec3 mirrored = p - 2.0 * normal.dot(p - point_on_plane) * normal;
    const auto nearest = tree_.nearest(mirrored, tolerance_);
    if (nearest.index != KdTree::npos)
      sum += weights.match *
             (normals_ ? std::abs((*normals_)[nearest.index].dot(mirrored - points_[nearest.index]))
                       : std::sqrt(nearest.distance2)) /
             tolerance_;
    else
      sum += free_space_ == nullptr || free_space_->seen(mirrored) ? 1.0 : weights.unseen;
  }
  return sum / static_cast<double>(samples_.size());
}

}  // namespace toolinc
