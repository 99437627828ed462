#include "toolinc/core/logistic.hpp"

#include <Eigen/Cholesky>
#include <stdexcept>

namespace toolinc {

LogisticFit fit_logistic(const Eigen::MatrixXd& rows, const std::vector<int>& labels, double ridge,
                         int max_iterations) {
  const Eigen::Index n = rows.rows(), d = rows.cols();
  if (static_cast<std::size_t>(n) != labels.size()) throw std::invalid_argument("fit_logistic: one label per row");
  // The bias as a last column of ones.
  Eigen::MatrixXd x(n, d + 1);
  x << rows, Eigen::VectorXd::Ones(n);
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(d + 1), y(n);
  for (Eigen::Index i = 0; i < n; ++i) y[i] = labels[static_cast<std::size_t>(i)] != 0;
  Eigen::VectorXd penalty = Eigen::VectorXd::Constant(d + 1, ridge);
  penalty[d] = 0.0;
  LogisticFit fit;
  for (fit.iterations = 0; fit.iterations < max_iterations; ++fit.iterations) {
    const Eigen::VectorXd p = (1.0 / (1.0 + (-(x * beta)).array().exp())).matrix();
    const Eigen::VectorXd w = (p.array() * (1.0 - p.array())).max(1e-12).matrix();
    const Eigen::VectorXd gradient = x.transpose() * (y - p) - penalty.cwiseProduct(beta);
    Eigen::MatrixXd hessian = x.transpose() * w.asDiagonal() * x;
    hessian.diagonal() += penalty;
    const Eigen::VectorXd step = hessian.ldlt().solve(gradient);
    beta += step;
    if (step.cwiseAbs().maxCoeff() < 1e-10) break;
  }
  fit.weights = beta.head(d);
  fit.bias = beta[d];
  return fit;
}

}  // namespace toolinc
