// Accuracy of the tool frame and tooltip on a canonical model held with random grasps: the loop the
// accuracy tests and the evaluate-models executable share.
#pragma once

#include <string>

#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/synth/grasp.hpp"

namespace toolinc {

struct HeldToolErrors {
  bool right_handed = false;
  double handle_axis_deg = 0.0;
  bool effector_sign_right = false;  // meaningful for tools with a salient effector
  double tooltip_m = 0.0;
  std::string failure;               // the MethodError's reason when the method failed, else empty
};

// Holds `canonical` with `grasp`, removes the hand's points, adds noise, runs estimate_tool_frame and
// find_tooltip, and compares with the ground truth.
HeldToolErrors evaluate_held_tool(const Points& canonical, ToolSymmetry symmetry, const Eigen::Matrix4d& grasp,
                                  double hand_radius, double noise_sigma, Rng& rng,
                                  const ToolFrameConfig& frame_config = {}, const TooltipConfig& tooltip_config = {});

// The symmetry class of a canonical model, measured: mirror symmetric about x = 0 too -> front_back,
// and also about the planes at 45 degrees -> axial; otherwise mirror (salient effector along +X).
ToolSymmetry measure_symmetry(const Points& canonical);

}  // namespace toolinc
