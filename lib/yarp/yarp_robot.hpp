// The recorder's devices over YARP (built only when YARP is found): the iCub's cartesian and gaze
// controllers through PolyDriver clients, and the camera, stereo module and blob detector through ports.
// This header is YARP-free so the executable can include it without YARP's headers.
#pragma once

#include <memory>

#include "toolinc/record/devices.hpp"
#include "toolinc/record/yarp_config.hpp"

namespace toolinc {

class YarpRobot {
 public:
  // Finds the name server, opens the controllers (unless config.controllers is false) and connects every
  // port, each within config.connect_timeout; throws InputError naming the first one missing.
  explicit YarpRobot(const YarpBackendConfig& config);
  ~YarpRobot();
  Arm* arm();        // null without controllers
  Arm* other_arm();  // null without controllers or config.other_arm
  Gaze* gaze();      // null without controllers
  Sources& sources();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace toolinc
