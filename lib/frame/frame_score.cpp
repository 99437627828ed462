#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{
      {3.867159783849039, -4.186742324840448, -2.35664048559253, -1.5008212291287255, -0.6762959543708551,
       -2.2541757891682126, 0.7244464967464661, 0.056699464755631396, 0.516126792934601, 1.6981411666779755,
       2.5820336260559733, 1.4327323815201736, -0.8378627513609964},
      0.9456403066220564,
      0.015};
  return model;
}

}  // namespace toolinc
