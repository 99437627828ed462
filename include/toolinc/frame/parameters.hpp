// Every parameter of the frame and tooltip algorithms, once (toolinc/core/parameter.hpp).
#pragma once

#include <vector>

#include "toolinc/core/parameter.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"

namespace toolinc {

const std::vector<Parameter<ToolFrameConfig>>& tool_frame_parameters();
const std::vector<Parameter<TooltipConfig>>& tooltip_parameters();  // but the rule, an enumeration

}  // namespace toolinc
