// align-pose: accuracy over random grasps of every family seen in one rendered partial view, symmetric
// tools reported as ambiguous, the feasibility figures, and the executable (outputs, bad input, exit codes).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>

#include "support/files.hpp"
#include "support/run_tool.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/registration/align_pose.hpp"
#include "toolinc/registration/parameters.hpp"
#include "toolinc/results/results_json.hpp"
#include "toolinc/synth/partial_view.hpp"

namespace toolinc {
namespace {

namespace fs = std::filesystem;
using testing::as_cloud;
using testing::error_lines;
using testing::run_tool;
using testing::scratch_dir;
using testing::slurp;

constexpr int kCasesPerFamily = 25;  // 8 families: 200 cases

Eigen::Matrix4d pose(double tilt_deg, double roll_deg, double about_deg, const Vec3& t) {
  const double k = M_PI / 180.0;
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() =
      (Eigen::AngleAxisd(tilt_deg * k, Vec3::UnitZ()) * Eigen::AngleAxisd(roll_deg * k, Vec3::UnitX()) *
       Eigen::AngleAxisd(about_deg * k, Vec3::UnitY()))
          .toRotationMatrix();
  m.topRightCorner<3, 1>() = t;
  return m;
}

TEST(AlignPoseAccuracy, OverRandomGraspsOfEveryFamily) {
  int successes = 0, total = 0, ambiguous = 0;
  double slowest_ms = 0, total_ms = 0;
  for (ToolFamily family : all_families()) {
    int family_successes = 0;
    for (int seed = 0; seed < kCasesPerFamily; ++seed, ++total) {
      const PartialViewCase c = make_partial_view_case(family, static_cast<std::uint32_t>(seed));
      const PoseModel model(c.model.points);
      const PoseResult result = align_pose(model, c.view);
      const PoseErrors e = pose_errors(c, result.best.hand_from_model);
      const bool success = e.within(3.0, 0.005, 0.010);
      successes += success, family_successes += success, ambiguous += result.ambiguous;
      const double ms = result.view_ms + result.global_ms + result.refine_ms;
      total_ms += ms, slowest_ms = std::max(slowest_ms, ms);
      if (!success)
        std::printf("  miss %s %d: rotation %.2f deg, translation %.1f mm, tooltip %.1f mm, %d view points%s\n",
                    to_string(family).c_str(), seed, e.rotation_deg, 1000 * e.translation_m, 1000 * e.tooltip_m,
                    result.view_points_used, result.ambiguous ? ", reported ambiguous" : "");
    }
    std::printf("%-9s %2d/%d\n", to_string(family).c_str(), family_successes, kCasesPerFamily);
  }
  std::printf(
      "align-pose: %d/%d within 3 deg, 5 mm, tooltip 10 mm (%.1f%%); %d reported ambiguous; "
      "%.0f ms mean, %.0f ms slowest\n",
      successes, total, 100.0 * successes / total, ambiguous, total_ms / total, slowest_ms);
  EXPECT_GE(successes, static_cast<int>(std::ceil(0.95 * total)));
}

// A long, thin, sparsely sampled plain stick (as the lab's CAD sticks are) seen in one partial view fixes
// its pose only up to a slide along the handle and a turn about it, and fits about as well either way
// round: before, the reversed poses could fill every hypothesis kept and the stick ended held by its far
// end, 33 cm off (seed 4), or slid along the handle. The hand must still decide, and the far end pins the
// slide. 34 cm long: the far end stays in the image (of longer ones it may not, and nothing pins them).
TEST(AlignPose, LongPlainStickNeitherFlipsNorSlides) {
  ToolShape shape = default_shape(ToolFamily::stick);
  shape.handle_length = 0.30;
  shape.handle_radius = 0.006;
  shape.spacing = 0.004;
  int pinned = 0;
  const int cases = 10;
  for (std::uint32_t seed = 0; seed < cases; ++seed) {
    const PartialViewCase c = make_model_partial_view_case(generate_tool(shape, seed + 1), ToolSymmetry::axial, seed);
    const PoseResult result = align_pose(PoseModel(c.model.points), c.view);
    const PoseErrors e = pose_errors(c, result.best.hand_from_model);
    // Right as the real-tools issue counts it: the pose within 3 degrees and 5 mm, or the tooltip within
    // 10 mm; and never the slide of the bug (24-33 cm), nor more than a handle's width.
    const bool right = e.within(3.0, 0.005, std::numeric_limits<double>::infinity()) || e.tooltip_m <= 0.010;
    pinned += right;
    EXPECT_LT(e.translation_m, 0.02) << "seed " << seed;
    EXPECT_TRUE(result.feasibility.feasible) << "seed " << seed << ": " << result.feasibility.reason;
    if (!right)
      std::printf("  stick %u: handle %.2f deg, slid %.1f mm, tooltip %.1f mm\n", seed, e.rotation_deg,
                  1000 * e.translation_m, 1000 * e.tooltip_m);
  }
  std::printf("long plain stick: %d/%d within 3 deg and 5 mm, or tooltip 10 mm\n", pinned, cases);
  EXPECT_EQ(pinned, cases);
}

TEST(AlignPose, SymmetricToolsAreReportedAmbiguous) {
  int stick = 0, t_bar = 0, hoe = 0;
  for (std::uint32_t seed = 0; seed < 5; ++seed) {
    const PartialViewCase s = make_partial_view_case(ToolFamily::stick, seed);
    const PoseResult rs = align_pose(PoseModel(s.model.points), s.view);
    stick += rs.ambiguous && rs.candidates.size() >= 2;

    const PartialViewCase t = make_partial_view_case(ToolFamily::t_bar, seed);
    const PoseResult rt = align_pose(PoseModel(t.model.points), t.view);
    // Front and back: two candidates half a turn apart about the handle, both on the truth modulo symmetry.
    if (rt.ambiguous && rt.candidates.size() == 2) {
      const double apart = rotation_difference_deg(rt.candidates[0].hand_from_model, rt.candidates[1].hand_from_model);
      t_bar += apart > 170 && pose_errors(t, rt.candidates[1].hand_from_model).rotation_deg < 3.0;
    }

    const PartialViewCase h = make_partial_view_case(ToolFamily::hoe, seed);
    hoe += !align_pose(PoseModel(h.model.points), h.view).ambiguous;
  }
  EXPECT_EQ(stick, 5);
  EXPECT_GE(t_bar, 4);
  EXPECT_GE(hoe, 4);
}

TEST(AlignPose, FeasibilityFiguresAreTheGraspParameters) {
  const AlignPoseConfig config;
  const Feasibility f = check_feasibility(pose(-35, 12, 150, Vec3(0.02, -0.04, 0.05)), config);
  EXPECT_TRUE(f.feasible) << f.reason;
  EXPECT_NEAR(f.tilt_deg, -35, 1e-9);
  EXPECT_NEAR(f.roll_deg, 12, 1e-9);
  EXPECT_NEAR(f.about_handle_deg, 150, 1e-9);
  EXPECT_NEAR(f.translation.z(), 0.05, 1e-12);

  const Feasibility far = check_feasibility(pose(0, 0, 0, Vec3(0, -0.12, 0)), config);
  EXPECT_FALSE(far.feasible);
  EXPECT_NE(far.reason.find("along y"), std::string::npos) << far.reason;
  const Feasibility tilted = check_feasibility(pose(80, 0, 0, Vec3::Zero()), config);
  EXPECT_FALSE(tilted.feasible);
  EXPECT_NE(tilted.reason.find("tilt"), std::string::npos) << tilted.reason;
  // The tool reversed in the hand is a half-turn tilt.
  EXPECT_FALSE(check_feasibility(pose(180, 0, 0, Vec3::Zero()), config).feasible);
  AlignPoseConfig narrow;
  narrow.max_about_handle_deg = 90;
  EXPECT_FALSE(check_feasibility(pose(0, 0, 120, Vec3::Zero()), narrow).feasible);
}

TEST(AlignPose, TooFewViewPointsIsAMethodError) {
  const PartialViewCase c = make_partial_view_case(ToolFamily::hook, 1);
  const Points few(c.view.begin(), c.view.begin() + 50);
  EXPECT_THROW(align_pose(PoseModel(c.model.points), few), MethodError);
}

// --- The executable ------------------------------------------------------------------------------------

// Exit code, one error line naming `word`, no output and no temporary file left.
void expect_clean_failure(const std::string& args, const fs::path& dir, int code, const std::string& word) {
  testing::expect_clean_failure("align-pose", args, dir / "pose.json", code, word);
}

struct CliCase {
  fs::path dir, model, view;
  PartialViewCase c;
};

CliCase write_case(const std::string& name, ToolFamily family = ToolFamily::hoe, std::uint32_t seed = 3) {
  CliCase k{scratch_dir(name), {}, {}, make_partial_view_case(family, seed)};
  k.model = k.dir / "model.ply";
  k.view = k.dir / "view.ply";
  write_ply(k.model.string(), as_cloud(k.c.model.points, "canonical"));
  write_ply(k.view.string(), as_cloud(k.c.view, "hand"));
  return k;
}

TEST(AlignPoseCli, WritesThePoseTheOrientedModelAndTheTooltip) {
  const CliCase k = write_case("align-pose-cli");
  const auto before = slurp(k.view);
  const auto run =
      run_tool("align-pose", "--model " + k.model.string() + " --view " + k.view.string() + " -o " +
                                 (k.dir / "pose.json").string() + " --oriented " + (k.dir / "oriented.ply").string() +
                                 " --tooltip " + (k.dir / "tip.json").string() + " --max-translation 0.12 -q");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  const Json pose_file = read_json((k.dir / "pose.json").string());
  EXPECT_EQ(pose_file["type"], "tool_pose");
  EXPECT_EQ(pose_file["version"], 1);
  EXPECT_TRUE(pose_file["ok"].get<bool>());
  EXPECT_TRUE(pose_file["feasible"].get<bool>());
  const Eigen::Matrix4d m = matrix4_field(pose_file, "matrix", "pose.json");
  EXPECT_TRUE(is_rigid(m, 1e-9));
  EXPECT_TRUE(pose_errors(k.c, m).within(3.0, 0.005, 0.010));
  EXPECT_GT(pose_file["fitness"]["inlier_ratio"].get<double>(), 0.9);
  EXPECT_LT(pose_file["fitness"]["inlier_rmse_m"].get<double>(), 0.003);
  // Every setting the pose was found with, the one given on the command line included.
  for (const auto& p : align_pose_parameters()) EXPECT_TRUE(pose_file["settings"].contains(p.name)) << p.name;
  EXPECT_EQ(pose_file["settings"].size(), align_pose_parameters().size());
  EXPECT_EQ(pose_file["settings"]["max-translation"], 0.12);
  EXPECT_GT(pose_file["iterations"].get<int>(), 0);
  EXPECT_TRUE(pose_file["timing_ms"].contains("total"));

  const PointCloud oriented = read_cloud((k.dir / "oriented.ply").string());
  ASSERT_EQ(oriented.size(), k.c.model.size());
  EXPECT_EQ(oriented.frame, "hand");
  EXPECT_LT((oriented.points[10] - (m.topLeftCorner<3, 3>() * k.c.model.points[10] + m.topRightCorner<3, 1>())).norm(),
            1e-5);
  const Json tip = read_json((k.dir / "tip.json").string());
  EXPECT_EQ(tip["type"], "tooltip");
  EXPECT_LT(tooltip_error(k.c.truth, vector3_field(tip, "position", "tip.json")), 0.015);
  EXPECT_EQ(slurp(k.view), before) << "the input was modified";
}

TEST(AlignPoseCli, InfeasiblePoseExits3WithTheReport) {
  const CliCase k = write_case("align-pose-infeasible");
  const auto run =
      run_tool("align-pose", "--model " + k.model.string() + " --view " + k.view.string() +
                                 " --max-translation 0.001 --oriented " + (k.dir / "oriented.ply").string() + " -o " +
                                 (k.dir / "pose.json").string());
  EXPECT_EQ(run.exit_code, 3) << run.err;
  ASSERT_EQ(error_lines(run.err).size(), 1u) << run.err;
  EXPECT_NE(run.err.find("infeasible"), std::string::npos);
  const Json report = read_json((k.dir / "pose.json").string());
  EXPECT_FALSE(report["ok"].get<bool>());
  EXPECT_FALSE(report["feasible"].get<bool>());
  EXPECT_NE(report["feasibility"]["reason"].get<std::string>().find("translation"), std::string::npos);
  EXPECT_FALSE(fs::exists(k.dir / "oriented.ply"));
}

TEST(AlignPoseCli, BadInputFailsCleanly) {
  const CliCase k = write_case("align-pose-bad", ToolFamily::rake, 4);
  const std::string view = " --view " + k.view.string();

  // The model in millimetres, the view in metres: detected by the extents.
  Points millimetres = k.c.model.points;
  for (auto& p : millimetres) p *= 1000.0;
  write_ply((k.dir / "model_mm.ply").string(), as_cloud(millimetres, "canonical"));
  expect_clean_failure("--model " + (k.dir / "model_mm.ply").string() + view, k.dir, 2, "model_mm.ply");
  expect_clean_failure("--model " + (k.dir / "model_mm.ply").string() + view, k.dir, 2, "millimetres");

  expect_clean_failure("--model " + (k.dir / "missing.ply").string() + view, k.dir, 2, "missing.ply");

  write_ply((k.dir / "fifty.ply").string(), as_cloud(Points(k.c.view.begin(), k.c.view.begin() + 50), "hand"));
  expect_clean_failure("--model " + k.model.string() + " --view " + (k.dir / "fifty.ply").string(), k.dir, 3,
                       "too few view points");

  // NaNs are dropped and counted; a view of NaNs only is bad input.
  Points with_nan = k.c.view;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < with_nan.size(); i += 10) with_nan[i] = Vec3(nan, 0.0, nan);
  write_ply((k.dir / "nan.ply").string(), as_cloud(with_nan, "hand"));
  const auto run = run_tool("align-pose", "--model " + k.model.string() + " --view " + (k.dir / "nan.ply").string() +
                                              " -o " + (k.dir / "nan.json").string());
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("dropped " + std::to_string((with_nan.size() + 9) / 10) + " non-finite"), std::string::npos)
      << run.err;
  write_ply((k.dir / "allnan.ply").string(), as_cloud(Points(100, Vec3::Constant(nan)), "hand"));
  expect_clean_failure("--model " + k.model.string() + " --view " + (k.dir / "allnan.ply").string(), k.dir, 2,
                       "allnan.ply");
}

}  // namespace
}  // namespace toolinc
