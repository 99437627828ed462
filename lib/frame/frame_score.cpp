#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{
      {3.613894493251169, -4.761527508193745, -2.6659188567565524, -3.5222073414629973, -2.2783085421886957,
       -1.4940050523274897, 0.5874005693493608, 0.3705865906394375, 0.5048748783616072, 1.5251039170938627,
       5.629079637318415, 1.8121645825960992, -0.9163791647459881},
      0.9967081949622528};
  return model;
}

}  // namespace toolinc
