#include "toolinc/appearance/depth_shape.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace toolinc {

Eigen::VectorXd depth_shape(const std::vector<Eigen::Vector3d>& points, const DepthShapeConfig& c) {
  Eigen::VectorXd block = Eigen::VectorXd::Zero(6 + c.radial_bins);
  if (points.size() < 3) return block;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& p : points) covariance += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> blob(covariance / static_cast<double>(points.size()));
  const Eigen::Vector3d major = blob.eigenvectors().col(2) * (blob.eigenvectors()(1, 2) > 0 ? -1.0 : 1.0);  // towards the top
  double lo = 0, hi = 0;
  for (const auto& p : points) lo = std::min(lo, (p - mean).dot(major)), hi = std::max(hi, (p - mean).dot(major));
  // The head's points across the major axis, in the blob's two minor directions.
  std::vector<Eigen::Vector2d> across;
  for (const auto& p : points)
    if ((p - mean).dot(major) >= hi - c.head_share * (hi - lo))
      across.emplace_back((p - mean).dot(blob.eigenvectors().col(1)), (p - mean).dot(blob.eigenvectors().col(0)));
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const auto& q : across) centre += q;
  centre /= static_cast<double>(across.size());  // not empty: the top point is in the head
  Eigen::Matrix2d head = Eigen::Matrix2d::Zero();
  for (const auto& q : across) {
    head += (q - centre) * (q - centre).transpose();
    block[6 + std::min(c.radial_bins - 1, static_cast<int>((q - centre).norm() / c.radial_step))] += 1;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> head_spread(head / static_cast<double>(across.size()));
  block.head(3) = blob.eigenvalues().cwiseMax(0).cwiseSqrt() / c.unit;
  block.segment(3, 2) = head_spread.eigenvalues().cwiseMax(0).cwiseSqrt() / c.unit;
  block[5] = (hi - lo) / c.unit;
  block.tail(c.radial_bins) = (block.tail(c.radial_bins) / static_cast<double>(across.size())).cwiseSqrt();
  return block.normalized();
}

}  // namespace toolinc
