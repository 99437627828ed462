// The workflow at scale: scripts/Snakefile runs every step on three simulated sessions with
// `snakemake --cores 2` and writes a summary table that agrees with the per-session results; the Slurm
// profile is valid for this snakemake; progress lines appear on a terminal only. Snakemake is required
// (CI installs it with scripts/install-deps.sh): without it these tests fail rather than skip.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <map>
#include <sstream>

#include "support/files.hpp"
#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "toolinc/app/progress.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/tool_generator.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

namespace {

const std::string kSnakefile = std::string(toolinc::testing::kSourceDir) + "/scripts/Snakefile";

// Runs a shell command, its output to `log`; returns the exit status.
int shell(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " >" + log.string() + " 2>&1 </dev/null").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> out(1);
  for (char c : line)
    if (c == separator)
      out.emplace_back();
    else
      out.back() += c;
  return out;
}

}  // namespace

TEST(Snakemake, ThreeSessionsAndTheSummary) {
  ASSERT_EQ(std::system("command -v snakemake >/dev/null 2>&1"), 0)
      << "snakemake is not installed (Debian package snakemake, in scripts/install-deps.sh)";
  const auto dir = scratch_dir("snakemake");
  const std::map<std::string, std::string> sessions = {{"hoe", "1"}, {"hook", "2"}, {"rake", "3"}};
  for (const auto& [family, seed] : sessions)
    ASSERT_EQ(run_tool("simulate-session",
                       "-q --family " + family + " --seed " + seed + " -o " + (dir / "sessions" / family).string())
                  .exit_code,
              0);
  fs::remove(dir / "sessions/rake/ground_truth.json");  // as a recorded session: no errors to report
  const std::string config = " --directory " + dir.string() + " --config sessions=" + (dir / "sessions").string() +
                             " out=" + (dir / "out").string() + " bin=" + toolinc::testing::kBinDir;
  ASSERT_EQ(shell("snakemake -s " + kSnakefile + " --cores 2" + config, dir / "run.log"), 0) << slurp(dir / "run.log");

  std::istringstream csv(slurp(dir / "out/summary.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  const auto header = split(line, ',');
  ASSERT_EQ(header.size(), 10u) << line;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(csv, line)) {
    const auto cells = split(line, ',');
    ASSERT_EQ(cells.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) {
    const std::string name = row.at("session");
    SCOPED_TRACE(name);
    ASSERT_TRUE(sessions.count(name));
    const fs::path out = dir / "out" / name;
    for (const char* file : {"views/view_000.ply", "model.ply", "frame.json", "model.png", "sheet.png", "report.html"})
      EXPECT_TRUE(fs::exists(out / file)) << file;
    const Json merge = read_json((out / "merge_report.json").string());
    int accepted = 0;
    for (const auto& v : merge["views"]) accepted += v["accepted"].get<bool>();
    EXPECT_EQ(number(row.at("views")), static_cast<double>(merge["views"].size()));
    EXPECT_EQ(number(row.at("views_accepted")), accepted);
    EXPECT_GE(accepted, 3);
    const Json tip = read_json((out / "tooltip.json").string());
    const char* axes[] = {"tooltip_x", "tooltip_y", "tooltip_z"};
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(number(row.at(axes[a])), tip["position"][a].get<double>(), 1e-6);
    if (name == "rake") {
      EXPECT_FALSE(fs::exists(out / "evaluation.json"));
      for (const char* column :
           {"tooltip_error_mm", "handle_axis_error_deg", "effector_axis_error_deg", "origin_error_mm"})
        EXPECT_EQ(row.at(column), "") << column;
      continue;
    }
    const Json evaluation = read_json((out / "evaluation.json").string());
    EXPECT_NEAR(number(row.at("tooltip_error_mm")), 1000 * evaluation["tooltip"]["error_m"].get<double>(), 1e-3);
    EXPECT_NEAR(number(row.at("handle_axis_error_deg")), evaluation["frame"]["handle_axis_error_deg"].get<double>(),
                1e-3);
    EXPECT_NEAR(number(row.at("effector_axis_error_deg")), evaluation["frame"]["effector_axis_error_deg"].get<double>(),
                1e-3);
    EXPECT_NEAR(number(row.at("origin_error_mm")), 1000 * evaluation["frame"]["origin_error_m"].get<double>(), 1e-3);
    EXPECT_LT(number(row.at("tooltip_error_mm")), 30.0);
  }

  // Done is done: a second run has nothing to do.
  ASSERT_EQ(shell("snakemake -s " + kSnakefile + " --cores 2 -n" + config, dir / "again.log"), 0)
      << slurp(dir / "again.log");
  EXPECT_NE(slurp(dir / "again.log").find("Nothing to be done"), std::string::npos) << slurp(dir / "again.log");

  // The Slurm profile parses for this snakemake and gives the merge its own resources (dry run: nothing
  // is submitted).
  ASSERT_EQ(shell("snakemake -s " + kSnakefile + " --profile " + toolinc::testing::kSourceDir +
                      "/scripts/slurm -n --forceall" + config,
                  dir / "slurm.log"),
            0)
      << slurp(dir / "slurm.log");
  const std::string slurm = slurp(dir / "slurm.log");
  EXPECT_NE(slurm.find("rule merge_views"), std::string::npos);
  EXPECT_NE(slurm.find("runtime=60"), std::string::npos) << slurm;
}

// A session whose step fails: a line says so with the step's own error, the others finish, the table at the
// end lists every session; once the session is mended, the same command runs its steps only.
TEST(Snakemake, AFailedSessionReportedTheOthersDoneAndResumed) {
  ASSERT_EQ(std::system("command -v snakemake >/dev/null 2>&1"), 0) << "snakemake is not installed";
  const auto dir = scratch_dir("snakemake-failed");
  for (const char* name : {"hoe", "broken"})
    ASSERT_EQ(
        run_tool("simulate-session", "-q --stereo ideal --family hoe --seed 1 -o " + (dir / "sessions" / name).string())
            .exit_code,
        0);
  const fs::path disparity = dir / "sessions/broken/views/000/disparity.png";
  fs::copy_file(disparity, dir / "disparity.png");
  write_text(disparity, "not a PNG");
  const std::string command = "snakemake -s " + kSnakefile + " --cores 2 --keep-going --directory " + dir.string() +
                              " --config sessions=" + (dir / "sessions").string() + " out=" + (dir / "out").string() +
                              " bin=" + toolinc::testing::kBinDir;
  EXPECT_NE(shell(command, dir / "run.log"), 0);
  const std::string log = slurp(dir / "run.log");
  const std::string error =
      "crop-cloud: error: " + disparity.parent_path().string() + ": disparity.png is not a readable PNG";
  EXPECT_NE(log.find("toolinc: session broken: crop_cloud failed: " + error), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: session hoe done (1 of 2)"), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: broken   failed   crop_cloud: " + error), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: hoe      done"), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: 1 done, 1 failed, 0 not run, of 2"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(dir / "out/hoe/report.html"));
  EXPECT_FALSE(fs::exists(dir / "out/summary.csv"));  // it waits for every session

  fs::copy_file(dir / "disparity.png", disparity, fs::copy_options::overwrite_existing);
  ASSERT_EQ(shell(command, dir / "again.log"), 0) << slurp(dir / "again.log");
  const std::string again = slurp(dir / "again.log");
  EXPECT_EQ(again.find("wildcards: name=hoe"), std::string::npos) << again;
  EXPECT_NE(again.find("toolinc: session broken done (2 of 2)"), std::string::npos) << again;
  EXPECT_NE(again.find("toolinc: 2 done, 0 failed, 0 not run, of 2"), std::string::npos) << again;
  EXPECT_TRUE(fs::exists(dir / "out/summary.csv"));
}

TEST(Snakemake, NoSessionsIsAClearError) {
  ASSERT_EQ(std::system("command -v snakemake >/dev/null 2>&1"), 0) << "snakemake is not installed";
  const auto dir = scratch_dir("snakemake-empty");
  EXPECT_NE(shell("snakemake -s " + kSnakefile + " --cores 1 --directory " + dir.string() +
                      " --config sessions=" + (dir / "nothing").string(),
                  dir / "log"),
            0);
  EXPECT_NE(slurp(dir / "log").find("no session"), std::string::npos) << slurp(dir / "log");
}

TEST(Progress, SilentWhenNotATerminal) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  const Progress progress("merging views", file);
  EXPECT_FALSE(progress.enabled());
  for (std::size_t done = 0; done <= 5; ++done) progress(done, 5);
  std::fflush(file);
  EXPECT_EQ(std::ftell(file), 0L);
  std::fclose(file);

  // merge-views, its stderr a file: the log, and no progress line.
  const auto dir = scratch_dir("progress");
  PointCloud view;
  view.points = generate_tool(default_shape(ToolFamily::hoe), 1).points;
  view.frame = "hand";
  write_ply((dir / "a.ply").string(), view);
  write_ply((dir / "b.ply").string(), view);
  const auto run = run_tool(
      "merge-views", (dir / "a.ply").string() + " " + (dir / "b.ply").string() + " -o " + (dir / "model.ply").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("accepted"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find('\r'), std::string::npos);
  EXPECT_EQ(run.err.find("merging views"), std::string::npos);
}

TEST(Progress, OneLineRedrawnOnATerminal) {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(::grantpt(master), 0);
  ASSERT_EQ(::unlockpt(master), 0);
  std::FILE* terminal = std::fopen(::ptsname(master), "w");
  ASSERT_NE(terminal, nullptr);
  {
    const Progress progress("merging views", terminal);
    EXPECT_TRUE(progress.enabled());
    progress(1, 4);
    progress(4, 4);
  }
  std::fclose(terminal);
  std::string seen;
  char buffer[256];
  for (ssize_t n; (n = ::read(master, buffer, sizeof buffer)) > 0;) seen.append(buffer, static_cast<std::size_t>(n));
  ::close(master);
  EXPECT_EQ(seen, "\rmerging views: 1/4 (25%)\033[K\r\033[K");
}
