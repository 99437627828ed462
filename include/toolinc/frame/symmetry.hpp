// Mirror symmetry of a point set about a plane. Two-sided (every sampled point is mirrored, whichever
// side it is on) and independent of density (the set is voxel-resampled first, and distances are
// measured in units of a tolerance and truncated there).
#pragma once

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/free_space.hpp"

namespace toolinc {

// How a mirror image counts in a score: where a sensor saw empty space (or with no free space given,
// anywhere off the cloud) 1; where no sensor could have seen it `unseen`; on the cloud `match` x its
// distance / tolerance.
struct MirrorWeights {
  double unseen = 1.0;
  double match = 1.0;
};

class SymmetryScorer {
 public:
  // points: the resampled cloud; the scorer mirrors an evenly spaced subset of at most `samples`
  // points. tolerance: mirrored points this far or farther from the cloud count as off it. free_space
  // (optional, must outlive the scorer): tells a never-seen mirror image from one where a sensor saw
  // nothing. normals (optional, one per point, must outlive the scorer): a matched image's distance is
  // then to the nearest point's tangent plane, which unlike the distance to the nearest point does not
  // depend on how the surface was sampled.
  SymmetryScorer(const Points& points, std::size_t samples, double tolerance, const FreeSpace* free_space = nullptr,
                 const Points* normals = nullptr);

  // Mean over the mirror images of what each counts (see MirrorWeights): 0 for a perfect mirror, 1 when
  // nothing matches.
  double score(const Vec3& normal, const Vec3& point_on_plane, const MirrorWeights& weights = {}) const;

 private:
  const Points& points_;
  KdTree tree_;
  std::vector<std::uint32_t> samples_;
  double tolerance_;
  const FreeSpace* free_space_;
  const Points* normals_;
};

}  // namespace toolinc
