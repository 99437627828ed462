// check-realism REAL_TOOLS_DIR [--seeds N] [--first-seed S] [--stereo elas|sgbm|ideal] [--grasp recorded|any]:
// the robot's own reconstructions of real tools (X_rec.ply, hand frame) against the tools' models (X.pcd,
// canonical pose) placed on them, beside the merged models of simulated sessions of the same models, by
// six figures: accuracy (median, 90th percentile and share of points beyond 5 mm from the true
// surface), coverage (share of the true surface within 5 and 10 mm of the cloud) and the tip gap (the
// true tooltip to the nearest cloud point: median, and the share of clouds within 10 mm). Per tool and
// in all: the median over tools (robot) and over sessions (simulated); a failed session counts as a
// cloud without the tip.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/synth/realism.hpp"

namespace {

using toolinc::CloudFigures;

constexpr double kTipReach = 0.010;  // m: a cloud "has the tip" within this

// The six figures of a set of clouds; `failed` clouds count only against the tip share.
struct Summary {
  std::vector<CloudFigures> clouds;
  int failed = 0;
  void add(const Summary& other) {
    clouds.insert(clouds.end(), other.clouds.begin(), other.clouds.end());
    failed += other.failed;
  }
};

double median_of(const Summary& s, double (*figure)(const CloudFigures&)) {
  std::vector<double> values;
  for (const auto& c : s.clouds) values.push_back(figure(c));
  return values.empty() ? NAN : toolinc::median(values);
}

void print_figures(const Summary& s) {
  const auto tips = std::count_if(s.clouds.begin(), s.clouds.end(),
                                  [](const CloudFigures& c) { return c.tip_gap_m <= kTipReach; });
  const int n = static_cast<int>(s.clouds.size()) + s.failed;
  std::printf(" %6.1f %6.1f %5.2f %5.2f %5.2f %6.1f %3ld/%-3d", 1000 * median_of(s, [](const CloudFigures& c) { return c.accuracy.median_m; }),
              1000 * median_of(s, [](const CloudFigures& c) { return c.accuracy.p90_m; }),
              median_of(s, [](const CloudFigures& c) { return c.accuracy.beyond; }),
              median_of(s, [](const CloudFigures& c) { return c.coverage_5mm; }),
              median_of(s, [](const CloudFigures& c) { return c.coverage_10mm; }),
              1000 * median_of(s, [](const CloudFigures& c) { return c.tip_gap_m; }), static_cast<long>(tips), n);
}

void print_row(const std::string& name, const Summary& robot, const Summary& simulated) {
  std::printf("%-8s", name.c_str());
  print_figures(robot);
  std::printf("  |");
  print_figures(simulated);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  toolinc::Command command("check-realism",
                           "The robot's reconstructions of real tools beside simulated sessions of the same tools");
  std::string real_dir, stereo = "elas", grasp = "recorded";
  int seeds = 4;
  std::uint32_t first_seed = 1;
  auto& cli = command.cli();
  cli.add_option("real_tools", real_dir, "Folder of X.pcd (model, canonical) and X_rec.ply (the robot's reconstruction)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cli.add_option("--seeds", seeds, "Simulated sessions per tool")->capture_default_str()->check(CLI::PositiveNumber);
  cli.add_option("--first-seed", first_seed, "Seed of the first session")->capture_default_str();
  cli.add_option("--stereo", stereo, "The simulated sessions' stereo model, as simulate-session --stereo")
      ->check(CLI::IsMember({"ideal", "sgbm", "elas"}))
      ->capture_default_str();
  cli.add_option("--grasp", grasp, "The simulated sessions' grasps, as simulate-session --grasp")
      ->check(CLI::IsMember({"recorded", "any"}))
      ->capture_default_str();
  return command.run(argc, argv, [&] {
    std::vector<std::filesystem::path> reconstructions;
    for (const auto& entry : std::filesystem::directory_iterator(real_dir)) {
      const std::string file = entry.path().filename().string();
      if (file.size() > 8 && file.substr(file.size() - 8) == "_rec.ply") reconstructions.push_back(entry.path());
    }
    std::sort(reconstructions.begin(), reconstructions.end());
    if (reconstructions.empty()) throw toolinc::InputError(real_dir, "no X_rec.ply reconstruction in the folder");
    std::printf("%-8s %-45s  | %s\n", "", "robot's reconstructions", "simulated sessions");
    const char* columns = " median    p90   >5mm  cov5 cov10   tip <=10mm";
    std::printf("%-8s%s  |%s\n", "tool", columns, columns);
    Summary robot_all, simulated_all;
    for (const auto& rec_path : reconstructions) {
      const std::string rec_name = rec_path.filename().string(), name = rec_name.substr(0, rec_name.size() - 8);
      const auto model_path = rec_path.parent_path() / (name + ".pcd");
      if (!std::filesystem::exists(model_path))
        throw toolinc::InputError(model_path.string(), "no model for the reconstruction " + rec_name);
      const toolinc::PointCloud model = toolinc::load_cloud(model_path.string());
      Summary robot, simulated;
      robot.clouds.push_back(toolinc::reconstruction_figures(model.points, toolinc::load_cloud(rec_path.string()).points,
                                                              toolinc::is_shovel_name(name)));
      for (const auto& s : toolinc::simulated_figures(model, name + ".pcd", toolinc::stereo_model_from_string(stereo),
                                                      toolinc::exploration_grasps_from_string(grasp), first_seed,
                                                      seeds)) {
        if (s.merged) {
          simulated.clouds.push_back(s.figures);
        } else {
          ++simulated.failed;
          spdlog::warn("{}: a simulated session failed: {}", name, s.errors.tool.failure);
        }
      }
      print_row(name, robot, simulated);
      robot_all.add(robot);
      simulated_all.add(simulated);
    }
    print_row("all", robot_all, simulated_all);
  });
}
