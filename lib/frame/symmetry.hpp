// Mirror symmetry of a point set about a plane. Independent of density (the set is voxel-resampled
// first, and distances are measured in units of a tolerance and truncated there) and of what was never
// seen (with a free-space model, only mirror images a sensor could have seen are evidence).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "cloud/free_space.hpp"
#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

// The cloud mirror images are matched against: the nearest point within tolerance of an image, and its
// tangent-plane normal (from normal_neighbors nearest points; 0: none) computed when first needed. Every
// scorer over the same cloud can share one, whatever it mirrors, so each normal is computed once. Not
// thread-safe (it caches normals); points must outlive it.
class MirrorTarget {
 public:
  MirrorTarget(const Points& points, double tolerance, int normal_neighbors = 0);

  const Points& points() const { return points_; }
  double tolerance() const { return tolerance_; }
  int normal_neighbors() const { return normal_neighbors_; }
  // The nearest point within tolerance (ties to the lowest index), as KdTree::nearest finds it.
  KdTree::Neighbor nearest(const Vec3& query) const;
  const Vec3& normal(std::uint32_t index) const;
  // The normal_neighbors nearest points of point, as KdTree::knn finds them.
  std::vector<KdTree::Neighbor> neighbours(const Vec3& point) const;

 private:
  // Calls visit(index, squared distance) for points around the query, among them every one within
  // sqrt(bound2) of it (which visit may lower); bound2 at most cell_ squared.
  template <typename Visit>
  void scan(const Vec3& query, double& bound2, Visit&& visit) const;
  // neighbours(), into `nearest` (its k normal_neighbors).
  void find_neighbours(const Vec3& point, KNearest& nearest) const;

  const Points& points_;
  double tolerance_;
  mutable std::optional<KdTree> tree_;  // for the normals' neighbours beyond a cell, built when first needed
  int normal_neighbors_;
  mutable KNearest neighbours_;  // a normal's, kept to be refilled: the normals allocate nothing
  mutable Points normals_;       // per point, valid where normal_known_
  mutable std::vector<bool> normal_known_;
  // Cells of at least the tolerance's size across x and y, cut into thinner slices along z, over the
  // points' box: a point within tolerance of an image lies in the image's row of slices or one of the 8
  // around it, within the tolerance along z. Scanning those (the farther ones only while they can hold a
  // nearer point) is cheaper than a kd-tree's descent and backtracking.
  Vec3 low_ = Vec3::Zero();
  double cell_ = 1.0;                              // across x and y
  Eigen::Array3d size_ = Eigen::Array3d::Ones();   // of a slice along x, y, z
  Eigen::Array3i cells_ = Eigen::Array3i::Zero();  // along x, y, z
  std::vector<std::uint32_t> cell_begin_;          // per slice, its first entry in by_cell_; one more at the end
  std::vector<std::uint32_t> by_cell_;             // the points' indices, slice after slice
  Points cell_points_;                             // the points in by_cell_'s order, side by side in memory
  // Blocks a cell wide along every axis (kSlicesPerCell slices along z), one more all round the grid: whether
  // a point lies in the block or one of the 26 around it. No point lies within a cell of a query in a block
  // without, as most mirror images off the cloud are: their scan ends there.
  Eigen::Array3i blocks_ = Eigen::Array3i::Zero();
  std::vector<std::uint8_t> points_near_;
};

// p's mirror image across the plane through point_on_plane with the unit normal.
inline Vec3 mirror_image(const Vec3& p, const Vec3& normal, const Vec3& point_on_plane) {
  return p - 2.0 * normal.dot(p - point_on_plane) * normal;
}

class SymmetryScorer {
 public:
  // target: the resampled cloud (which must outlive the scorer); the scorer mirrors an evenly spaced subset
  // of at most `samples` of its points, drawn from `mirrored` (indices into them) when given, else from
  // every point. Mirror images farther than the target's tolerance from the cloud are off it. match_weight:
  // what a matched image's distance / tolerance weighs against a contradicted image (1). free_space (optional,
  // must outlive the scorer): an image off the cloud is a contradiction only where a sensor saw empty
  // space, and no evidence where no sensor could have seen it; without it every image off the cloud
  // contradicts. With the target's normals, a matched image's distance is to the nearest point's tangent
  // plane, which unlike the distance to the nearest point does not depend on how the surface was sampled.
  SymmetryScorer(const MirrorTarget& target, std::size_t samples, double match_weight = 1.0,
                 const FreeSpace* free_space = nullptr, const std::vector<std::uint32_t>* mirrored = nullptr);

  // Over the mirror images that are evidence (matched, or off the cloud where a sensor could have seen
  // them): (contradicted + match_weight x matched distance / tolerance) / their number. 0 for a perfect
  // mirror, 1 when every image contradicts or none is evidence. Not thread-safe (the target caches normals).
  double score(const Vec3& normal, const Vec3& point_on_plane) const;

  // A sample's mirror image's part of a score: what it adds to the sum, and whether it is evidence.
  struct Image {
    double cost = 0.0;
    bool evidence = false;
  };
  // Images a scorer recorded of a plane: its samples (ascending, as every scorer's are) and their images. Only
  // another scorer over the same target, with the same match weight and free space, may take them.
  struct Recorded {
    const std::vector<std::uint32_t>& samples;
    const std::vector<Image>& images;
  };
  // The score, each sample's image recorded into `record` (one per sample, in order) when given, and taken
  // from `known`, the same plane's images by another scorer, where it holds the sample: a sweep scores its
  // planes with a subset of the samples first, and rescores its best with them all.
  double score(const Vec3& normal, const Vec3& point_on_plane, std::vector<Image>* record,
               const Recorded* known = nullptr) const;
  const std::vector<std::uint32_t>& samples() const { return samples_; }

 private:
  Image image(std::uint32_t index, const Vec3& normal, const Vec3& point_on_plane) const;

  const MirrorTarget& target_;
  std::vector<std::uint32_t> samples_;
  double match_weight_;
  const FreeSpace* free_space_;
};

}  // namespace toolinc
