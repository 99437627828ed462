// One partial view of a held tool, as align-pose receives it: the simulator's scene (the tool held with
// a grasp at one exploration pose, the left eye fixating it) rendered with the same z-buffer, and the
// tool's surface samples that the camera sees kept: its back faces and whatever the hand box hides are
// gone, the points near the hand are cropped as the original does, and Gaussian noise is added.
#pragma once

#include <Eigen/Core>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/session_simulator.hpp"
#include "toolinc/synth/tool_generator.hpp"

namespace toolinc {

struct PartialViewConfig {
  Eigen::Vector2d wrist_deg{0.0, 0.0};  // the exploration pose (wrist X, Y) the view is taken from
  double depth_tolerance = 0.003;       // m: a sample is seen when it lies within this of the z-buffer's
                                        //    depth at its pixel (the splats of its neighbours on a slanted
                                        //    surface are up to ~3 mm nearer; back faces are >= 4 mm behind)
  double spacing = 0.002;               // m: the seen samples are resampled to one per voxel of this size
  double hand_radius = 0.06;            // m: points this close to the hand origin are cropped (the original)
  double noise_sigma = 0.0015;          // m per coordinate
};

// The tool's visible points in the hand frame. `scene` describes the tool (shape or model), the grasp
// (hand_from_canonical), the hand, the camera and the scene exactly as for simulate_session; its seed
// draws the dense rendering samples, rng the noise.
Points render_partial_view(const SessionSimulatorConfig& scene, const PartialViewConfig& config, Rng& rng);

// One accuracy case: a family's default shape with every dimension varied by up to +/-15%, held with a
// random grasp from `range` and seen in one partial view; the model is the same shape sampled at its
// default spacing (other samples than the rendered ones). Deterministic for (family, seed).
struct PartialViewCase {
  ToolShape shape;
  PointCloud model;       // canonical
  Eigen::Matrix4d grasp;  // hand_from_canonical
  Points view;            // hand frame
  ToolGroundTruth truth;
};
PartialViewCase make_partial_view_case(ToolFamily family, std::uint32_t seed,
                                       const GraspRange& range = any_grasp_range(),
                                       const PartialViewConfig& config = {});
// The same for a canonical model (e.g. a CAD model read from a file) with the given symmetry: the model
// itself is rendered (its points as the dense samples) and is the case's model. Deterministic for
// (model, seed).
PartialViewCase make_model_partial_view_case(const PointCloud& model, ToolSymmetry symmetry, std::uint32_t seed,
                                             const GraspRange& range = any_grasp_range(),
                                             const PartialViewConfig& config = {});

// Errors of an estimated hand_from_canonical, modulo the tool's symmetry: the rotation (for an axial tool
// only the handle's direction counts), the translation of the canonical origin (the handle's start, on
// every symmetry axis), and the tooltip (tool_ground_truth's, carried by the estimate).
struct PoseErrors {
  double rotation_deg = 0, translation_m = 0, tooltip_m = 0;
  bool within(double rotation_deg_max, double translation_m_max, double tooltip_m_max) const {
    return rotation_deg <= rotation_deg_max && translation_m <= translation_m_max && tooltip_m <= tooltip_m_max;
  }
};
PoseErrors pose_errors(const PartialViewCase& c, const Eigen::Matrix4d& hand_from_canonical);

}  // namespace toolinc
