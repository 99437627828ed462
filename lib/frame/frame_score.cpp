#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{
      {-0.3181518205035117, -1.4358852042005308, -0.02649053171106653, -9.521203711148381, 0.11605519633330072,
       -0.05357247160580788, -1.6180955752031494, 0.21058619154279462},
      2.019700518202189};
  return model;
}

}  // namespace toolinc
