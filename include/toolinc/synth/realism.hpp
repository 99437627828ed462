// How realistic simulated sessions are: the distance profile of the robot's own reconstruction of a real
// tool to that tool's model, against the profile of the merged models of simulated sessions of the same
// model (the realistic-stereo calibration: a folder of the lab's real tools holds such pairs).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "toolinc/ann/nearest_distance.hpp"
#include "toolinc/core/point_cloud.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc {

// The real model (canonical pose) aligned onto the reconstruction (hand frame) by align_pose, and every
// reconstruction point's distance to the aligned model. Throws MethodError when no pose is found.
DistanceProfile reconstruction_profile(const Points& model, const Points& reconstruction);

// Sessions of `model` (its measured symmetry, simulate-session's grasp for each seed, the given stereo
// model) through the whole pipeline at its defaults (crop without the depth-edge filter, as the original
// pipeline that made the real reconstructions): per seed the merged model's profile to the true surface
// and the frame and tooltip errors.
std::vector<SessionErrors> simulated_sessions(const PointCloud& model, const std::string& name, StereoModel stereo,
                                              std::uint32_t first_seed, int seeds);

}  // namespace toolinc
