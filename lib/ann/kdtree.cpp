#include "toolinc/ann/kdtree.hpp"

#include <algorithm>
#include <numeric>

namespace toolinc {

KdTree::KdTree(const Points& points, int leaf_size) : points_(points) {
  // Built on the points themselves, beside their indices: the partitions read them in memory order.
  std::vector<Entry> entries(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    entries[i] = {{points[i].x(), points[i].y(), points[i].z()}, static_cast<std::uint32_t>(i)};
  nodes_.reserve(2 * points.size() / std::max(1, leaf_size) + 1);
  if (!points.empty()) build(entries, 0, static_cast<std::uint32_t>(points.size()), std::max(1, leaf_size));
  order_.reserve(points.size());
  ordered_.reserve(points.size());
  for (const auto& e : entries) order_.push_back(e.index), ordered_.emplace_back(e.point[0], e.point[1], e.point[2]);
}

// The widest side of the node's points' own box (a sample's) is split at the median, which keeps the tree
// balanced, robust to duplicate points, and its cells compact where the points are sparse (a box cut only
// by the splits above stays as wide as the cloud: k-NN queries took a fifth longer).
std::int32_t KdTree::build(std::vector<Entry>& entries, std::uint32_t begin, std::uint32_t end, int leaf_size) {
  const auto id = static_cast<std::int32_t>(nodes_.size());
  nodes_.push_back({begin, end, -1, -1, -1, 0.0});
  if (end - begin <= static_cast<std::uint32_t>(leaf_size)) return id;

  const auto point = [&](std::uint32_t i) { return Eigen::Map<const Vec3>(entries[i].point.data()); };
  Vec3 lo = point(begin), hi = lo;
  const std::uint32_t stride = std::max<std::uint32_t>(1, (end - begin) / 64);
  for (std::uint32_t i = begin; i < end; i += stride) lo = lo.cwiseMin(point(i)), hi = hi.cwiseMax(point(i));
  int dim = 0;
  (hi - lo).maxCoeff(&dim);
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(entries.begin() + begin, entries.begin() + mid, entries.begin() + end,
                   [&](const Entry& a, const Entry& b) { return a.point[dim] < b.point[dim]; });
  const double split = entries[mid].point[dim];
  const std::int32_t left = build(entries, begin, mid, leaf_size);
  const std::int32_t right = build(entries, mid, end, leaf_size);
  Node& node = nodes_[id];
  node.left = left;
  node.right = right;
  node.split_dim = dim;
  node.split_value = split;
  return id;
}

// Depth-first search, the near child first, pruning against a shrinking squared bound; `visit(index, d2)`
// may lower it. min_d2 is the squared distance from the query to the node's box, kept per axis in
// axis_d2 so that a split updates it exactly: a node is skipped only when no point of its box can be
// within the bound.
template <typename Visit>
void KdTree::search(std::int32_t id, const Vec3& query, double min_d2, Vec3& axis_d2, double& bound2,
                    Visit& visit) const {
  const Node& node = nodes_[id];
  if (node.split_dim < 0) {
    for (std::uint32_t i = node.begin; i < node.end; ++i) {
      const double d2 = (ordered_[i] - query).squaredNorm();
      if (d2 <= bound2) visit(order_[i], d2);
    }
    return;
  }
  const int dim = node.split_dim;
  const double diff = query[dim] - node.split_value;
  search(diff < 0 ? node.left : node.right, query, min_d2, axis_d2, bound2, visit);
  const double previous = axis_d2[dim];
  const double far_d2 = min_d2 - previous + diff * diff;
  // The box distance is rounded differently from a point's: a margin of a few ulps keeps a point at
  // exactly the bound (a tie, broken by index) from being pruned.
  if (far_d2 > bound2 * (1.0 + 1e-12)) return;
  axis_d2[dim] = diff * diff;
  search(diff < 0 ? node.right : node.left, query, far_d2, axis_d2, bound2, visit);
  axis_d2[dim] = previous;
}

template <typename Visit>
void KdTree::search(const Vec3& query, double& bound2, Visit&& visit) const {
  if (nodes_.empty()) return;
  Vec3 axis_d2 = Vec3::Zero();
  search(0, query, 0.0, axis_d2, bound2, visit);
}

KdTree::Neighbor KdTree::nearest(const Vec3& query, double max_distance) const {
  Neighbor best{npos, std::numeric_limits<double>::infinity()};
  double bound2 = max_distance * max_distance;
  search(query, bound2, [&](std::uint32_t index, double d2) {
    if (d2 < best.distance2 || (d2 == best.distance2 && index < best.index)) {
      best = {index, d2};
      bound2 = d2;
    }
  });
  return best;
}

std::vector<KdTree::Neighbor> KdTree::knn(const Vec3& query, int k) const {
  if (k <= 0) return {};
  KNearest nearest(k);
  knn(query, nearest);
  return nearest.take();
}

void KdTree::knn(const Vec3& query, KNearest& nearest) const {
  nearest.clear();
  double bound2 = std::numeric_limits<double>::infinity();
  if (!nearest.full()) search(query, bound2, [&](std::uint32_t index, double d2) { nearest.offer(index, d2, bound2); });
}

KNearest::KNearest(int k) : k_(std::max(k, 0)) { kept_.reserve(k_ + 1); }

std::size_t KdTree::count_within(const Vec3& query, double radius, std::size_t enough) const {
  std::size_t count = 0;
  double bound2 = radius * radius;
  search(query, bound2, [&](std::uint32_t, double) {
    if (++count >= enough) bound2 = -1.0;  // stop: every remaining node is pruned
  });
  return count;
}

std::vector<std::uint32_t> KdTree::within(const Vec3& query, double radius) const {
  std::vector<std::uint32_t> found;
  double bound2 = radius * radius;
  search(query, bound2, [&](std::uint32_t index, double) { found.push_back(index); });
  return found;
}

}  // namespace toolinc
