#include "toolinc/app/options.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

#include "toolinc/core/error.hpp"
#include "toolinc/frame/parameters.hpp"
#include "toolinc/io/cloud_io.hpp"

namespace toolinc {

namespace {

// The option of each parameter of a table, with its help (meaning and unit), default and range.
template <class Config>
void add_parameter_options(CLI::App& cli, Config& config, const std::vector<Parameter<Config>>& table,
                           const std::string& group) {
  for (const auto& p : table) {
    const std::string help = *p.unit ? std::string(p.meaning) + " (" + p.unit + ")" : std::string(p.meaning);
    std::visit(
        [&](auto member) {
          using Value = std::remove_reference_t<decltype(config.*member)>;
          CLI::Option* option = cli.add_option(std::string("--") + p.name, config.*member, help);
          option->capture_default_str()->group(group);
          if (p.min_exclusive && p.min == 0 && std::isinf(p.max))
            option->check(CLI::PositiveNumber);
          else if (p.min == 0 && std::isinf(p.max))
            option->check(CLI::NonNegativeNumber);
          else
            option->check(CLI::Range(static_cast<Value>(p.min), std::isinf(p.max) ? std::numeric_limits<Value>::max()
                                                                                  : static_cast<Value>(p.max)));
        },
        p.field);
  }
}

}  // namespace

void add_tool_frame_options(CLI::App& cli, ToolFrameConfig& c) {
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
  cli.add_option("--voxel-size", config.voxel_size, "Model grid (m)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cli.add_option("--max-translation", config.max_translation, "Largest correction per axis (m)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--max-rotation-deg", config.max_rotation_deg, "Largest correction rotation (deg)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 180.0));
  cli.add_option("--min-inlier-ratio", config.min_inlier_ratio, "Share of a view that must land on the model")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cli.add_option("--min-points", config.min_points, "A view with fewer points is rejected")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--max-correspondence", config.icp.max_correspondence, "ICP correspondence radius (m)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
}

void add_align_pose_options(CLI::App& cli, AlignPoseConfig& c) {
  const auto group = "Alignment";
  const auto positive = CLI::PositiveNumber;
  cli.add_option("--hand-radius", c.hand_radius, "View points this close to the hand origin are the hand's (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--min-view-points", c.min_view_points, "Fewer resampled view points cannot fix a pose")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--max-extent-ratio", c.max_extent_ratio, "Model and view extents further apart: different units")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(1.0, 1e6));
  cli.add_option("--model-voxel", c.model_voxel, "Resampling of the model (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--view-voxel", c.view_voxel, "Resampling of the view (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--roll-step-deg", c.roll_step_deg, "Step of the rolls about the handle tried as hypotheses (deg)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(1.0, 180.0));
  cli.add_option("--refine-candidates", c.refine_candidates, "Distinct hypotheses refined fully")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--slide-step", c.slide_step, "Step of the search along the handle pinned by the far end (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--slide-margin", c.slide_margin,
                 "Far ends of view and model this far apart still meet; beyond, the fit is discounted (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--max-iterations", c.icp.max_iterations, "Iterations of the final ICP")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--max-correspondence", c.icp.max_correspondence, "Correspondence distance of the final ICP (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--inlier-distance", c.icp.inlier_distance, "View points this close to the model are inliers (m)")
      ->capture_default_str()
      ->group(group)
      ->check(positive);
  cli.add_option("--max-translation", c.max_translation, "Feasible translation of the tool per axis (m)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--max-tilt-deg", c.max_tilt_deg, "Feasible tilt about the hand's Z (deg)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 180.0));
  cli.add_option("--max-roll-deg", c.max_roll_deg, "Feasible roll about the hand's X (deg)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 90.0));
  cli.add_option("--max-about-handle-deg", c.max_about_handle_deg, "Feasible rotation about the handle (deg)")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::Range(0.0, 180.0));
  cli.add_option("--ambiguity-margin", c.ambiguity_margin, "Poses scoring within this of the best fit as well")
      ->capture_default_str()
      ->group(group)
      ->check(CLI::NonNegativeNumber);
}

PoseModel pose_model_of(const PointCloud& model, const PointCloud& view, const AlignPoseConfig& config,
                        const std::string& model_file, const std::string& view_file) {
  if (const std::string mismatch = unit_mismatch(model.points, view.points, config.max_extent_ratio); !mismatch.empty())
    throw InputError(mismatch.rfind("the model", 0) == 0 ? model_file : view_file, mismatch);
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
