#include "toolinc/frame/tooltip.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/error.hpp"

namespace toolinc {

TooltipRule tooltip_rule_from_string(const std::string& name) {
  if (name == "furthest") return TooltipRule::furthest;
  if (name == "weighted") return TooltipRule::weighted;
  throw std::invalid_argument("unknown tooltip rule '" + name + "' (furthest, weighted)");
}

std::string to_string(TooltipRule rule) { return rule == TooltipRule::furthest ? "furthest" : "weighted"; }

Tooltip find_tooltip(const Points& points, const ToolFrame& frame, const TooltipConfig& config) {
  const Eigen::Matrix3d tool_from_hand = frame.axes.transpose();
  const double hand_r2 = config.hand_radius * config.hand_radius;
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t i = 0; i < points.size(); ++i)
    if (points[i].squaredNorm() > hand_r2 && (points[i] - frame.origin).dot(frame.handle_axis()) < 0)
      candidates.push_back(i);

  // The density check needs a radius search, so it runs lazily, best candidates first.
  const KdTree tree(points);
  const auto dense = [&](std::uint32_t i) {
    const auto needed = static_cast<std::size_t>(config.min_neighbors) + 2;  // the point itself + "more than"
    return tree.count_within(points[i], config.density_radius, needed) >= needed;
  };
  const auto front = [&](std::uint32_t i) { return (points[i] - frame.origin).dot(frame.effector_axis()); };
  const auto weighted = [&](std::uint32_t i) {
    return config.effector_weight * front(i) + (1.0 - config.effector_weight) * points[i].norm();
  };
  // Sort by the primary score, ties by index, so the result does not depend on the sort's stability.
  const auto by_score_desc = [&](auto&& score) {
    std::vector<double> s(points.size());
    for (auto i : candidates) s[i] = score(i);
    std::sort(candidates.begin(), candidates.end(),
              [&](std::uint32_t a, std::uint32_t b) { return s[a] > s[b] || (s[a] == s[b] && a < b); });
  };

  Tooltip tip;
  tip.candidates = static_cast<int>(candidates.size());
  std::uint32_t chosen = KdTree::npos;
  // Points scoring within tie-tolerance (about 3 sigma of the noise) of the best dense point tie: noise,
  // not the shape, decides which of them scores best.
  const auto primary = [&](std::uint32_t i) { return config.rule == TooltipRule::weighted ? weighted(i) : front(i); };
  by_score_desc(primary);
  auto first_dense = std::find_if(candidates.begin(), candidates.end(), dense);
  tip.rejected_sparse = static_cast<int>(first_dense - candidates.begin());
  std::vector<std::uint32_t> tied;
  if (first_dense != candidates.end()) {
    const double cutoff = primary(*first_dense) - config.tie_tolerance;
    for (auto it = first_dense; it != candidates.end() && primary(*it) >= cutoff; ++it)
      if (dense(*it)) tied.push_back(*it);
  }
  // The tie-break. furthest: the point farthest from the hand. weighted: the point whose
  // smoothing-neighbors nearest points score best on average. Along a flat front the weighted score
  // changes by only (1 - w) per metre, so a point's own noise moves its maximum by several times that
  // noise; the mean's noise is about 3 times smaller, its bias second order in the neighbourhood's size.
  const auto tie_break = [&](std::uint32_t i) {
    if (config.rule == TooltipRule::furthest) return points[i].squaredNorm();
    double sum = 0.0;
    const auto near = tree.knn(points[i], config.smoothing_neighbors);
    for (const auto& n : near) sum += front(n.index);
    return config.effector_weight * sum / static_cast<double>(near.size()) +
           (1.0 - config.effector_weight) * points[i].norm();
  };
  double best = -std::numeric_limits<double>::infinity();
  for (auto i : tied)
    if (const double t = tie_break(i); t > best) best = t, chosen = i;
  if (chosen == KdTree::npos)
    throw MethodError(fmt::format("no tooltip: none of the {} effector-side points has more than {} "
                                  "neighbours within {} m", candidates.size(), config.min_neighbors,
                                  config.density_radius));

  tip.surface_point = points[chosen];
  tip.score = config.rule == TooltipRule::weighted ? weighted(chosen) : front(chosen);
  tip.position_in_tool = tool_from_hand * (points[chosen] - frame.origin);
  tip.position_in_tool.z() = 0.0;  // projected onto the symmetry plane
  tip.position = frame.origin + frame.axes * tip.position_in_tool;
  return tip;
}

}  // namespace toolinc
