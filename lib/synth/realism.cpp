#include "toolinc/synth/realism.hpp"

#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/registration/align_pose.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/grasp.hpp"

namespace toolinc {

DistanceProfile reconstruction_profile(const Points& model, const Points& reconstruction) {
  const PoseModel pose_model(model);
  const PoseResult pose = align_pose(pose_model, reconstruction);
  return distance_profile(reconstruction, transform_points(model, pose.best.hand_from_model));
}

std::vector<SessionErrors> simulated_sessions(const PointCloud& model, const std::string& name, StereoModel stereo,
                                              std::uint32_t first_seed, int seeds) {
  SessionSimulatorConfig config;
  config.model = model;
  config.model_name = name;
  config.model_symmetry = measure_symmetry(model.points);
  config.stereo = stereo;
  std::vector<SessionErrors> sessions;
  for (int s = 0; s < seeds; ++s) {
    config.seed = first_seed + static_cast<std::uint32_t>(s);
    config.hand_from_canonical = exploration_grasp(config.seed);
    sessions.push_back(evaluate_simulated_session(config));
  }
  return sessions;
}

}  // namespace toolinc
