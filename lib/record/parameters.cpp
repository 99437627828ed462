#include "toolinc/record/parameters.hpp"

namespace toolinc {

namespace {
constexpr bool kOpen = true, kClosed = false;
using R = RecordConfig;
using G = GazeConfig;
}  // namespace

const std::vector<Parameter<RecordConfig>>& record_parameters() {
  static const std::vector<Parameter<RecordConfig>> table{
      {"gaze-iterations", "", "Re-fixations from the blob, at most", &nested<R, &R::gaze, &G::refine_iterations>, 0,
       kClosed, 100},
      {"gaze-fraction", "", "Fixate this far from the hand to the blob's far end",
       &nested<R, &R::gaze, &G::refine_fraction>, 0, kOpen, 1},
      {"gaze-tolerance-px", "px", "A target this close to the image centre is fixated",
       &nested<R, &R::gaze, &G::tolerance_px>, 0, kOpen, 10000},
      {"arm-timeout", "s", "Time for the arm to reach a pose", &R::arm_timeout, 0, kOpen, kMaxWait},
      {"gaze-timeout", "s", "Time for the gaze to settle", &R::gaze_timeout, 0, kOpen, kMaxWait},
      {"read-timeout", "s", "Time for a fresh message on a port or an RPC answer", &R::read_timeout, 0, kOpen,
       kMaxWait},
      {"settle-time", "s", "Waited after the motions before reading (the original's 1 s)", &R::settle_time, 0, kClosed,
       kMaxSettle},
      {"attempts", "", "Reads of a view before giving up", &R::attempts, 1, kClosed, 100},
      {"sfm-step", "px", "Pixel step of the exact-3D query (1: every pixel of the blob's box)", &R::sfm_step, 1,
       kClosed, 10000},
      {"num-disparities", "", "The stereo module's, recorded with the camera (0: 96 at width <= 320, else 128)",
       &R::num_disparities, 0, kClosed, 1024},
      {"baseline", "m", "Stereo baseline recorded with the camera", &R::baseline, kMinLength, kClosed, kMaxLength},
  };
  return table;
}

}  // namespace toolinc
