// toolinc's common path in one header: a held tool's cloud in the hand frame in (read_cloud), its
// intrinsic frame (estimate_tool_frame), its tooltip (find_tooltip) and their confidence
// (tooltip.confidence) out, every parameter in the two config structs (documented in
// toolinc/frame/parameters.hpp), written as the executables write them (results_json). Link
// toolinc::results, which brings the clouds and the geometry (not OpenCV).
#pragma once

#include "toolinc/core/error.hpp"
#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/confidence.hpp"
#include "toolinc/frame/parameters.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/results/results_json.hpp"
