// evaluate-poses: the executable's table and JSON on generated
// models (the same for any -j), its rates against the cases it lists, bad input.
#include <gtest/gtest.h>

#include "support/run_tool.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/synth/tool_generator.hpp"

namespace toolinc {
namespace {

using testing::run_tool;
using testing::scratch_dir;
using testing::slurp;

TEST(EvaluatePoses, TableAndJsonOnGeneratedModels) {
  const auto dir = scratch_dir("evaluate-poses");
  std::string models;
  for (const auto& [name, family] :
       {std::pair{"hoe1.ply", ToolFamily::hoe}, {"HOK1.ply", ToolFamily::hook}, {"hook2.ply", ToolFamily::hook}}) {
    write_ply((dir / name).string(), generate_tool(default_shape(family), 5));
    models += " " + (dir / name).string();
  }
  const auto one = run_tool("evaluate-poses", models + " --grasps 3 -j 1 -q -o " + (dir / "one.json").string());
  const auto two = run_tool("evaluate-poses", models + " --grasps 3 -j 2 -q -o " + (dir / "two.json").string());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_EQ(slurp(dir / "one.json"), slurp(dir / "two.json"));
  EXPECT_EQ(one.out, two.out);
  EXPECT_NE(one.out.find("95%"), std::string::npos) << one.out;

  const Json results = read_json((dir / "one.json").string());
  EXPECT_EQ(results["type"], "pose_evaluation");
  ASSERT_EQ(results["cases"].size(), 9u);
  ASSERT_EQ(results["kinds"].size(), 2u);  // hoe, and hook for both spellings
  EXPECT_EQ(results["kinds"][1]["kind"], "hook");
  EXPECT_EQ(results["kinds"][1]["cases"], 6);
  // Each rate is the count of the cases listed as right, its interval around it.
  int right = 0;
  for (const auto& c : results["cases"]) {
    const bool pose = c["rotation_deg"].get<double>() <= 3.0 && c["translation_m"].get<double>() <= 0.005;
    const bool tip = c["tooltip_m"].get<double>() <= 0.010;
    EXPECT_EQ(c["right"].get<bool>(), pose || tip);
    right += c["right"].get<bool>();
  }
  EXPECT_EQ(results["all"]["right"], right);
  const double lo = results["all"]["rate_interval_95"][0], hi = results["all"]["rate_interval_95"][1];
  EXPECT_LE(lo, right / 9.0);
  EXPECT_GE(hi, right / 9.0);
  // Generated hoes and hooks are aligned (tests/test_align_pose.cpp: 24/25 each).
  EXPECT_GE(right, 8);
}

TEST(EvaluatePoses, MissingModelIsBadInput) {
  const auto dir = scratch_dir("evaluate-poses-bad");
  const auto run = run_tool("evaluate-poses", (dir / "missing.pcd").string() + " -q -o " + (dir / "r.json").string());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("missing.pcd"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "r.json"));
}

}  // namespace
}  // namespace toolinc
