// Synthetic held-tool cases with known answers, shared by the accuracy tests.
#pragma once

#include <vector>

#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/session_simulator.hpp"
#include "toolinc/synth/tool_generator.hpp"

namespace toolinc::testing {

// The generated families' regression mode: ideal stereo and the `any` grasps the floors were measured on.
inline SessionSimulatorConfig ideal_family_session(ToolFamily family, std::uint32_t seed) {
  SessionSimulatorConfig config = family_session(family, seed, ExplorationGrasps::any);
  config.stereo = StereoModel::ideal;
  return config;
}

struct HeldToolCase {
  ToolShape shape;
  PointCloud model;       // canonical, noise-free
  Eigen::Matrix4d grasp;  // hand_from_canonical
  Points observed;        // hand frame, hand removed, noisy
  ToolGroundTruth truth;
};

// A family's default shape with every dimension varied by up to +/-`variation` (relative), held with a
// random grasp from `range`, the points within hand_radius removed and noise of sigma added.
inline HeldToolCase make_held_tool(ToolFamily family, std::uint32_t seed, const GraspRange& range = {},
                                   double noise_sigma = 0.0015, double hand_radius = 0.06, double variation = 0.15) {
  Rng rng(seed * 7919u + static_cast<std::uint32_t>(family) * 104729u + 17u);
  HeldToolCase c;
  c.shape = default_shape(family);
  const auto vary = [&](double& v) { v *= 1.0 + rng.uniform(-variation, variation); };
  vary(c.shape.handle_length);
  vary(c.shape.handle_radius);
  vary(c.shape.head_length);
  vary(c.shape.head_width);
  vary(c.shape.head_height);
  c.model = generate_tool(c.shape, seed);
  c.grasp = random_grasp(range, rng);
  c.observed = observe_in_hand(c.model.points, c.grasp, hand_radius, noise_sigma, rng);
  c.truth = tool_ground_truth(c.model.points, symmetry_of(family), truth_tip_of(family), c.grasp);
  return c;
}

}  // namespace toolinc::testing
