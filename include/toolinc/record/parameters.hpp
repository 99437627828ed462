// Every numeric parameter of record's exploration, once (toolinc/core/parameter.hpp). The poses, positions,
// names and the YARP ports are not numbers of the exploration and are declared beside the table.
#pragma once

#include <vector>

#include "toolinc/core/parameter.hpp"
#include "toolinc/record/recorder.hpp"

namespace toolinc {

// The longest wait for the robot (s): a controller, a port or the name server that has not answered in
// five minutes will not; and the longest settling pause after a motion (the original's is 1 s).
constexpr double kMaxWait = 300.0;
constexpr double kMaxSettle = 60.0;

const std::vector<Parameter<RecordConfig>>& record_parameters();

}  // namespace toolinc
