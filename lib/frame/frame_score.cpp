#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{{3.311151165811972, -4.6733775270013584, -2.6564891845010155, -3.4223360376109,
                                      -1.8211246574368822, -5.4225289735692295, 0.7681046481334692, 0.33747134358391767,
                                      0.5049609034718556, 1.5464382614027015, 5.6010388418296175, 1.6530437744999384},
                                     0.9966802088242713};
  return model;
}

}  // namespace toolinc
