#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{{3.2766704882003603, -4.542919378708202, -2.5628423093512747, -3.5097850725144006,
                                      -2.2588448914532786, -5.46122515032473, 0.801943553002008, 0.34827017631390544,
                                      0.5055033781278082, 1.5341478144576952, 5.571587320422203, 1.6347325453955532},
                                     0.9967629568635193};
  return model;
}

}  // namespace toolinc
