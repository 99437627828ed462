#include "toolinc/frame/frame_search.hpp"

namespace toolinc {

// Fitted by fit-frame-score (configs/frame-score.json says on what); a test checks the two agree.
const FrameScoreModel& fitted_frame_score() {
  static const FrameScoreModel model{
      {-0.26426096962211615, 0.5290068164039768, -3.8309690937687186, -2.681074196611913, -2.3821319003717556,
       1.5546879961595572, 0.6299181785747081, 0.017558758905308728, 1.0094700472927565},
      0.9394736740063971};
  return model;
}

}  // namespace toolinc
