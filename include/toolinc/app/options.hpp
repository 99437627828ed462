// Option groups and loading steps shared by several executables, so each is defined once.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/record/recorder.hpp"
#include "toolinc/registration/align_pose.hpp"
#include "toolinc/registration/merge_views.hpp"
#include "toolinc/session/crop.hpp"

namespace toolinc {

void add_tool_frame_options(CLI::App& cli, ToolFrameConfig& config);
// rule: the --rule option's string, set to config.rule's name as its default.
void add_tooltip_options(CLI::App& cli, TooltipConfig& config, std::string& rule);
void add_merge_options(CLI::App& cli, MergeConfig& config);
void add_align_pose_options(CLI::App& cli, AlignPoseConfig& config);
void add_crop_options(CLI::App& cli, CropConfig& config);
void add_record_options(CLI::App& cli, RecordConfig& config);

// An option of exactly three numbers (x y z), its default shown; it takes no more, so a positional
// argument may follow it (`--box-max 0.4 0 0.2 SESSION`).
CLI::Option* add_xyz_option(CLI::App& cli, const std::string& name, std::vector<double>& xyz,
                            const std::string& description);

// The model align-pose fits a view to. Throws InputError naming the file when model and view are in
// different units or the model is not usable as a tool model (its frame cannot be estimated).
PoseModel pose_model_of(const PointCloud& model, const PointCloud& view, const AlignPoseConfig& config,
                        const std::string& model_file, const std::string& view_file);
// A tool model as pose_model_of takes it, whatever the view: throws InputError naming the file when its
// extent is no tool's (too small, or millimetres) or its frame cannot be estimated.
PoseModel tool_model_of(const PointCloud& model, const AlignPoseConfig& config, const std::string& model_file);

// Reads a cloud, logs what was read (and how many non-finite points were dropped), and rejects a cloud
// with no finite point as bad input.
PointCloud load_cloud(const std::string& path);

}  // namespace toolinc
