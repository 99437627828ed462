// A choice among candidates (McFadden's conditional logit): within each group of rows (the candidates of
// one decision), P(row) = exp(w . x) / sum over the group of exp(w . x'). Fitted by Newton's method with a
// small ridge, so that separable data still gives finite weights. Deterministic.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace toolinc {

struct ChoiceFit {
  Eigen::VectorXd weights;  // one per column of the rows
  int groups = 0;           // groups with right and wrong rows, the only ones that say anything
  int iterations = 0;
};

// rows: one candidate per row; labels: 1 for a right candidate (several right ones share their group's
// mass equally), else 0; groups: one id per row. No bias: it cancels within a group.
ChoiceFit fit_choice_model(const Eigen::MatrixXd& rows, const std::vector<int>& labels, const std::vector<int>& groups,
                           double ridge = 1e-3, int max_iterations = 100);

}  // namespace toolinc
