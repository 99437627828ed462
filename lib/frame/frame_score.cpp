#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{
      {3.6875252408437604, -4.093400598179779, -2.239268393392061, -1.8099402939183917, -0.6435818133335613,
       -2.026005621387567, 0.7141441886645735, 0.17832920405325525, 0.42801923605795383, 1.6053776534478752,
       2.634375995115425, 1.436847371673663, -0.8988673108543666},
      0.9459345886323502,
      0.015};
  return model;
}

}  // namespace toolinc
