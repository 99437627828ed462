// One-vs-all regularised least squares, the iCub recognition lineage (GURLS / himrep's RLS): per label a
// linear score w.x + b fitted to +1 for the label's samples and -1 for the others, in closed form, with
// an unregularised bias (features and targets centred). The regularisation lambda is chosen among
// log-spaced candidates by leave-one-out error, which closed form gives for free: with the centred
// features' thin SVD X = U S V^T and f_k = s_k^2 / (s_k^2 + lambda), the fit is Y_hat = ybar + U diag(f)
// U^T (Y - ybar), the hat matrix's diagonal h_i = 1/n + sum_k U_ik^2 f_k, and each left-out residual
// (y_i - y_hat_i) / (1 - h_i). U and s come from the eigendecomposition of the smaller Gram matrix:
// X X^T (n x n, the kernel form) when there are fewer samples than dimensions, X^T X otherwise, computed
// in single precision (twice as fast; see rls.cpp).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace toolinc {

struct RlsConfig {
  // Lambda candidates, log-spaced between these multiples of the mean eigenvalue of the centred Gram
  // matrix, so the grid follows the features' scale.
  double lambda_min_ratio = 1e-5;
  double lambda_max_ratio = 10.0;
  int lambda_count = 25;
};

struct RlsModel {
  std::vector<std::string> labels;
  Eigen::MatrixXd weights;  // dimension x labels
  Eigen::RowVectorXd bias;  // per label
  double lambda = 0;
  double loo_error = 0;     // mean squared leave-one-out residual at lambda, over samples and labels
  double loo_accuracy = 0;  // share of samples whose leave-one-out best score is their own label
};

// features: one sample per row; targets: per row, an index into labels. Throws MethodError when fewer
// than two labels have samples, std::invalid_argument on sizes that do not match or a bad config.
RlsModel train_rls(const Eigen::MatrixXd& features, const std::vector<std::size_t>& targets,
                   const std::vector<std::string>& labels, const RlsConfig& config = {});

// The scores each row gets from the classifier fitted at `lambda` without the rows of its group (a group:
// the views of one session, which resemble one another more than another grasp's), in closed form: with
// the hat matrix H = 11^T / n + U diag(f) U^T, a group's left-out residuals are (I - H_gg)^-1 r_g.
// groups: per row, any id. Throws std::invalid_argument on sizes that do not match.
Eigen::MatrixXd leave_group_out_scores(const Eigen::MatrixXd& features, const std::vector<std::size_t>& targets,
                                       std::size_t labels, const std::vector<std::size_t>& groups, double lambda);

// How much a block of columns (a descriptor's colour, say) should count, decided by the data: the
// classifier trained with the block scaled by each of 1, 1/2, 1/4, 1/8 and 0, keeping the weight whose
// leave-group-out scores come closest to the targets (mean squared residual; ties keep the larger
// weight). Features that change between the groups of one label (a colour all tools share) then count
// for little, features that mark a label fully. Scales x's block in place, sets model to the classifier
// trained on it and returns the weight.
double weigh_block(Eigen::MatrixXd& x, const std::vector<std::size_t>& targets, const std::vector<std::string>& labels,
                   const std::vector<std::size_t>& groups, Eigen::Index start, Eigen::Index size,
                   const RlsConfig& config, RlsModel& model);

// Scores, one row per feature row, one column per label.
Eigen::MatrixXd rls_scores(const RlsModel& model, const Eigen::MatrixXd& features);

}  // namespace toolinc
