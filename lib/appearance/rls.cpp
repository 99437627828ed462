#include "toolinc/appearance/rls.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "toolinc/core/error.hpp"

namespace toolinc {
namespace {

// The centred features' left singular vectors U (n x r) and squared singular values, r = numerical rank.
struct Spectrum {
  Eigen::MatrixXd u;
  Eigen::VectorXd s2;
};

Spectrum spectrum(const Eigen::MatrixXd& x) {
  const Eigen::Index n = x.rows(), d = x.cols();
  const bool kernel = n <= d;
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(kernel ? n : d, kernel ? n : d);
  if (kernel)
    gram.selfadjointView<Eigen::Lower>().rankUpdate(x);
  else
    gram.selfadjointView<Eigen::Lower>().rankUpdate(x.transpose());
  // The eigendecomposition runs in single precision: it dominates training (Eigen's QR iterations
  // accumulate rotations at memory speed) and takes half as long, while its relative error of about 1e-7
  // is far below anything choosing lambda or fitting +-1 targets can notice. Components below that
  // resolution are dropped.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXf> eigen(gram.cast<float>());  // reads the lower triangle
  const Eigen::VectorXd values = eigen.eigenvalues().cast<double>();               // ascending
  const double tolerance =
      std::max(values.maxCoeff(), 0.0) * static_cast<double>(values.size()) * std::numeric_limits<float>::epsilon();
  Eigen::Index first = 0;
  while (first < values.size() && values[first] <= tolerance) ++first;
  const Eigen::Index rank = values.size() - first;
  Spectrum result{eigen.eigenvectors().rightCols(rank).cast<double>(), values.tail(rank)};
  if (!kernel)  // U = X V S^-1
    result.u = x * result.u * result.s2.cwiseSqrt().cwiseInverse().asDiagonal();
  return result;
}

// +1 for the row's label, -1 for the others.
Eigen::MatrixXd target_matrix(const std::vector<std::size_t>& targets, std::size_t labels) {
  Eigen::MatrixXd y =
      -Eigen::MatrixXd::Ones(static_cast<Eigen::Index>(targets.size()), static_cast<Eigen::Index>(labels));
  for (std::size_t i = 0; i < targets.size(); ++i) {
    if (targets[i] >= labels) throw std::invalid_argument("train_rls: target out of range");
    y(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(targets[i])) = 1.0;
  }
  return y;
}

// train_rls's argument checks (see rls.hpp).
void check_training(const Eigen::MatrixXd& features, const std::vector<std::size_t>& targets,
                    const std::vector<std::string>& labels, const RlsConfig& config) {
  const Eigen::Index n = features.rows(), classes = static_cast<Eigen::Index>(labels.size());
  if (static_cast<std::size_t>(n) != targets.size()) throw std::invalid_argument("train_rls: one target per row");
  if (config.lambda_count < 1 || !(config.lambda_min_ratio > 0) ||
      !(config.lambda_max_ratio >= config.lambda_min_ratio))
    throw std::invalid_argument("train_rls: bad lambda range");
  Eigen::VectorXi count = Eigen::VectorXi::Zero(classes);
  for (const std::size_t target : targets) {
    if (target >= labels.size()) throw std::invalid_argument("train_rls: target out of range");
    ++count[static_cast<Eigen::Index>(target)];
  }
  if ((count.array() > 0).count() < 2)
    throw MethodError(fmt::format("the training data hold {} label(s); recognition needs samples of at least two",
                                  (count.array() > 0).count()));
}

// train_rls on features whose centred copy has spectrum s; y: target_matrix.
RlsModel fit(const Eigen::MatrixXd& features, const Spectrum& s, const Eigen::MatrixXd& y,
             const std::vector<std::size_t>& targets, const std::vector<std::string>& labels, const RlsConfig& config) {
  const Eigen::Index n = features.rows(), classes = static_cast<Eigen::Index>(labels.size());
  const Eigen::RowVectorXd x_mean = features.colwise().mean(), y_mean = y.colwise().mean();
  const Eigen::MatrixXd x = features.rowwise() - x_mean, yc = y.rowwise() - y_mean;
  const Eigen::MatrixXd z = s.u.transpose() * yc;            // r x classes
  const Eigen::MatrixXd u2 = s.u.array().square().matrix();  // for the hat diagonal
  const double mean_eigenvalue = s.s2.size() ? s.s2.mean() : 1.0;

  RlsModel best;
  best.loo_error = std::numeric_limits<double>::infinity();
  for (int k = 0; k < config.lambda_count; ++k) {
    const double t = config.lambda_count == 1 ? 0.0 : static_cast<double>(k) / (config.lambda_count - 1);
    const double lambda =
        mean_eigenvalue * config.lambda_min_ratio * std::pow(config.lambda_max_ratio / config.lambda_min_ratio, t);
    const Eigen::VectorXd shrink = s.s2.array() / (s.s2.array() + lambda);
    const Eigen::MatrixXd residual = yc - s.u * (shrink.asDiagonal() * z);
    const Eigen::VectorXd hat = (u2 * shrink).array() + 1.0 / n;
    const Eigen::MatrixXd loo = residual.array().colwise() / (1.0 - hat.array()).max(1e-12);
    const double error = loo.squaredNorm() / static_cast<double>(n * classes);
    spdlog::trace("lambda {:.3g}: leave-one-out error {:.5f}", lambda, error);
    if (error < best.loo_error) {
      best.lambda = lambda, best.loo_error = error;
      const Eigen::MatrixXd loo_scores = y - loo;  // the left-out predictions
      Eigen::Index right = 0;
      for (Eigen::Index i = 0; i < n; ++i) {
        Eigen::Index predicted;
        loo_scores.row(i).maxCoeff(&predicted);
        right += predicted == static_cast<Eigen::Index>(targets[i]);
      }
      best.loo_accuracy = static_cast<double>(right) / n;
    }
  }
  // W = X^T (X X^T + lambda I)^-1 Yc = X^T U diag(1 / (s^2 + lambda)) U^T Yc (X's rows lie in U's span).
  const Eigen::VectorXd inverse = (s.s2.array() + best.lambda).inverse();
  best.labels = labels;
  best.weights = x.transpose() * (s.u * (inverse.asDiagonal() * z));
  best.bias = y_mean - x_mean * best.weights;
  return best;
}

// leave_group_out_scores on features whose centred copy has spectrum s; y: target_matrix.
Eigen::MatrixXd group_out(const Spectrum& s, const Eigen::MatrixXd& y, const std::vector<std::size_t>& groups,
                          double lambda) {
  const Eigen::Index n = y.rows();
  const Eigen::RowVectorXd y_mean = y.colwise().mean();
  const Eigen::MatrixXd yc = y.rowwise() - y_mean;
  const Eigen::VectorXd shrink = s.s2.array() / (s.s2.array() + lambda);
  const Eigen::MatrixXd residual = yc - s.u * (shrink.asDiagonal() * (s.u.transpose() * yc));
  std::map<std::size_t, std::vector<Eigen::Index>> members;
  for (Eigen::Index i = 0; i < n; ++i) members[groups[static_cast<std::size_t>(i)]].push_back(i);
  Eigen::MatrixXd scores(n, y.cols());
  for (const auto& [group, rows] : members) {
    const Eigen::MatrixXd u = s.u(rows, Eigen::all);
    const auto m = static_cast<Eigen::Index>(rows.size());
    const Eigen::MatrixXd hat = Eigen::MatrixXd::Constant(m, m, 1.0 / n) + u * shrink.asDiagonal() * u.transpose();
    const Eigen::MatrixXd loo = (Eigen::MatrixXd::Identity(m, m) - hat).lu().solve(residual(rows, Eigen::all));
    scores(rows, Eigen::all) = y(rows, Eigen::all) - loo;
  }
  return scores;
}

}  // namespace

RlsModel train_rls(const Eigen::MatrixXd& features, const std::vector<std::size_t>& targets,
                   const std::vector<std::string>& labels, const RlsConfig& config) {
  check_training(features, targets, labels, config);
  return fit(features, spectrum(features.rowwise() - features.colwise().mean()), target_matrix(targets, labels.size()),
             targets, labels, config);
}

Eigen::MatrixXd leave_group_out_scores(const Eigen::MatrixXd& features, const std::vector<std::size_t>& targets,
                                       std::size_t labels, const std::vector<std::size_t>& groups, double lambda) {
  if (static_cast<std::size_t>(features.rows()) != targets.size() || targets.size() != groups.size())
    throw std::invalid_argument("leave_group_out_scores: one target and one group per row");
  return group_out(spectrum(features.rowwise() - features.colwise().mean()), target_matrix(targets, labels), groups,
                   lambda);
}

double weigh_block(Eigen::MatrixXd& x, const std::vector<std::size_t>& targets, const std::vector<std::string>& labels,
                   const std::vector<std::size_t>& groups, Eigen::Index start, Eigen::Index size,
                   const RlsConfig& config, RlsModel& model) {
  check_training(x, targets, labels, config);
  if (groups.size() != targets.size()) throw std::invalid_argument("weigh_block: one group per row");
  const Eigen::MatrixXd y = target_matrix(targets, labels.size());
  double best_error = std::numeric_limits<double>::infinity(), best_weight = 1;
  for (const double weight : {1.0, 0.5, 0.25, 0.125, 0.0}) {
    Eigen::MatrixXd scaled = x;
    scaled.middleCols(start, size) *= weight;
    // One eigendecomposition serves the fit and its leave-group-out scores.
    const Spectrum s = spectrum(scaled.rowwise() - scaled.colwise().mean());
    RlsModel candidate = fit(scaled, s, y, targets, labels, config);
    const double error = (group_out(s, y, groups, candidate.lambda) - y).squaredNorm() / y.size();
    spdlog::debug("block weight {}: leave-group-out error {:.4f}", weight, error);
    if (error < best_error) best_error = error, best_weight = weight, model = std::move(candidate);
  }
  x.middleCols(start, size) *= best_weight;
  return best_weight;
}

Eigen::MatrixXd rls_scores(const RlsModel& model, const Eigen::MatrixXd& features) {
  return (features * model.weights).rowwise() + model.bias;
}

}  // namespace toolinc
