#include "toolinc/cloud/preprocessing.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/scatter.hpp"

namespace toolinc {

namespace {

// The mean of each run of points with equal keys, keyed sorted by key then index, so that the result does
// not depend on the input's order.
template <typename Key>
Points voxel_means(const std::vector<std::pair<Key, std::uint32_t>>& keyed, const Points& points) {
  Points out;
  for (std::size_t begin = 0; begin < keyed.size();) {
    std::size_t end = begin;
    Vec3 sum = Vec3::Zero();
    for (; end < keyed.size() && keyed[end].first == keyed[begin].first; ++end) sum += points[keyed[end].second];
    out.push_back(sum / static_cast<double>(end - begin));
    begin = end;
  }
  return out;
}

// Least-significant-digit radix sort by key, 11 bits a pass, over the bits below max_key only. Stable: the
// pairs come in index order, so the result is that of sorting by (key, index).
void radix_sort(std::vector<std::pair<std::uint64_t, std::uint32_t>>& keyed, std::uint64_t max_key) {
  constexpr int kBits = 11;
  constexpr std::size_t kDigits = std::size_t{1} << kBits;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted(keyed.size());
  for (int shift = 0; shift < 64 && (max_key >> shift) != 0; shift += kBits) {
    std::array<std::size_t, kDigits> start{};
    for (const auto& k : keyed) ++start[(k.first >> shift) & (kDigits - 1)];
    std::size_t total = 0;
    for (auto& s : start) total += std::exchange(s, total);
    for (const auto& k : keyed) sorted[start[(k.first >> shift) & (kDigits - 1)]++] = k;
    keyed.swap(sorted);
  }
}

}  // namespace

Points voxel_downsample(const Points& points, double voxel_size) {
  using Cell = Eigen::Matrix<std::int64_t, 3, 1>;
  std::vector<Cell> cells(points.size());
  Cell lo = Cell::Constant(std::numeric_limits<std::int64_t>::max()), hi = -lo;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d cell = (points[i] / voxel_size).array().floor();
    // Beyond 2^62 cells the cast to int64 is undefined (and NaN never fits): a voxel far too small for
    // the points, or points from outside any physical range.
    if (!(cell.cwiseAbs().maxCoeff() < 0x1p62))
      throw std::invalid_argument(fmt::format("voxel size {} m is too small for a point at ({}, {}, {}) m", voxel_size,
                                              points[i].x(), points[i].y(), points[i].z()));
    cells[i] = cell.cast<std::int64_t>();
    lo = lo.cwiseMin(cells[i]);
    hi = hi.cwiseMax(cells[i]);
  }
  // The cells numbered x then y then z within the cloud's box, as the three keys order them, when that
  // number fits in 63 bits (a box of 2^21 voxels a side: 8 km at 4 mm): one integer, radix-sorted.
  const Cell span = points.empty() ? Cell::Ones() : Cell(hi - lo + Cell::Ones());
  if (static_cast<long double>(span.x()) * span.y() * span.z() < 0x1p63L) {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
    std::uint64_t max_key = 0;
    for (std::uint32_t i = 0; i < points.size(); ++i) {
      const Cell c = cells[i] - lo;
      keyed[i] = {static_cast<std::uint64_t>((c.x() * span.y() + c.y()) * span.z() + c.z()), i};
      max_key = std::max(max_key, keyed[i].first);
    }
    radix_sort(keyed, max_key);
    return voxel_means(keyed, points);
  }
  std::vector<std::pair<std::array<std::int64_t, 3>, std::uint32_t>> keyed(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) keyed[i] = {{cells[i].x(), cells[i].y(), cells[i].z()}, i};
  std::sort(keyed.begin(), keyed.end());
  return voxel_means(keyed, points);
}

Points remove_within(const Points& points, const Vec3& center, double radius) {
  Points out;
  out.reserve(points.size());
  const double r2 = radius * radius;
  for (const auto& p : points)
    if ((p - center).squaredNorm() > r2) out.push_back(p);
  return out;
}

Points remove_isolated(const Points& points, double radius, std::size_t min_neighbors) {
  const KdTree tree(points);
  Points out;
  out.reserve(points.size());
  for (const auto& p : points)  // the point itself is counted by the tree, hence the + 1
    if (tree.count_within(p, radius, min_neighbors + 1) >= min_neighbors + 1) out.push_back(p);
  return out;
}

std::vector<std::uint32_t> statistical_inliers(const Points& points, int k, double std_multiplier) {
  std::vector<std::uint32_t> kept(points.size());
  std::iota(kept.begin(), kept.end(), 0u);
  if (points.size() <= static_cast<std::size_t>(k)) return kept;
  const KdTree tree(points);
  std::vector<double> mean_distance(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto neighbors = tree.knn(points[i], k + 1);  // the first is the point itself
    double sum = 0.0;
    for (std::size_t j = 1; j < neighbors.size(); ++j) sum += std::sqrt(neighbors[j].distance2);
    mean_distance[i] = sum / static_cast<double>(neighbors.size() - 1);
  }
  const double n = static_cast<double>(points.size());
  const double mean = std::accumulate(mean_distance.begin(), mean_distance.end(), 0.0) / n;
  double var = 0.0;
  for (double d : mean_distance) var += (d - mean) * (d - mean);
  const double threshold = mean + std_multiplier * std::sqrt(var / (n - 1.0));
  kept.clear();
  for (std::uint32_t i = 0; i < points.size(); ++i)
    if (mean_distance[i] <= threshold) kept.push_back(i);
  return kept;
}

Vec3 normal_at(const KdTree& tree, const Vec3& point, int k) { return normal_of(tree.points(), tree.knn(point, k)); }

Vec3 normal_of(const Points& points, const std::vector<KdTree::Neighbor>& neighbours) {
  if (neighbours.size() < 3) return Vec3::UnitZ();
  const auto spread = scatter_of<3>(neighbours.size(), [&](std::size_t j) { return points[neighbours[j].index]; });
  // The closed-form 3x3 solver: several times faster than the iterative one, and accurate enough
  // for the smallest eigenvector of a neighbourhood's spread.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(spread.scatter);
  return solver.eigenvectors().col(0);
}

Points estimate_normals(const Points& points, int k) {
  const KdTree tree(points);
  Points normals(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) normals[i] = normal_at(tree, points[i], k);
  return normals;
}

Points transform_points(const Points& points, const Eigen::Matrix4d& target_from_source) {
  const Eigen::Matrix3d rotation = target_from_source.topLeftCorner<3, 3>();
  const Vec3 translation = target_from_source.topRightCorner<3, 1>();
  Points out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = rotation * points[i] + translation;
  return out;
}

PrincipalAxes principal_axes(const Points& points) {
  PrincipalAxes result;
  if (points.empty()) return result;
  const auto spread = scatter_of<3>(points.size(), [&](std::size_t i) { return points[i]; });
  result.centroid = spread.mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(
      spread.scatter / static_cast<double>(std::max<std::size_t>(points.size() - 1, 1)));
  // Eigen sorts ascending; reverse to major, middle, minor and make the triple right-handed.
  result.eigenvalues = solver.eigenvalues().reverse().cwiseMax(0.0);
  result.axes = solver.eigenvectors().rowwise().reverse();
  result.axes.col(2) = result.axes.col(0).cross(result.axes.col(1));
  return result;
}

}  // namespace toolinc
