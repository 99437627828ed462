#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{{3.2169934522308736, -4.576143380891187, -2.578360484183059, -3.512338857812203,
                                      -1.9880155482850346, -5.510734368087185, 0.7629831129244774, 0.339504439003957,
                                      0.50525446354474, 1.5420525237067748, 5.607671005472564, 1.655008538419347},
                                     0.9966936486343558};
  return model;
}

}  // namespace toolinc
