// The result files the executables exchange: tool_frame, tool_pose, tooltip, merge_report (docs/formats.md).
#pragma once

#include <string>

#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/registration/align_pose.hpp"
#include "toolinc/registration/merge_views.hpp"

namespace toolinc {

Json tool_frame_json(const ToolFrame& frame, const ToolFrameConfig& config);
// Reads the frame's matrix; throws InputError when the file is not a tool_frame or its rotation is not
// a rotation (not orthonormal, or det != +1, e.g. a mirror-image frame).
ToolFrame read_tool_frame(const std::string& path);
// The same, of a file already read (path names it in errors).
ToolFrame tool_frame_from_json(const Json& json, const std::string& path);
// align-pose's result: the chosen pose, its fitness, feasibility and the poses fitting as well; the
// files it came from and how long each stage took.
Json tool_pose_json(const PoseResult& result, const AlignPoseConfig& config, const std::string& model_file,
                    const std::string& view_file, double model_ms, double total_ms);
// hand_from_model of a tool_pose file (align-pose's -o). Throws InputError naming the file when it is
// not a tool_pose or its matrix is not rigid.
Eigen::Matrix4d read_tool_pose(const std::string& path);

Json tooltip_json(const Tooltip& tooltip, const ToolFrame& frame, const TooltipConfig& config);

// The merge report: per input view accepted or rejected, its correction and why; `failure` non-empty
// when the merge as a whole failed (then "ok" is false).
Json merge_report_json(const std::vector<std::string>& inputs, const MergeResult& merged, const MergeConfig& config,
                       const std::string& failure);
// Reads the "position" of a tooltip file.
Vec3 read_tooltip_position(const std::string& path);
Vec3 tooltip_position_from_json(const Json& json, const std::string& path);

}  // namespace toolinc
