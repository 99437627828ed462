#include "toolinc/cloud/preprocessing.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/scatter.hpp"

namespace toolinc {

namespace {

// The mean of each run of points with equal keys, keyed sorted by key then index, so that the result does
// not depend on the input's order; with masks, each run's union of them in voxel_masks.
template <typename Key>
Points voxel_means(const std::vector<std::pair<Key, std::uint32_t>>& keyed, const Points& points,
                   const std::vector<std::uint32_t>* masks, std::vector<std::uint32_t>* voxel_masks) {
  Points out;
  for (std::size_t begin = 0; begin < keyed.size();) {
    std::size_t end = begin;
    Vec3 sum = Vec3::Zero();
    std::uint32_t mask = 0;
    for (; end < keyed.size() && keyed[end].first == keyed[begin].first; ++end) {
      sum += points[keyed[end].second];
      if (masks) mask |= (*masks)[keyed[end].second];
    }
    out.push_back(sum / static_cast<double>(end - begin));
    if (voxel_masks) voxel_masks->push_back(mask);
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

using CellKey = std::array<std::int64_t, 3>;

// The cell of a grid `size` a side that holds p. Beyond 2^62 cells the cast to int64 is undefined (and NaN
// never fits): a cell far too small for the points, or points from outside any physical range; the error
// names the parameter that set the size.
CellKey cell_of(const Vec3& p, double size, const char* parameter, double value) {
  const Eigen::Vector3d c = (p / size).array().floor();
  if (!(c.cwiseAbs().maxCoeff() < 0x1p62))
    throw std::invalid_argument(
        fmt::format("{} {} m is too small for a point at ({}, {}, {}) m", parameter, value, p.x(), p.y(), p.z()));
  return {static_cast<std::int64_t>(c.x()), static_cast<std::int64_t>(c.y()), static_cast<std::int64_t>(c.z())};
}

// voxel_downsample, with the voxels' masks when masks are given.
Points downsample(const Points& points, double voxel_size, const std::vector<std::uint32_t>* masks,
                  std::vector<std::uint32_t>* voxel_masks) {
  using Cell = Eigen::Matrix<std::int64_t, 3, 1>;
  std::vector<Cell> cells(points.size());
  Cell lo = Cell::Constant(std::numeric_limits<std::int64_t>::max()), hi = -lo;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const CellKey key = cell_of(points[i], voxel_size, "voxel size", voxel_size);
    cells[i] = Cell(key[0], key[1], key[2]);
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
    return voxel_means(keyed, points, masks, voxel_masks);
  }
  std::vector<std::pair<CellKey, std::uint32_t>> keyed(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) keyed[i] = {{cells[i].x(), cells[i].y(), cells[i].z()}, i};
  std::sort(keyed.begin(), keyed.end());
  return voxel_means(keyed, points, masks, voxel_masks);
}

// A cell's key hashed: its coordinates mixed by large odd multipliers.
struct CellHash {
  std::size_t operator()(const CellKey& key) const {
    return static_cast<std::size_t>(key[0] * 0x9E3779B97F4A7C15ull ^ key[1] * 0xC2B2AE3D27D4EB4Full ^
                                    key[2] * 0x165667B19E3779F9ull);
  }
};

// Cells numbered as first met, found by key in a flat table of numbers probed linearly, with at least twice
// as many slots as cells: unlike a hash map's node per cell, it allocates once.
class CellNumbers {
 public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  explicit CellNumbers(std::size_t most_cells) {
    while (slots_ < 2 * most_cells) slots_ *= 2;
    number_at_.assign(slots_, kNone);
  }
  // The cell's number, numbering it if it is new.
  std::uint32_t number(const CellKey& key) {
    const std::size_t slot = slot_of(key);
    if (number_at_[slot] == kNone) {
      number_at_[slot] = static_cast<std::uint32_t>(keys_.size());
      keys_.push_back(key);
    }
    return number_at_[slot];
  }
  // The cell's number, kNone if it has none.
  std::uint32_t find(const CellKey& key) const { return number_at_[slot_of(key)]; }
  std::size_t size() const { return keys_.size(); }

 private:
  std::size_t slot_of(const CellKey& key) const {
    std::size_t slot = CellHash{}(key) & (slots_ - 1);
    while (number_at_[slot] != kNone && keys_[number_at_[slot]] != key) slot = (slot + 1) & (slots_ - 1);
    return slot;
  }

  std::size_t slots_ = 1;
  std::vector<std::uint32_t> number_at_;  // per slot
  std::vector<CellKey> keys_;             // per cell
};

// The pieces of points joined through points at most gap apart, numbered from 0 (count of them in pieces).
// Points sharing a block of gap / 2 a side lie within 0.87 gap of each other, so each block is one piece
// and only pairs of points in different blocks within reach need a check: the pieces of checking every
// pair, for a fraction of the distances.
std::vector<std::uint32_t> joined_within(const Points& points, double gap, std::uint32_t& pieces) {
  std::map<CellKey, std::uint32_t> block_of_key;
  std::vector<std::uint32_t> block(points.size());
  std::vector<std::vector<std::uint32_t>> members;
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    const auto [it, added] = block_of_key.try_emplace(cell_of(points[i], gap / 2.0, "piece gap", gap),
                                                      static_cast<std::uint32_t>(members.size()));
    if (added) members.emplace_back();
    block[i] = it->second;
    members[it->second].push_back(i);
  }
  // Union-find over the blocks.
  std::vector<std::uint32_t> parent(members.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto root = [&](std::uint32_t b) {
    while (parent[b] != b) b = parent[b] = parent[parent[b]];
    return b;
  };
  const double gap2 = gap * gap;
  const auto touch = [&](std::uint32_t a, std::uint32_t b) {
    for (const auto i : members[a])
      for (const auto j : members[b])
        if ((points[j] - points[i]).squaredNorm() <= gap2) return true;
    return false;
  };
  // Blocks 4 or more apart along an axis hold points over 1.5 gap apart; 3 apart, rounding aside, over gap.
  // Neighbouring blocks are joined first: the farther pairs are then mostly one piece already, unchecked.
  for (const std::int64_t apart : {1, 3})
    for (auto a = block_of_key.begin(); a != block_of_key.end(); ++a)
      for (auto b = std::next(a); b != block_of_key.end() && b->first[0] - a->first[0] <= apart; ++b)
        if (std::abs(b->first[1] - a->first[1]) <= apart && std::abs(b->first[2] - a->first[2]) <= apart &&
            root(a->second) != root(b->second) && touch(a->second, b->second))
          parent[root(a->second)] = root(b->second);
  std::vector<std::uint32_t> number(members.size(), std::numeric_limits<std::uint32_t>::max()), piece(points.size());
  pieces = 0;
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    auto& n = number[root(block[i])];
    if (n == std::numeric_limits<std::uint32_t>::max()) n = pieces++;
    piece[i] = n;
  }
  return piece;
}

}  // namespace

Points voxel_downsample(const Points& points, double voxel_size) {
  return downsample(points, voxel_size, nullptr, nullptr);
}

Points voxel_downsample(const Points& points, double voxel_size, const std::vector<std::uint32_t>& masks,
                        std::vector<std::uint32_t>& voxel_masks) {
  if (masks.size() != points.size()) throw std::invalid_argument("voxel_downsample: one mask per point needed");
  voxel_masks.clear();
  return downsample(points, voxel_size, &masks, &voxel_masks);
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
  Points out;
  for (const auto i : non_isolated(points, radius, min_neighbors)) out.push_back(points[i]);
  return out;
}

std::vector<std::uint32_t> non_isolated(const Points& points, double radius, std::size_t min_neighbors) {
  // Cells a shade wider than the radius: a point's neighbours within it lie in its cell or the 26 around it,
  // rounding aside. Its own cell, searched first, mostly holds enough of them.
  const double cell_size = radius * (1.0 + 1e-9);
  std::vector<CellKey> key(points.size());
  CellNumbers numbers(points.size());
  std::vector<std::uint32_t> cell(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    key[i] = cell_of(points[i], cell_size, "radius", radius);
    cell[i] = numbers.number(key[i]);
  }
  // Each cell's points, by ascending index, side by side: a counting sort by cell.
  std::vector<std::uint32_t> first(numbers.size() + 1, 0), members(points.size());
  for (const auto c : cell) ++first[c + 1];
  for (std::size_t c = 1; c < first.size(); ++c) first[c] += first[c - 1];
  std::vector<std::uint32_t> next(first.begin(), first.end() - 1);
  for (std::uint32_t i = 0; i < points.size(); ++i) members[next[cell[i]]++] = i;
  const double r2 = radius * radius;
  const std::size_t enough = min_neighbors + 1;  // the point itself is counted, as a radius search counts it
  std::vector<std::uint32_t> kept;
  kept.reserve(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    std::size_t count = 0;
    for (int k = 0; k < 27 && count < enough; ++k) {
      const int dx = (k + 1) % 3 - 1, dy = (k / 3 + 1) % 3 - 1, dz = (k / 9 + 1) % 3 - 1;  // own cell first
      const std::uint32_t c = numbers.find({key[i][0] + dx, key[i][1] + dy, key[i][2] + dz});
      if (c == CellNumbers::kNone) continue;
      for (std::uint32_t m = first[c]; m < first[c + 1]; ++m)
        if ((points[members[m]] - points[i]).squaredNorm() <= r2 && ++count >= enough) break;
    }
    if (count >= enough) kept.push_back(i);
  }
  return kept;
}

HeldPiece held_piece(const Points& points, double hand_radius, double gap) {
  HeldPiece held;
  const double hand_r2 = hand_radius * hand_radius;
  std::vector<std::uint32_t> beyond;
  beyond.reserve(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i)
    if (points[i].squaredNorm() > hand_r2) beyond.push_back(i);
  if (gap <= 0.0 || beyond.empty()) {
    held.indices = std::move(beyond);
    return held;
  }
  // The pieces are joined on a grid an eighth of the gap fine, between the means of its cells: a dense
  // reconstruction has thousands of points within a gap of each, its cells a few hundred.
  const double cell_size = gap / 8.0;
  CellNumbers numbers(beyond.size());
  std::vector<std::uint32_t> cell(points.size());
  Points sums;
  std::vector<int> counts;
  for (const auto i : beyond) {
    cell[i] = numbers.number(cell_of(points[i], cell_size, "piece gap", gap));
    if (cell[i] == sums.size()) sums.push_back(Vec3::Zero()), counts.push_back(0);  // numbered now
    sums[cell[i]] += points[i];
    ++counts[cell[i]];
  }
  Points means(sums.size());
  for (std::size_t c = 0; c < sums.size(); ++c) means[c] = sums[c] / counts[c];
  std::uint32_t pieces = 0;
  const std::vector<std::uint32_t> piece = joined_within(means, gap, pieces);
  std::vector<double> nearest(pieces, std::numeric_limits<double>::infinity());  // from the hand
  std::vector<int> sizes(pieces, 0);
  for (const auto i : beyond) {
    const std::uint32_t p = piece[cell[i]];
    nearest[p] = std::min(nearest[p], points[i].norm());
    ++sizes[p];
  }
  const double reach = *std::min_element(nearest.begin(), nearest.end()) + gap;
  held.indices.reserve(beyond.size());
  for (const auto i : beyond)
    if (nearest[piece[cell[i]]] <= reach) held.indices.push_back(i);
  for (std::uint32_t p = 0; p < pieces; ++p)
    if (nearest[p] > reach) held.detached_points += sizes[p], ++held.detached_pieces;
  return held;
}

std::vector<std::uint32_t> statistical_inliers(const Points& points, int k, double std_multiplier) {
  std::vector<std::uint32_t> kept(points.size());
  std::iota(kept.begin(), kept.end(), 0u);
  if (points.size() <= static_cast<std::size_t>(k)) return kept;
  const KdTree tree(points);
  std::vector<double> mean_distance(points.size());
  KNearest nearest(k + 1);  // the first is the point itself
  for (std::size_t i = 0; i < points.size(); ++i) {
    tree.knn(points[i], nearest);
    const auto& neighbors = nearest.kept();
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
