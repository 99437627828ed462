#include "toolinc/appearance/depth_shape.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "toolinc/core/scatter.hpp"

namespace toolinc {
namespace {

constexpr std::size_t kMinPoints = 20;  // fewer: no shape worth describing (a few stray disparities)
constexpr int kExtents = 6;
constexpr int kAxisRefinements = 5;  // the band moves with the axis; 5 passes settle it (median error 1 deg)

struct Axis {
  Eigen::Vector3d origin, direction;  // direction towards the far end
  double far = 0, near = 0;           // the points' extreme coordinates along it
};

Eigen::Vector3d principal_direction(const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d& mean) {
  const Scatter<3> s = scatter_of<3>(points.size(), [&](std::size_t i) { return points[i]; });
  mean = s.mean;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(s.scatter).eigenvectors().col(2);
}

void set_extremes(const std::vector<Eigen::Vector3d>& points, Axis& axis) {
  axis.far = -1e9, axis.near = 1e9;
  for (const auto& p : points) {
    const double s = (p - axis.origin).dot(axis.direction);
    axis.far = std::max(axis.far, s), axis.near = std::min(axis.near, s);
  }
}

// The whole tool's principal axis, pointing away from the hand (the origin), then the handle band's.
Axis handle_axis(const std::vector<Eigen::Vector3d>& points, const DepthShapeConfig& c) {
  Axis axis;
  Eigen::Vector3d centroid;  // the whole tool's, kept for the hand check below
  axis.direction = principal_direction(points, centroid);
  axis.origin = centroid;
  if (axis.origin.dot(axis.direction) < 0) axis.direction = -axis.direction;
  for (int pass = 0; pass < kAxisRefinements; ++pass) {
    set_extremes(points, axis);
    std::vector<Eigen::Vector3d> band;
    for (const auto& p : points) {
      const Eigen::Vector3d d = p - axis.origin;
      const double along = d.dot(axis.direction), from_far = axis.far - along;
      if (from_far >= c.handle_near && from_far <= c.handle_far &&
          (pass == 0 || (d - along * axis.direction).norm() <= c.handle_trim))
        band.push_back(p);
    }
    if (band.size() < kMinPoints) break;
    const Eigen::Vector3d direction = principal_direction(band, axis.origin);
    axis.direction = direction.dot(axis.direction) < 0 ? -direction : direction;
  }
  // The hand holds the handle, so its line passes near the hand. A line farther away was fitted to the
  // head alone (a view down the handle, the handle hidden behind the head): the line from the hand
  // through the tool's centroid is then the better guess (43-90 degrees off -> 2-20).
  const Eigen::Vector3d from_hand = axis.origin - axis.origin.dot(axis.direction) * axis.direction;
  if (from_hand.norm() > c.grasp_reach && centroid.squaredNorm() > 0)
    axis.origin = Eigen::Vector3d::Zero(), axis.direction = centroid.normalized();
  set_extremes(points, axis);
  return axis;
}

// The points outside the hand's box.
std::vector<Eigen::Vector3d> tool_points(const std::vector<Eigen::Vector3d>& points, const DepthShapeConfig& c) {
  std::vector<Eigen::Vector3d> tool;
  for (const auto& p : points)
    if (((p - c.hand_min).array() < -c.hand_margin).any() || ((p - c.hand_max).array() > c.hand_margin).any())
      tool.push_back(p);
  return tool;
}

int bin(double value, double step, int bins) {
  return std::clamp(static_cast<int>(std::floor(value / step)), 0, bins - 1);
}

}  // namespace

int depth_shape_dimension(const DepthShapeConfig& c) {
  return kExtents + c.head_bins * c.radial_bins + c.head_bins * c.footprint_bins * c.footprint_depth_bins;
}

std::optional<Eigen::Vector3d> depth_shape_axis(const std::vector<Eigen::Vector3d>& points, const DepthShapeConfig& c) {
  const std::vector<Eigen::Vector3d> tool = tool_points(points, c);
  if (tool.size() < kMinPoints) return std::nullopt;
  return handle_axis(tool, c).direction;
}

Eigen::VectorXd depth_shape(const std::vector<Eigen::Vector3d>& points, const DepthShapeConfig& c) {
  Eigen::VectorXd block = Eigen::VectorXd::Zero(depth_shape_dimension(c));
  const std::vector<Eigen::Vector3d> tool = tool_points(points, c);
  if (tool.size() < kMinPoints) return block;
  const Axis axis = handle_axis(tool, c);
  // The head in cylindrical-like coordinates: distance from the far end, and the 2D offset across.
  const Eigen::Vector3d across_1 = axis.direction.unitOrthogonal(), across_2 = axis.direction.cross(across_1);
  std::vector<double> along;
  std::vector<Eigen::Vector2d> across;
  for (const auto& p : tool) {
    const Eigen::Vector3d d = p - axis.origin;
    const double from_far = axis.far - d.dot(axis.direction);
    if (from_far <= c.head_length) along.push_back(from_far), across.emplace_back(d.dot(across_1), d.dot(across_2));
  }
  const auto n = static_cast<double>(along.size());  // not empty: the far end is in the head
  const Scatter<2> spread = scatter_of<2>(across.size(), [&](std::size_t i) { return across[i]; });
  const Scatter<1> length =
      scatter_of<1>(along.size(), [&](std::size_t i) { return Eigen::Matrix<double, 1, 1>(along[i]); });
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> head(spread.scatter / n);
  Eigen::Vector2d main = head.eigenvectors().col(1);
  const Eigen::Vector2d second = head.eigenvectors().col(0);
  double skew = 0, farthest = 0;
  for (const auto& q : across) skew += std::pow(q.dot(main), 3), farthest = std::max(farthest, q.norm());
  if (skew < 0) main = -main;
  const int radial_at = kExtents, footprint_at = radial_at + c.head_bins * c.radial_bins;
  const double head_step = c.head_length / c.head_bins;
  for (std::size_t i = 0; i < along.size(); ++i) {
    const int h = bin(along[i], head_step, c.head_bins);
    block[radial_at + h * c.radial_bins + bin(across[i].norm(), c.across_step, c.radial_bins)] += 1;
    const int side = bin(across[i].dot(main) / c.across_step + c.footprint_bins / 2, 1.0, c.footprint_bins);
    const int depth = bin(std::abs(across[i].dot(second)), c.across_step, c.footprint_depth_bins);
    block[footprint_at + (h * c.footprint_bins + side) * c.footprint_depth_bins + depth] += 1;
  }
  block.tail(block.size() - kExtents) = (block.tail(block.size() - kExtents) / n).cwiseSqrt();
  block.head(kExtents) << spread.mean.norm(), head.eigenvalues().reverse().cwiseMax(0).cwiseSqrt(),
      std::sqrt(length.scatter(0, 0) / n), farthest, (axis.far - axis.near) / 3;
  block.head(kExtents) /= c.unit;
  return block.normalized();
}

}  // namespace toolinc
