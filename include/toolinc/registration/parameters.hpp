// Every parameter of align-pose and merge-views, once (toolinc/core/parameter.hpp).
#pragma once

#include <vector>

#include "toolinc/core/parameter.hpp"
#include "toolinc/registration/align_pose.hpp"
#include "toolinc/registration/merge_views.hpp"

namespace toolinc {

const std::vector<Parameter<AlignPoseConfig>>& align_pose_parameters();
const std::vector<Parameter<MergeConfig>>& merge_parameters();

}  // namespace toolinc
