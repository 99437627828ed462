// Mirror symmetry of a point set about a plane. Two-sided (every sampled point is mirrored, whichever
// side it is on) and independent of density (the set is voxel-resampled first, and distances are
// measured in units of a tolerance and truncated there).
#pragma once

#include <memory>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/free_space.hpp"

namespace toolinc {

class SymmetryScorer {
 public:
  // points: the resampled cloud; the scorer mirrors an evenly spaced subset of at most `samples`
  // points. tolerance: mirrored points this far or farther from the cloud count as fully asymmetric.
  // free_space (optional, must outlive the scorer): mirror images that no sensor could have seen count
  // as `unseen_score` instead of as fully asymmetric. match_weight scales the distance of the mirror
  // images that land on the cloud. normals (optional, one per point, must outlive the scorer): that
  // distance is then to the nearest point's tangent plane, which unlike the distance to the nearest
  // point does not depend on how the surface was sampled.
  SymmetryScorer(const Points& points, std::size_t samples, double tolerance, const FreeSpace* free_space = nullptr,
                 double unseen_score = 0.5, double match_weight = 1.0, const Points* normals = nullptr);

  // Mean over the mirror images of: match_weight x distance to the cloud / tolerance when within the
  // tolerance, else 1 (or unseen_score where no sensor could have seen it). 0 for a perfect mirror, 1
  // when nothing matches.
  double score(const Vec3& normal, const Vec3& point_on_plane) const;

 private:
  const Points& points_;
  KdTree tree_;
  std::vector<std::uint32_t> samples_;
  double tolerance_;
  const FreeSpace* free_space_;
  double unseen_score_;
  double match_weight_;
  const Points* normals_;
};

}  // namespace toolinc
