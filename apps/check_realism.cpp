// check-realism REAL_TOOLS_DIR [--seeds N] [--first-seed S] [--stereo sgbm|ideal]: how far the robot's own
// reconstructions of real tools (X_rec.ply, hand frame) lie from the tools' models (X.pcd, canonical
// pose), beside the merged models of simulated sessions of the same models: median, 90th percentile
// and share of points beyond 5 mm, per tool and as the median over tools (real) and over sessions
// (simulated), and the simulated sessions' tooltip errors. The simulator is realistic when each simulated
// figure is within a factor 1.5 of the real.
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

using toolinc::DistanceProfile;

DistanceProfile median_profile(const std::vector<DistanceProfile>& profiles) {
  std::vector<double> medians, p90s, beyond;
  for (const auto& p : profiles) medians.push_back(p.median_m), p90s.push_back(p.p90_m), beyond.push_back(p.beyond);
  return {toolinc::median(medians), toolinc::median(p90s), toolinc::median(beyond)};
}

// The simulated sessions' tooltip errors: within 10 mm, within 20 mm, median (failed sessions count as misses).
struct TooltipFigures {
  int within_10mm = 0, within_20mm = 0;
  std::vector<double> errors;
  void add(const toolinc::SessionErrors& e) {
    if (!e.tool.failure.empty()) return errors.push_back(NAN);
    within_10mm += e.tool.tooltip_m <= 0.010;
    within_20mm += e.tool.tooltip_m <= 0.020;
    errors.push_back(e.tool.tooltip_m);
  }
};

void print_row(const std::string& name, const DistanceProfile& real, const DistanceProfile& simulated,
               const TooltipFigures& tips) {
  std::vector<double> valid;
  for (double e : tips.errors)
    if (!std::isnan(e)) valid.push_back(e);
  const auto n = static_cast<double>(tips.errors.size());
  std::printf("%-14s %7.1fmm %7.1fmm %6.0f%%   %7.1fmm %7.1fmm %6.0f%% %9zu %6.0f%% %6.0f%% %7.1fmm\n", name.c_str(),
              1000 * real.median_m, 1000 * real.p90_m, 100 * real.beyond, 1000 * simulated.median_m,
              1000 * simulated.p90_m, 100 * simulated.beyond, tips.errors.size(), 100 * tips.within_10mm / n,
              100 * tips.within_20mm / n, 1000 * toolinc::median(valid));
}

}  // namespace

int main(int argc, char** argv) {
  toolinc::Command command("check-realism",
                           "Distance profiles of real reconstructions and of simulated sessions of the same tools");
  std::string real_dir, stereo = "sgbm";
  int seeds = 4;
  std::uint32_t first_seed = 1;
  auto& cli = command.cli();
  cli.add_option("real_tools", real_dir, "Folder of X.pcd (model, canonical) and X_rec.ply (the robot's reconstruction)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cli.add_option("--seeds", seeds, "Simulated sessions per tool")->capture_default_str()->check(CLI::PositiveNumber);
  cli.add_option("--first-seed", first_seed, "Seed of the first session")->capture_default_str();
  cli.add_option("--stereo", stereo, "The simulated sessions' stereo model")
      ->check(CLI::IsMember({"ideal", "sgbm"}))
      ->capture_default_str();
  return command.run(argc, argv, [&] {
    std::vector<std::filesystem::path> reconstructions;
    for (const auto& entry : std::filesystem::directory_iterator(real_dir)) {
      const std::string file = entry.path().filename().string();
      if (file.size() > 8 && file.substr(file.size() - 8) == "_rec.ply") reconstructions.push_back(entry.path());
    }
    std::sort(reconstructions.begin(), reconstructions.end());
    if (reconstructions.empty()) throw toolinc::InputError(real_dir, "no X_rec.ply reconstruction in the folder");
    std::printf("%-14s %29s   %29s %33s\n", "", "real reconstruction", "simulated merged model",
                "simulated tooltip error");
    std::printf("%-14s %9s %9s %7s   %9s %9s %7s %9s %7s %7s %9s\n", "tool", "median", "p90", ">5mm", "median", "p90",
                ">5mm", "sessions", "<=10mm", "<=20mm", "median");
    std::vector<DistanceProfile> real_all, simulated_all;
    TooltipFigures tips_all;
    for (const auto& rec_path : reconstructions) {
      const std::string rec_name = rec_path.filename().string(), name = rec_name.substr(0, rec_name.size() - 8);
      const auto model_path = rec_path.parent_path() / (name + ".pcd");
      if (!std::filesystem::exists(model_path))
        throw toolinc::InputError(model_path.string(), "no model for the reconstruction " + rec_name);
      const toolinc::PointCloud model = toolinc::load_cloud(model_path.string());
      const DistanceProfile real = toolinc::reconstruction_profile(model.points, toolinc::load_cloud(rec_path.string()).points);
      std::vector<DistanceProfile> simulated;
      TooltipFigures tips;
      for (const auto& e : toolinc::simulated_sessions(model, name + ".pcd", toolinc::stereo_model_from_string(stereo),
                                                       first_seed, seeds)) {
        tips.add(e);
        tips_all.add(e);
        if (e.tool.failure.empty())
          simulated.push_back(e.model);
        else
          spdlog::warn("{}: a simulated session failed: {}", name, e.tool.failure);
      }
      real_all.push_back(real);
      simulated_all.insert(simulated_all.end(), simulated.begin(), simulated.end());
      print_row(name, real, simulated.empty() ? DistanceProfile{NAN, NAN, NAN} : median_profile(simulated), tips);
    }
    if (simulated_all.empty()) throw toolinc::MethodError("no simulated session merged");
    const DistanceProfile real = median_profile(real_all), simulated = median_profile(simulated_all);
    print_row("all", real, simulated, tips_all);
    std::printf("simulated / real: median %.2f, p90 %.2f, >5mm %.2f (realistic within 0.67-1.5)\n",
                simulated.median_m / real.median_m, simulated.p90_m / real.p90_m, simulated.beyond / real.beyond);
  });
}
