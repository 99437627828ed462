// The unknown-tool floor of a classifier, chosen on its own training data: how the scores of
// known tools seen in new grasps compare with those of tools never seen.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "toolinc/appearance/recognition.hpp"
#include "toolinc/appearance/rls.hpp"
#include "toolinc/io/json_file.hpp"

namespace toolinc {

// How the floor is chosen. Turning away a tool the robot knows is the error users see first (every
// classify of a known tool that answers "unknown"), so the floor bounds it: it is the known_rejection
// quantile of the scores known sessions get when left out (at most the default floor), and it rejects
// unknown tools only as far as that allows.
struct UnknownFloorConfig {
  double known_rejection = 0.05;  // share of known sessions (left out of training) the floor may turn away
};

// The floor on the best score: the known_rejection quantile (core/statistics quantile) of the scores a
// known tool gets from the classifier trained without its session (another grasp of a tool it knows;
// leave_group_out_scores at model's lambda), per session (group), but never above DecisionConfig's
// default (0: known tools in new grasps score lower than sessions left out of training do). The best scores a tool gets
// from the classifier trained without its label (a tool it has never seen) are recorded in summary: the share of them
// the floor accepts. Needs three labels (two left when one is out), and sessions only: of images or database rows it is
// not known which come from one session, and a row left out beside its session's other frames would look better known
// than a new grasp does; otherwise the defaults. x, targets, groups: the training rows as model was trained on them.
// summary receives how the thresholds were chosen and the shares of known rejected and unknown accepted on the training
// data.
DecisionConfig calibrate_decision(const Eigen::MatrixXd& x, const std::vector<std::size_t>& targets,
                                  const std::vector<std::string>& labels, const std::vector<std::size_t>& groups,
                                  bool sessions_only, const RlsModel& model, const RlsConfig& rls,
                                  const UnknownFloorConfig& floor, Json& summary);

}  // namespace toolinc
