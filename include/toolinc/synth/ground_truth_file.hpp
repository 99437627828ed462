// The tool_ground_truth file (docs/formats.md): a synthetic held tool's grasp, true tool frame and
// tooltip(s) in the hand frame, as generate-tool --truth and simulated sessions write it.
#pragma once

#include <string>

#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/grasp.hpp"

namespace toolinc {

Json ground_truth_json(const ToolGroundTruth& truth, const ToolShape& shape);
// Throws InputError naming the file when it is not a tool_ground_truth or its transforms are not rigid.
ToolGroundTruth read_ground_truth(const std::string& path);

}  // namespace toolinc
