// Mirror symmetry of a point set about a plane. Independent of density (the set is voxel-resampled
// first, and distances are measured in units of a tolerance and truncated there) and of what was never
// seen (with a free-space model, only mirror images a sensor could have seen are evidence).
#pragma once

#include <cstdint>
#include <vector>

#include "cloud/free_space.hpp"
#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

class SymmetryScorer {
 public:
  // points: the resampled cloud; the scorer mirrors an evenly spaced subset of at most `samples` of
  // them, drawn from `mirrored` (indices into points) when given, else from every point. tolerance:
  // mirror images this far or farther from the cloud are off it. match_weight: what a matched image's
  // distance / tolerance weighs against a contradicted image (1). free_space (optional, must outlive
  // the scorer): an image off the cloud is a contradiction only where a sensor saw empty space, and no
  // evidence where no sensor could have seen it; without it every image off the cloud contradicts.
  // normal_neighbors (0: none): a matched image's distance is then to the nearest point's tangent plane
  // (its normal from that many nearest points), which unlike the distance to the nearest point does not
  // depend on how the surface was sampled. Normals are computed when first needed: mirror images land
  // near the mirrored part only.
  SymmetryScorer(const Points& points, std::size_t samples, double tolerance, double match_weight = 1.0,
                 const FreeSpace* free_space = nullptr, int normal_neighbors = 0,
                 const std::vector<std::uint32_t>* mirrored = nullptr);

  // Over the mirror images that are evidence (matched, or off the cloud where a sensor could have seen
  // them): (contradicted + match_weight x matched distance / tolerance) / their number. 0 for a perfect
  // mirror, 1 when every image contradicts or none is evidence. Not thread-safe (it caches normals).
  double score(const Vec3& normal, const Vec3& point_on_plane) const;

 private:
  const Points& points_;
  KdTree tree_;
  std::vector<std::uint32_t> samples_;
  double tolerance_;
  double match_weight_;
  const FreeSpace* free_space_;
  int normal_neighbors_;
  mutable Points normals_;  // per point, valid where normal_known_
  mutable std::vector<bool> normal_known_;
};

}  // namespace toolinc
