// merge-views VIEW.ply... -o MODEL.ply [--report REPORT.json]: one tool model from the exploration views.
#include "toolinc/registration/merge_views.hpp"

#include <spdlog/spdlog.h>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/progress.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/results/results_json.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("merge-views", "Merge hand-frame views of a tool into one model");
  std::vector<std::string> inputs;
  std::string report_file;
  bool ascii = false;
  toolinc::MergeConfig config;
  auto& cli = command.cli();
  cli.add_option("views", inputs, "View clouds in the hand frame; the first is the reference")->required();
  command.add_output("Output model PLY");
  cli.add_option("--report", report_file, "Merge report JSON: per view accepted or rejected, correction, why");
  cli.add_flag("--revisit-views", config.revisit_views,
               "Try a view that does not fit again after the later views, and while one still does not, every view "
               "as the reference");
  toolinc::add_merge_options(cli, config);
  cli.add_flag("--ascii", ascii, "Write ASCII PLY");
  return command.run(argc, argv, [&] {
    std::vector<toolinc::PointCloud> views;
    for (const auto& input : inputs) views.push_back(toolinc::load_cloud(input));
    config.progress = toolinc::Progress("merging views");
    toolinc::MergeResult merged;
    try {
      merged = toolinc::merge_views(views, config);
    } catch (const toolinc::MethodError& e) {
      if (!report_file.empty())
        toolinc::write_json(report_file, toolinc::merge_report_json(inputs, {}, config, e.what()));
      throw;
    }
    for (std::size_t v = 0; v < merged.views.size(); ++v)
      spdlog::info("{}: {} ({})", inputs[v], merged.views[v].accepted ? "accepted" : "REJECTED",
                   merged.views[v].reason);
    toolinc::write_ply(command.output(), merged.model, {ascii, command.command_line()});
    if (!report_file.empty()) toolinc::write_json(report_file, toolinc::merge_report_json(inputs, merged, config, ""));
    spdlog::info("{} points -> {}", merged.model.size(), command.output());
  });
}
