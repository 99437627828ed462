// The sessions a classifier was trained on, as points of the descriptor's depth block: a tool
// never seen often gets a fair score from the label whose head looks most like its own (a hook's from
// the L-stick's), while its head, described about its handle, lies farther from every training session
// of that label than another grasp of that tool would.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "toolinc/io/json_file.hpp"

namespace toolinc {

struct KnownSessions {
  Eigen::Index start = 0, size = 0;  // the columns compared (the builtin descriptor's "depth" block)
  std::vector<std::size_t> labels;   // per session, an index into the classifier's labels
  Eigen::MatrixXd means;             // per session (row) the mean of those columns over its views
  Eigen::RowVectorXd scale;          // per column, what distances are measured in (known_sessions)
};

// From training rows (x, targets as for train_rls), groups: per row its session. Distances are measured
// with each column divided by its spread between sessions of one label (the root of the pooled variance,
// plus the mean variance of all columns, which keeps a column steady in training from weighing without
// bound); ones when no label has two sessions.
KnownSessions known_sessions(const Eigen::MatrixXd& x, const std::vector<std::size_t>& targets,
                             const std::vector<std::size_t>& groups, Eigen::Index start, Eigen::Index size);

// The largest distance from a known session to the nearest other session of its label (another grasp of
// the same tool): a session farther than this from every session of its answer is not that tool.
// Infinite when no label has two sessions.
double sibling_radius(const KnownSessions& known);

// Distance from the mean of rows' columns to the nearest known session of label (infinite: none).
double distance_to_label(const KnownSessions& known, const Eigen::MatrixXd& rows, std::size_t label);

Json to_json(const KnownSessions& known);
// Throws InputError(file, ...) on a malformed record; labels: how many the classifier has, dimension: its
// feature length.
KnownSessions known_sessions_from_json(const Json& json, std::size_t labels, Eigen::Index dimension,
                                       const std::string& file);

}  // namespace toolinc
