// The tool frame as a search over hypotheses: every candidate handle (the fits started from the whole
// tool's axis and from the held half's, the held part's trimmed line, the whole tool's principal line),
// the frame completed about each (symmetry plane, effector axis, head kind), with either effector side.
// Each hypothesis has features with a physical meaning; a logistic model fitted on simulated sessions of
// the generated families (fit-frame-score, configs/frame-score.json) turns them into the probability
// that the hypothesis's tooltip lies within 10 mm of the truth, and the search keeps the most likely.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "toolinc/frame/tool_frame.hpp"

namespace toolinc {

constexpr int kFrameFeatures = 8;

// The features' names, in order, as the weights file has them.
const std::array<const char*, kFrameFeatures>& frame_feature_names();

struct FrameHypothesis {
  ToolFrame frame;
  std::string handle_source;   // which candidate handle
  bool side_reversed = false;  // the effector side turned against the one the rules take about that handle
  std::array<double, kFrameFeatures> features{};
  double log_odds = 0.0;  // the fitted model's score
};

// The fitted model: log-odds = bias + weights . features.
struct FrameScoreModel {
  std::array<double, kFrameFeatures> weights{};
  double bias = 0.0;
  double log_odds(const std::array<double, kFrameFeatures>& features) const;
};

// The weights shipped (configs/frame-score.json holds the same, with what they were fitted on).
const FrameScoreModel& fitted_frame_score();

// Every hypothesis, scored by `model`, in a fixed order (candidate handles as listed above, the rules'
// side before the other). Throws MethodError on degenerate input, as estimate_tool_frame does.
std::vector<FrameHypothesis> frame_hypotheses(const Points& points, const ToolFrameConfig& config = {},
                                              const Points& viewpoints = {},
                                              const FrameScoreModel& model = fitted_frame_score());

}  // namespace toolinc
