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
#include "support/workflow.hpp"
#include "toolinc/app/progress.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/tool_generator.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

namespace {

const std::string kSnakefile = std::string(toolinc::testing::kSourceDir) + "/scripts/Snakefile";

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

  std::vector<std::string> header;
  const auto rows = read_summary(dir / "out/summary.csv", &header);
  ASSERT_EQ(header.size(), 12u) << slurp(dir / "out/summary.csv");
  ASSERT_EQ(rows.size(), 3u) << slurp(dir / "out/summary.csv");
  for (const auto& [name, row] : rows) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(sessions.count(name));
    const fs::path out = dir / "out" / name;
    expect_done(row, out);
    EXPECT_GE(number(row.at("views_accepted")), 3);
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

// Two malformed sessions (a view's image, session.json itself) among good ones, with --keep-going: a line
// says so with the step's own error, the good one finishes, the table at the end and summary.csv list every
// session, the failed ones with their error; once a session is mended, the same command runs its steps only.
TEST(Snakemake, FailedSessionsReportedTheOthersDoneAndResumed) {
  ASSERT_EQ(std::system("command -v snakemake >/dev/null 2>&1"), 0) << "snakemake is not installed";
  const auto dir = scratch_dir("snakemake-failed");
  for (const char* name : {"hoe", "broken"}) ASSERT_EQ(simulate_session(dir / "sessions" / name, "hoe", 1), 0);
  const fs::path disparity = dir / "sessions/broken/views/000/disparity.png";
  fs::copy_file(disparity, dir / "disparity.png");
  write_text(disparity, "not a PNG");
  fs::create_directories(dir / "sessions/garbage");
  const fs::path garbage = dir / "sessions/garbage/session.json";
  write_text(garbage, "{ this is not a session");
  const std::string command = "snakemake -s " + kSnakefile + " --cores 2 --keep-going --directory " + dir.string() +
                              " --config sessions=" + (dir / "sessions").string() + " out=" + (dir / "out").string() +
                              " bin=" + toolinc::testing::kBinDir;
  EXPECT_NE(shell(command, dir / "run.log"), 0);
  const std::string log = slurp(dir / "run.log");
  const std::string error =
      "crop-cloud: error: " + disparity.parent_path().string() + ": disparity.png is not a readable PNG";
  const std::string garbage_error = "crop_cloud: crop-cloud: error: " + garbage.string() + ": not valid JSON";
  EXPECT_NE(log.find("toolinc: session broken: crop_cloud failed: " + error), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: session hoe done (1 of 3)"), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: broken   failed   crop_cloud: " + error), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: garbage  failed   " + garbage_error), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: hoe      done"), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: 1 done, 2 failed, 0 not run, of 3"), std::string::npos) << log;
  std::vector<std::string> header;
  auto rows = read_summary(dir / "out/summary.csv", &header);
  ASSERT_EQ(rows.size(), 3u) << slurp(dir / "out/summary.csv");
  expect_done(rows["hoe"], dir / "out/hoe");
  expect_failed(rows["broken"], "crop_cloud: " + error);
  expect_failed(rows["garbage"], garbage_error);

  fs::copy_file(dir / "disparity.png", disparity, fs::copy_options::overwrite_existing);
  EXPECT_NE(shell(command, dir / "again.log"), 0);
  const std::string again = slurp(dir / "again.log");
  EXPECT_EQ(again.find("wildcards: name=hoe"), std::string::npos) << again;
  EXPECT_NE(again.find("toolinc: session broken done (2 of 3)"), std::string::npos) << again;
  EXPECT_NE(again.find("toolinc: 2 done, 1 failed, 0 not run, of 3"), std::string::npos) << again;
  rows = read_summary(dir / "out/summary.csv", &header);
  ASSERT_EQ(rows.size(), 3u) << slurp(dir / "out/summary.csv");
  expect_done(rows["broken"], dir / "out/broken");
  expect_failed(rows["garbage"], garbage_error);
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
