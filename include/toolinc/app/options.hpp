// Option groups and loading steps shared by several executables, so each is defined once.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"

namespace toolinc {

void add_tool_frame_options(CLI::App& cli, ToolFrameConfig& config);
void add_tooltip_options(CLI::App& cli, TooltipConfig& config, std::string& rule);

// Reads a cloud, logs what was read (and how many non-finite points were dropped), and rejects a cloud
// with no finite point as bad input.
PointCloud load_cloud(const std::string& path);

}  // namespace toolinc
