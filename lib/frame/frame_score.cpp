#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{
      {3.417512655583261, -3.9674211846067924, -2.45103688849698, -2.455439367260751, -0.33661387563555134,
       -1.7355210204166451, 0.8394204054699189, 0.13188907589221213, 0.41542968299949473, 1.6741780555304768,
       2.488472695879549, 1.021565494813284, -0.9310570952798501},
      0.9686859569813422,
      0.015};
  return model;
}

}  // namespace toolinc
