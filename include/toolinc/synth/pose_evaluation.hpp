// Accuracy of align-pose on canonical models (e.g. CAD models read from files): each model held with
// random grasps, one rendered partial view per grasp (make_model_partial_view_case), the pose found from
// it compared with the grasp modulo the model's measured symmetry. The loop evaluate-poses runs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/registration/align_pose.hpp"
#include "toolinc/synth/partial_view.hpp"

namespace toolinc {

struct PoseEvaluationConfig {
  int grasps = 5;                    // random grasps per model (any_grasp_range: any turn about the handle)
  std::uint32_t seed = 1;            // grasp g of every model is drawn from seed and g alone
  unsigned jobs = 1;                 // cases in parallel (the results do not depend on it)
  double max_rotation_deg = 3.0;     // a pose is right within this rotation ...
  double max_translation_m = 0.005;  // ... and this translation of the canonical origin,
  double max_tooltip_m = 0.010;      // or with its tooltip within this (all modulo symmetry)
  AlignPoseConfig align;
  PartialViewConfig view;
};

struct PoseEvaluationModel {
  std::string name;       // the file, as given
  std::string kind;       // model_kind(name)
  PointCloud cloud;       // canonical
  ToolSymmetry symmetry;  // measured (measure_symmetry)
};

struct PoseCaseResult {
  int model = 0;  // index into the models
  int grasp = 0;
  PoseErrors errors;           // NaN-free only when failure is empty
  bool pose_right = false;     // rotation and translation within the limits
  bool tooltip_right = false;  // tooltip within its limit
  bool right = false;          // either (a failure is wrong)
  bool ambiguous = false, feasible = false;
  int view_points = 0;
  std::string failure;  // the MethodError's reason when align-pose failed
};

// Every model under config.grasps grasps, in model-then-grasp order, whatever config.jobs.
std::vector<PoseCaseResult> evaluate_poses(const std::vector<PoseEvaluationModel>& models,
                                           const PoseEvaluationConfig& config);

}  // namespace toolinc
