#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{
      {3.8347881314577426, -4.095500850052268, -2.316613587722292, -1.418710085405528, -0.7137696734790127,
       -2.1997320566995557, 0.731469283393954, 0.22122245210033292, 0.5334350307175485, 1.5668082529194556,
       2.525999004753581, 1.425701497555269, -0.8494807967091659},
      0.9463184668881449,
      0.015};
  return model;
}

}  // namespace toolinc
