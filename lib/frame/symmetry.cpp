#include "frame/symmetry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "toolinc/cloud/preprocessing.hpp"

namespace toolinc {

namespace {

// At most this many cells along the box's longest side (kSlicesPerCell times as many slices along z): a far
// stray point does not make the grid huge.
constexpr double kMaxCellsAlong = 64.0;
// Cells a shade wider than the tolerance, so that rounding cannot put a point within it two cells away.
constexpr double kCellMargin = 1e-9;
// Cells are cut this many times thinner along z: a row of them holds its points in z order, so a lookup
// scans only those within its bound's reach along z, which shrinks to the nearest point's distance once
// that is found, rather than three cells' depth.
constexpr int kSlicesPerCell = 4;

}  // namespace

MirrorTarget::MirrorTarget(const Points& points, double tolerance, int normal_neighbors)
    : points_(points),
      tolerance_(tolerance),
      normal_neighbors_(normal_neighbors),
      neighbours_(normal_neighbors),
      normals_(normal_neighbors > 0 ? points.size() : 0),
      normal_known_(normals_.size(), false) {
  if (points.empty()) return;
  low_ = points[0];
  Vec3 high = low_;
  for (const auto& p : points) low_ = low_.cwiseMin(p), high = high.cwiseMax(p);
  cell_ = std::max({tolerance * (1.0 + kCellMargin), (high - low_).maxCoeff() / kMaxCellsAlong, 1e-9});
  size_ = Eigen::Array3d(cell_, cell_, cell_ / kSlicesPerCell);
  cells_ = ((high - low_).array() / size_).floor().cast<int>() + 1;
  const auto slice_of = [&](const Vec3& p) -> Eigen::Array3i {
    return ((p - low_).array() / size_).floor().cast<int>().min(cells_ - 1);
  };
  const auto cell_of = [&](const Vec3& p) {
    const Eigen::Array3i c = slice_of(p);
    return (static_cast<std::size_t>(c.x()) * cells_.y() + c.y()) * cells_.z() + c.z();
  };
  // A counting sort by cell, stable: each cell lists its points by ascending index.
  cell_begin_.assign(static_cast<std::size_t>(cells_.prod()) + 1, 0);
  for (const auto& p : points) ++cell_begin_[cell_of(p) + 1];
  for (std::size_t c = 1; c < cell_begin_.size(); ++c) cell_begin_[c] += cell_begin_[c - 1];
  std::vector<std::uint32_t> next(cell_begin_.begin(), cell_begin_.end() - 1);
  by_cell_.resize(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) by_cell_[next[cell_of(points[i])]++] = i;
  cell_points_.reserve(points.size());
  for (const auto i : by_cell_) cell_points_.push_back(points[i]);
  blocks_ = Eigen::Array3i(cells_.x(), cells_.y(), (cells_.z() + kSlicesPerCell - 1) / kSlicesPerCell) + 2;
  points_near_.assign(static_cast<std::size_t>(blocks_.prod()), 0);
  // From a block's index, less one along each axis, to its own and its 26 neighbours' in points_near_.
  std::vector<std::size_t> around;
  for (int dx = 0; dx < 3; ++dx)
    for (int dy = 0; dy < 3; ++dy)
      for (int dz = 0; dz < 3; ++dz)
        around.push_back((static_cast<std::size_t>(dx) * blocks_.y() + dy) * blocks_.z() + dz);
  // The points slice after slice: those of a block mostly follow one another, and it is marked around once.
  std::size_t last = std::numeric_limits<std::size_t>::max();
  for (const auto& p : cell_points_) {
    const Eigen::Array3i c = slice_of(p);
    const std::size_t block =
        (static_cast<std::size_t>(c.x()) * blocks_.y() + c.y()) * blocks_.z() + c.z() / kSlicesPerCell;
    if (block == last) continue;
    last = block;
    for (const auto offset : around) points_near_[block + offset] = 1;
  }
}

template <typename Visit>
void MirrorTarget::scan(const Vec3& query, double& bound2, Visit&& visit) const {
  const Eigen::Array2d at = ((query - low_).head<2>().array() / cell_).floor();
  if (points_.empty() || !query.allFinite() || (at < -1.0).any() || (at > cells_.head<2>().cast<double>()).any())
    return;
  // Per axis x and y, the query's cell and its two neighbours, each with the squared distance from the
  // query to its side (less a margin for rounding): no point of a cell lies nearer than the sum over the axes.
  const double margin = kCellMargin * cell_;
  int index[2][3];
  double gap2[2][3];
  for (int a = 0; a < 2; ++a) {
    const auto c = static_cast<int>(at[a]);
    const double inside = query[a] - (low_[a] + c * cell_);
    const double below = std::max(0.0, inside - margin), above = std::max(0.0, cell_ - inside - margin);
    index[a][0] = c, index[a][1] = c - 1, index[a][2] = c + 1;
    gap2[a][0] = 0.0, gap2[a][1] = below * below, gap2[a][2] = above * above;
  }
  // Each row is scanned nearest first: the three slices about the query's height, then the rest of its
  // reach above and below them only when the bound, lowered by what they held, still reaches beyond them.
  const double height = (query.z() - low_.z()) / size_.z();  // in slices
  const double middle = std::floor(height);
  // Mirror images off the cloud mostly lie in a block with no point near, and nothing is within a cell of
  // them. The query's block along z, in points_near_'s numbering: middle, a whole number, clamped to two
  // blocks beyond the grid's ends so that it is not negative and the integer division rounds it down.
  const int beyond = 2 * kSlicesPerCell;
  const int block = (static_cast<int>(std::clamp(middle, -1.0 * beyond, 1.0 * kSlicesPerCell * blocks_.z())) + beyond) /
                        kSlicesPerCell -
                    1;
  if (block < 0 || block >= blocks_.z() ||
      !points_near_[(static_cast<std::size_t>(index[0][0] + 1) * blocks_.y() + (index[1][0] + 1)) * blocks_.z() +
                    block])
    return;
  // A slice's index, or one beyond the grid's either end.
  const auto slice = [&](double at) { return static_cast<int>(std::clamp(at, -1.0, static_cast<double>(cells_.z()))); };
  const int near_first = slice(middle - 1.0), near_last = slice(middle + 1.0);
  // A point nearer the query than this along z lies in those three slices.
  const double clear = std::min(height - (middle - 1.0), middle + 2.0 - height) * size_.z() - margin;
  for (int i = 0; i < 3; ++i) {
    const int x = index[0][i];
    if (x < 0 || x >= cells_.x() || gap2[0][i] > bound2) continue;
    for (int j = 0; j < 3; ++j) {
      const int y = index[1][j];
      const double xy = gap2[0][i] + gap2[1][j];
      if (y < 0 || y >= cells_.y() || xy > bound2) continue;
      // The row's points lie side by side in by_cell_ in z order: those within the bound lie within
      // sqrt(bound2 - xy) of the query along z, one run of slices.
      const std::size_t row = (static_cast<std::size_t>(x) * cells_.y() + y) * cells_.z();
      const auto slices = [&](int first, int last) {
        first = std::max(first, 0), last = std::min(last, cells_.z() - 1);
        if (first > last) return;
        const std::uint32_t end = cell_begin_[row + last + 1];
        for (std::uint32_t n = cell_begin_[row + first]; n < end; ++n) {
          const double d2 = (cell_points_[n] - query).squaredNorm();
          if (d2 <= bound2) visit(by_cell_[n], d2);
        }
      };
      slices(near_first, near_last);
      const double left = bound2 - xy;
      if (left <= clear * clear) continue;
      const double reach = (std::sqrt(left) + margin) / size_.z();
      slices(slice(std::floor(height - reach)), near_first - 1);
      slices(near_last + 1, slice(std::floor(height + reach)));
    }
  }
}

KdTree::Neighbor MirrorTarget::nearest(const Vec3& query) const {
  KdTree::Neighbor best{KdTree::npos, std::numeric_limits<double>::infinity()};
  double bound2 = tolerance_ * tolerance_;
  scan(query, bound2, [&](std::uint32_t index, double d2) {
    if (d2 < best.distance2 || (d2 == best.distance2 && index < best.index)) {
      best = {index, d2};
      bound2 = d2;
    }
  });
  return best;
}

const Vec3& MirrorTarget::normal(std::uint32_t index) const {
  if (!normal_known_[index]) {
    find_neighbours(points_[index], neighbours_);
    normals_[index] = normal_of(points_, neighbours_.kept());
    normal_known_[index] = true;
  }
  return normals_[index];
}

std::vector<KdTree::Neighbor> MirrorTarget::neighbours(const Vec3& point) const {
  KNearest nearest(normal_neighbors_);
  find_neighbours(point, nearest);
  return nearest.take();
}

void MirrorTarget::find_neighbours(const Vec3& point, KNearest& nearest) const {
  // Every point within a cell's width of the query (less the margin, twice: once for the query's own cell)
  // lies in the cells a scan visits: when normal_neighbors of them are that near, they are the nearest,
  // and the grid finds them for a fraction of the kd-tree's search. Otherwise the tree does.
  nearest.clear();
  double bound2 = std::pow(cell_ * (1.0 - 2.0 * kCellMargin), 2);
  scan(point, bound2, [&](std::uint32_t index, double d2) { nearest.offer(index, d2, bound2); });
  if (nearest.full()) return;
  if (!tree_) tree_.emplace(points_);
  tree_->knn(point, nearest);
}

SymmetryScorer::SymmetryScorer(const MirrorTarget& target, std::size_t samples, double match_weight,
                               const FreeSpace* free_space, const std::vector<std::uint32_t>* mirrored)
    : target_(target), match_weight_(match_weight), free_space_(free_space) {
  const std::size_t n = mirrored ? mirrored->size() : target.points().size();
  const std::size_t count = std::min(n, std::max<std::size_t>(samples, 1));
  samples_.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const auto k = static_cast<std::uint32_t>(i * n / count);
    samples_.push_back(mirrored ? (*mirrored)[k] : k);
  }
}

double SymmetryScorer::score(const Vec3& normal, const Vec3& point_on_plane) const {
  return score(normal, point_on_plane, nullptr);
}

double SymmetryScorer::score(const Vec3& normal, const Vec3& point_on_plane, std::vector<Image>* record,
                             const Recorded* known) const {
  double sum = 0.0;
  std::size_t evidence = 0;
  std::size_t j = 0;  // into known
  for (const std::uint32_t index : samples_) {
    if (known)
      while (j < known->samples.size() && known->samples[j] < index) ++j;
    const Image image = known && j < known->samples.size() && known->samples[j] == index
                            ? known->images[j]
                            : this->image(index, normal, point_on_plane);
    if (record) record->push_back(image);
    sum += image.cost;  // 0 for an image that is no evidence, which leaves the sum as it is
    evidence += image.evidence;
  }
  return evidence == 0 ? 1.0 : sum / static_cast<double>(evidence);
}

SymmetryScorer::Image SymmetryScorer::image(std::uint32_t index, const Vec3& normal, const Vec3& point_on_plane) const {
  const Vec3& p = target_.points()[index];
  const Vec3 mirrored = mirror_image(p, normal, point_on_plane);
  const auto nearest = target_.nearest(mirrored);
  if (nearest.index != KdTree::npos) {
    double distance = std::sqrt(nearest.distance2);
    if (target_.normal_neighbors() > 0)
      distance = std::abs(target_.normal(nearest.index).dot(mirrored - target_.points()[nearest.index]));
    return {match_weight_ * distance / target_.tolerance(), true};
  }
  if (free_space_ == nullptr || free_space_->seen(mirrored)) return {1.0, true};
  return {};
}

}  // namespace toolinc
