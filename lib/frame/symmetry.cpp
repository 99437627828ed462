#include "frame/symmetry.hpp"

#include <algorithm>
#include <cmath>

#include "toolinc/cloud/preprocessing.hpp"

namespace toolinc {

SymmetryScorer::SymmetryScorer(const Points& points, std::size_t samples, double tolerance, double match_weight,
                               const FreeSpace* free_space, int normal_neighbors,
                               const std::vector<std::uint32_t>* mirrored)
    : points_(points),
      tree_(points),
      tolerance_(tolerance),
      match_weight_(match_weight),
      free_space_(free_space),
      normal_neighbors_(normal_neighbors),
      normals_(normal_neighbors > 0 ? points.size() : 0),
      normal_known_(normals_.size(), false) {
  const std::size_t n = mirrored ? mirrored->size() : points.size();
  const std::size_t count = std::min(n, std::max<std::size_t>(samples, 1));
  samples_.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const auto k = static_cast<std::uint32_t>(i * n / count);
    samples_.push_back(mirrored ? (*mirrored)[k] : k);
  }
}

double SymmetryScorer::score(const Vec3& normal, const Vec3& point_on_plane) const {
  double sum = 0.0;
  std::size_t evidence = 0;
  for (std::uint32_t index : samples_) {
    const Vec3& p = points_[index];
    const Vec3 mirrored = p - 2.0 * normal.dot(p - point_on_plane) * normal;
    const auto nearest = tree_.nearest(mirrored, tolerance_);
    if (nearest.index != KdTree::npos) {
      double distance = std::sqrt(nearest.distance2);
      if (normal_neighbors_ > 0) {
        if (!normal_known_[nearest.index]) {
          normals_[nearest.index] = normal_at(tree_, points_[nearest.index], normal_neighbors_);
          normal_known_[nearest.index] = true;
        }
        distance = std::abs(normals_[nearest.index].dot(mirrored - points_[nearest.index]));
      }
      sum += match_weight_ * distance / tolerance_;
      ++evidence;
    } else if (free_space_ == nullptr || free_space_->seen(mirrored)) {
      sum += 1.0;
      ++evidence;
    }
  }
  return evidence == 0 ? 1.0 : sum / static_cast<double>(evidence);
}

}  // namespace toolinc
