// Logistic regression by iteratively reweighted least squares (Newton's method on the log-likelihood),
// with a small ridge so that separable data still gives finite weights. Deterministic.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace toolinc {

struct LogisticFit {
  Eigen::VectorXd weights;  // one per column of the features
  double bias = 0.0;
  int iterations = 0;
};

// rows: one sample per row; labels: 0 or 1 per row. ridge: the L2 penalty on the weights (not the bias).
LogisticFit fit_logistic(const Eigen::MatrixXd& rows, const std::vector<int>& labels, double ridge = 1e-3,
                         int max_iterations = 100);

}  // namespace toolinc
