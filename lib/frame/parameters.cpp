#include "toolinc/frame/parameters.hpp"

namespace toolinc {

namespace {
constexpr bool kOpen = true, kClosed = false;
using F = ToolFrameConfig;
using T = TooltipConfig;
}  // namespace

const std::vector<Parameter<ToolFrameConfig>>& tool_frame_parameters() {
  static const std::vector<Parameter<ToolFrameConfig>> table{
      {"hand-radius", "m", "Points this close to the hand origin are the hand's", &F::hand_radius, 0, kClosed,
       kMaxLength},
      {"piece-gap", "m",
       "Points at most this far apart are one piece; pieces not joined to the one the hand holds are not the tool "
       "(0: no split)",
       &F::piece_gap, 0, kClosed, kMaxLength},
      {"voxel-size", "m", "Resampling voxel for density-independent statistics", &F::voxel_size, kMinLength, kClosed,
       kMaxLength},
      {"isolated-radius", "m", "Resampled points with fewer than isolated-min-neighbors others within this are stray",
       &F::isolated_radius, kMinLength, kClosed, kMaxLength},
      {"isolated-min-neighbors", "", "Fewer neighbours within isolated-radius makes a resampled point stray",
       &F::isolated_min_neighbors, 0, kClosed, 1000},
      {"min-points", "", "Fewer points outside the hand is degenerate", &F::min_points, 0, kOpen, kMaxCount},
      {"min-length", "m", "Shortest acceptable extent along the major axis", &F::min_length, 0, kClosed, kMaxLength},
      {"min-thickness", "m", "RMS spread below which points are collinear/planar", &F::min_thickness, 0, kClosed,
       kMaxLength},
      {"handle-fraction", "", "Share of the length, from the hand end, fitted as handle", &F::handle_fraction, 0.05,
       kClosed, 1.0},
      {"handle-hand-skip", "",
       "Share of the length, at the hand end, left out of the handle fit (the hand may survive the cut)",
       &F::handle_hand_skip, 0, kClosed, 0.9},
      {"handle-radial-factor", "", "Handle points lie within this times the fitted cylinder's median radius",
       &F::handle_radial_factor, 1, kClosed, 100},
      {"handle-iterations", "", "Iterations of the handle's robust cylinder fit", &F::handle_iterations, 1, kClosed,
       kMaxIterations},
      {"handle-residual-scale", "m", "Huber scale of the handle's cylinder fit (about the stereo noise)",
       &F::handle_residual_scale, kMinLength, kClosed, kMaxLength},
      {"handle-solid-fraction", "",
       "More of the handle's points than this inside half its radius is a filled model: its principal axis is "
       "used instead of the cylinder's",
       &F::handle_solid_fraction, 0, kClosed, 1},
      {"handle-max-radius", "m", "A fitted handle cylinder wider than this is not trusted", &F::handle_max_radius,
       kMinLength, kClosed, kMaxLength},
      {"handle-section-length", "m",
       "The handle's radius is refitted per section of this length, so a grip and a thinner shaft do not tilt it",
       &F::handle_section_length, kMinLength, kClosed, kMaxLength},
      {"held-share", "",
       "The part the hand holds, for the search's held-part line: points within this share of the way from the "
       "tool's nearest point to its farthest",
       &F::held_share, 0.1, kClosed, 1.0},
      {"stick-width", "m",
       "A tool whose effector side stays this close to its axis has no head: a stick, its tip its far end",
       &F::stick_width, 0, kClosed, kMaxLength},
      {"clean-stick-width", "m",
       "A stick whose effector side stands out more than this (but less than stick-width) may be fringed or bent: "
       "doubtful",
       &F::clean_stick_width, 0, kClosed, kMaxLength},
      {"symmetry-step-deg", "deg", "Coarse sweep step of the symmetry plane", &F::symmetry_step_deg, 0.5, kClosed, 45},
      {"symmetry-tolerance", "m", "Mirror distance counted as fully asymmetric", &F::symmetry_tolerance, kMinLength,
       kClosed, kMaxLength},
      {"symmetry-samples", "", "Points mirrored per symmetry score", &F::symmetry_samples, 0, kOpen, 100000},
      {"symmetry-tie-margin", "", "Planes scoring within this of the best are equally symmetric",
       &F::symmetry_tie_margin, 0, kClosed, 1},
      {"symmetry-doubt-margin", "",
       "A plane 30 degrees or more from the chosen one scoring within this of it is a rival, whose tip "
       "find-tooltip reports",
       &F::symmetry_doubt_margin, 0, kClosed, 1},
      {"head-radius-factor", "",
       "Effector-side points this many handle radii from the handle axis are the head "
       "(mirrored)",
       &F::head_radius_factor, 0, kClosed, 100},
      {"min-head-points", "", "Fewer head points than this is no head: all are mirrored", &F::min_head_points, 0,
       kClosed, kMaxCount},
      {"head-line-elongation", "", "Spread ratio along/across a line, seen along the handle, that makes the head a bar",
       &F::head_line_elongation, 1, kClosed, 1e6},
      {"symmetry-normal-neighbors", "", "Neighbours of the normals a mirror image's distance is measured along",
       &F::symmetry_normal_neighbors, 3, kClosed, 100},
      {"symmetry-match-weight", "", "Weight of a matched mirror image's distance against a contradicted image (1)",
       &F::symmetry_match_weight, 0, kClosed, 1},
      {"blade-flatness", "", "A blade, seen along the handle, is deep (RMS) at most this share of its width",
       &F::blade_flatness, 0, kClosed, 1},
      {"blade-centring", "",
       "A blade's extent, seen along the handle, is centred on its axis within this share of "
       "its width",
       &F::blade_centring, 0, kClosed, 1},
      {"blade-min-aspect", "",
       "A blade or scoop reaching along the handle this share of its width continues it: its tip is its far end",
       &F::blade_min_aspect, 0, kClosed, 100},
      {"front-band", "m", "Depth of the effector's front telling a face from a corner", &F::front_band, kMinLength,
       kClosed, kMaxLength},
      {"head-curl-min", "m", "A blade or scoop whose edges rise this much above its middle faces its concave side",
       &F::head_curl_min, 0, kClosed, kMaxLength},
      {"salience-quantile", "", "Quantile of the points' offsets that is the effector's reach on each side",
       &F::salience_quantile, 0.5, kClosed, 1},
      {"salience-ratio", "", "Reach ratio that makes an effector side salient", &F::salience_ratio, 1, kClosed, 100},
      {"salience-min", "m", "Reach difference that makes an effector side salient", &F::salience_min, 0, kClosed,
       kMaxLength},
      {"grasp-reach", "m", "The handle's axis passes this close to the hand; a farther one makes the frame doubtful",
       &F::grasp_reach, kMinLength, kClosed, kMaxLength},
      {"grasp-hold", "m",
       "A closed hand holds its handle's axis about this far from the hand's origin; the search finds a handle line "
       "passing farther less likely",
       &F::grasp_hold, kMinLength, kClosed, kMaxLength},
      {"grasp-max-radius", "m",
       "The hand closes on handles up to this radius; a thicker fitted handle makes the frame doubtful",
       &F::grasp_max_radius, kMinLength, kClosed, kMaxLength},
  };
  return table;
}

const std::vector<Parameter<TooltipConfig>>& tooltip_parameters() {
  static const std::vector<Parameter<TooltipConfig>> table{
      {"tie-tolerance", "m", "Points scoring this close to the best tie", &T::tie_tolerance, 0, kClosed, kMaxLength},
      {"effector-weight", "", "weighted rule: weight of the distance in front (0..1)", &T::effector_weight, 0, kClosed,
       1},
      {"smoothing-neighbors", "",
       "weighted rule: tied points compared by their this many nearest points' mean distance in front",
       &T::smoothing_neighbors, 1, kClosed, 1000},
      {"ambiguity-distance", "m", "An alternative tip this far from the chosen one makes the tooltip ambiguous",
       &T::ambiguity_distance, kMinLength, kClosed, kMaxLength},
      {"density-radius", "m", "Density check radius", &T::density_radius, kMinLength, kClosed, kMaxLength},
      {"min-neighbors", "", "A tooltip needs more than this many neighbours", &T::min_neighbors, 0, kClosed, kMaxCount},
      {"tip-edge-radius", "m", "The surface's density at the tip is counted within this, to find its edge",
       &T::tip_edge_radius, 1e-4, kClosed, 1},
      {"fringe-depth", "m",
       "How deep a fringe of fattened or misregistered surface may lie beyond the true edge; 0: none", &T::fringe_depth,
       0, kClosed, 1},
      {"tip-views", "",
       "In a merge of views: a blade's far end counts only where the points within tip-edge-radius of it were seen "
       "by this many views (or all the cloud's, if fewer); 1: any",
       &T::tip_views, 1, kClosed, 32},
  };
  return table;
}

}  // namespace toolinc
