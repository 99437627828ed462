// An arm and a gaze that stay where they are, with their poses and the camera read from a JSON file: for
// checking the sources (cameras, stereo module, blob detector) without the motion controllers, e.g. the
// loopback run (README "Recording on the robot"). The file:
//   {"root_from_hand": 4x4, "root_from_camera": 4x4,
//    "camera": {"width": 320, "height": 240, "fx": ..., "fy": ..., "cx": ..., "cy": ...}}
#pragma once

#include <memory>
#include <string>

#include "toolinc/record/devices.hpp"

namespace toolinc {

struct StaticMotion {
  std::unique_ptr<Arm> arm;
  std::unique_ptr<Gaze> gaze;
};

// Throws InputError naming the file when it is missing, malformed or a pose is not rigid.
StaticMotion read_static_motion(const std::string& path);

}  // namespace toolinc
