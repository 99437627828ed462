#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{
      {-0.15862671407222484, 1.1651958508669507, -4.5054560639432815, -3.4465305487981346, -4.1115497167065,
       1.147615319698413, 0.6979192458974919, 0.20490932906714032, 1.4306417875769712, 1.9278720301973609},
      0.9841915406560107};
  return model;
}

}  // namespace toolinc
