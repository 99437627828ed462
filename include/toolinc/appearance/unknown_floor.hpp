// The unknown-tool floor of a classifier, chosen on its own training data (issue 18): how the scores of
// known tools seen in new grasps compare with those of tools never seen.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "toolinc/appearance/recognition.hpp"
#include "toolinc/appearance/rls.hpp"
#include "toolinc/io/json_file.hpp"

namespace toolinc {

// The floor on the best score: the scores a known tool gets from the classifier trained without its
// session (another grasp of a tool it knows; leave_group_out_scores at model's lambda), against the best
// scores a tool gets from the classifier trained without its label (a tool it has never seen), per
// session (group): separating_floor between the two. Needs three labels (two left when one is out), and
// sessions only: of images or database rows it is not known which come from one session, and a row left
// out beside its session's other frames would look better known than a new grasp does; otherwise the
// defaults. x, targets, groups: the training rows as model was trained on them. summary receives how the
// thresholds were chosen and the shares of known rejected and unknown accepted on the training data.
DecisionConfig calibrate_decision(const Eigen::MatrixXd& x, const std::vector<std::size_t>& targets,
                                  const std::vector<std::string>& labels, const std::vector<std::size_t>& groups,
                                  bool sessions_only, const RlsModel& model, const RlsConfig& rls, Json& summary);

}  // namespace toolinc
