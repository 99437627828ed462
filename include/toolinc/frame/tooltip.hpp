// The tooltip (paper sect. 4.3): the point on the symmetry plane, on the effector side of the handle
// plane, furthest in front of the effector plane.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/tool_frame.hpp"

namespace toolinc {

enum class TooltipRule {
  furthest,  // furthest in front of the effector plane; near-ties go to the point farthest from the hand
  weighted,  // the original's score: w * (in front of the effector plane) + (1 - w) * (distance from hand)
};
TooltipRule tooltip_rule_from_string(const std::string& name);  // throws std::invalid_argument
std::string to_string(TooltipRule rule);

struct TooltipConfig {
  TooltipRule rule = TooltipRule::weighted;
  double tie_tolerance = 0.005;      // m: points scoring within this of the best are tied (~3 sigma of the
                                     //    stereo noise); furthest: the tie goes to the point farthest from the hand
  double effector_weight = 0.8;      // w of the weighted rule (the original's value)
  int smoothing_neighbors = 10;      // weighted rule: tied points are compared with their distance in front
                                     //    averaged over this many nearest points (noise down by about 3)
  double density_radius = 0.02;      // m: a candidate needs more than min_neighbors points within this,
  int min_neighbors = 20;            //    so isolated outliers are never the tooltip (the original's check)
  double hand_radius = 0.06;         // m: points this close to the hand origin are ignored, and ...
  double piece_gap = 0.06;           // m: ... those not joined to what the hand holds (share_hand_settings)
  double ambiguity_distance = 0.01;  // m: an alternative tip this far from the chosen one makes the
                                     //    tooltip ambiguous (the accuracy a tool's use needs)
  double tip_edge_radius = 0.005;    // m: the surface's density at the tip is counted within this (a few
                                     //    sampling spacings of a reconstruction)
  double fringe_depth = 0.015;       // m: how deep a fringe of fattened or misregistered surface may lie
                                     //    beyond the true edge (the robot's reconstructions reach a median
                                     //    10.5 mm beyond the true tooltip, 17 mm at the 90th percentile; views
                                     //    left at their recorded poses 6 mm); 0: no fringe
  int tip_views = 2;                 // in a merge of views, a blade's far end counts only where the points
                                     //    within tip-edge-radius of it were seen by this many views (or all
                                     //    the cloud's, if fewer): smear stretches a plate's edge along one
                                     //    view's rays, where no other view saw anything, while the plate
                                     //    faces several. A hook's or hoe's front may face one view alone, and
                                     //    the weighted rule takes it. A blade none of whose points pass keeps
                                     //    every candidate. 1: any
};

// The tooltip ignores the hand and what it does not hold as the frame does: its hand-radius and piece-gap.
void share_hand_settings(const ToolFrameConfig& frame, TooltipConfig& tooltip);

// Another tip the rule could have given: on another symmetry plane that scored as well as the chosen
// one, or another point tied with the chosen one on the same plane.
struct TooltipAlternative {
  Vec3 position = Vec3::Zero();       // hand frame, on its symmetry plane
  Vec3 symmetry_axis = Vec3::Zero();  // the plane's normal
  double plane_score = 0.0;           // the plane's symmetry score (0 perfect)
  std::string source;                 // "tied symmetry plane" or "tied point"
};

struct Tooltip {
  Vec3 position = Vec3::Zero();          // hand frame, on the symmetry plane
  Vec3 position_in_tool = Vec3::Zero();  // tool frame (z = 0)
  Vec3 surface_point = Vec3::Zero();     // the chosen cloud point before projection (hand frame)
  double edge_retreat_m = 0.0;           // how far behind surface_point the surface's edge lies (the fringe)
  double score = 0.0;
  int candidates = 0;          // effector-side points considered
  int rejected_sparse = 0;     // better-scoring candidates rejected by the density check
  int tied = 0;                // dense candidates scoring within tie-tolerance of the best
  int detached_points = 0;     // beyond the hand but not joined to what it holds: never candidates
  int detached_pieces = 0;     // how many pieces those form
  double noise_m = 0.0;        // RMS distance of the tip's neighbours from their plane
  double uncertainty_m = 0.0;  // how far the tip would move under that noise: the farthest
                               // tied point whose tie-break is within 2 sigma of the best
  int views_in_cloud = 0;      // how many views saw the cloud (0: its points carry no view labels)
  int views_at_tip = 0;        // ... and the points within density-radius of surface_point: one of several
                               //    is a tip nothing else backs (a patch of the scene one view took in)
  std::vector<TooltipAlternative> alternatives;
  bool ambiguous = false;  // an alternative lies farther than ambiguity-distance away
  Confidence confidence;   // the frame's, whether another tip scores as well, and whether one view alone saw it
};

// How far back from point, along -direction, the surface's edge lies: where the density within
// tip-edge-radius first reaches half that of the surface fringe-depth behind the point. 0 at a sharp edge.
double edge_retreat(const KdTree& tree, const Vec3& point, const Vec3& direction, const TooltipConfig& config);

// What the tooltip's rule measures of a cloud whatever the frame, kept for the many frames of one cloud (the
// search's hypotheses, a frame's alternatives): each point's distance from the hand, the points beyond it
// joined to what it holds (the candidates), and each point's density check and smoothing neighbours,
// computed when first needed. Not thread-safe (it caches); points and tree (over points) must outlive it.
class TooltipCache {
 public:
  // views (empty, or one per point): which of the views merged into the cloud saw each point.
  TooltipCache(const Points& points, const KdTree& tree, const TooltipConfig& config,
               std::vector<std::uint32_t> views = {});

  const Points& points() const { return points_; }
  const KdTree& tree() const { return tree_; }
  const TooltipConfig& config() const { return config_; }
  double from_hand(std::uint32_t index) const { return from_hand_[index]; }  // the point's distance from the hand
  // The indices of the points farther than hand-radius from the hand and joined to what it holds, ascending.
  const std::vector<std::uint32_t>& beyond_hand() const { return held_.indices; }
  const HeldPiece& held() const { return held_; }
  // Whether the point has more than min-neighbors others within density-radius.
  bool dense(std::uint32_t index) const;
  const std::vector<std::uint32_t>& views() const { return views_; }
  int views_in_cloud() const { return views_in_cloud_; }  // how many views saw the cloud (0: no view labels)
  // How many views saw the points within radius of the point (0 without view labels).
  int views_near(const Vec3& point, double radius) const;
  // Whether the points within tip-edge-radius of the point were seen by tip-views views, or by all the cloud's.
  bool seen_by_enough(std::uint32_t index) const;
  // The point's smoothing-neighbors nearest points (itself included), nearest first.
  const std::vector<KdTree::Neighbor>& smoothing_neighbors(std::uint32_t index) const;

 private:
  const Points& points_;
  const KdTree& tree_;
  TooltipConfig config_;
  std::vector<double> from_hand_;
  HeldPiece held_;
  std::vector<std::uint32_t> views_;
  int views_in_cloud_ = 0;
  mutable std::vector<std::int8_t> dense_;  // per point: 1 dense, 0 sparse, -1 not checked yet
  mutable std::vector<std::int8_t> seen_;   // per point: 1 seen by enough views, 0 not, -1 not checked yet
  mutable std::unordered_map<std::uint32_t, std::vector<KdTree::Neighbor>> smoothing_;  // of the points searched
};

// Throws MethodError when no effector-side point passes the density check. views (empty, or one per point):
// which of the views merged into the cloud saw each point (PointCloud::views); they decide tip-views, and
// when the cloud has several and the points within density-radius of the tip all come from one, the tip is
// doubtful.
Tooltip find_tooltip(const Points& points, const ToolFrame& frame, const TooltipConfig& config = {},
                     const std::vector<std::uint32_t>& views = {});
// The same with the points' tree already built (tree over points).
Tooltip find_tooltip(const Points& points, const KdTree& tree, const ToolFrame& frame, const TooltipConfig& config,
                     const std::vector<std::uint32_t>& views = {});
// The same with what the rule measures of the cloud kept from other frames of it, with the cache's config and views.
Tooltip find_tooltip(const TooltipCache& cache, const ToolFrame& frame);

// find-tooltip's whole job: the frame estimated from the cloud and its tooltip, on one kd-tree and held
// piece (the search's hypotheses' tooltips by tooltip_config too). The hand settings are the frame's
// (share_hand_settings); viewpoints and views as estimate_tool_frame and find_tooltip take them.
struct FrameAndTooltip {
  ToolFrame frame;
  Tooltip tooltip;
};
FrameAndTooltip estimate_frame_and_tooltip(const Points& points, const ToolFrameConfig& frame_config,
                                           TooltipConfig tooltip_config, const Points& viewpoints = {},
                                           const std::vector<std::uint32_t>& views = {});
// A cloud that views of its session are missing from (PointCloud::unmerged_views) may lack what they alone saw, the
// head or its tip among it: a tooltip on it is doubtful, however well it scores.
void check_unmerged_views(Confidence& confidence, int unmerged_views);
// The same on a cloud as merge-views writes it: its viewpoints, views and unmerged views.
FrameAndTooltip estimate_frame_and_tooltip(const PointCloud& cloud, const ToolFrameConfig& frame_config,
                                           const TooltipConfig& tooltip_config);
Tooltip find_tooltip(const PointCloud& cloud, const ToolFrame& frame, const TooltipConfig& config);

// find_tooltip's position alone (nothing where it throws), without the noise, the tied points' spread and
// the alternatives it measures around it: what the search needs of each hypothesis, at a fraction of the cost.
std::optional<Vec3> tooltip_position(const TooltipCache& cache, const ToolFrame& frame);

}  // namespace toolinc
