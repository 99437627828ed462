// The tool's intrinsic frame (paper sect. 4.1-4.2, docs/formats.md): origin at the centre of mass, X the
// effector axis (towards the salient side of the effector), Y the handle axis (towards the hand), Z the
// symmetry axis = X x Y. Always right-handed.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/confidence.hpp"

namespace toolinc {

// How the frame is found: `rules` decides each axis once (the handle, then the plane, then the side);
// `search` completes the frame about every candidate handle with either effector side and keeps the one
// the fitted score rates most likely right (frame_search.hpp).
enum class FrameMethod { rules, search };
std::string to_string(FrameMethod method);
FrameMethod frame_method_from_string(const std::string& name);  // throws std::invalid_argument

struct ToolFrameConfig {
  FrameMethod method = FrameMethod::search;
  double hand_radius = 0.06;          // m: points this close to the hand origin belong to the hand
  double piece_gap = 0.06;            // m: points at most this far apart are one piece; a piece not joined to
                                      //    the one the hand holds is not the tool (a patch of the scene,
                                      //    smear). The robot's reconstructions are whole from 7 mm, simulated
                                      //    sessions' from 45 mm (holes stereo leaves in a head); 0: no split
  double voxel_size = 0.004;          // m: resampling that makes every statistic density-independent
  double isolated_radius = 0.01;      // m: resampled points with fewer than isolated_min_neighbors ...
  int isolated_min_neighbors = 3;     //    ... others within isolated_radius are stray and dropped
  int min_points = 100;               // fewer input points (outside the hand) is degenerate
  double min_length = 0.04;           // m: the tool's extent along its major axis must reach this
  double min_thickness = 0.001;       // m: RMS spread across the major axis (collinear) or across the
                                      //    plane (planar) below this is degenerate
  double handle_fraction = 0.5;       // share of the tool's length, from the hand end, fitted as handle
  double handle_hand_skip = 0.2;      // share of the length at the hand end left out of the handle fit:
                                      //    on a tilted grasp part of the hand survives the hand cut there
                                      //    and tilts and widens the fitted cylinder
  double handle_radial_factor = 1.5;  // handle points lie within this times the median radius of the fit
  int handle_iterations = 20;
  double handle_residual_scale = 0.002;  // m: Huber scale of the handle's cylinder fit (~ stereo noise)
  double handle_solid_fraction = 0.1;    // more of the handle's points than this inside half its radius
                                         //    means a filled model (about 25%; a noisy surface has < 1%): its
                                         //    principal axis is used instead of the cylinder's
  double handle_max_radius = 0.03;       // m: a fitted handle cylinder wider than this is not trusted
  double handle_section_length = 0.02;   // m: the handle's radius is fitted per section of this length, so
                                         //    a grip and a thinner shaft on the same axis do not tilt it
  double held_share = 0.7;               // the part the hand holds, for the search's held-part line: points
                                         //    within this share of the way from the tool's nearest point to
                                         //    its farthest (handles are 45-75 % of the lab's tools)
  double symmetry_step_deg = 7.5;        // coarse sweep of the symmetry plane about the handle axis
  double symmetry_tolerance = 0.01;      // m: mirrored points this far from the cloud are fully asymmetric
  int symmetry_samples = 400;            // points mirrored per score
  int symmetry_normal_neighbors = 6;     // a mirror image's distance is to the tangent plane of its
                                         //    nearest point, the normal from this many neighbours
  double symmetry_match_weight = 0.25;   // a matched mirror image's distance / tolerance weighs this
                                         //    much against an image where a sensor saw empty space (1)
  double head_radius_factor = 2.5;       // effector-side points farther than this many handle radii from
                                         //    the handle's axis are the head: the points mirrored
  int min_head_points = 30;              // fewer head points than this is no head (a stick): all are mirrored
  double head_line_elongation = 16.0;    // a head whose points, seen along the handle, spread this many
                                         //    times more (variance) along a line than across it is a bar:
                                         //    the symmetry plane near that line contains it
  double blade_flatness = 0.7;           // a blade (a flat or curled plate continuing the handle: shovel,
                                         //    spatula), seen along the handle, is deep (RMS) at most this share
                                         //    of its width: wider than deep (a scoop 0.2-0.5 with smear)
  double blade_centring = 0.15;          // ... and centred on the handle's axis across it: the middle of its
                                         //    extent lies within this share of its width from the axis (a
                                         //    shovel's blade within 0.1; a hook or an L, reaching out on one
                                         //    side, 0.25-0.5)
  double blade_min_aspect = 0.5;         // ... and reaches along the handle at least this share of its width
                                         //    (a shovel's blade 0.8-2, a spatula more; a rake's comb or a T's
                                         //    bar 0.1-0.3): its tip is its far end
  double front_band = 0.01;              // m: depth of the effector's front when telling a face (its points
                                         //    grow like the depth) from a corner (like its square); deeper than the
                                         //    noise lifts the foremost point (~3 sigma)
  double symmetry_tie_margin = 0.05;     // planes scoring within this of the best are equally symmetric
  double symmetry_doubt_margin = 0.1;    // a plane of another basin (30 degrees or more from the chosen one)
                                         //    scoring within this of it is a rival: the mirror does not single
                                         //    out the chosen plane, and find-tooltip reports the rival's tip
  double stick_width = 0.025;            // m: a tool whose effector side stays this close to the handle's
                                         //    axis has no head (a stick, however bent): its effector axis is
                                         //    arbitrary. Heads stand out 2.6 cm (a flat shovel) to 13 cm; a
                                         //    view merged a few degrees off fringes a stick's far end to one
                                         //    side, 5-10 mm beyond a clean stick's
  double clean_stick_width = 0.02;       // m: a clean stick's effector side stays this close (the lab's sticks
                                         //    14 mm, the CAD models' up to 19 mm); a stick standing out more is
                                         //    a fringed straight stick or a bent one, alike there: doubtful
  double head_curl_min = 0.005;          // m: a head thinnest along the effector axis (blade, scoop) whose
                                         //    edges rise this much above its middle faces its concave side
                                         //    (about 3 sigma of the stereo noise)
  double salience_quantile = 0.99;       // robust reach of the effector on each side of the handle
  double salience_ratio = 1.5;           // the effector is salient when one reach exceeds the other by ...
  double salience_min = 0.01;            // ... this ratio and this many metres
  double grasp_reach = 0.10;             // m: the hand holds the handle, so the handle's axis passes within
                                         //    this of the hand's origin (the original's grasp check: the tool
                                         //    at most 10 cm from the hand); a farther axis is doubtful
  double grasp_hold = 0.04;              // m: a closed hand holds its handle's axis about this far from the
                                         //    hand's origin (the palm to the fist's middle); the search finds
                                         //    a line passing farther less likely
  double grasp_max_radius = 0.02;        // m: the iCub's hand closes on handles up to about 4 cm across; a
                                         //    thicker fitted handle is not what it holds (a head, the hand or
                                         //    smear in the fit): doubtful
};

// What the head is, decided once from its points about the handle: it decides the tooltip's rule.
enum class HeadKind {
  none,   // a stick: nothing stands out from the handle's axis by stick-width
  bar,    // seen along the handle, the head lies along a line (L, T, hook): the plane contains its axis
  blade,  // a flat plate continuing the handle (shovel, spatula): its tip is its far end
  scoop,  // a curled plate continuing the handle (a shovel's scoop): its tip is its far end
  plate,  // a flat head across the handle's line of sight (a rake's comb, a hoe's blade face-on)
  other,
};
std::string to_string(HeadKind kind);
HeadKind head_kind_from_string(const std::string& name);  // throws std::invalid_argument

struct SymmetryCandidate {
  double angle_deg;  // about the handle axis, from the middle principal axis
  Vec3 normal;
  double score;  // the sweep's score (by contradiction): 0 perfect mirror, 1 none
};

// One hypothesis of the frame search, for the record.
struct ScoredHypothesis {
  std::string handle_source;  // which candidate handle
  bool rules_plane = true;    // the plane the rules choose about that handle, not an alternative
  bool other_side = false;    // the effector on the other side from the one the rules take about that handle
  double probability = 0.0;   // that it is the right one among the hypotheses, as the fitted choice model says
  Vec3 effector_axis = Vec3::Zero(), handle_axis = Vec3::Zero();
  std::optional<Vec3> tooltip;    // its tooltip by the paper's rule, when it has one
  std::optional<Vec3> other_end;  // where a two-ended tool's other end puts it (FrameHypothesis::other_end)
  std::vector<double> features;   // what the choice model weighed, in frame_feature_names()'s order
};

// How the frame was found: for the record (the tool_frame JSON's diagnostics), not for use.
struct ToolFrameDiagnostics {
  Vec3 centroid = Vec3::Zero();                             // mean of the resampled points (before projection)
  Eigen::Matrix3d principal = Eigen::Matrix3d::Identity();  // major, middle, minor axes
  double handle_refinement_deg = 0.0;                       // angle between the major axis and the refined handle axis
  int handle_points = 0;
  double handle_rms = 0.0;                             // m, RMS radial residual of the handle points
  bool handle_cylinder = true;                         // false when the handle points are not a cylinder surface
  std::vector<SymmetryCandidate> symmetry_candidates;  // the sweep, then the refined best
  double across_handle_score = 1.0;                    // plane across the handle: reported, never eligible
  std::string handle_sign_rule;
  std::string effector_sign_rule;
  double effector_reach_positive = 0.0;  // m, along +X from the handle axis
  double effector_reach_negative = 0.0;  // m, along -X
  bool salient_effector = false;
  bool head_is_blade = false;                  // the head is a blade (see blade_flatness)
  double head_length = 0.0, head_width = 0.0;  // m: the head's extent along the handle and across the plane
  double hand_to_handle = 0.0;                 // m: distance from the hand's origin to the handle's axis line
  double head_extent = 0.0;                    // m: how far the effector side stands out from the handle's axis
                                               // (salience-quantile of its points' distances)
  double head_curl = 0.0;                      // m: how far the head's edges rise along +X above its middle,
                                               // measured when the head is thinnest along X
  int points_input = 0, points_outside_hand = 0, points_used = 0;
  int points_detached = 0, pieces_detached = 0;  // beyond the hand but not joined to what it holds: dropped
  std::vector<ScoredHypothesis> hypotheses;      // the search's, the chosen first, then by probability; empty
                                                 // under the rules
  double tooltip_probability = 0.0;              // the search's: that of the chosen tooltip (frame_search.hpp)
};

struct ToolFrame {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // hand_from_tool rotation: columns X, Y, Z
  Vec3 origin = Vec3::Zero();                          // centre of mass, on the symmetry plane
  Vec3 eigenvalues = Vec3::Zero();                     // of the resampled cloud, descending, m^2
  Vec3 handle_point = Vec3::Zero();                    // a point on the handle's axis line
  double handle_radius = 0.0;                          // m, of the handle's fitted cylinder
  HeadKind head_kind = HeadKind::other;
  bool stick = false;                           // nothing stands out from the handle by stick-width: no head
  bool effector_side_clear = true;              // salience or the head's curl decided the effector's side, or
                                                // the search weighed both sides
  double symmetry_score = 1.0;                  // the chosen plane's score
  std::string symmetry_plane_rule;              // what chose the plane
  std::vector<SymmetryCandidate> tied_planes;   // every basin of the sweep scoring within the tie margin of
                                                // the best, refined; the rules above chose one of them
  std::vector<SymmetryCandidate> rival_planes;  // planes of the sweep 30 degrees or more from the chosen one
                                                // scoring within symmetry-doubt-margin of it, best first
  Confidence confidence;                        // whether the handle is the one held and the effector's side clear
  ToolFrameDiagnostics diagnostics;

  Eigen::Matrix4d hand_from_tool() const;
  // A blade or scoop continuing the handle works with its far end, not with its front.
  bool tip_at_far_end() const { return head_kind == HeadKind::blade || head_kind == HeadKind::scoop; }
  Vec3 effector_axis() const { return axes.col(0); }
  Vec3 handle_axis() const { return axes.col(1); }
  Vec3 symmetry_axis() const { return axes.col(2); }
};

// How far the effector reaches on each side of the handle axis along x_axis: the q-quantile of the
// effector-side points' (beyond centre along -y_axis) distances from handle_point along +x_axis and
// along -x_axis. The effector axis points to the side that reaches farther.
struct Reach {
  double positive, negative;  // m, along +X and -X from the handle axis
};
Reach effector_reach(const Points& cloud, const Vec3& centre, const Vec3& handle_point, const Vec3& y_axis,
                     const Vec3& x_axis, double q);

// The searched frame's best hypothesis whose tooltip lies farther than `radius` from the chosen one's and
// from its other end (or that has none): what a doubtful search was torn between. Null for a frame made by the rules,
// or when every hypothesis agrees on the tip.
const ScoredHypothesis* next_tip_elsewhere(const ToolFrame& frame, double radius);

// points: the tool in the hand frame (the hand at the origin). viewpoints (optional): where the sensors
// saw it from (hand frame), so that parts never seen do not count against a symmetry plane. views
// (optional, one per point): which of the views merged into the cloud saw each point, for the search's
// hypotheses' tooltips (find_tooltip's). Throws MethodError with the reason on degenerate input (too few
// points, collinear, planar, everything inside the hand radius).
ToolFrame estimate_tool_frame(const Points& points, const ToolFrameConfig& config = {}, const Points& viewpoints = {},
                              const std::vector<std::uint32_t>& views = {});

class TooltipCache;
// The same on the points, views, kd-tree and held piece of a tooltip cache (find-tooltip's whole job builds
// them once for the frame and the tooltip); the search's hypotheses' tooltips are then the cache's. Its
// hand-radius and piece-gap must be the config's (share_hand_settings): std::invalid_argument otherwise.
ToolFrame estimate_tool_frame(const TooltipCache& cache, const ToolFrameConfig& config, const Points& viewpoints = {});

}  // namespace toolinc
