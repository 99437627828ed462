// The tool frame as a search over hypotheses: every candidate handle (the fits started from the whole
// tool's axis and from the held half's, the held part's trimmed line, the whole tool's principal line),
// about each the symmetry plane the rules choose and its alternatives (the quarter turn, the mirror
// sweep's rival basins), each with either effector side. Each hypothesis has features with a physical
// meaning, measured alike whatever the candidate; a choice model fitted on simulated sessions of the
// generated families (fit-frame-score, configs/frame-score.json) turns them into the probability that it
// is the right one among them (its tooltip within 10 mm of the truth), and the search keeps the one whose
// tooltip is likeliest.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "toolinc/frame/tool_frame.hpp"

namespace toolinc {

constexpr int kFrameFeatures = 13;

// The features' names, in order, as the weights file has them.
const std::array<const char*, kFrameFeatures>& frame_feature_names();

struct FrameHypothesis {
  ToolFrame frame;
  std::string handle_source;   // which candidate handle
  bool rules_plane = true;     // the plane the rules choose about that handle, not an alternative
  bool side_reversed = false;  // the effector side turned against the one the rules take about that handle
  std::array<double, kFrameFeatures> features{};
  double log_odds = 0.0;        // the fitted model's score
  std::optional<Vec3> tooltip;  // by the paper's rule (find-tooltip's defaults); none without one
  // Where the tool's other end puts the same tip, when the head mirrors across the plane through the handle's
  // axis normal to X as well as across its symmetry plane (within symmetry-tie-margin: a T, a flat top): the
  // tooltip mirrored across that plane, as right as the tooltip itself. None for a tool with one end.
  std::optional<Vec3> other_end;
};

// The fitted choice model: a hypothesis's score is weights . features, its probability its share of
// exp(score) among the cloud's hypotheses.
struct FrameScoreModel {
  std::array<double, kFrameFeatures> weights{};
  double confident_probability = 1.0;  // the chosen hypothesis is confident from this probability on,
                                       // calibrated on sessions the weights were not fitted on
  double confident_tolerance = 0.015;  // m: what a confident tooltip claims, its error at most this: the
                                       // probability calibrated is the share of the hypotheses whose tips
                                       // lie within this of the chosen one
  double log_odds(const std::array<double, kFrameFeatures>& features) const;
};

// The weights shipped (configs/frame-score.json holds the same, with what they were fitted on).
const FrameScoreModel& fitted_frame_score();

// The probability of the chosen hypothesis's tooltip: the share of exp(score) of every hypothesis whose
// tooltip lies within `radius` of it (hypotheses that disagree on the frame may agree on the tip: a
// scoop's either side, a handle fitted two ways) or of the chosen one's other end (other_ends: one per
// hypothesis, FrameHypothesis::other_end, or empty for none: either end of a T is its tip). 0 when the
// chosen one has no tooltip.
double tooltip_probability(const std::vector<double>& scores, const std::vector<std::optional<Vec3>>& tooltips,
                           std::size_t chosen, double radius, const std::vector<std::optional<Vec3>>& other_ends = {});

// The side a hypothesis puts the effector on, as most_probable_tooltip compares them: its effector axis,
// or none (zero) for a stick, whose effector axis is arbitrary.
Vec3 effector_side(const ToolFrame& frame);

// The hypothesis to choose when what matters is a tooltip within `radius` of the truth (the Bayes choice
// for that loss): the tip whose probability is highest (ties to the higher score, then to the earlier
// one); of the hypotheses within `radius` of it, the effector side with the most probability (effector
// sides, one per hypothesis, within 90 degrees of one another; none agrees with either: on either side
// of a blade's or a scoop's plane the tip is its far end, so the tip does not tell the side, and the
// side's own evidence is summed as the tip's is); and of those the likeliest, whose frame is then the best
// for that tip. Several hypotheses that agree outweigh a likelier one alone. A two-ended tool's other end
// does not count here: a wrong plane's tip may have its mirror image on the right one, and be chosen for it.
std::size_t most_probable_tooltip(const std::vector<double>& scores, const std::vector<std::optional<Vec3>>& tooltips,
                                  const std::vector<Vec3>& effector_sides, double radius);

// Every hypothesis, scored by `model`, in a fixed order (candidate handles as listed above; about each the
// rules' plane, then its alternatives; on each plane the rules' side, then the other). Throws MethodError on degenerate
// input, as estimate_tool_frame does; viewpoints and views as it takes them.
std::vector<FrameHypothesis> frame_hypotheses(const Points& points, const ToolFrameConfig& config = {},
                                              const Points& viewpoints = {},
                                              const FrameScoreModel& model = fitted_frame_score(),
                                              const std::vector<std::uint32_t>& views = {});
// The same on a tooltip cache's points, views, kd-tree and held piece, its tooltips the hypotheses' (as
// estimate_tool_frame on a cache).
std::vector<FrameHypothesis> frame_hypotheses(const TooltipCache& cache, const ToolFrameConfig& config,
                                              const Points& viewpoints = {},
                                              const FrameScoreModel& model = fitted_frame_score());

}  // namespace toolinc
