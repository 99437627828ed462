#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{{0.4129042515127068, -1.2596197917803875, 1.125923243919989, -3.91624996391203,
                                      -3.044515355160407, -4.118515838911741, 1.143559396398206, 0.6431158542788621,
                                      0.20873873293591907, 1.4687150443834989, 1.945689441479325},
                                     0.9763456208793242};
  return model;
}

}  // namespace toolinc
