// The pose of a known tool from one partial view (paper sect. 5): the model, in the canonical pose, is
// aligned to the view, in the hand frame, from any grasp. Global initialisation from the tool frames (the
// view's handle axis is reliable on partial views, the roll about it is not, so rolls are swept, and both
// handle directions), each hypothesis refined coarsely and ranked by a fit that weights the tool's head;
// then robust point-to-plane ICP of the view onto the model from the best few; then feasibility (hand
// translation and rotation limits) and ambiguity (poses that fit equally well: a stick's roll, a T's
// front and back).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/registration/icp.hpp"

namespace toolinc {

struct AlignPoseConfig {
  // Inputs.
  double hand_radius = 0.06;       // m: view points this close to the hand origin are the hand's (the
                                   //    original's crop); also the tool frames' hand radius
  int min_view_points = 100;       // fewer resampled view points than this cannot fix a pose (a thin
                                   //    stick's visible strip, 1 cm wide and 30 cm long at 3 mm, has 100)
  double max_extent_ratio = 20.0;  // model and view extents further apart than this factor are in
                                   //    different units (mm against m is 1000)
  double model_voxel = 0.003;      // m: the model is resampled to this for the ICP target
  double view_voxel = 0.003;       // m: the view is resampled to this for the refinement

  // Global initialisation.
  double max_handle_radius_factor = 2.0;  // the view's handle is its tool frame's when the fitted cylinder
  double max_handle_offset = 0.08;        //    is at most this times as thick as the model's and passes this
                                          //    close to the hand (m); otherwise the hand-to-view line ...
  double fallback_cone_deg = 15.0;        //    and six axes tilted this much around it
  double roll_step_deg = 20.0;            // rolls about the view's handle axis, in both handle directions
  int coarse_points = 300;                // view points that test each hypothesis
  double prescore_sigma = 0.01;           // m: fit sigma of the hypotheses as they are ...
  int coarse_candidates = 12;             // ... the best this many of which are refined coarsely
  double coarse_far = 0.03;               // m: correspondence distance of the first coarse stage ...
  double coarse_near = 0.012;             // m: ... and of the second
  int coarse_iterations = 6;              // per stage
  double score_sigma = 0.004;             // m: a point's fit is exp(-d^2 / 2 sigma^2), d its distance to the model
  int refine_candidates = 3;              // distinct hypotheses refined fully
  double same_pose_deg = 5.0;             // hypotheses closer than this rotation ...
  double same_pose_m = 0.01;              // ... and this translation converged to the same pose

  // The slide along a plain handle, which the fit leaves free, pinned by the view's far end.
  double slide_step = 0.002;   // m: step of the 1-D search along the handle (under the view's 3 mm
                               //    resampling and the 5 mm a pose may be off)
  double slide_margin = 0.01;  // m: far ends of view and model this far apart still meet (their
                               //    quantiles differ by the noise and a partly seen end face): searched
                               //    this far beyond; further apart, the fit is discounted (a Gaussian
                               //    of this width)

  // Local refinement (view onto model). A lighter prior than the default: the refinement starts from a
  // coarse hypothesis, and the view's head must be free to turn the tool about its handle.
  // Steps below 1e-5 (10 um, 0.0006 deg) are far under the stereo noise.
  IcpConfig icp{30, 0.01, 0.003, 0.005, 1e-5, 1e-4};

  // Feasibility of hand_from_model = T(t) Rz(tilt) Rx(roll) Ry(about_handle) (the grasp's parameters).
  double max_translation = 0.10;        // m per axis (the paper)
  double max_tilt_deg = 75.0;           // |tilt| about the hand's Z
  double max_roll_deg = 75.0;           // |roll| about the hand's X
  double max_about_handle_deg = 180.0;  // |rotation about the handle| (any by default)

  // Ambiguity.
  double ambiguity_margin = 0.03;  // candidates scoring within this of the best ...
  double ambiguity_deg = 10.0;     // ... and rotated more than this from it fit equally well
};

// The model prepared once for many views.
struct PoseModel {
  PoseModel(const Points& canonical, const AlignPoseConfig& config = {});
  PoseModel(const PoseModel&) = delete;
  PoseModel& operator=(const PoseModel&) = delete;
  IcpTarget target;  // resampled model with normals and its kd-tree
  ToolFrame frame;   // the model's tool frame in the canonical pose
};

struct Feasibility {
  Vec3 translation = Vec3::Zero();  // m, of hand_from_model
  double tilt_deg = 0, roll_deg = 0, about_handle_deg = 0;
  bool feasible = false;
  std::string reason;  // the first limit exceeded, empty when feasible
};
// Decomposes the pose as the grasp parameters and checks them against the config's limits.
Feasibility check_feasibility(const Eigen::Matrix4d& hand_from_model, const AlignPoseConfig& config);

struct PoseCandidate {
  Eigen::Matrix4d hand_from_model = Eigen::Matrix4d::Identity();
  double score = 0;         // head-weighted fit of the view, 0..1
  double inlier_ratio = 0;  // share of view points within icp.inlier_distance of the model
  double inlier_rmse = 0;   // m, RMS point-to-plane distance of those inliers
  int iterations = 0;       // of the final refinement
  bool converged = false;
};

struct PoseResult {
  PoseCandidate best;
  Feasibility feasibility;
  bool ambiguous = false;
  std::vector<PoseCandidate> candidates;  // when ambiguous: the poses fitting equally well, best first
  int view_points_input = 0;              // as given
  int view_points_used = 0;               // outside the hand, resampled
  int hypotheses = 0;
  double view_ms = 0, global_ms = 0, refine_ms = 0;  // timing: view preparation and frame, hypotheses,
                                                     // final refinement
};

// Why a cloud cannot be a tool, what being "the model" or "the view", or empty: its bounding box's diagonal
// is under 1 cm (a single point, copies of one, a speck) or over 2 m (no tool the hand holds: millimetres?).
std::string implausible_extent(const Points& points, const std::string& what);

// Why model and view cannot be a tool and its view in metres, or empty: either's extent is implausible (the
// view's checked first) or their extents differ by more than max_extent_ratio. The reason starts with
// "the model" or "the view", whichever is at fault.
std::string unit_mismatch(const Points& model, const Points& view, double max_extent_ratio);

// view: the tool in the hand frame. Throws MethodError when the view has too few points or no tool frame.
PoseResult align_pose(const PoseModel& model, const Points& view, const AlignPoseConfig& config = {});

// The local refinement alone: the view (resampled, hand removed) onto the model from model_from_view.
IcpResult refine_pose(const PoseModel& model, const Points& view, const Eigen::Matrix4d& model_from_view,
                      const AlignPoseConfig& config = {});

// Rotation angle between two poses' rotations, in degrees.
double rotation_difference_deg(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b);

// The oriented model: the model (points and normals) moved into the hand frame by the pose.
PointCloud oriented_model(const PointCloud& model, const Eigen::Matrix4d& hand_from_model);

// The model's tool frame and tooltip, found on the model in its canonical pose, carried into the hand
// frame by the pose.
struct CarriedTooltip {
  ToolFrame frame;
  Tooltip tooltip;
};
CarriedTooltip carry_tooltip(const PoseModel& model, const Points& canonical, const Eigen::Matrix4d& hand_from_model,
                             const TooltipConfig& config = {});

}  // namespace toolinc
