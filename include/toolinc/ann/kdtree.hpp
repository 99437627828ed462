// A static 3D kd-tree over a set of points: nearest neighbour, k nearest, and radius queries.
// Built once, queried many times (symmetry scores, density checks, ICP correspondences); it keeps a
// reference to the points, which must outlive it.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

class KNearest;

class KdTree {
 public:
  explicit KdTree(const Points& points, int leaf_size = 12);

  struct Neighbor {
    std::uint32_t index;
    double distance2;
  };

  // The nearest point within max_distance; index == npos when there is none.
  Neighbor nearest(const Vec3& query, double max_distance = std::numeric_limits<double>::infinity()) const;
  // Up to k nearest, sorted by distance.
  std::vector<Neighbor> knn(const Vec3& query, int k) const;
  // The same into `nearest` (emptied first, its k asked): a loop of queries allocates nothing.
  void knn(const Vec3& query, KNearest& nearest) const;
  // How many points lie within radius, stopping early once `enough` have been found.
  std::size_t count_within(const Vec3& query, double radius,
                           std::size_t enough = std::numeric_limits<std::size_t>::max()) const;
  // The indices of every point within radius, in no particular order.
  std::vector<std::uint32_t> within(const Vec3& query, double radius) const;

  const Points& points() const { return points_; }
  static constexpr std::uint32_t npos = std::numeric_limits<std::uint32_t>::max();

 private:
  struct Node {
    // Leaf when split_dim < 0: indices [begin, end). Inner: children at left/right.
    std::uint32_t begin, end;
    std::int32_t left, right;
    int split_dim;
    double split_value;
  };
  struct Entry {
    std::array<double, 3> point;  // plain data, which the partitions move as bytes
    std::uint32_t index;
  };
  std::int32_t build(std::vector<Entry>& entries, std::uint32_t begin, std::uint32_t end, int leaf_size);
  template <typename Visit>
  void search(const Vec3& query, double& bound2, Visit&& visit) const;
  template <typename Visit>
  void search(std::int32_t id, const Vec3& query, double min_d2, Vec3& axis_d2, double& bound2, Visit& visit) const;

  const Points& points_;
  std::vector<std::uint32_t> order_;
  Points ordered_;  // points_ in order_'s order: a leaf's points lie side by side in memory
  std::vector<Node> nodes_;
};

// The k nearest of the points offered, as KdTree::knn keeps them: sorted by distance, ties by index.
// Another search (a grid's) that offers every point within the bound it lowers finds the same neighbours.
class KNearest {
 public:
  explicit KNearest(int k);
  // Keeps the point if it is among the k nearest so far; once k are kept, lowers bound2 to the k-th's.
  // Inline: a search offers every point within its bound.
  void offer(std::uint32_t index, double distance2, double& bound2) {
    const auto closer = [](const KdTree::Neighbor& a, const KdTree::Neighbor& b) {
      return a.distance2 < b.distance2 || (a.distance2 == b.distance2 && a.index < b.index);
    };
    const KdTree::Neighbor candidate{index, distance2};
    if (k_ == 0 || (full() && !closer(candidate, kept_.back()))) return;
    // Into its place by insertion, over the farthest kept when full: for so few, cheaper than a vector insert.
    std::size_t at = kept_.size();
    if (full())
      --at;
    else
      kept_.push_back(candidate);
    for (; at > 0 && closer(candidate, kept_[at - 1]); --at) kept_[at] = kept_[at - 1];
    kept_[at] = candidate;
    if (full()) bound2 = kept_.back().distance2;
  }
  bool full() const { return static_cast<int>(kept_.size()) == k_; }
  void clear() { kept_.clear(); }
  const std::vector<KdTree::Neighbor>& kept() const { return kept_; }
  // The kept neighbours moved out, which leaves none kept: a search's result without a copy.
  std::vector<KdTree::Neighbor> take() { return std::move(kept_); }

 private:
  int k_;
  std::vector<KdTree::Neighbor> kept_;  // sorted: for the few neighbours asked for, cheaper than a heap
};

}  // namespace toolinc
