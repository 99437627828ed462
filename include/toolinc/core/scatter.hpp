// The mean and scatter of a set of vectors: what principal axes, normals and line fits are made of.
#pragma once

#include <Eigen/Core>
#include <cstddef>

namespace toolinc {

template <int D>
struct Scatter {
  Eigen::Matrix<double, D, 1> mean = Eigen::Matrix<double, D, 1>::Zero();
  Eigen::Matrix<double, D, D> scatter = Eigen::Matrix<double, D, D>::Zero();  // sum of (x - mean)(x - mean)^T
};

// Over the n vectors at(0), ..., at(n - 1) (n > 0), in two passes for accuracy far from the origin.
template <int D, typename At>
Scatter<D> scatter_of(std::size_t n, At at) {
  Scatter<D> s;
  for (std::size_t i = 0; i < n; ++i) s.mean += at(i);
  s.mean /= static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix<double, D, 1> d = at(i) - s.mean;
    s.scatter.noalias() += d * d.transpose();
  }
  return s;
}

}  // namespace toolinc
