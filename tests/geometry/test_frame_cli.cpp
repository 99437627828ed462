// estimate-frame and find-tooltip as users run them: outputs, exit codes, one-line errors naming the
// file, and no output left behind on failure.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <vector>

#include "support/files.hpp"
#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "support/synthetic_cases.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

namespace {

// `tool INPUT EXTRA -o INPUT.out.json` fails with `code` and leaves nothing (testing::expect_clean_failure).
void expect_clean_failure(const std::string& tool, const fs::path& input, const std::string& extra, int code,
                          const std::string& word) {
  toolinc::testing::expect_clean_failure(tool, input.string() + " " + extra,
                                         input.parent_path() / (input.filename().string() + ".out.json"), code, word);
}

}  // namespace

TEST(FrameCli, EstimateFrameThenFindTooltip) {
  const auto dir = scratch_dir("frame-cli");
  const auto held = make_held_tool(ToolFamily::hoe, 5);
  write_ply((dir / "hoe.ply").string(), as_cloud(held.observed));
  const auto before = slurp(dir / "hoe.ply");

  auto run = run_tool("estimate-frame", (dir / "hoe.ply").string() + " -o " + (dir / "frame.json").string() + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  const Json frame = read_json((dir / "frame.json").string());
  EXPECT_EQ(frame["type"], "tool_frame");
  EXPECT_EQ(frame["version"], 1);
  const Eigen::Matrix4d m = matrix4_field(frame, "matrix", "frame.json");
  EXPECT_TRUE(is_rigid(m, 1e-9));
  EXPECT_GT(Vec3(m.block<3, 1>(0, 0)).dot(held.truth.axes.col(0)), 0.9);

  run = run_tool("find-tooltip", (dir / "hoe.ply").string() + " --frame " + (dir / "frame.json").string() + " -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json tip = Json::parse(run.out);
  EXPECT_EQ(tip["type"], "tooltip");
  const Vec3 position = vector3_field(tip, "position", "stdout");
  EXPECT_LT(tooltip_error(held.truth, position), 0.010);
  EXPECT_EQ(tip["attach_tip_frame"]["axis_angle"].size(), 4u);

  // Without --frame, find-tooltip estimates the same frame itself: same bytes.
  const auto again = run_tool("find-tooltip", (dir / "hoe.ply").string() + " -o -");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out, run.out);
  EXPECT_EQ(slurp(dir / "hoe.ply"), before) << "the input was modified";
}

TEST(FrameCli, ConfigFileAndCommandLinePrecedence) {
  const auto dir = scratch_dir("frame-config");
  const auto held = make_held_tool(ToolFamily::rake, 2);
  write_ply((dir / "rake.ply").string(), as_cloud(held.observed));
  write_text(dir / "config.json", R"({"estimate-frame": {"hand-radius": 0.07}, "other-tool": {"x": 1}})");
  auto run =
      run_tool("estimate-frame", (dir / "rake.ply").string() + " -c " + (dir / "config.json").string() + " -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Json::parse(run.out)["settings"]["hand-radius"], 0.07);
  run = run_tool("estimate-frame",
                 (dir / "rake.ply").string() + " -c " + (dir / "config.json").string() + " --hand-radius 0.065 -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Json::parse(run.out)["settings"]["hand-radius"], 0.065);
  write_text(dir / "typo.json", R"({"estimate-frame": {"hand-radius-typo": 0.07}})");
  run = run_tool("estimate-frame", (dir / "rake.ply").string() + " -c " + (dir / "typo.json").string() + " -o -");
  EXPECT_EQ(run.exit_code, 2);
}

TEST(FrameCli, HelpAndVersion) {
  auto run = run_tool("estimate-frame", "--help");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.out.find("--hand-radius"), std::string::npos);
  run = run_tool("find-tooltip", "--version");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.out.find("toolinc"), std::string::npos);
  EXPECT_EQ(run_tool("estimate-frame", "").exit_code, 2);
}

TEST(FrameCli, BadInputFailsCleanly) {
  const auto dir = scratch_dir("frame-bad");
  expect_clean_failure("estimate-frame", dir / "missing.ply", "", 2, "missing.ply");

  write_text(dir / "empty.ply", "");
  expect_clean_failure("estimate-frame", dir / "empty.ply", "", 2, "empty.ply");

  const auto held = make_held_tool(ToolFamily::hook, 1);
  write_ply((dir / "whole.ply").string(), as_cloud(held.observed));
  const std::string whole = slurp(dir / "whole.ply");
  write_text(dir / "truncated.ply", whole.substr(0, whole.size() / 2));
  expect_clean_failure("estimate-frame", dir / "truncated.ply", "", 2, "truncated");

  write_text(dir / "noxyz.ply",
             "ply\nformat ascii 1.0\nelement vertex 2\nproperty float a\nproperty float b\n"
             "end_header\n1 2\n3 4\n");
  expect_clean_failure("estimate-frame", dir / "noxyz.ply", "", 2, "x/y/z");

  write_text(dir / "badheader.pcd",
             "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
             "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA foo\n1 2 3\n");
  expect_clean_failure("estimate-frame", dir / "badheader.pcd", "", 2, "badheader.pcd");

  write_text(dir / "nan.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nend_header\nnan nan nan\nnan 0 0\n0 nan 1\n");
  expect_clean_failure("estimate-frame", dir / "nan.ply", "", 2, "finite");

  write_text(dir / "three.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nend_header\n0.1 -0.1 0\n0.1 -0.2 0\n0.2 -0.1 0\n");
  expect_clean_failure("estimate-frame", dir / "three.ply", "", 3, "too few");

  Points line;
  for (int i = 0; i < 400; ++i) line.emplace_back(0.1, -0.1 - 0.0005 * i, 0.0);
  write_ply((dir / "line.ply").string(), as_cloud(line));
  expect_clean_failure("estimate-frame", dir / "line.ply", "", 3, "collinear");
  expect_clean_failure("find-tooltip", dir / "line.ply", "", 3, "collinear");

  // A mirror-image frame (det -1) and a non-orthonormal one are refused, naming the frame file.
  write_text(dir / "mirror.json", R"({"type": "tool_frame", "version": 1, "matrix":
      [[-1,0,0,0.1],[0,1,0,-0.1],[0,0,1,0],[0,0,0,1]]})");
  expect_clean_failure("find-tooltip", dir / "whole.ply", "--frame " + (dir / "mirror.json").string(), 2,
                       "mirror.json");
  write_text(dir / "skew.json", R"({"type": "tool_frame", "version": 1, "matrix":
      [[1,0.2,0,0.1],[0,1,0,-0.1],[0,0,1,0],[0,0,0,1]]})");
  expect_clean_failure("find-tooltip", dir / "whole.ply", "--frame " + (dir / "skew.json").string(), 2,
                       "not a rotation");
  write_text(dir / "wrongtype.json", R"({"type": "tooltip", "version": 1})");
  expect_clean_failure("find-tooltip", dir / "whole.ply", "--frame " + (dir / "wrongtype.json").string(), 2,
                       "tool_frame");
}

TEST(FrameCli, ShippedConfigHoldsTheDefaults) {
  // configs/icub.json documents every default: running with it must change nothing.
  const auto dir = scratch_dir("frame-shipped-config");
  const auto held = make_held_tool(ToolFamily::hook, 9);
  write_ply((dir / "hook.ply").string(), as_cloud(held.observed));
  const std::string config = std::string(toolinc::testing::kSourceDir) + "/configs/icub.json";
  for (const std::string tool : {"estimate-frame", "find-tooltip"}) {
    const auto plain = run_tool(tool, (dir / "hook.ply").string() + " -o -");
    const auto configured = run_tool(tool, (dir / "hook.ply").string() + " -c " + config + " -o -");
    ASSERT_EQ(plain.exit_code, 0) << plain.err;
    ASSERT_EQ(configured.exit_code, 0) << configured.err;
    EXPECT_EQ(plain.out, configured.out) << tool;
  }
}

TEST(FrameCli, ConfigSectionsLaterWinTopLevelLast) {
  // find-tooltip reads the estimate-frame section, then its own: its own wins; top-level keys lose to both.
  const auto dir = scratch_dir("frame-config-order");
  const auto held = make_held_tool(ToolFamily::hoe, 4);
  write_ply((dir / "hoe.ply").string(), as_cloud(held.observed));
  write_text(dir / "c.json", R"({"min-neighbors": 1000, "find-tooltip": {"min-neighbors": 5}})");
  auto run = run_tool("find-tooltip", (dir / "hoe.ply").string() + " -c " + (dir / "c.json").string() + " -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Json::parse(run.out)["settings"]["min-neighbors"], 5);
  write_text(dir / "d.json", R"({"estimate-frame": {"hand-radius": 0.07}, "find-tooltip": {"hand-radius": 0.065}})");
  run = run_tool("find-tooltip", (dir / "hoe.ply").string() + " -c " + (dir / "d.json").string() + " -o -");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  write_text(dir / "e.json", R"({"estimate-frame": {"hand-radius": 0.065}})");
  const auto same = run_tool("find-tooltip", (dir / "hoe.ply").string() + " -c " + (dir / "e.json").string() + " -o -");
  EXPECT_EQ(run.out, same.out);
}
