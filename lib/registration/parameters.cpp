#include "toolinc/registration/parameters.hpp"

namespace toolinc {

namespace {
constexpr bool kOpen = true, kClosed = false;
using A = AlignPoseConfig;
using M = MergeConfig;
using I = IcpConfig;
}  // namespace

const std::vector<Parameter<AlignPoseConfig>>& align_pose_parameters() {
  static const std::vector<Parameter<AlignPoseConfig>> table{
      {"hand-radius", "m", "View points this close to the hand origin are the hand's", &A::hand_radius, 0, kClosed,
       kMaxLength},
      {"min-view-points", "", "Fewer resampled view points cannot fix a pose", &A::min_view_points, 0, kOpen,
       kMaxCount},
      {"max-extent-ratio", "", "Model and view extents further apart: different units", &A::max_extent_ratio, 1,
       kClosed, 1e6},
      {"model-voxel", "m", "Resampling of the model", &A::model_voxel, kMinLength, kClosed, kMaxLength},
      {"view-voxel", "m", "Resampling of the view", &A::view_voxel, kMinLength, kClosed, kMaxLength},
      {"max-handle-radius-factor", "",
       "The view's handle is its tool frame's when its cylinder is at most this times as thick as the model's (and "
       "passes within max-handle-offset of the hand)",
       &A::max_handle_radius_factor, 1, kClosed, 100},
      {"max-handle-offset", "m",
       "The view's handle is its tool frame's when it passes this close to the hand; otherwise the line from the hand "
       "through the view",
       &A::max_handle_offset, kMinLength, kClosed, kMaxLength},
      {"fallback-cone-deg", "deg", "Tilt of the six axes tried around that line", &A::fallback_cone_deg, 0, kClosed,
       90},
      {"roll-step-deg", "deg", "Step of the rolls about the handle tried as hypotheses", &A::roll_step_deg, 1, kClosed,
       180},
      {"coarse-points", "", "View points that test each hypothesis", &A::coarse_points, 0, kOpen, 100000},
      {"prescore-sigma", "m", "Fit sigma of the hypotheses as they are", &A::prescore_sigma, kMinLength, kClosed,
       kMaxLength},
      {"coarse-candidates", "", "Best hypotheses refined coarsely", &A::coarse_candidates, 0, kOpen, 1000},
      {"coarse-far", "m", "Correspondence distance of the first coarse stage", &A::coarse_far, kMinLength, kClosed,
       kMaxLength},
      {"coarse-near", "m", "Correspondence distance of the second coarse stage", &A::coarse_near, kMinLength, kClosed,
       kMaxLength},
      {"coarse-iterations", "", "ICP iterations per coarse stage", &A::coarse_iterations, 0, kOpen, kMaxIterations},
      {"score-sigma", "m", "A point's fit is exp(-d^2 / 2 sigma^2), d its distance to the model", &A::score_sigma,
       kMinLength, kClosed, kMaxLength},
      {"refine-candidates", "", "Distinct hypotheses refined fully", &A::refine_candidates, 0, kOpen, 1000},
      {"same-pose-deg", "deg", "Hypotheses closer than this rotation and same-pose-m converged to the same pose",
       &A::same_pose_deg, 0, kClosed, 180},
      {"same-pose-m", "m", "Hypotheses closer than this translation and same-pose-deg converged to the same pose",
       &A::same_pose_m, 0, kClosed, kMaxLength},
      {"slide-step", "m", "Step of the search along the handle pinned by the far end", &A::slide_step, kMinLength,
       kClosed, kMaxLength},
      {"slide-margin", "m", "Far ends of view and model this far apart still meet; beyond, the fit is discounted",
       &A::slide_margin, kMinLength, kClosed, kMaxLength},
      {"max-iterations", "", "Iterations of the final ICP", &nested<A, &A::icp, &I::max_iterations>, 0, kOpen,
       kMaxIterations},
      {"max-correspondence", "m", "Correspondence distance of the final ICP",
       &nested<A, &A::icp, &I::max_correspondence>, kMinLength, kClosed, kMaxLength},
      {"kernel-scale", "m", "Geman-McClure scale of the final ICP (about 2 sigma of the noise)",
       &nested<A, &A::icp, &I::kernel_scale>, kMinLength, kClosed, kMaxLength},
      {"inlier-distance", "m", "View points this close to the model are inliers",
       &nested<A, &A::icp, &I::inlier_distance>, kMinLength, kClosed, kMaxLength},
      {"min-step", "", "The final ICP stops when an update moves less than this (m, rad)",
       &nested<A, &A::icp, &I::min_step>, 0, kOpen, 1},
      {"damping", "", "Weight of the final ICP's prior towards its start, relative to the mean curvature",
       &nested<A, &A::icp, &I::damping>, 0, kClosed, 1e6},
      {"max-translation", "m", "Feasible translation of the tool per axis", &A::max_translation, 0, kClosed,
       kMaxLength},
      {"max-tilt-deg", "deg", "Feasible tilt about the hand's Z", &A::max_tilt_deg, 0, kClosed, 180},
      {"max-roll-deg", "deg", "Feasible roll about the hand's X", &A::max_roll_deg, 0, kClosed, 90},
      {"max-about-handle-deg", "deg", "Feasible rotation about the handle", &A::max_about_handle_deg, 0, kClosed, 180},
      {"ambiguity-margin", "",
       "Poses scoring within this of the best and rotated more than ambiguity-deg from it fit as well",
       &A::ambiguity_margin, 0, kClosed, 1},
      {"ambiguity-deg", "deg",
       "Poses rotated more than this from the best and scoring within ambiguity-margin of it fit as well",
       &A::ambiguity_deg, 0, kClosed, 180},
  };
  return table;
}

const std::vector<Parameter<MergeConfig>>& merge_parameters() {
  static const std::vector<Parameter<MergeConfig>> table{
      {"voxel-size", "m", "Model grid", &M::voxel_size, kMinLength, kClosed, kMaxLength},
      {"registration-voxel", "m", "Views are resampled this coarsely for ICP", &M::registration_voxel, kMinLength,
       kClosed, kMaxLength},
      {"max-translation", "m", "Largest correction per axis", &M::max_translation, 0, kClosed, kMaxLength},
      {"max-rotation-deg", "deg", "Largest correction rotation", &M::max_rotation_deg, 0, kClosed, 180},
      {"min-inlier-ratio", "", "Share of a view that must land on the model", &M::min_inlier_ratio, 0, kClosed, 1},
      {"min-points", "", "A view with fewer points is rejected", &M::min_points, 0, kClosed, kMaxCount},
      {"clean-radius", "m", "At the end, points with fewer than clean-min-neighbors within this are stray",
       &M::clean_radius, kMinLength, kClosed, kMaxLength},
      {"clean-min-neighbors", "", "Fewer neighbours within clean-radius makes a point stray", &M::clean_min_neighbors,
       0, kClosed, 1000},
      {"see-through-tolerance", "m",
       "A view's point another view saw through by more than this (its ray met the tool farther on) is smear and "
       "is dropped; 0: none",
       &M::see_through_tolerance, 0, kClosed, kMaxLength},
      {"max-iterations", "", "Iterations of each view's ICP", &nested<M, &M::icp, &I::max_iterations>, 0, kOpen,
       kMaxIterations},
      {"max-correspondence", "m", "ICP correspondence radius", &nested<M, &M::icp, &I::max_correspondence>, kMinLength,
       kClosed, kMaxLength},
      {"kernel-scale", "m", "Geman-McClure scale of the ICP (about 2 sigma of the noise)",
       &nested<M, &M::icp, &I::kernel_scale>, kMinLength, kClosed, kMaxLength},
      {"inlier-distance", "m", "View points this close to the model are inliers",
       &nested<M, &M::icp, &I::inlier_distance>, kMinLength, kClosed, kMaxLength},
      {"min-step", "", "The ICP stops when an update moves less than this (m, rad)", &nested<M, &M::icp, &I::min_step>,
       0, kOpen, 1},
      {"damping", "", "Weight of the ICP's prior towards its start, relative to the mean curvature",
       &nested<M, &M::icp, &I::damping>, 0, kClosed, 1e6},
  };
  return table;
}

}  // namespace toolinc
