#include "toolinc/core/choice_model.hpp"

#include <Eigen/Cholesky>
#include <map>
#include <stdexcept>

namespace toolinc {

ChoiceFit fit_choice_model(const Eigen::MatrixXd& rows, const std::vector<int>& labels, const std::vector<int>& groups,
                           double ridge, int max_iterations) {
  const Eigen::Index d = rows.cols();
  if (static_cast<std::size_t>(rows.rows()) != labels.size() || labels.size() != groups.size())
    throw std::invalid_argument("fit_choice_model: one label and one group per row");
  // The informative groups (some rows right, some wrong), each as its rows and its target shares.
  std::map<int, std::vector<Eigen::Index>> members;
  for (std::size_t i = 0; i < groups.size(); ++i) members[groups[i]].push_back(static_cast<Eigen::Index>(i));
  std::vector<std::pair<Eigen::MatrixXd, Eigen::VectorXd>> informative;
  for (const auto& [id, list] : members) {
    const auto n = static_cast<Eigen::Index>(list.size());
    Eigen::MatrixXd x(n, d);
    Eigen::VectorXd target(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      x.row(k) = rows.row(list[static_cast<std::size_t>(k)]);
      target[k] = labels[static_cast<std::size_t>(list[static_cast<std::size_t>(k)])] != 0;
    }
    if (target.sum() > 0 && target.sum() < static_cast<double>(n)) informative.emplace_back(x, target / target.sum());
  }
  ChoiceFit fit;
  fit.groups = static_cast<int>(informative.size());
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(d);
  for (fit.iterations = 0; fit.iterations < max_iterations; ++fit.iterations) {
    // Gradient and Hessian of the penalised log-likelihood: per group, the target's mean row less the
    // model's, and the model's covariance of the rows.
    Eigen::VectorXd gradient = -ridge * beta;
    Eigen::MatrixXd hessian = ridge * Eigen::MatrixXd::Identity(d, d);
    for (const auto& [x, target] : informative) {
      const Eigen::VectorXd z = x * beta;
      Eigen::VectorXd p = (z.array() - z.maxCoeff()).exp().matrix();
      p /= p.sum();
      const Eigen::VectorXd mean = x.transpose() * p;
      gradient += x.transpose() * (target - p);
      hessian += x.transpose() * p.asDiagonal() * x - mean * mean.transpose();
    }
    const Eigen::VectorXd step = hessian.ldlt().solve(gradient);
    beta += step;
    if (step.cwiseAbs().maxCoeff() < 1e-10) break;
  }
  fit.weights = beta;
  return fit;
}

}  // namespace toolinc
