// Every numeric parameter of record's exploration, once (toolinc/core/parameter.hpp). The poses, positions,
// names and the YARP ports are not numbers of the exploration and are declared beside the table.
#pragma once

#include <vector>

#include "toolinc/core/parameter.hpp"
#include "toolinc/record/recorder.hpp"

namespace toolinc {

const std::vector<Parameter<RecordConfig>>& record_parameters();

}  // namespace toolinc
