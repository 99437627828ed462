#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{{2.5629599975717556, -4.585538918719986, -2.103421558423854, -3.232608230171139,
                                      -3.219338195796618, -3.929561054054162, 1.2056854326591633, 0.4843360130484447,
                                      0.4889805106345239, 1.4659404432500733, 4.338342482497368},
                                     0.987644548078251};
  return model;
}

}  // namespace toolinc
