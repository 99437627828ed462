// Settings of the YARP adapter (lib/yarp/, built only with YARP): which controllers and ports the recorder
// connects on the iCub. Plain data, so the executable's options and configs/ exist in every build.
#pragma once

#include <string>

namespace toolinc {

struct YarpBackendConfig {
  std::string robot = "icub";
  std::string hand = "right";  // the arm holding the tool
  // Remotes of the controllers (iKinGazeCtrl, iKinCartesianSolver); an empty arm remote means
  // /<robot>/cartesianController/<hand>_arm.
  std::string gaze_remote = "/iKinGazeCtrl";
  std::string arm_remote, other_arm_remote;
  bool other_arm = true;                              // open the other arm's controller too (to move it out of view)
  bool controllers = true;                            // false: no controller is opened (the caller supplies the motion)
  std::string left_port = "/icub/camcalib/left/out";  // PixelRgb
  std::string disparity_port = "/SFM/disp:o";         // PixelMono, 8-bit disparity
  std::string blob_mask_port = "/dispBlobber/opt:o";  // PixelMono, 255 = blob
  std::string blob_roi_port = "/dispBlobber/roi/left:o";  // ((tlx tly brx bry))
  std::string blobs_port = "/dispBlobber/blobs/left:o";   // ((cx cy area))
  std::string sfm_rpc = "/SFM/rpc";                       // Rect tlx tly w h step -> X Y Z ...
  std::string local_prefix = "/toolinc/record";           // local port names start with this (+ pid)
  double connect_timeout = 5.0;                           // s to find the name server, a port or a controller
  double rpc_timeout = 3.0;                               // s for the stereo module's answer
};

// The cartesian controller's remote for an arm: the configured one, or /<robot>/cartesianController/<hand>_arm.
inline std::string arm_remote_for(const YarpBackendConfig& config, const std::string& hand,
                                  const std::string& configured) {
  return configured.empty() ? "/" + config.robot + "/cartesianController/" + hand + "_arm" : configured;
}

}  // namespace toolinc
