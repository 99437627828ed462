#include "frame/symmetry.hpp"

#include <algorithm>
#include <cmath>

#include "toolinc/cloud/preprocessing.hpp"

namespace toolinc {

MirrorTarget::MirrorTarget(const Points& points, int normal_neighbors)
    : points_(points),
      tree_(points),
      normal_neighbors_(normal_neighbors),
      normals_(normal_neighbors > 0 ? points.size() : 0),
      normal_known_(normals_.size(), false) {}

const Vec3& MirrorTarget::normal(std::uint32_t index) const {
  if (!normal_known_[index]) {
    normals_[index] = normal_at(tree_, points_[index], normal_neighbors_);
    normal_known_[index] = true;
  }
  return normals_[index];
}

SymmetryScorer::SymmetryScorer(const MirrorTarget& target, std::size_t samples, double tolerance, double match_weight,
                               const FreeSpace* free_space, const std::vector<std::uint32_t>* mirrored)
    : target_(target), tolerance_(tolerance), match_weight_(match_weight), free_space_(free_space) {
  const std::size_t n = mirrored ? mirrored->size() : target.points().size();
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
    const Vec3& p = target_.points()[index];
    const Vec3 mirrored = p - 2.0 * normal.dot(p - point_on_plane) * normal;
    const auto nearest = target_.tree().nearest(mirrored, tolerance_);
    if (nearest.index != KdTree::npos) {
      double distance = std::sqrt(nearest.distance2);
      if (target_.normal_neighbors() > 0)
        distance = std::abs(target_.normal(nearest.index).dot(mirrored - target_.points()[nearest.index]));
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
