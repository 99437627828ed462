// How far a result stands from the decisions that could have made it wrong. Each check contributes a
// margin in [0, 1] (1: far from its threshold, 0: at it or beyond); the confidence is the smallest, and a
// check at 0 makes the result doubtful, with its reason. The README gives how often results of each
// confidence were right on generated sessions and real models.
#pragma once

#include <string>
#include <vector>

namespace toolinc {

struct Confidence {
  double value = 1.0;
  bool confident = true;
  std::vector<std::string> doubts;  // one line each, why the result is doubtful

  // margin: how far the check passed, as a share of its own scale (clamped to [0, 1]); at 0 or below
  // the check failed for `reason`.
  void check(double margin, const std::string& reason);
};

}  // namespace toolinc
