#include "toolinc/app/options.hpp"

#include <spdlog/spdlog.h>

#include "toolinc/app/range.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/frame/parameters.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/record/parameters.hpp"
#include "toolinc/registration/parameters.hpp"
#include "toolinc/session/parameters.hpp"

namespace toolinc {

namespace {

// The option of each parameter of a table, with its help (meaning and unit), default and range.
template <class Config>
void add_parameter_options(CLI::App& cli, Config& config, const std::vector<Parameter<Config>>& table,
                           const std::string& group) {
  for (const auto& p : table) {
    const std::string help = *p.unit ? std::string(p.meaning) + " (" + p.unit + ")" : std::string(p.meaning);
    visit_value(p, config, [&](auto& value) {
      cli.add_option(std::string("--") + p.name, value, help)
          ->capture_default_str()
          ->group(group)
          ->check(in_range(range_of(p)));
    });
  }
}

}  // namespace

void add_tool_frame_options(CLI::App& cli, ToolFrameConfig& c) {
  cli.add_option_function<std::string>(
         "--method", [&c](const std::string& name) { c.method = frame_method_from_string(name); },
         "rules (each axis decided once) or search (every hypothesis scored by the fitted model, the one whose "
         "tooltip is likeliest kept)")
      ->default_str(to_string(c.method))
      ->group("Tool frame")
      ->check(CLI::IsMember({"rules", "search"}));
  add_parameter_options(cli, c, tool_frame_parameters(), "Tool frame");
}

void add_tooltip_options(CLI::App& cli, TooltipConfig& c, std::string& rule) {
  rule = to_string(c.rule);
  cli.add_option("--rule", rule,
                 "weighted (the original's 0.8 x in front + 0.2 x distance from the hand) or furthest (furthest "
                 "in front, ties by distance from the hand)")
      ->capture_default_str()
      ->group("Tooltip")
      ->check(CLI::IsMember({"furthest", "weighted"}));
  add_parameter_options(cli, c, tooltip_parameters(), "Tooltip");
}

CLI::Option* add_xyz_option(CLI::App& cli, const std::string& name, std::vector<double>& xyz,
                            const std::string& description) {
  return cli.add_option(name, xyz, description)->expected(3)->allow_extra_args(false)->capture_default_str();
}

void add_merge_options(CLI::App& cli, MergeConfig& config) {
  add_parameter_options(cli, config, merge_parameters(), "Merging");
}

void add_align_pose_options(CLI::App& cli, AlignPoseConfig& config) {
  add_parameter_options(cli, config, align_pose_parameters(), "Alignment");
}

void add_crop_options(CLI::App& cli, CropConfig& config) {
  add_parameter_options(cli, config, crop_parameters(), "Cropping");
}

void add_record_options(CLI::App& cli, RecordConfig& config) {
  add_parameter_options(cli, config, record_parameters(), "Exploration");
}

PoseModel pose_model_of(const PointCloud& model, const PointCloud& view, const AlignPoseConfig& config,
                        const std::string& model_file, const std::string& view_file) {
  if (const std::string mismatch = unit_mismatch(model.points, view.points, config.max_extent_ratio); !mismatch.empty())
    throw InputError(mismatch.rfind("the model", 0) == 0 ? model_file : view_file, mismatch);
  return tool_model_of(model, config, model_file);
}

PoseModel tool_model_of(const PointCloud& model, const AlignPoseConfig& config, const std::string& model_file) {
  if (const std::string problem = implausible_extent(model.points, "the model"); !problem.empty())
    throw InputError(model_file, problem);
  try {
    return PoseModel(model.points, config);
  } catch (const MethodError& e) {
    throw InputError(model_file, std::string("not usable as a tool model: ") + e.what());
  }
}

PointCloud load_cloud(const std::string& path) {
  CloudReadStats stats;
  PointCloud cloud = read_cloud(path, &stats);
  if (stats.non_finite_dropped > 0)
    spdlog::warn("{}: dropped {} non-finite points of {}", path, stats.non_finite_dropped, stats.points_in_file);
  if (cloud.empty())
    throw InputError(path, stats.points_in_file == 0 ? "the cloud has no points" : "the cloud has no finite points");
  spdlog::info("{}: {} points{}", path, cloud.size(), cloud.frame.empty() ? "" : " (frame " + cloud.frame + ")");
  return cloud;
}

}  // namespace toolinc
