// check-realism's figures and the recorded grasps: a reconstruction made from the model itself scores
// as a perfect one, the tooltip rules, the grasps drawn as the lab held its tools, and the executable on
// a generated folder of "real" tools.
#include "toolinc/synth/realism.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "run_tool.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/pcd_write.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/tool_generator.hpp"

namespace toolinc {
namespace {

TEST(Realism, AReconstructionOfTheModelItselfScoresAsPerfect) {
  const Points model = generate_tool(default_shape(ToolFamily::hoe), 1).points;
  const Eigen::Matrix4d grasp = exploration_grasp(3);
  Rng rng(3);
  const Points reconstruction = observe_in_hand(model, grasp, 0.0, 0.0005, rng);
  EXPECT_TRUE(place_model(model, reconstruction).isApprox(grasp, 0.01));
  const CloudFigures f = reconstruction_figures(model, reconstruction, false);
  EXPECT_LT(f.accuracy.median_m, 0.001);
  EXPECT_LT(f.accuracy.beyond, 0.01);
  EXPECT_GT(f.coverage_5mm, 0.99);
  EXPECT_LT(f.tip_gap_m, 0.002);
  // Half the tool seen: coverage halves, accuracy does not change.
  Points half;
  for (const auto& p : model)
    if (p.y() > -0.15) half.push_back(apply(grasp, p));
  const CloudFigures h = cloud_figures(half, transform_points(model, grasp), realism_truth(model, ToolSymmetry::mirror, false, grasp));
  EXPECT_LT(h.accuracy.median_m, 0.0005);
  EXPECT_LT(h.coverage_10mm, 0.8);
}

TEST(Realism, TooltipRules) {
  // A hoe's tip is its blade's front edge; a shovel's, the blade's far end from the hand.
  const Points hoe = generate_tool(default_shape(ToolFamily::hoe), 1).points;
  const Vec3 tip = realism_tooltip(hoe, false);
  EXPECT_EQ(tip.z(), 0.0);
  double max_x = 0;
  for (const auto& p : hoe) max_x = std::max(max_x, p.x());
  EXPECT_NEAR(tip.x(), max_x, 0.005);
  const Points shovel = generate_tool(default_shape(ToolFamily::shovel), 1).points;
  const Vec3 far_end = realism_tooltip(shovel, true);
  for (const auto& p : shovel) EXPECT_LE(Vec3(p.x(), p.y(), 0).norm(), far_end.norm() + std::abs(p.z()) + 1e-9);
  EXPECT_TRUE(is_shovel_name("SHO1.pcd"));
  EXPECT_TRUE(is_shovel_name("sho3"));
  EXPECT_FALSE(is_shovel_name("HOE1"));
}

TEST(Realism, RecordedGraspsLeanAndTurnAsTheLabHeldTools) {
  for (std::uint32_t seed = 1; seed <= 200; ++seed) {
    const Eigen::Matrix3d r = exploration_grasp(seed).topLeftCorner<3, 3>();
    // hand_from_canonical = Rz(tilt) Rx(roll) Ry(about the handle)
    const double tilt = std::atan2(-r(0, 1), r(1, 1)) * 180 / M_PI, roll = std::asin(r(2, 1)) * 180 / M_PI;
    const double about = std::atan2(-r(2, 0), r(2, 2)) * 180 / M_PI;
    EXPECT_GE(tilt, 31.0 - 1e-9);
    EXPECT_LE(tilt, 48.0 + 1e-9);
    EXPECT_GE(roll, 8.5 - 1e-9);
    EXPECT_LE(roll, 16.5 + 1e-9);
    EXPECT_TRUE(about <= -90.0 + 1e-9 || about >= 180.0 - 1e-9) << about;
  }
  EXPECT_EQ(exploration_grasps_from_string(to_string(ExplorationGrasps::any)), ExplorationGrasps::any);
  EXPECT_THROW(exploration_grasps_from_string("sideways"), std::invalid_argument);
}

TEST(Realism, ExecutablePrintsTheSixFiguresPerToolAndInAll) {
  // A folder of one "real" tool: a generated rake and its reconstruction, the model seen whole.
  const auto dir = testing::scratch_dir("check-realism");
  PointCloud model = generate_tool(default_shape(ToolFamily::rake), 2);
  write_pcd((dir / "RAK9.pcd").string(), model.points, static_cast<int>(model.size()), 1);
  Rng rng(2);
  PointCloud reconstruction;
  reconstruction.points = observe_in_hand(model.points, exploration_grasp(5), 0.0, 0.001, rng);
  write_ply((dir / "RAK9_rec.ply").string(), reconstruction);
  const auto run = testing::run_tool("check-realism", dir.string() + " --seeds 1 -q");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const std::string word : {"median", "p90", ">5mm", "cov5", "cov10", "tip", "<=10mm", "RAK9", "all"})
    EXPECT_NE(run.out.find(word), std::string::npos) << word << "\n" << run.out;
  const auto empty = testing::scratch_dir("check-realism-empty");
  EXPECT_EQ(testing::run_tool("check-realism", empty.string() + " -q").exit_code, 2);
}

}  // namespace
}  // namespace toolinc
