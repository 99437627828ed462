// scripts/pipeline.mk, as the README runs it (no -k), on a folder with one malformed session among good
// ones: the good ones are done, summary.csv and the table list the failed one with its error, make fails
// at the end; the same command again redoes only the failed session; a report left from an earlier run is
// not taken for a success once its session fails.
#include <gtest/gtest.h>

#include "support/files.hpp"
#include "support/workflow.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

TEST(PipelineMake, AMalformedSessionFailsAloneAndIsListed) {
  const auto dir = scratch_dir("pipeline-make-failed");
  ASSERT_EQ(simulate_session(dir / "sessions/hoe", "hoe", 1), 0);
  ASSERT_EQ(simulate_session(dir / "sessions/hook", "hook", 2), 0);
  fs::create_directories(dir / "sessions/broken");
  const fs::path garbage = dir / "sessions/broken/session.json";
  write_text(garbage, "{ this is not a session");
  const std::string command = "make -f " + std::string(kSourceDir) +
                              "/scripts/pipeline.mk SESSIONS=" + (dir / "sessions").string() +
                              " OUT=" + (dir / "out").string() + " BIN=" + kBinDir + " -j2";
  const std::string error = "crop_cloud: crop-cloud: error: " + garbage.string() + ": not valid JSON";

  EXPECT_EQ(shell(command, dir / "run.log"), 2);
  const std::string log = slurp(dir / "run.log");
  EXPECT_NE(log.find("toolinc: broken   failed   " + error), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: hoe      done"), std::string::npos) << log;
  EXPECT_NE(log.find("toolinc: 2 done, 1 failed, 0 not run, of 3"), std::string::npos) << log;
  std::vector<std::string> header;
  auto rows = read_summary(dir / "out/summary.csv", &header);
  ASSERT_EQ(rows.size(), 3u) << slurp(dir / "out/summary.csv");
  EXPECT_EQ(header.front(), "session");
  EXPECT_EQ(header.back(), "failure");
  for (const std::string name : {"hoe", "hook"}) {
    expect_done(rows[name], dir / "out" / name);
    EXPECT_LT(number(rows[name].at("tooltip_error_mm")), 30.0);
  }
  expect_failed(rows["broken"], error);
  EXPECT_FALSE(fs::exists(dir / "out/broken/views"));
  EXPECT_FALSE(fs::exists(dir / "out/broken/report.html"));

  // Again: only the failed session's steps run, and it fails the same way.
  const auto report_time = fs::last_write_time(dir / "out/hoe/report.html");
  EXPECT_EQ(shell(command, dir / "again.log"), 2);
  const std::string again = slurp(dir / "again.log");
  EXPECT_EQ(again.find((dir / "out/hoe/").string()), std::string::npos) << again;
  EXPECT_EQ(again.find((dir / "out/hook/").string()), std::string::npos) << again;
  EXPECT_NE(again.find((dir / "out/broken/").string()), std::string::npos) << again;
  EXPECT_NE(again.find("toolinc: 2 done, 1 failed, 0 not run, of 3"), std::string::npos) << again;
  EXPECT_EQ(fs::last_write_time(dir / "out/hoe/report.html"), report_time);

  // hoe's session turns bad: its old report is still there, but hoe failed.
  const std::string hoe = slurp(dir / "sessions/hoe/session.json");
  write_text(dir / "sessions/hoe/session.json", "[");
  EXPECT_EQ(shell(command, dir / "stale.log"), 2);
  rows = read_summary(dir / "out/summary.csv", &header);
  EXPECT_TRUE(fs::exists(dir / "out/hoe/report.html"));
  expect_failed(rows["hoe"],
                "crop_cloud: crop-cloud: error: " + (dir / "sessions/hoe/session.json").string() + ": not valid JSON");
  EXPECT_NE(slurp(dir / "stale.log").find("toolinc: 1 done, 2 failed, 0 not run, of 3"), std::string::npos)
      << slurp(dir / "stale.log");

  // Mended (and the bad one gone): every session done, exit 0.
  write_text(dir / "sessions/hoe/session.json", hoe);
  fs::remove_all(dir / "sessions/broken");
  ASSERT_EQ(shell(command, dir / "mended.log"), 0) << slurp(dir / "mended.log");
  rows = read_summary(dir / "out/summary.csv", &header);
  ASSERT_EQ(rows.size(), 2u);
  expect_done(rows["hoe"], dir / "out/hoe");
  EXPECT_NE(slurp(dir / "mended.log").find("toolinc: 2 done, 0 failed, 0 not run, of 2"), std::string::npos);
}

TEST(PipelineMake, NoSessionsIsAClearError) {
  const auto dir = scratch_dir("pipeline-make-empty");
  fs::create_directories(dir / "nothing");
  EXPECT_EQ(shell("make -f " + std::string(kSourceDir) + "/scripts/pipeline.mk SESSIONS=" + (dir / "nothing").string() +
                      " OUT=" + (dir / "out").string() + " BIN=" + kBinDir,
                  dir / "log"),
            2);
  EXPECT_NE(slurp(dir / "log").find("no session"), std::string::npos) << slurp(dir / "log");
}
