#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{
      {-0.020372704266417477, 0.6856292013338108, -3.756270570702074, -3.2847820894400526, -2.837668704419701,
       1.229848983360724, 0.6154436314881168, -0.27639049573186864, 1.1158186825553893, 2.0343203194786197},
      0.9482935926758612};
  return model;
}

}  // namespace toolinc
