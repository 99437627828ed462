// Point-set preprocessing shared by every stage: resampling, removal of the hand and of outliers,
// principal axes.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

// One point per occupied voxel (the mean of its points), in voxel-key order so the result does not
// depend on the input order. Makes later statistics independent of how densely a part was sampled.
Points voxel_downsample(const Points& points, double voxel_size);
// The same carrying a bit mask per point (the views that saw it): each voxel's mask, in voxel_masks, is
// the union of its points' masks.
Points voxel_downsample(const Points& points, double voxel_size, const std::vector<std::uint32_t>& masks,
                        std::vector<std::uint32_t>& voxel_masks);

// Keeps the points strictly farther than radius from center (the hand is a sphere at the origin).
Points remove_within(const Points& points, const Vec3& center, double radius);

// Keeps the points with at least min_neighbors others within radius.
Points remove_isolated(const Points& points, double radius, std::size_t min_neighbors);
// The same as the indices of the points it keeps, ascending (so attributes follow their points).
std::vector<std::uint32_t> non_isolated(const Points& points, double radius, std::size_t min_neighbors);

// The pieces the hand holds. Of the points farther than hand_radius from the hand (at the origin), those
// joined through points at most gap apart to a point about as near the hand as the nearest of them (within
// gap of its distance: a handle leaving the hand on both sides is held on both). What no such chain
// reaches (a patch of the scene beside the tool, an island of smear) is not the tool, however far it
// reaches. The points are joined as the means of a grid of gap / 8 cells (at most gap apart), so a gap is
// measured to within a cell. gap <= 0: every point beyond the hand.
struct HeldPiece {
  std::vector<std::uint32_t> indices;  // of the held points, ascending
  int detached_points = 0;             // beyond the hand but not joined to what it holds
  int detached_pieces = 0;             // how many pieces those form
};
HeldPiece held_piece(const Points& points, double hand_radius, double gap);

// PCL-style statistical outlier removal, as the indices of the points it keeps (so attributes follow
// their points): drops points whose mean distance to their k nearest neighbours exceeds the global mean
// of that statistic by more than std_multiplier deviations.
std::vector<std::uint32_t> statistical_inliers(const Points& points, int k, double std_multiplier);

// Unit normals from the covariance of each point's k nearest neighbours (sign arbitrary).
Points estimate_normals(const Points& points, int k);
// The same for one point of the tree's points (+Z when it has fewer than 3 neighbours).
Vec3 normal_at(const KdTree& tree, const Vec3& point, int k);
// The normal of a point's neighbours among points (+Z when fewer than 3), as normal_at finds it from them.
Vec3 normal_of(const Points& points, const std::vector<KdTree::Neighbor>& neighbours);

Points transform_points(const Points& points, const Eigen::Matrix4d& target_from_source);

struct PrincipalAxes {
  Vec3 centroid = Vec3::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: major, middle, minor (right-handed)
  Vec3 eigenvalues = Vec3::Zero();                     // descending, m^2
};
PrincipalAxes principal_axes(const Points& points);

}  // namespace toolinc
