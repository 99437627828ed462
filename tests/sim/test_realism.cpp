// check-realism's figures and the recorded grasps: a reconstruction made from the model itself scores
// as a perfect one, the tooltip rules, the grasps drawn as the lab held its tools, the executable on a
// generated folder of "real" tools and models, and its table of generated families against the
// library's own figures.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

#include "support/run_tool.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/pcd_write.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/model_kinds.hpp"
#include "toolinc/synth/realism.hpp"
#include "toolinc/synth/tool_generator.hpp"

namespace toolinc {
namespace {

TEST(Realism, AReconstructionOfTheModelItselfScoresAsPerfect) {
  const Points model = generate_tool(default_shape(ToolFamily::hoe), 1).points;
  const Eigen::Matrix4d grasp = exploration_grasp(3);
  Rng rng(3);
  const Points reconstruction = observe_in_hand(model, grasp, 0.0, 0.0005, rng);
  EXPECT_TRUE(place_model(model, reconstruction).isApprox(grasp, 0.01));
  const CloudFigures f = reconstruction_figures(model, reconstruction, TruthTip::weighted);
  EXPECT_LT(f.accuracy.median_m, 0.001);
  EXPECT_LT(f.accuracy.beyond, 0.01);
  EXPECT_GT(f.coverage_5mm, 0.99);
  EXPECT_LT(f.tip_gap_m, 0.002);
  // Half the tool seen: coverage halves, accuracy does not change.
  Points half;
  for (const auto& p : model)
    if (p.y() > -0.15) half.push_back(apply(grasp, p));
  const CloudFigures h = cloud_figures(half, transform_points(model, grasp),
                                       tool_ground_truth(model, ToolSymmetry::mirror, TruthTip::weighted, grasp));
  EXPECT_LT(h.accuracy.median_m, 0.0005);
  EXPECT_LT(h.coverage_10mm, 0.8);
}

TEST(Realism, TooltipRules) {
  // The truth's tooltip rule comes from the model's kind: a shovel's ("sho") is the blade's far end.
  EXPECT_EQ(truth_tip_of_kind(model_kind("SHO1.pcd")), TruthTip::far_end);
  EXPECT_EQ(truth_tip_of_kind(model_kind("sho3")), TruthTip::far_end);
  EXPECT_EQ(truth_tip_of_kind(model_kind("HOE1")), TruthTip::weighted);
  // A hoe's tip is its blade's front edge; a shovel's, the blade's point farthest from the hand.
  const Eigen::Matrix4d grasp = exploration_grasp(4);
  const Eigen::Matrix3d r = grasp.topLeftCorner<3, 3>();
  const Vec3 t = grasp.topRightCorner<3, 1>();
  const Points hoe = generate_tool(default_shape(ToolFamily::hoe), 1).points;
  const Vec3 tip =
      r.transpose() * (tool_ground_truth(hoe, ToolSymmetry::mirror, TruthTip::weighted, grasp).tooltips.front() - t);
  EXPECT_NEAR(tip.z(), 0.0, 1e-9);
  double max_x = 0;
  for (const auto& p : hoe) max_x = std::max(max_x, p.x());
  EXPECT_NEAR(tip.x(), max_x, 0.005);
  const Points shovel = generate_tool(default_shape(ToolFamily::shovel), 1).points;
  const Vec3 far_end = tool_ground_truth(shovel, ToolSymmetry::mirror, TruthTip::far_end, grasp).tooltips.front();
  double centroid_y = 0;
  for (const auto& p : shovel) centroid_y += p.y() / static_cast<double>(shovel.size());
  Vec3 farthest = Vec3::Zero();  // from the hand, on the blade's side of the centroid
  for (const auto& p : shovel)
    if (p.y() < centroid_y && (r * p + t).norm() > (r * farthest + t).norm()) farthest = p;
  EXPECT_LT((far_end - (r * Vec3(farthest.x(), farthest.y(), 0) + t)).norm(), 1e-9);
  EXPECT_LT(farthest.y(), -0.2);  // at the blade's end, far down the handle
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
  // And a model without a reconstruction: simulated alone, in a row for its kind.
  const PointCloud hoe = generate_tool(default_shape(ToolFamily::hoe), 3);
  write_pcd((dir / "hoe7.pcd").string(), hoe.points, static_cast<int>(hoe.size()), 1);
  const auto run = testing::run_tool("check-realism", dir.string() + " --seeds 1 -q");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const std::string word : {"median", "p90", ">5mm", "cov5", "cov10", "tip", "<=10mm", "RAK9", "all",
                                 "robot's reconstructions", "models without a reconstruction", "\nhoe "})
    EXPECT_NE(run.out.find(word), std::string::npos) << word << "\n" << run.out;
  EXPECT_EQ(run.out.find("hoe7"), std::string::npos) << run.out;  // per kind, not per model
  const auto empty = testing::scratch_dir("check-realism-empty");
  EXPECT_EQ(testing::run_tool("check-realism", empty.string() + " -q").exit_code, 2);
  EXPECT_EQ(testing::run_tool("check-realism", "-q").exit_code, 2);  // neither a folder nor families
  EXPECT_EQ(testing::run_tool("check-realism", "--families spoon -q").exit_code, 2);
}

// A row of check-realism's simulated columns: the six figures (mm where lengths), the tip count and,
// in "all", the tip share's interval (per cent).
struct PrintedRow {
  double median_mm = 0, p90_mm = 0, beyond = 0, cov5 = 0, cov10 = 0, tip_mm = 0;
  int tips = 0, clouds = 0;
  double lo_percent = -1, hi_percent = -1;
};

std::optional<PrintedRow> printed_row(const std::string& out, const std::string& name) {
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string first;
    if (!(fields >> first) || first != name) continue;
    PrintedRow row;
    char slash = 0;
    if (!(fields >> row.median_mm >> row.p90_mm >> row.beyond >> row.cov5 >> row.cov10 >> row.tip_mm >> row.tips >>
          slash >> row.clouds) ||
        slash != '/')
      return std::nullopt;
    char open = 0, dash = 0;
    if (fields >> open >> row.lo_percent >> dash >> row.hi_percent) EXPECT_TRUE(open == '(' && dash == '-') << line;
    return row;
  }
  return std::nullopt;
}

// The six figures as check-realism prints them: medians over the clouds; failed sessions count only
// against the tip share.
void expect_printed(const std::optional<PrintedRow>& row, const std::vector<SimulatedFigures>& sessions,
                    const std::string& what) {
  ASSERT_TRUE(row.has_value()) << what;
  std::vector<double> median, p90, beyond, cov5, cov10, gap;
  int tips = 0;
  for (const auto& s : sessions) {
    if (!s.merged) continue;
    const CloudFigures& f = s.figures;
    median.push_back(1000 * f.accuracy.median_m), p90.push_back(1000 * f.accuracy.p90_m);
    beyond.push_back(f.accuracy.beyond), cov5.push_back(f.coverage_5mm), cov10.push_back(f.coverage_10mm);
    gap.push_back(1000 * f.tip_gap_m);
    tips += f.tip_gap_m <= 0.010;
  }
  ASSERT_FALSE(median.empty()) << what << ": no session merged";
  EXPECT_NEAR(row->median_mm, toolinc::median(median), 0.051) << what;
  EXPECT_NEAR(row->p90_mm, toolinc::median(p90), 0.051) << what;
  EXPECT_NEAR(row->beyond, toolinc::median(beyond), 0.0051) << what;
  EXPECT_NEAR(row->cov5, toolinc::median(cov5), 0.0051) << what;
  EXPECT_NEAR(row->cov10, toolinc::median(cov10), 0.0051) << what;
  EXPECT_NEAR(row->tip_mm, toolinc::median(gap), 0.051) << what;
  EXPECT_EQ(row->tips, tips) << what;
  EXPECT_EQ(row->clouds, static_cast<int>(sessions.size())) << what;
}

TEST(Realism, ExecutableTablesGeneratedFamiliesAsTheLibraryComputesThem) {
  // Two families, one session each (seed 1, recorded grasps), with ideal and with ELAS stereo.
  const std::vector<ToolFamily> families = {ToolFamily::hoe, ToolFamily::shovel};
  std::map<std::string, double> p90_all;
  for (const std::string stereo : {"ideal", "elas"}) {
    const auto run = testing::run_tool("check-realism", "--families hoe shovel --seeds 1 --stereo " + stereo + " -q");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_NE(run.out.find("generated families: simulated sessions (--stereo " + stereo + ")"), std::string::npos)
        << run.out;
    EXPECT_EQ(run.out.find("robot's"), std::string::npos) << run.out;  // no robot's columns without reconstructions
    std::vector<SimulatedFigures> all;
    for (const auto family : families) {
      SessionSimulatorConfig session = family_session(family, 1);
      session.stereo = stereo_model_from_string(stereo);
      const auto sessions = simulated_figures(session, ExplorationGrasps::recorded, 1);
      ASSERT_EQ(sessions.size(), 1u);
      expect_printed(printed_row(run.out, to_string(family)), sessions, stereo + " " + to_string(family));
      all.insert(all.end(), sessions.begin(), sessions.end());
    }
    const auto all_row = printed_row(run.out, "all");
    expect_printed(all_row, all, stereo + " all");
    ASSERT_TRUE(all_row.has_value());
    const auto [lo, hi] = wilson_interval(all_row->tips, all_row->clouds);
    EXPECT_NEAR(all_row->lo_percent, 100 * lo, 0.51) << run.out;
    EXPECT_NEAR(all_row->hi_percent, 100 * hi, 0.51) << run.out;
    p90_all[stereo] = all_row->p90_mm;
  }
  // Ideal disparity makes cleaner clouds than matched stereo.
  EXPECT_LT(p90_all["ideal"], p90_all["elas"]);
}

}  // namespace
}  // namespace toolinc
