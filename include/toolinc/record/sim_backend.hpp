// The simulated robot: Arm, Gaze and Sources over the session simulator's renderer, so the recorder runs
// end to end on any machine (`record --backend sim`, CI). The arm puts the simulated hand where it is
// sent, the eye (at scene.eye_position) looks where it is told, and each fresh read renders the scene as
// it is then and observes it as the stereo module and the blob detector would.
#pragma once

#include <memory>
#include <optional>

#include "toolinc/record/clock.hpp"
#include "toolinc/record/devices.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc {

struct SimBackendConfig {
  SessionSimulatorConfig scene;  // the tool, the grasp, the camera, the eye and the noise (seed)
  double motion_time = 0.5;      // s of the clock a motion takes
  // A stream that never answers, to show how the recorder copes with a module that is not running.
  std::optional<Sources::Stream> silent;
};

class SimRobot {
 public:
  // Throws std::invalid_argument on a bad scene (see simulate_session).
  SimRobot(const SimBackendConfig& config, Clock& clock);
  ~SimRobot();
  Arm& arm();        // the hand holding the tool
  Arm& other_arm();  // not rendered
  Gaze& gaze();
  Sources& sources();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// "left", "disparity", "blob_mask", "blob_box", "points" -> the stream; std::invalid_argument otherwise.
Sources::Stream stream_from_string(const std::string& name);

}  // namespace toolinc
