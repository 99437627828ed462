// Accuracy against a synthetic ground truth: of the tool frame and tooltip on a canonical model held
// with random grasps (the loop the accuracy tests and evaluate-models share), and of the whole offline
// pipeline on a simulated session (the loop the session test and evaluate-sessions share).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "toolinc/ann/nearest_distance.hpp"
#include "toolinc/frame/frame_search.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/registration/merge_views.hpp"
#include "toolinc/session/crop.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc {

struct HeldToolErrors {
  bool right_handed = false;
  double handle_axis_deg = 0.0;
  bool effector_sign_right = false;  // meaningful for tools with a salient effector
  double tooltip_m = 0.0;
  // What the frame costs: the tooltip rule applied to the same cloud with the true frame, and how far
  // the estimated symmetry plane is turned from the true one (0-90 degrees). A miss that the true frame
  // also makes lies in the cloud (the tip not seen, or points off the tool in front of it), not in the frame.
  double tooltip_true_frame_m = 0.0;
  // The tooltip's error against the true model aligned onto the cloud (ICP from its true pose), as the
  // robot's reconstructions are judged: the views' kinematic error moves a merged model as a whole, which
  // no frame rule can see. The same as tooltip_m for a held tool's cloud, which nothing moved.
  double tooltip_relative_m = 0.0;
  double symmetry_plane_deg = 0.0;
  bool confident = false;          // the tooltip's confidence.confident
  double tooltip_probability = 0;  // the search's probability of the chosen tooltip (0 by the rules)
  std::string failure;             // the MethodError's reason when the method failed, else empty
};

// Holds `canonical` with `grasp`, removes the hand's points, adds noise, runs estimate_tool_frame and
// find_tooltip, and compares with the ground truth.
HeldToolErrors evaluate_held_tool(const Points& canonical, ToolSymmetry symmetry, TruthTip tip,
                                  const Eigen::Matrix4d& grasp, double hand_radius, double noise_sigma, Rng& rng,
                                  const ToolFrameConfig& frame_config = {}, const TooltipConfig& tooltip_config = {});

struct PipelineConfig {
  CropConfig crop;
  MergeConfig merge;
  // The merged model as bare points, without the views that saw each point and their viewpoints: as the
  // robot's reconstructions are (PLY of x, y, z and colour).
  bool bare_model = false;
  ToolFrameConfig frame;
  TooltipConfig tooltip;
};

// crop-cloud's settings for sessions of this stereo model: the defaults on ideal disparity, the matcher's
// (matched_stereo_crop) on matched disparity.
CropConfig session_crop(StereoModel stereo);

// The pipeline as the robot's reconstructions were made by the original exploreTool: its merge
// (original_merge) and the model kept as bare points.
PipelineConfig as_original_reconstruction(PipelineConfig pipeline);

struct SessionErrors {
  int views_rejected = 0;       // by crop-cloud (too few points) or merge-views
  double model_median_m = 0.0;  // median distance from the merged model to the true surface
  DistanceProfile model;        // the merged model's whole distance profile to the true surface
  Points merged;                // the merged model (hand frame), empty when the merge failed
  HeldToolErrors tool;          // of the frame and tooltip; failure also says when the merge failed
};

// The tool's pose in the hand frame as the merged model has it: the true surface (canonical) aligned onto
// the merged model by point-to-plane ICP from its true pose (hand_from_canonical).
Eigen::Matrix4d pose_on_merged_model(const Points& merged, const Points& canonical,
                                     const Eigen::Matrix4d& hand_from_canonical);

// The configured tool's true surface in the canonical pose: a model's own points; a family's shape
// sampled at 1 mm, finer than the merged model's 2 mm grid, so that distances to it measure the model.
Points true_surface(const SessionSimulatorConfig& session);

// Simulates the session, then crop-cloud (all views), merge-views, estimate-frame and find-tooltip, as
// scripts/pipeline.mk runs them, and compares with the tool's true surface and ground truth.
SessionErrors evaluate_simulated_session(const SessionSimulatorConfig& session, const PipelineConfig& pipeline = {});

// Every frame hypothesis (frame_search.hpp) on a simulated session's merged model, with its tooltip's
// error against the truth carried by the true model aligned onto that model (infinite where the
// hypothesis has no tip) and whether its effector points the true way: the search's training data. Empty
// when the session does not merge.
struct LabelledHypothesis {
  std::array<double, kFrameFeatures> features;
  std::string handle_source;
  bool side_reversed = false;
  std::optional<Vec3> tooltip;        // hand frame
  std::optional<Vec3> other_end;      // hand frame, as FrameHypothesis::other_end
  Vec3 effector_side = Vec3::Zero();  // hand frame, as frame_search.hpp's effector_side
  double tooltip_m = 0.0;
  // The effector along the true +X, or the tool has no salient effector (a stick, a T): a scoop's tip is
  // its far end whichever side the frame takes, so the tip alone does not tell its working side.
  bool effector_right = true;
  double handle_deg = 0.0;  // the handle axis's angle from the true one (a stick's tip does not tell it)
  // Every check of find-tooltip's confidence but the choice's probability passes (the grasp, a tied point or
  // plane, a blade's spread, a tip one view saw): only such a hypothesis, chosen, can be called confident.
  bool backed = false;
};
std::vector<LabelledHypothesis> labelled_frame_hypotheses(const SessionSimulatorConfig& session,
                                                          const PipelineConfig& pipeline = {});

// A rate and its 95 % (Wilson) interval: "95.0% (92.0-96.9%)", and as JSON {name, trials, successes,
// rate, rate_interval_95}; the reports over families, kinds and models share them.
std::string rate_text(int successes, int trials);
nlohmann::ordered_json rate_json(const std::string& name, int successes, int trials);

// The symmetry class of a canonical model, measured: mirror symmetric about x = 0 too -> front_back,
// also about the planes at 45 degrees -> fourfold, and also at 22.5 and 67.5 degrees -> axial;
// otherwise mirror (salient effector along +X).
ToolSymmetry measure_symmetry(const Points& canonical);

}  // namespace toolinc
