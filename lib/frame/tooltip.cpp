#include "toolinc/frame/tooltip.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <bitset>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "frame/cylinder_fit.hpp"
#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/scatter.hpp"
#include "toolinc/core/statistics.hpp"

namespace toolinc {

TooltipRule tooltip_rule_from_string(const std::string& name) {
  if (name == "furthest") return TooltipRule::furthest;
  if (name == "weighted") return TooltipRule::weighted;
  throw std::invalid_argument("unknown tooltip rule '" + name + "' (furthest, weighted)");
}

std::string to_string(TooltipRule rule) { return rule == TooltipRule::furthest ? "furthest" : "weighted"; }

void share_hand_settings(const ToolFrameConfig& frame, TooltipConfig& tooltip) {
  tooltip.hand_radius = frame.hand_radius;
  tooltip.piece_gap = frame.piece_gap;
}

namespace {

// How many views a bit mask of views names.
int views_in(std::uint32_t mask) { return static_cast<int>(std::bitset<32>(mask).count()); }

// Where a blade's far end is measured from: the point of the handle's axis line nearest the hand. A hand
// holds the handle a few centimetres off its axis; measured from the hand itself, the far end of a wide or
// pointed blade would turn towards the corner opposite the hand.
Vec3 far_end_centre(const ToolFrame& frame) {
  const Vec3 y = frame.handle_axis();
  return frame.handle_point - frame.handle_point.dot(y) * y;
}

// One application of the rule on one frame: the chosen point, the tied points and their tie-breaks.
struct Pick {
  std::uint32_t chosen = KdTree::npos;
  std::vector<std::uint32_t> tied;
  std::vector<double> tie_breaks;  // of tied
  double score = 0.0;
  int candidates = 0, rejected_sparse = 0;
};

// with_views: a candidate must also pass tip-views.
Pick pick(const TooltipCache& cache, const ToolFrame& frame, bool with_views) {
  const Points& points = cache.points();
  const TooltipConfig& config = cache.config();
  const Vec3 y = frame.handle_axis(), x = frame.effector_axis();
  // The density check needs a radius search, so it runs lazily, best candidates first.
  const auto dense = [&](std::uint32_t i) { return cache.dense(i) && (!with_views || cache.seen_by_enough(i)); };
  const auto front = [&](std::uint32_t i) { return (points[i] - frame.origin).dot(x); };
  const Vec3 centre = far_end_centre(frame);
  const auto from_centre = [&](std::uint32_t i) { return (points[i] - centre).norm(); };
  // A stick's effector axis is arbitrary (nothing stands out from its handle), so "in front" means
  // nothing there: its tip is its far end, along the handle away from the hand.
  // A blade or scoop continuing the handle works with its far end: the farthest from the handle's axis
  // where the hand holds it (far_end_centre).
  const auto primary = [&](std::uint32_t i, double along) {
    if (frame.stick) return -along;
    if (frame.tip_at_far_end()) return from_centre(i);
    return config.rule == TooltipRule::furthest
               ? front(i)
               : config.effector_weight * front(i) + (1.0 - config.effector_weight) * cache.from_hand(i);
  };
  // The candidates: the effector side's points (beyond the origin along the handle, away from the hand).
  // Best first by the primary score, ties by index, so the order does not depend on the sort's stability.
  // Only the best end is needed (the first dense candidate and those tied with it), so the candidates
  // within twice tie-tolerance of the best are sorted first, and the rest only if the search reaches them.
  // Each with its score beside it: the sorts and scans read them together.
  struct Candidate {
    double score;
    std::uint32_t index;
  };
  std::vector<Candidate> candidates;
  candidates.reserve(cache.beyond_hand().size());
  double best_score = -std::numeric_limits<double>::infinity();
  for (const auto i : cache.beyond_hand())
    if (const double along = (points[i] - frame.origin).dot(y); along < 0) {
      candidates.push_back({primary(i, along), i});
      best_score = std::max(best_score, candidates.back().score);
    }
  const auto better = [](const Candidate& a, const Candidate& b) {
    return a.score > b.score || (a.score == b.score && a.index < b.index);
  };
  const auto top_end = std::partition(candidates.begin(), candidates.end(), [&](const Candidate& c) {
    return c.score >= best_score - 2 * config.tie_tolerance;
  });
  std::sort(candidates.begin(), top_end, better);
  bool all_sorted = top_end == candidates.end();
  const auto sort_all = [&] {
    if (!all_sorted) std::sort(top_end, candidates.end(), better);
    all_sorted = true;
  };

  Pick p;
  p.candidates = static_cast<int>(candidates.size());
  // Points scoring within tie-tolerance (about 3 sigma of the noise) of the best dense point tie: noise,
  // not the shape, decides which of them scores best.
  const auto dense_candidate = [&](const Candidate& c) { return dense(c.index); };
  auto first_dense = std::find_if(candidates.begin(), top_end, dense_candidate);
  if (first_dense == top_end) {
    sort_all();
    first_dense = std::find_if(top_end, candidates.end(), dense_candidate);
  }
  p.rejected_sparse = static_cast<int>(first_dense - candidates.begin());
  if (first_dense == candidates.end()) return p;
  const double cutoff = first_dense->score - config.tie_tolerance;
  if (cutoff < best_score - 2 * config.tie_tolerance) sort_all();  // the ties reach below the sorted part
  std::vector<double> tied_scores;
  for (auto it = first_dense; it != candidates.end() && it->score >= cutoff; ++it)
    if (dense(it->index)) p.tied.push_back(it->index), tied_scores.push_back(it->score);
  // The tie-break. furthest: the distance from the hand. weighted: the original's score with the
  // distance in front averaged over the smoothing-neighbors nearest points: along a flat front the
  // score changes by only (1 - w) per metre, so a point's own noise would move the choice by several
  // times that noise; the mean's noise is about 3 times smaller. On a smooth surface its bias is second
  // order in the neighbourhood's size; at an edge (a hoe blade's bottom corner) it is first order and
  // draws the choice up the front by about a neighbourhood's radius.
  // far end: among points tied at the far end, how far a point lies from far_end_centre varies more with
  // its distance from the handle's line through it than with its noise along it: that distance,
  // averaged over the same neighbours, decides (a scoop's rim corner, as the rule says).
  // A stick's: the middle of its far end, the tied point nearest their centroid.
  const Cylinder handle_line{centre, y, 0.0, 0.0};
  const auto across_handle = [&](std::uint32_t i) { return radial_distance(handle_line, points[i]); };
  Vec3 end_centre = Vec3::Zero();
  for (auto i : p.tied) end_centre += points[i] / static_cast<double>(p.tied.size());
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < p.tied.size(); ++j) {
    const std::uint32_t i = p.tied[j];
    double t = cache.from_hand(i);
    if (frame.stick) {
      t = -(points[i] - end_centre).norm();
    } else if (frame.tip_at_far_end() || config.rule == TooltipRule::weighted) {
      const auto& near = cache.smoothing_neighbors(i);
      double sum = 0.0;
      for (const auto& n : near) sum += frame.tip_at_far_end() ? across_handle(n.index) : front(n.index);
      const double mean = sum / static_cast<double>(near.size());
      t = frame.tip_at_far_end() ? mean : config.effector_weight * mean + (1.0 - config.effector_weight) * t;
    }
    p.tie_breaks.push_back(t);
    if (t > best) best = t, p.chosen = i, p.score = tied_scores[j];
  }
  return p;
}

// The rule's pick among the candidates tip-views allows (a blade's far end), or among them all when it
// allows none.
Pick pick(const TooltipCache& cache, const ToolFrame& frame) {
  const bool with_views = cache.config().tip_views > 1 && cache.views_in_cloud() > 1 && frame.tip_at_far_end();
  Pick p = pick(cache, frame, with_views);
  if (with_views && p.chosen == KdTree::npos) p = pick(cache, frame, false);
  return p;
}

// How far apart edge_retreat measures the density along its line, and how many steps back it goes.
double retreat_step(const TooltipConfig& config) { return config.tip_edge_radius / 5.0; }
int retreat_steps(const TooltipConfig& config) {
  return static_cast<int>(std::round(std::max(0.0, config.fringe_depth) / retreat_step(config)));
}

// edge_retreat with the density at each step counted by count(centre): the points within tip-edge-radius.
template <typename Count>
double retreat_along(const Vec3& point, const Vec3& direction, const TooltipConfig& config, Count&& count) {
  if (config.fringe_depth <= 0.0) return 0.0;
  const double step = retreat_step(config);
  const int steps = retreat_steps(config);
  std::vector<std::size_t> along;
  for (int k = 0; k <= steps; ++k) along.push_back(count(Vec3(point - k * step * direction)));
  const std::size_t peak = *std::max_element(along.begin(), along.end());
  for (int k = 0; k < steps; ++k)
    if (2 * along[k] >= peak) return k * step;
  return config.fringe_depth;
}

// The distance from q to the segment from a to b.
double distance_to_segment(const Vec3& q, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((q - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (q - (a + t * ab)).norm();
}

// The point projected onto the frame's symmetry plane.
Vec3 on_symmetry_plane(const Vec3& point, const ToolFrame& frame) {
  return point - (point - frame.origin).dot(frame.symmetry_axis()) * frame.symmetry_axis();
}

// The frame with another symmetry plane through the handle axis: the effector axis signed, as the
// frame's, towards the side the effector reaches farther.
ToolFrame with_symmetry_plane(const Points& points, const ToolFrame& frame, const Vec3& normal) {
  ToolFrame other = frame;
  const Vec3 y = frame.handle_axis();
  Vec3 x = y.cross(normal).normalized();
  const Reach reach = effector_reach(points, frame.origin, frame.origin, y, x, ToolFrameConfig{}.salience_quantile);
  if (reach.negative > reach.positive) x = -x;
  other.axes.col(0) = x;
  other.axes.col(2) = x.cross(y);
  return other;
}

// RMS distance of the k nearest points of `point` from their plane: the noise there.
double local_noise(const KdTree& tree, const Vec3& point, int k) {
  const auto near = tree.knn(point, std::max(k, 4));
  const auto spread = scatter_of<3>(near.size(), [&](std::size_t j) { return tree.points()[near[j].index]; });
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(spread.scatter);
  return std::sqrt(std::max(0.0, solver.eigenvalues()(0)) / static_cast<double>(near.size()));
}

// How far the points within radius of the line through point along f's effector axis spread along it (their
// 10th to 90th percentile): across a blade's far end, a plate's thickness and the noise, unless stereo smeared
// the plate seen face-on into a tail behind it or the edge bends along the axis, which leave where across the
// blade its tip lies uncertain.
double across_blade_spread(const Points& points, const ToolFrame& f, const Vec3& point, double radius) {
  const Cylinder line{point, f.effector_axis(), 0.0, 0.0};
  std::vector<double> across;
  for (const auto& q : points)
    if (radial_distance(line, q) <= radius) across.push_back((q - point).dot(line.axis));
  return quantile(across, 0.9) - quantile(across, 0.1);
}

// The way a fringe runs out of the surface at a tip projected onto f's symmetry plane (point: the surface
// point it came from). A blade's far end is the farthest from the handle's axis, and only a fringe reaching
// farther from it moves that choice: its way is radial. Any other tip's way runs from the surface's mass,
// the centroid of the projected points within fringe-depth of it: the weighted rule likes distance from the
// hand as well as distance in front, so it also takes smear running along the handle off a head's edge
// (below a rake's teeth or a hoe's blade), which lies off the front, and back along the rule's gradient
// (mostly along the effector axis) the way would stay in that smear. At a front face or a stick's far end
// the two agree. Zero where nothing else lies within reach.
Vec3 outwards(const Vec3& point, const Vec3& on_plane, const ToolFrame& f, const Points& near, double depth) {
  if (f.tip_at_far_end()) {
    Vec3 radial = point - far_end_centre(f);
    radial -= radial.dot(f.symmetry_axis()) * f.symmetry_axis();
    return radial.norm() < 1e-9 ? Vec3::Zero() : Vec3(radial.normalized());
  }
  Vec3 sum = Vec3::Zero();
  std::size_t n = 0;
  for (const auto& q : near)
    if ((q - on_plane).squaredNorm() <= depth * depth) sum += q, ++n;
  const Vec3 direction = n > 0 ? Vec3(on_plane - sum / static_cast<double>(n)) : Vec3::Zero();
  return direction.norm() < 1e-9 ? Vec3::Zero() : Vec3(direction.normalized());
}

// The rule's tips at these surface points, each projected onto f's symmetry plane and moved back off the
// fringe to the surface's edge (and how far, in retreats). The edge is sought among the points projected
// there too: the head's whole width piles up on the plane, so a lobe of fringe at one side of it is sparse
// against it. Only the projected points within reach of the search (fringe-depth from a tip, then
// tip-edge-radius around, with a margin for the steps' rounding) can count, so only those are kept.
std::vector<Vec3> edges_on_plane(const Points& points, const ToolFrame& f, const std::vector<Vec3>& surface_points,
                                 const TooltipConfig& config, std::vector<double>* retreats = nullptr) {
  const double depth = std::max(0.0, config.fringe_depth);
  std::vector<Vec3> on_plane;
  Eigen::AlignedBox3d reach;
  for (const auto& point : surface_points) reach.extend(on_plane.emplace_back(on_symmetry_plane(point, f)));
  const double margin = depth + config.tip_edge_radius + retreat_step(config);
  reach.min().array() -= margin;
  reach.max().array() += margin;
  Points near;
  for (const auto& q : points)
    if (const Vec3 projected = on_symmetry_plane(q, f); reach.contains(projected)) near.push_back(projected);
  // Each line's density counted among the points within tip-edge-radius of it (and a hair more, so that
  // rounding keeps every point a count takes): for the few points about one line, cheaper than a kd-tree,
  // and the same count, as the same squared distances are compared.
  const double r2 = config.tip_edge_radius * config.tip_edge_radius;
  const double line_reach = config.tip_edge_radius + 1e-9;
  Points about_line;
  std::vector<Vec3> edges;
  const auto count = [&](const Vec3& centre) {
    return static_cast<std::size_t>(std::count_if(about_line.begin(), about_line.end(),
                                                  [&](const Vec3& q) { return (q - centre).squaredNorm() <= r2; }));
  };
  for (std::size_t i = 0; i < on_plane.size(); ++i) {
    const Vec3& point = on_plane[i];
    const Vec3 direction = outwards(surface_points[i], point, f, near, depth);
    double back = 0.0;
    if (!direction.isZero()) {
      const Vec3 back_end = point - retreat_steps(config) * retreat_step(config) * direction;
      Eigen::AlignedBox3d around(point.cwiseMin(back_end), point.cwiseMax(back_end));
      around.min().array() -= line_reach;
      around.max().array() += line_reach;
      about_line.clear();
      for (const auto& q : near)
        if (around.contains(q) && distance_to_segment(q, point, back_end) <= line_reach) about_line.push_back(q);
      back = retreat_along(point, direction, config, count);
    }
    if (retreats) retreats->push_back(back);
    edges.push_back(point - back * direction);
  }
  return edges;
}

// A tip that one view alone saw, in a cloud that several saw, is backed by nothing else: a blob may take
// in a patch of the scene behind the tool that no other view looks at, and then the tip goes onto it.
void check_seen_by_several(Tooltip& tip, const TooltipCache& cache) {
  const TooltipConfig& config = cache.config();
  tip.views_in_cloud = cache.views_in_cloud();
  tip.views_at_tip = cache.views_near(tip.surface_point, config.density_radius);
  if (tip.views_in_cloud > 1)
    tip.confidence.check(tip.views_at_tip > 1 ? 1.0 : 0.0,
                         fmt::format("the tip's points (within density-radius, {:.0f} mm) were seen by one view only "
                                     "of the {} that saw the cloud: nothing else backs it",
                                     1000 * config.density_radius, tip.views_in_cloud));
}

}  // namespace

TooltipCache::TooltipCache(const Points& points, const KdTree& tree, const TooltipConfig& config,
                           std::vector<std::uint32_t> views)
    : points_(points),
      tree_(tree),
      config_(config),
      held_(held_piece(points, config.hand_radius, config.piece_gap)),
      views_(std::move(views)),
      dense_(points.size(), -1),
      seen_(points.size(), -1) {
  if (!views_.empty() && views_.size() != points.size())
    throw std::invalid_argument("find_tooltip: views must be empty or one per point");
  std::uint32_t in_cloud = 0;
  for (const auto v : views_) in_cloud |= v;
  views_in_cloud_ = views_in(in_cloud);
  from_hand_.reserve(points.size());
  for (const auto& p : points) from_hand_.push_back(p.norm());
}

int TooltipCache::views_near(const Vec3& point, double radius) const {
  if (views_.empty()) return 0;
  std::uint32_t near = 0;
  for (const auto i : tree_.within(point, radius)) near |= views_[i];
  return views_in(near);
}

bool TooltipCache::seen_by_enough(std::uint32_t index) const {
  if (seen_[index] < 0)
    seen_[index] = views_near(points_[index], config_.tip_edge_radius) >= std::min(config_.tip_views, views_in_cloud_);
  return seen_[index] == 1;
}

bool TooltipCache::dense(std::uint32_t index) const {
  if (dense_[index] < 0) {
    const auto needed = static_cast<std::size_t>(config_.min_neighbors) + 2;  // the point itself + "more than"
    dense_[index] = tree_.count_within(points_[index], config_.density_radius, needed) >= needed;
  }
  return dense_[index] == 1;
}

const std::vector<KdTree::Neighbor>& TooltipCache::smoothing_neighbors(std::uint32_t index) const {
  const auto [known, added] = smoothing_.try_emplace(index);
  if (added) known->second = tree_.knn(points_[index], config_.smoothing_neighbors);
  return known->second;
}

double edge_retreat(const KdTree& tree, const Vec3& point, const Vec3& direction, const TooltipConfig& config) {
  return retreat_along(point, direction, config,
                       [&](const Vec3& centre) { return tree.count_within(centre, config.tip_edge_radius); });
}

Tooltip find_tooltip(const Points& points, const ToolFrame& frame, const TooltipConfig& config,
                     const std::vector<std::uint32_t>& views) {
  return find_tooltip(points, KdTree(points), frame, config, views);
}

Tooltip find_tooltip(const Points& points, const KdTree& tree, const ToolFrame& frame, const TooltipConfig& config,
                     const std::vector<std::uint32_t>& views) {
  return find_tooltip(TooltipCache(points, tree, config, views), frame);
}

std::optional<Vec3> tooltip_position(const TooltipCache& cache, const ToolFrame& frame) {
  const Pick p = pick(cache, frame);
  if (p.chosen == KdTree::npos) return std::nullopt;
  // The chosen point's edge alone: its retreat counts only projected points near its own line, which
  // edges_on_plane keeps whatever other points it is given, so the position is find_tooltip's.
  return edges_on_plane(cache.points(), frame, {cache.points()[p.chosen]}, cache.config())[0];
}

FrameAndTooltip estimate_frame_and_tooltip(const Points& points, const ToolFrameConfig& frame_config,
                                           TooltipConfig tooltip_config, const Points& viewpoints,
                                           const std::vector<std::uint32_t>& views) {
  share_hand_settings(frame_config, tooltip_config);
  const KdTree tree(points);
  const TooltipCache cache(points, tree, tooltip_config, views);
  FrameAndTooltip result{estimate_tool_frame(cache, frame_config, viewpoints), {}};
  result.tooltip = find_tooltip(cache, result.frame);
  return result;
}

void check_unmerged_views(Confidence& confidence, int unmerged_views) {
  if (unmerged_views > 0)
    confidence.check(0.0, fmt::format("{} of the session's views are missing from the cloud (no tool found in "
                                      "them, or they did not fit the others): what they alone saw is missing",
                                      unmerged_views));
}

FrameAndTooltip estimate_frame_and_tooltip(const PointCloud& cloud, const ToolFrameConfig& frame_config,
                                           const TooltipConfig& tooltip_config) {
  FrameAndTooltip result =
      estimate_frame_and_tooltip(cloud.points, frame_config, tooltip_config, cloud.viewpoints, cloud.views);
  check_unmerged_views(result.tooltip.confidence, cloud.unmerged_views);
  return result;
}

Tooltip find_tooltip(const PointCloud& cloud, const ToolFrame& frame, const TooltipConfig& config) {
  Tooltip tooltip = find_tooltip(cloud.points, frame, config, cloud.views);
  check_unmerged_views(tooltip.confidence, cloud.unmerged_views);
  return tooltip;
}

Tooltip find_tooltip(const TooltipCache& cache, const ToolFrame& frame) {
  const Points& points = cache.points();
  const KdTree& tree = cache.tree();
  const TooltipConfig& config = cache.config();
  const Pick p = pick(cache, frame);
  if (p.chosen == KdTree::npos)
    throw MethodError(
        fmt::format("no tooltip: none of the {} effector-side points has more than {} "
                    "neighbours within {} m",
                    p.candidates, config.min_neighbors, config.density_radius));
  Tooltip tip;
  tip.candidates = p.candidates;
  tip.rejected_sparse = p.rejected_sparse;
  tip.tied = static_cast<int>(p.tied.size());
  tip.detached_points = cache.held().detached_points;
  tip.detached_pieces = cache.held().detached_pieces;
  tip.surface_point = points[p.chosen];
  tip.score = p.score;
  // Uncertainty: the tied points whose tie-break is within 2 sigma of the best could as well have won
  // under the measured noise. The tie-break's sigma: the noise itself for the distance from the hand;
  // w times the noise over the square root of the neighbourhood for the averaged distance in front.
  tip.noise_m = local_noise(tree, points[p.chosen], config.smoothing_neighbors);
  const double smoothed = tip.noise_m / std::sqrt(std::max(1, config.smoothing_neighbors));
  const double sigma = frame.stick                            ? tip.noise_m
                       : frame.tip_at_far_end()               ? smoothed
                       : config.rule == TooltipRule::furthest ? tip.noise_m
                                                              : config.effector_weight * smoothed;
  const double best = *std::max_element(p.tie_breaks.begin(), p.tie_breaks.end());
  std::vector<std::size_t> close;  // of p.tied: within 2 sigma of the best
  std::vector<Vec3> surface_points{points[p.chosen]};
  for (std::size_t j = 0; j < p.tied.size(); ++j)
    if (p.tie_breaks[j] >= best - 2 * sigma) close.push_back(j), surface_points.push_back(points[p.tied[j]]);
  std::vector<double> retreats;
  const std::vector<Vec3> edges = edges_on_plane(points, frame, surface_points, config, &retreats);
  tip.position = edges[0];
  tip.edge_retreat_m = retreats[0];
  tip.position_in_tool = frame.axes.transpose() * (tip.position - frame.origin);
  tip.position_in_tool.z() = 0.0;

  std::size_t other_tied = p.tied.size();   // the best of those farther than ambiguity-distance
  Vec3 other_tied_position = Vec3::Zero();  // its tip
  for (std::size_t c = 0; c < close.size(); ++c) {
    const std::size_t j = close[c];
    const Vec3& position = edges[c + 1];
    const double d = (position - tip.position).norm();
    tip.uncertainty_m = std::max(tip.uncertainty_m, d);
    if (d > config.ambiguity_distance && (other_tied == p.tied.size() || p.tie_breaks[j] > p.tie_breaks[other_tied])) {
      other_tied = j;
      other_tied_position = position;
    }
  }
  // Alternatives: that point; the rule's tip on every other symmetry plane that scored as well as the
  // chosen one (a T, a square plate, a flat blade seen edge-on) or nearly as well from another basin (a
  // rival); and, when neither salience nor a curl decided the effector's side, the tip on the other side.
  if (other_tied < p.tied.size())
    tip.alternatives.push_back({other_tied_position, frame.symmetry_axis(), frame.symmetry_score, "tied point"});
  const auto add_tip_with = [&](const ToolFrame& other, double plane_score, const char* source) {
    const Pick q = pick(cache, other);
    if (q.chosen != KdTree::npos)
      tip.alternatives.push_back(
          {edges_on_plane(points, other, {points[q.chosen]}, config)[0], other.symmetry_axis(), plane_score, source});
  };
  for (const auto& [planes, source] :
       {std::pair{&frame.tied_planes, "tied symmetry plane"}, std::pair{&frame.rival_planes, "rival symmetry plane"}})
    for (const auto& plane : *planes)
      if (std::abs(plane.normal.dot(frame.symmetry_axis())) <= std::cos(M_PI / 36))  // not the chosen plane
        add_tip_with(with_symmetry_plane(points, frame, plane.normal), plane.score, source);
  if (!frame.effector_side_clear && !frame.stick && !frame.tip_at_far_end()) {
    ToolFrame reversed = frame;
    reversed.axes.col(0) = -frame.effector_axis();
    reversed.axes.col(2) = -frame.symmetry_axis();
    add_tip_with(reversed, frame.symmetry_score, "other effector side");
  }
  double farthest = tip.uncertainty_m;
  for (const auto& a : tip.alternatives) farthest = std::max(farthest, (a.position - tip.position).norm());
  tip.ambiguous = farthest > config.ambiguity_distance;
  tip.confidence = frame.confidence;
  if (frame.tip_at_far_end()) {
    const double spread = across_blade_spread(points, frame, tip.surface_point, config.tip_edge_radius);
    tip.confidence.check(1.0 - spread / config.ambiguity_distance,
                         fmt::format("the blade's far end spreads {:.0f} mm across it (smear behind a plate seen "
                                     "face-on, or an edge bent along it), beyond ambiguity-distance ({:.0f} mm)",
                                     1000 * spread, 1000 * config.ambiguity_distance));
  }
  tip.confidence.check(1.0 - farthest / config.ambiguity_distance,
                       fmt::format("another tip {:.0f} mm away scores as well (a tied point, a tied or rival symmetry "
                                   "plane, the other effector side), beyond ambiguity-distance ({:.0f} mm)",
                                   1000 * farthest, 1000 * config.ambiguity_distance));
  if (!cache.views().empty()) check_seen_by_several(tip, cache);
  return tip;
}

}  // namespace toolinc
