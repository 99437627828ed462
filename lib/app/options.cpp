#include "toolinc/app/options.hpp"

#include <spdlog/spdlog.h>

#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"

namespace toolinc {

void add_tool_frame_options(CLI::App& cli, ToolFrameConfig& c) {
  const auto group = "Tool frame";
  const auto positive = CLI::PositiveNumber;
  cli.add_option("--hand-radius", c.hand_radius, "Points this close to the hand origin are the hand's (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--voxel-size", c.voxel_size, "Resampling voxel for density-independent statistics (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--min-points", c.min_points, "Fewer points outside the hand is degenerate")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--min-length", c.min_length, "Shortest acceptable extent along the major axis (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--min-thickness", c.min_thickness, "RMS spread below which points are collinear/planar (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--handle-fraction", c.handle_fraction, "Share of the length, from the hand end, fitted as handle")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.05, 1.0));
  cli.add_option("--handle-hand-skip", c.handle_hand_skip,
                 "Share of the length, at the hand end, left out of the handle fit (the hand may survive the cut)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 0.9));
  cli.add_option(
         "--handle-section-length", c.handle_section_length,
         "The handle's radius is refitted per section of this length, so a grip and a thinner shaft do not tilt it (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option(
         "--stick-width", c.stick_width,
         "A tool whose effector side stays this close to its axis has no head: a stick, its tip its far end (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--symmetry-step-deg", c.symmetry_step_deg, "Coarse sweep step of the symmetry plane (deg)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.5, 45.0));
  cli.add_option("--symmetry-tolerance", c.symmetry_tolerance, "Mirror distance counted as fully asymmetric (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--symmetry-samples", c.symmetry_samples, "Points mirrored per symmetry score")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--symmetry-tie-margin", c.symmetry_tie_margin,
                 "Planes scoring within this of the best are equally symmetric")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 1.0));
  cli.add_option("--symmetry-doubt-margin", c.symmetry_doubt_margin,
                 "A plane 30 degrees or more from the chosen one scoring within this of it is a rival, whose tip "
                 "find-tooltip reports")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 1.0));
  cli.add_option("--head-radius-factor", c.head_radius_factor,
                 "Effector-side points this many handle radii from the handle axis are the head (mirrored)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 100.0));
  cli.add_option("--min-head-points", c.min_head_points, "Fewer head points than this is no head: all are mirrored")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--head-line-elongation", c.head_line_elongation,
                 "Spread ratio along/across a line, seen along the handle, that makes the head a bar")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(1.0, 1e6));
  cli.add_option("--symmetry-normal-neighbors", c.symmetry_normal_neighbors,
                 "Neighbours of the normals a mirror image's distance is measured along")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(3, 100));
  cli.add_option("--symmetry-match-weight", c.symmetry_match_weight,
                 "Weight of a matched mirror image's distance against a contradicted image (1)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 1.0));
  cli.add_option("--blade-flatness", c.blade_flatness,
                 "A blade, seen along the handle, is deep (RMS) at most this share of its width")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 1.0));
  cli.add_option("--blade-centring", c.blade_centring,
                 "A blade's extent, seen along the handle, is centred on its axis within this share of its width")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 1.0));
  cli.add_option("--front-band", c.front_band, "Depth of the effector's front telling a face from a corner (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--head-curl-min", c.head_curl_min,
                 "A blade or scoop whose edges rise this much above its middle faces its concave side (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--salience-ratio", c.salience_ratio, "Reach ratio that makes an effector side salient")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(1.0, 100.0));
  cli.add_option("--salience-min", c.salience_min, "Reach difference that makes an effector side salient (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option(
         "--blade-min-aspect", c.blade_min_aspect,
         "A blade or scoop reaching along the handle this share of its width continues it: its tip is its far end")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 100.0));
  cli.add_option("--grasp-reach", c.grasp_reach,
                 "The handle's axis passes this close to the hand; a farther one makes the frame doubtful (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--grasp-max-radius", c.grasp_max_radius,
                 "The hand closes on handles up to this radius; a thicker fitted handle makes the frame doubtful (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
}

void add_tooltip_options(CLI::App& cli, TooltipConfig& c, std::string& rule) {
  const auto group = "Tooltip";
  rule = to_string(c.rule);
  cli.add_option("--rule", rule,
                 "weighted (the original's 0.8 x in front + 0.2 x distance from the hand) or furthest (furthest "
                 "in front, ties by distance from the hand)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::IsMember({"furthest", "weighted"}));
  cli.add_option("--tie-tolerance", c.tie_tolerance, "Points scoring this close to the best tie (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--effector-weight", c.effector_weight, "weighted rule: weight of the distance in front (0..1)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 1.0));
  cli.add_option("--smoothing-neighbors", c.smoothing_neighbors,
                 "weighted rule: tied points compared by their this many nearest points' mean distance in front")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(1, 1000));
  cli.add_option("--ambiguity-distance", c.ambiguity_distance,
                 "An alternative tip this far from the chosen one makes the tooltip ambiguous (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::PositiveNumber);
  cli.add_option("--density-radius", c.density_radius, "Density check radius (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::PositiveNumber);
  cli.add_option("--min-neighbors", c.min_neighbors, "A tooltip needs more than this many neighbours")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--tip-edge-radius", c.tip_edge_radius,
                 "The surface's density at the tip is counted within this, to find its edge (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(1e-4, 1.0));
  cli.add_option("--fringe-depth", c.fringe_depth,
                 "How deep a fringe of fattened or misregistered surface may lie beyond the true edge; 0: none (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 1.0));
}

CLI::Option* add_xyz_option(CLI::App& cli, const std::string& name, std::vector<double>& xyz,
                            const std::string& description) {
  return cli.add_option(name, xyz, description)->expected(3)->allow_extra_args(false)->capture_default_str();
}

void add_merge_options(CLI::App& cli, MergeConfig& config) {
  cli.add_option("--voxel-size", config.voxel_size, "Model grid (m)")->capture_default_str();
  cli.add_option("--max-translation", config.max_translation, "Largest correction per axis (m)")->capture_default_str();
  cli.add_option("--max-rotation-deg", config.max_rotation_deg, "Largest correction rotation (deg)")
      ->capture_default_str();
  cli.add_option("--min-inlier-ratio", config.min_inlier_ratio, "Share of a view that must land on the model")
      ->capture_default_str();
  cli.add_option("--min-points", config.min_points, "A view with fewer points is rejected")->capture_default_str();
  cli.add_option("--max-correspondence", config.icp.max_correspondence, "ICP correspondence radius (m)")
      ->capture_default_str();
}

void add_align_pose_options(CLI::App& cli, AlignPoseConfig& c) {
  const auto group = "Alignment";
  const auto positive = CLI::PositiveNumber;
  cli.add_option("--hand-radius", c.hand_radius, "View points this close to the hand origin are the hand's (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--min-view-points", c.min_view_points, "Fewer resampled view points cannot fix a pose")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--max-extent-ratio", c.max_extent_ratio, "Model and view extents further apart: different units")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(1.0, 1e6));
  cli.add_option("--model-voxel", c.model_voxel, "Resampling of the model (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--view-voxel", c.view_voxel, "Resampling of the view (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--roll-step-deg", c.roll_step_deg, "Step of the rolls about the handle tried as hypotheses (deg)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(1.0, 180.0));
  cli.add_option("--refine-candidates", c.refine_candidates, "Distinct hypotheses refined fully")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--slide-step", c.slide_step, "Step of the search along the handle pinned by the far end (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--slide-margin", c.slide_margin,
                 "Far ends of view and model this far apart still meet; beyond, the fit is discounted (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--max-iterations", c.icp.max_iterations, "Iterations of the final ICP")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--max-correspondence", c.icp.max_correspondence, "Correspondence distance of the final ICP (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--inlier-distance", c.icp.inlier_distance, "View points this close to the model are inliers (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--max-translation", c.max_translation, "Feasible translation of the tool per axis (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--max-tilt-deg", c.max_tilt_deg, "Feasible tilt about the hand's Z (deg)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 180.0));
  cli.add_option("--max-roll-deg", c.max_roll_deg, "Feasible roll about the hand's X (deg)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 90.0));
  cli.add_option("--max-about-handle-deg", c.max_about_handle_deg, "Feasible rotation about the handle (deg)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 180.0));
  cli.add_option("--ambiguity-margin", c.ambiguity_margin, "Poses scoring within this of the best fit as well")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
}

PoseModel pose_model_of(const PointCloud& model, const PointCloud& view, const AlignPoseConfig& config,
                        const std::string& model_file, const std::string& view_file) {
  if (const std::string mismatch = unit_mismatch(model.points, view.points, config.max_extent_ratio); !mismatch.empty())
    throw InputError(mismatch.rfind("the model", 0) == 0 ? model_file : view_file, mismatch);
  try {
    return PoseModel(model.points, config);
  } catch (const MethodError& e) {
    throw InputError(model_file, std::string("not usable as a tool model: ") + e.what());
  }
}

PointCloud load_cloud(const std::string& path) {
  CloudReadStats stats;
  PointCloud cloud = read_cloud(path, &stats);
  if (stats.non_finite_dropped > 0)
    spdlog::warn("{}: dropped {} non-finite points of {}", path, stats.non_finite_dropped, stats.points_in_file);
  if (cloud.empty())
    throw InputError(path, stats.points_in_file == 0 ? "the cloud has no points" : "the cloud has no finite points");
  spdlog::info("{}: {} points{}", path, cloud.size(), cloud.frame.empty() ? "" : " (frame " + cloud.frame + ")");
  return cloud;
}

}  // namespace toolinc
