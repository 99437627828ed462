// The recording on the robot: for each exploration pose, move the hand holding the tool, fixate
// the tool, wait for both motions to settle, drain stale messages, read fresh ones, ask the stereo module
// for the exact 3D of the blob's box, and write the view. The session is written view by view
// (session.json last), so whatever stops the recording - Ctrl-C, a timeout - leaves a consistent session
// with the views captured so far. Every wait is bounded and checks the stop flag.
#pragma once

#include <atomic>
#include <optional>
#include <string>

#include "toolinc/record/clock.hpp"
#include "toolinc/record/devices.hpp"
#include "toolinc/record/exploration.hpp"
#include "toolinc/record/gaze.hpp"

namespace toolinc {

struct RecordConfig {
  std::string robot = "icub";
  std::string hand = "right";  // the hand holding the tool: "left" | "right"
  std::optional<std::string> tool_label;
  std::string created;  // ISO 8601, recorded in session.json
  std::string notes;
  ExplorationConfig exploration;
  GazeConfig gaze;
  double arm_timeout = 20.0;   // s for the arm to reach a pose
  double gaze_timeout = 10.0;  // s for the gaze to settle on a point
  double read_timeout = 3.0;   // s for a fresh message on each stream, and for the 3D query's answer
  double settle_time = 1.0;    // s waited once the motions are done (the original waits 1 s)
  int attempts = 3;            // reads of a view before giving up on it (the original retries forever)
  double poll_period = 0.01;   // s between polls of a motion or a stream
  int sfm_step = 1;            // pixel step of the 3D query (1: every pixel of the blob's box)
  int num_disparities = 0;     // recorded with the camera; 0: the stereo module's, 96 at width <= 320, else 128
  double baseline = 0.068;     // m, recorded with the camera (for reprojecting the 8-bit disparity)
};

// The robot's parts; other_arm may be null (it then stays where it is).
struct Robot {
  Arm& arm;
  Arm* other_arm;
  Gaze& gaze;
  Sources& sources;
  Clock& clock;
};

struct RecordResult {
  std::size_t views = 0;  // views written
  bool stopped = false;   // the stop flag ended the recording early
};

// Records a session into session_dir, which must not exist or be empty (InputError otherwise). Bad
// configuration (refused poses, bad hand) throws std::invalid_argument before anything moves. A motion or
// stream that times out (after config.attempts reads for streams) stops the motions and throws
// MethodError naming the controller or port; the views written so far stay a consistent session. When
// `stop` is set, the motions are stopped and the result says so.
RecordResult record_session(const std::string& session_dir, const RecordConfig& config, Robot& robot,
                            const std::atomic<bool>& stop);

}  // namespace toolinc
