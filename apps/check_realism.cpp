// check-realism [FOLDER] [--families F...] [--seeds N] [--first-seed S] [--stereo elas|sgbm|ideal]
//               [--grasp recorded|any]:
// six figures of clouds against the truth of the tool they show: accuracy (median, 90th percentile and
// share of points beyond 5 mm from the true surface), coverage (share of the true surface within 5 and
// 10 mm of the cloud) and the tip gap (the true tooltip to the nearest cloud point: median, and the share
// of clouds within 10 mm).
// - A model in FOLDER with the robot's reconstruction of it (X.pcd, canonical pose, and X_rec.ply, hand
//   frame): a row per tool, the reconstruction against the model placed on it beside the merged models
//   of simulated sessions of the same model.
// - Models without a reconstruction (X.pcd or X.ply alone, e.g. CAD models) and the generated families
//   (--families): the simulated sessions alone (the simulator knows where the truth lies), a row per
//   kind of tool (the file name's, as evaluate-models names it; its tooltip rule too) and per family.
// "all": the median over tools (robot) and over sessions (simulated), the simulated tip share with its
// 95 % (Wilson) interval; a failed session counts as a cloud without the tip.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <utility>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/progress.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/synth/model_kinds.hpp"
#include "toolinc/synth/realism.hpp"

namespace {

using toolinc::CloudFigures;

constexpr double kTipReach = 0.010;  // m: a cloud "has the tip" within this
constexpr const char* kColumns = " median    p90   >5mm  cov5 cov10   tip <=10mm";

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

// `interval`: the tip share's 95 % (Wilson) interval after it.
void print_figures(const Summary& s, bool interval) {
  const int tips = static_cast<int>(
      std::count_if(s.clouds.begin(), s.clouds.end(), [](const CloudFigures& c) { return c.tip_gap_m <= kTipReach; }));
  const int n = static_cast<int>(s.clouds.size()) + s.failed;
  std::printf(" %6.1f %6.1f %5.2f %5.2f %5.2f %6.1f %3d/%-3d",
              1000 * median_of(s, [](const CloudFigures& c) { return c.accuracy.median_m; }),
              1000 * median_of(s, [](const CloudFigures& c) { return c.accuracy.p90_m; }),
              median_of(s, [](const CloudFigures& c) { return c.accuracy.beyond; }),
              median_of(s, [](const CloudFigures& c) { return c.coverage_5mm; }),
              median_of(s, [](const CloudFigures& c) { return c.coverage_10mm; }),
              1000 * median_of(s, [](const CloudFigures& c) { return c.tip_gap_m; }), tips, n);
  if (interval) {
    const auto [lo, hi] = toolinc::wilson_interval(tips, n);
    std::printf(" (%.0f-%.0f%%)", 100 * lo, 100 * hi);
  }
}

// `robot`: the robot's columns before the simulated ones, when there are any.
void print_row(const std::string& name, const Summary* robot, const Summary& simulated, bool interval = false) {
  std::printf("%-13s", name.c_str());
  if (robot != nullptr) {
    print_figures(*robot, false);
    std::printf("  |");
  }
  print_figures(simulated, interval);
  std::printf("\n");
}

// Rows of simulated sessions alone, in the order they first appear, and "all".
using Groups = std::vector<std::pair<std::string, Summary>>;

void add_to(Groups& groups, const std::string& name, const Summary& s) {
  auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == name; });
  if (it == groups.end()) it = groups.insert(groups.end(), {name, Summary{}});
  it->second.add(s);
}

void print_groups(const std::string& first_column, const std::string& title, const Groups& groups) {
  std::printf("%-13s %s\n%-13s%s\n", "", title.c_str(), first_column.c_str(), kColumns);
  Summary all;
  for (const auto& [name, s] : groups) {
    print_row(name, nullptr, s);
    all.add(s);
  }
  print_row("all", nullptr, all, true);
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  toolinc::Command command("check-realism",
                           "The robot's reconstructions of real tools beside simulated sessions of the same tools, "
                           "and simulated sessions of models and generated families alone");
  std::string folder, stereo = "elas", grasp = "recorded";
  std::vector<std::string> family_names;
  int seeds = 4;
  std::uint32_t first_seed = 1;
  auto& cli = command.cli();
  cli.add_option("folder", folder,
                 "Folder of models (X.pcd, canonical), each with the robot's reconstruction (X_rec.ply) or without")
      ->check(CLI::ExistingDirectory);
  cli.add_option("--families", family_names, "Generated tool families, simulated alone (all: the regression set)");
  cli.add_option("--seeds", seeds, "Simulated sessions per tool")
      ->capture_default_str()
      ->check(toolinc::in_range({1, false, 10000, ""}));
  cli.add_option("--first-seed", first_seed, "Seed of the first session")->capture_default_str();
  cli.add_option("--stereo", stereo, "The simulated sessions' stereo model, as simulate-session --stereo")
      ->check(CLI::IsMember({"ideal", "sgbm", "elas"}))
      ->capture_default_str();
  cli.add_option("--grasp", grasp, "The simulated sessions' grasps, as simulate-session --grasp")
      ->check(CLI::IsMember({"recorded", "any"}))
      ->capture_default_str();
  return command.run(argc, argv, [&] {
    if (folder.empty() && family_names.empty())
      throw std::invalid_argument("give a folder of models, --families, or both");
    std::vector<toolinc::ToolFamily> families;
    for (const auto& name : family_names) {
      if (name == "all") {
        for (const auto f : toolinc::all_families()) families.push_back(f);
      } else {
        families.push_back(toolinc::family_from_string(name));
      }
    }
    const toolinc::StereoModel stereo_model = toolinc::stereo_model_from_string(stereo);
    const toolinc::ExplorationGrasps grasps = toolinc::exploration_grasps_from_string(grasp);

    std::vector<std::filesystem::path> reconstructions, models;
    if (!folder.empty())
      for (const auto& path : toolinc::expand_model_paths({folder})) {
        const std::string file = lower(std::filesystem::path(path).filename().string());
        (file.size() > 8 && file.substr(file.size() - 8) == "_rec.ply" ? reconstructions : models).emplace_back(path);
      }
    const auto model_of = [](const std::filesystem::path& rec_path) {
      const std::string rec_name = rec_path.filename().string();
      return rec_path.parent_path() / (rec_name.substr(0, rec_name.size() - 8) + ".pcd");
    };
    for (const auto& rec_path : reconstructions) {
      if (!std::filesystem::exists(model_of(rec_path)))
        throw toolinc::InputError(model_of(rec_path).string(),
                                  "no model for the reconstruction " + rec_path.filename().string());
      const auto model_file = model_of(rec_path).filename();
      models.erase(std::remove_if(models.begin(), models.end(),
                                  [&](const std::filesystem::path& m) { return m.filename() == model_file; }),
                   models.end());
    }

    const toolinc::Progress progress("simulating sessions");
    const std::size_t total = (reconstructions.size() + models.size() + families.size()) * seeds;
    std::size_t done = 0;
    // The one path every table's simulated columns take: the sessions of one tool, failures counted.
    const auto simulate = [&](toolinc::SessionSimulatorConfig session, const std::string& name) {
      session.stereo = stereo_model;
      Summary simulated;
      for (const auto& s : toolinc::simulated_figures(session, grasps, seeds)) {
        if (s.merged) {
          simulated.clouds.push_back(s.figures);
        } else {
          ++simulated.failed;
          spdlog::warn("{}: a simulated session failed: {}", name, s.errors.tool.failure);
        }
      }
      progress(done += seeds, total);
      return simulated;
    };
    const auto model_session = [&](const toolinc::PointCloud& model, const std::filesystem::path& path) {
      return toolinc::model_session(model, path.filename().string(), toolinc::measure_symmetry(model.points),
                                    first_seed, grasps);
    };
    const std::string simulated_title = "simulated sessions (--stereo " + stereo + ")";

    if (!reconstructions.empty()) {
      std::printf("%-13s %-45s  | %s\n%-13s%s  |%s\n", "", "robot's reconstructions", simulated_title.c_str(), "tool",
                  kColumns, kColumns);
      Summary robot_all, simulated_all;
      for (const auto& rec_path : reconstructions) {
        const auto model_path = model_of(rec_path);
        const std::string name = model_path.stem().string();
        const toolinc::PointCloud model = toolinc::load_cloud(model_path.string());
        Summary robot;
        robot.clouds.push_back(
            toolinc::reconstruction_figures(model.points, toolinc::load_cloud(rec_path.string()).points,
                                            toolinc::truth_tip_of_kind(toolinc::model_kind(model_path.string()))));
        const Summary simulated = simulate(model_session(model, model_path), name);
        print_row(name, &robot, simulated);
        robot_all.add(robot);
        simulated_all.add(simulated);
      }
      print_row("all", &robot_all, simulated_all, true);
    }
    if (!models.empty()) {
      Groups by_kind;
      for (const auto& path : models) {
        const toolinc::PointCloud model = toolinc::load_cloud(path.string());
        add_to(by_kind, toolinc::model_kind(path.string()), simulate(model_session(model, path), path.stem().string()));
      }
      if (!reconstructions.empty()) std::printf("\n");
      print_groups("kind", "models without a reconstruction: " + simulated_title, by_kind);
    }
    if (!families.empty()) {
      Groups by_family;
      for (const auto family : families)
        add_to(by_family, toolinc::to_string(family),
               simulate(toolinc::family_session(family, first_seed, grasps), toolinc::to_string(family)));
      if (!reconstructions.empty() || !models.empty()) std::printf("\n");
      print_groups("family", "generated families: " + simulated_title, by_family);
    }
  });
}
