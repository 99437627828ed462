// The offline pipeline on simulated sessions (issue: recorded sessions end to end): crop-cloud's two 3D
// paths, merge-views' accuracy and rejection of gross errors, the tooltip from the whole pipeline, and
// bad input to crop-cloud and merge-views.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "support/synthetic_cases.hpp"
#include "toolinc/ann/nearest_distance.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/frame/frame_search.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/registration/merge_views.hpp"
#include "toolinc/session/crop.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/realism.hpp"
#include "toolinc/synth/session_simulator.hpp"
#include "toolinc/synth/tool_generator.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

namespace {

std::vector<PointCloud> crop_all(const SimulatedSession& session, const CropConfig& config = {}) {
  std::vector<PointCloud> views;
  for (std::size_t v = 0; v < session.views.size(); ++v)
    views.push_back(crop_view(session.info, session.info.views[v], session.views[v], config).cloud);
  return views;
}

}  // namespace

TEST(SessionPipeline, ExactPointsAndReprojectionAgreeWithinQuantisation) {
  const SimulatedSession session = simulate_session(ideal_family_session(ToolFamily::hoe, 3));
  const ViewRecord& record = session.info.views[0];
  ViewData without_points = session.views[0];
  without_points.points.clear();
  const CropResult exact = crop_view(session.info, record, session.views[0]);
  const CropResult reprojected = crop_view(session.info, record, without_points);
  EXPECT_EQ(exact.points_source, "points.pcd");
  EXPECT_NE(reprojected.points_source.find("approximate"), std::string::npos);
  // The 8-bit disparity is quantised to num_disparities / 255 px (0.38 px): at the tool's depth z the
  // depth step is z^2 * 0.38 / (fx b), about half a step of error plus the disparity noise.
  const double z = 0.47, step = z * z * session.info.camera.disparity_px(1) /
                                (session.info.camera.fx * session.info.camera.baseline);
  const double d = median_nearest_distance(reprojected.cloud.points, exact.cloud.points);
  std::printf("quantisation step %.1f mm, median distance between the paths %.1f mm\n", 1000 * step, 1000 * d);
  EXPECT_LT(d, step);
  EXPECT_NEAR(static_cast<double>(reprojected.cloud.size()), static_cast<double>(exact.cloud.size()),
              0.1 * exact.cloud.size());
}

TEST(SessionPipeline, BlobDetectionWithoutAMask) {
  const SimulatedSession session = simulate_session(ideal_family_session(ToolFamily::rake, 5));
  ViewData without_blob = session.views[1];
  without_blob.blob.release();
  const CropResult with_mask = crop_view(session.info, session.info.views[1], session.views[1]);
  const CropResult detected = crop_view(session.info, session.info.views[1], without_blob);
  EXPECT_EQ(detected.mask_source, "closest blob on the disparity");
  EXPECT_LT(median_nearest_distance(detected.cloud.points, with_mask.cloud.points), 0.002);
  EXPECT_GT(detected.cloud.size(), 0.8 * with_mask.cloud.size());
}

// Where neither a recorded nor a detected blob holds anything, the tool is followed out of the hand on the
// disparity (view_tool_mask's seed): the crop holds about the points the blob's would.
TEST(SessionPipeline, NoBlobAtAllToolFollowedOutOfTheHand) {
  const SimulatedSession session = simulate_session(ideal_family_session(ToolFamily::rake, 5));
  ViewData without_blob = session.views[1];
  without_blob.blob.release();
  CropConfig nothing_detected;
  nothing_detected.blob.min_blob_size = nothing_detected.blob.max_blob_size + 1;
  const CropResult with_mask = crop_view(session.info, session.info.views[1], session.views[1]);
  const CropResult followed = crop_view(session.info, session.info.views[1], without_blob, nothing_detected);
  EXPECT_EQ(followed.mask_source, "no blob: the tool followed out of the hand");
  EXPECT_LT(median_nearest_distance(followed.cloud.points, with_mask.cloud.points), 0.002);
  EXPECT_GT(followed.cloud.size(), 0.8 * with_mask.cloud.size());
}

// A blob short of the hand (the closest blob a head nearer than its handle, cut off from it at their depth
// edge) is joined by the tool followed out of the hand: the crop holds about the points the whole blob's
// would; the blob alone, only the head's part.
TEST(SessionPipeline, BlobShortOfTheHandJoinedByTheToolFollowedOutOfIt) {
  const SimulatedSession session = simulate_session(ideal_family_session(ToolFamily::hoe, 3));
  const ViewRecord& record = session.info.views[1];
  const CropResult whole = crop_view(session.info, record, session.views[1]);
  ViewData short_of_the_hand = session.views[1];
  short_of_the_hand.blob = session.views[1].blob.clone();
  const std::vector<Vec3> points = view_root_points(session.info.camera, record, session.views[1]);
  const Eigen::Matrix4d hand_from_root = record.root_from_hand.inverse();
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite() || apply(hand_from_root, points[i]).norm() < 0.2) short_of_the_hand.blob.data[i] = 0;
  CropConfig follow_hand;
  follow_hand.follow_hand = true;
  const cv::Mat as_read = short_of_the_hand.blob.clone();
  const CropResult followed = crop_view(session.info, record, short_of_the_hand, follow_hand);
  EXPECT_EQ(cv::countNonZero(short_of_the_hand.blob != as_read), 0) << "the view's blob was modified";
  const CropResult alone = crop_view(session.info, record, short_of_the_hand);
  std::printf("whole blob %zu points, short of the hand %zu, followed out of the hand %zu\n", whole.cloud.size(),
              alone.cloud.size(), followed.cloud.size());
  EXPECT_EQ(followed.mask_source, "blob.png short of the hand, with the tool followed out of the hand");
  EXPECT_EQ(alone.mask_source, "blob.png");
  EXPECT_GT(followed.cloud.size(), 0.9 * whole.cloud.size());
  EXPECT_LT(median_nearest_distance(followed.cloud.points, whole.cloud.points), 0.002);
  EXPECT_LT(alone.cloud.size(), 0.7 * whole.cloud.size());
}

TEST(SessionPipelineAccuracy, EveryFamilyManySessions) {
  // Measured on 8 families x 10 grasps: the merged model and the tooltip from the whole pipeline. The
  // merge floors are the issue's; the tooltip floor is a regression floor below the 95 %: 75 of
  // 80 in a GCC build, 70 in a Clang build (the simulated disparities differ in their last bits, and a
  // few tips lie near 10 mm), so the floor is 85 %, 68. Over more sessions (evaluate-sessions, docs/accuracy.md) the
  // rate is about 95 %. The exploration sees the tool from one side: where the effector points away from the cameras
  // its front face is never seen, and the tip found lies about the effector's thickness behind.
  int sessions = 0, tips_within_10mm = 0;
  std::vector<double> model_errors;
  for (ToolFamily family : all_families()) {
    for (std::uint32_t g = 0; g < 10; ++g) {
      const SessionErrors e = evaluate_simulated_session(ideal_family_session(family, 100 + g));
      ASSERT_EQ(e.tool.failure, "") << to_string(family) << " grasp " << g;
      EXPECT_EQ(e.views_rejected, 0) << to_string(family) << " grasp " << g;
      model_errors.push_back(e.model_median_m);
      tips_within_10mm += e.tool.tooltip_m <= 0.010;
      ++sessions;
      std::printf("%-9s grasp %u: model %.1f mm from the truth, tooltip error %.1f mm\n", to_string(family).c_str(), g,
                  1000 * e.model_median_m, 1000 * e.tool.tooltip_m);
    }
  }
  std::sort(model_errors.begin(), model_errors.end());
  std::printf("merged model: median %.2f mm, worst %.2f mm; tooltip within 10 mm in %d of %d sessions\n",
              1000 * model_errors[model_errors.size() / 2], 1000 * model_errors.back(), tips_within_10mm, sessions);
  EXPECT_LT(model_errors[model_errors.size() / 2], 0.003);
  EXPECT_GE(tips_within_10mm, static_cast<int>(0.85 * sessions));
}

TEST(SessionPipeline, EvaluateSessionsReportsThePipelinesErrors) {
  // The executable reports what the library measures, case by case, and its output does not depend on
  // how many sessions run in parallel.
  const auto dir = scratch_dir("evaluate-sessions");
  const std::string args = "-q --stereo ideal --grasp any --families hook stick --first-seed 100 --grasps 2 -o ";
  const ToolRun parallel = run_tool("evaluate-sessions", args + (dir / "parallel.json").string() + " -j 2");
  const ToolRun serial = run_tool("evaluate-sessions", args + (dir / "serial.json").string());
  ASSERT_EQ(parallel.exit_code, 0) << parallel.err;
  ASSERT_EQ(serial.exit_code, 0) << serial.err;
  EXPECT_EQ(slurp(dir / "parallel.json"), slurp(dir / "serial.json"));
  const Json results = read_json((dir / "serial.json").string());
  ASSERT_EQ(results["sessions"].size(), 4u);
  int within = 0;
  for (const auto& s : results["sessions"]) {
    const SessionErrors e = evaluate_simulated_session(
        ideal_family_session(family_from_string(s["family"].get<std::string>()), s["seed"].get<std::uint32_t>()));
    EXPECT_EQ(s["failure"], e.tool.failure);
    EXPECT_EQ(s["tooltip_error_m"].get<double>(), e.tool.tooltip_m);
    EXPECT_EQ(s["model_median_m"].get<double>(), e.model_median_m);
    EXPECT_EQ(s["confident"].get<bool>(), e.tool.confident);
    EXPECT_EQ(s["tooltip_probability"].get<double>(), e.tool.tooltip_probability);
    if (e.tool.failure.empty()) {
      EXPECT_GT(e.tool.tooltip_probability, 0.0);  // the search's: some hypothesis has the chosen tooltip
      EXPECT_LE(e.tool.tooltip_probability, 1.0);
    }
    if (e.tool.confident) {
      EXPECT_GE(e.tool.tooltip_probability, fitted_frame_score().confident_probability);
    }
    within += e.tool.tooltip_m <= 0.010;
  }
  EXPECT_NE(serial.out.find("all: tooltip within 10 mm in " + std::to_string(within) + " of 4 sessions"),
            std::string::npos)
      << serial.out;
  const Json& all = results["summary"].back();
  EXPECT_EQ(all["family"], "all");
  EXPECT_EQ(all["sessions"], 4);
  EXPECT_EQ(all["tooltip_within_tolerance"], within);
  EXPECT_LE(all["rate_interval_95"][0].get<double>(), within / 4.0);
  EXPECT_GE(all["rate_interval_95"][1].get<double>(), within / 4.0);

  // A looser tolerance counts every session whose error is within it.
  const ToolRun loose = run_tool("evaluate-sessions", args + (dir / "loose.json").string() + " --tip-tolerance 1");
  ASSERT_EQ(loose.exit_code, 0) << loose.err;
  EXPECT_EQ(read_json((dir / "loose.json").string())["summary"].back()["tooltip_within_tolerance"], 4);
  EXPECT_NE(loose.out.find("all: tooltip within 1000 mm in 4 of 4 sessions"), std::string::npos) << loose.out;

  const ToolRun unknown = run_tool("evaluate-sessions", "--families spoon -o " + (dir / "bad.json").string());
  EXPECT_EQ(unknown.exit_code, 2);
  expect_failure_left_nothing(unknown, "spoon", dir / "bad.json", dir);
}

namespace {

// A view recorded with a grossly wrong hand pose is rejected either by crop-cloud (its points fall
// outside the hand-frame box: too few left) or by merge-views (implausible correction or poor fit).
// On matched (elas, sgbm) sessions crop may also reject a good view (the closest blob there was a wrong-match patch or
// only the tool's nearest part: too few points), and merge-views one that fits poorly: those views are
// lost, but at least three views are merged. Returns in how many sessions the bad view was merged.
int gross_errors_merged(StereoModel stereo, std::uint32_t sessions, const CropConfig& crop = {}) {
  const bool all_good_kept = stereo == StereoModel::ideal;
  int bad_merged = 0;
  for (std::uint32_t g = 0; g < sessions; ++g) {
    const ToolFamily family = g % 2 ? ToolFamily::hook : ToolFamily::shovel;
    SessionSimulatorConfig config =
        all_good_kept ? ideal_family_session(family, 200 + g) : family_session(family, 200 + g);
    config.stereo = stereo;
    const std::size_t bad = 1 + g % 4;
    config.gross_errors.push_back({bad, g % 4 < 2 ? 0.15 : 0.0, g % 4 < 2 ? 0.0 : 60.0});
    const SimulatedSession session = simulate_session(config);
    std::vector<PointCloud> cropped;
    std::vector<std::size_t> index;
    for (std::size_t v = 0; v < session.views.size(); ++v) {
      try {
        cropped.push_back(crop_view(session.info, session.info.views[v], session.views[v], crop).cloud);
        index.push_back(v);
      } catch (const MethodError& e) {
        if (all_good_kept) EXPECT_EQ(v, bad) << "session " << g << ": " << e.what();
      }
    }
    const MergeResult merged = merge_views(cropped);
    int accepted = 0;
    for (std::size_t k = 0; k < merged.views.size(); ++k) {
      accepted += merged.views[k].accepted;
      if (index[k] == bad && merged.views[k].accepted) {
        ++bad_merged;
        std::printf("session %u: the bad view %zu was merged (%s)\n", g, bad, merged.views[k].reason.c_str());
      }
      if (all_good_kept)
        EXPECT_EQ(merged.views[k].accepted, index[k] != bad)
            << "session " << g << " view " << index[k] << ": " << merged.views[k].reason;
    }
    EXPECT_GE(accepted, 3) << "session " << g;
  }
  return bad_merged;
}

}  // namespace

TEST(SessionPipeline, GrossErrorsRejectedRestMerged) { EXPECT_EQ(gross_errors_merged(StereoModel::ideal, 4), 0); }

TEST(SessionPipeline, TheTrueModelIsAlignedOntoTheMergedModel) {
  // A merged model as the views' kinematic error leaves it: the hook's surface seen from one side, with
  // 1 mm of noise, moved as a whole by 6 mm and 2 degrees. The true model aligned onto it from the true
  // grasp takes that move: its far end within 1.5 mm (the noise's share over ~600 points is ~0.1 mm;
  // the rest is the one-sided view's slack along the surface).
  const SessionSimulatorConfig config = family_session(ToolFamily::hook, 3);
  const Points canonical = true_surface(config);
  const Points in_hand = transform_points(canonical, config.hand_from_canonical);
  std::vector<double> heights;
  for (const auto& p : in_hand) heights.push_back(p.z());
  const double middle = median(heights);
  Eigen::Matrix4d moved = Eigen::Matrix4d::Identity();
  moved.topLeftCorner<3, 3>() = Eigen::AngleAxisd(2.0 * M_PI / 180, Eigen::Vector3d(1, 1, 0).normalized()).matrix();
  moved.topRightCorner<3, 1>() = Eigen::Vector3d(0.004, -0.003, 0.0035);
  Rng rng(7);
  Points seen;
  for (const auto& p : in_hand)
    if (p.z() > middle) seen.push_back(p + 0.001 * Vec3(rng.gaussian(), rng.gaussian(), rng.gaussian()));
  const Points merged = voxel_downsample(transform_points(seen, moved), 0.002);
  const Eigen::Matrix4d pose = pose_on_merged_model(merged, canonical, config.hand_from_canonical);
  const Eigen::Matrix4d expected = moved * config.hand_from_canonical;
  double worst = 0.0, unmoved = 0.0;
  for (const auto& p : canonical) {
    worst = std::max(worst, ((pose - expected) * p.homogeneous()).norm());
    unmoved = std::max(unmoved, ((config.hand_from_canonical - expected) * p.homogeneous()).norm());
  }
  EXPECT_LT(worst, 0.0015) << "the move itself shifts points up to " << unmoved;
  EXPECT_GT(unmoved, 0.008);
}

TEST(SessionPipeline, EvaluateSessionsMergesAsTheOriginalDid) {
  // --reconstruction original and the kinematic error: the library's session with that error, through the
  // original's merge, the model as bare points; what differs from merge-views is tested in test_merge_views.
  const auto dir = scratch_dir("evaluate-sessions-original");
  const ToolRun run = run_tool("evaluate-sessions",
                               "-q --stereo ideal --grasp any --families hook --grasps 2 --reconstruction original "
                               "--kinematic-error-mm 6 --kinematic-error-deg 3 -o " +
                                   (dir / "out.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json results = read_json((dir / "out.json").string());
  ASSERT_EQ(results["sessions"].size(), 2u);
  const PipelineConfig original = as_original_reconstruction(PipelineConfig{});
  EXPECT_FALSE(PipelineConfig{}.bare_model);
  EXPECT_TRUE(original.bare_model);
  EXPECT_EQ(original.merge.icp.max_iterations, 0);
  for (const auto& s : results["sessions"]) {
    SessionSimulatorConfig session =
        ideal_family_session(family_from_string(s["family"].get<std::string>()), s["seed"].get<std::uint32_t>());
    session.kinematic_error_m = 0.006;
    session.kinematic_error_deg = 3.0;
    const SessionErrors e = evaluate_simulated_session(session, original);
    EXPECT_EQ(s["failure"], e.tool.failure);
    EXPECT_EQ(s["tooltip_error_m"].get<double>(), e.tool.tooltip_m);
    EXPECT_EQ(s["model_median_m"].get<double>(), e.model_median_m);
    // The option reaches the merge: merge-views moves the views, so its model is another cloud. Which of
    // the two lies nearer the true surface on one session is not a property (ICP may settle a view a
    // millimetre worse than the hand put it); over many sessions it is measured in docs/simulation.md.
    EXPECT_NE(evaluate_simulated_session(session).model_median_m, e.model_median_m) << s["seed"];
  }
}

TEST(SessionPipeline, EvaluateSessionsOnSgbmSessions) {
  // evaluate-sessions --stereo sgbm reports what the library measures on SGBM sessions with crop's
  // depth-edge filter, and differs from the ideal sessions' figures.
  const auto dir = scratch_dir("evaluate-sessions-sgbm");
  const ToolRun run = run_tool("evaluate-sessions", "-q --stereo sgbm --families hook --first-seed 100 --grasps 1 -o " +
                                                        (dir / "sgbm.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Json session = read_json((dir / "sgbm.json").string())["sessions"][0];
  SessionSimulatorConfig config = family_session(ToolFamily::hook, 100);
  config.stereo = StereoModel::sgbm;
  PipelineConfig pipeline;
  pipeline.crop = session_crop(StereoModel::sgbm);
  const SessionErrors e = evaluate_simulated_session(config, pipeline);
  EXPECT_EQ(session["failure"], e.tool.failure);
  EXPECT_EQ(session["model_median_m"].get<double>(), e.model_median_m);
  EXPECT_EQ(session["tooltip_error_m"].get<double>(), e.tool.tooltip_m);
  EXPECT_EQ(session["tooltip_error_true_frame_m"].get<double>(), e.tool.tooltip_true_frame_m);
  EXPECT_EQ(session["tooltip_error_relative_m"].get<double>(), e.tool.tooltip_relative_m);
  EXPECT_EQ(session["symmetry_plane_error_deg"].get<double>(), e.tool.symmetry_plane_deg);
  EXPECT_NE(e.model_median_m, evaluate_simulated_session(family_session(ToolFamily::hook, 100)).model_median_m);
}

TEST(SessionPipelineAccuracy, HandRemnantBesideTheHandleDoesNotTiltIt) {
  // A hoe on the robot's stereo whose merged model keeps a remnant of the hand 7-12 cm from its origin,
  // 2-3 cm beside the handle, where the handle's points form no surface: a line through all of them was
  // tilted 19-20 degrees (tooltip 30 mm off, called confident); the handle's own points, trimmed to those
  // near their line, are 6 degrees off at most. The tooltip then lies 4 mm off in a GCC build and 15 mm
  // in a Clang build (the simulated disparities differ in their last bits, and so does the head's front).
  PipelineConfig pipeline;
  pipeline.crop = session_crop(StereoModel::elas);
  const SessionErrors e = evaluate_simulated_session(family_session(ToolFamily::hoe, 202), pipeline);
  ASSERT_EQ(e.tool.failure, "");
  EXPECT_LT(e.tool.handle_axis_deg, 8.0);
  EXPECT_LT(e.tool.tooltip_m, 0.020);
}

TEST(SessionPipelineAccuracy, DefaultStereoGrossErrorsRejectedRestMerged) {
  // On the robot's stereo (elas, recorded grasps). A displaced view whose few points left in the box
  // lie on a part that slides along itself (a handle along its axis) fits where it lands, and the
  // inlier test cannot tell it from a good view: measured, none of the 8 merged in a GCC build, one in a
  // Clang build (the simulated disparities differ in the last bits, and so do the crops).
  EXPECT_LE(gross_errors_merged(StereoModel::elas, 8, session_crop(StereoModel::elas)), 1);
}

TEST(SessionPipelineAccuracy, DefaultStereoSessionsCompleteAndTheImageTrimsTheSmear) {
  // Every family, two grasps, the default (the robot's) stereo: every session merges, and crop's matched
  // settings (the blob trimmed by the left image) remove far-off (smeared) points and keep most good ones.
  PipelineConfig pipeline;
  pipeline.crop = session_crop(StereoModel::elas);
  std::vector<double> model_errors;
  int far_without = 0, far_with = 0, points_without = 0, points_with = 0;
  int tips_within_20mm = 0, true_frame_within_20mm = 0, tips_in_cloud = 0;
  std::vector<double> coverage_5mm;
  for (ToolFamily family : all_families())
    for (std::uint32_t g = 0; g < 2; ++g) {
      SessionSimulatorConfig config = family_session(family, 100 + g);
      const SessionErrors e = evaluate_simulated_session(config, pipeline);
      ASSERT_EQ(e.tool.failure, "") << to_string(family) << " grasp " << g;
      model_errors.push_back(e.model_median_m);
      tips_within_20mm += e.tool.tooltip_m <= 0.020;
      true_frame_within_20mm += e.tool.tooltip_true_frame_m <= 0.020;
      const Points canonical = generate_tool(config.shape, 1).points;
      const CloudFigures figures = cloud_figures(
          e.merged, transform_points(canonical, config.hand_from_canonical),
          tool_ground_truth(canonical, symmetry_of(family), truth_tip_of(family), config.hand_from_canonical));
      tips_in_cloud += figures.tip_gap_m <= 0.010;
      coverage_5mm.push_back(figures.coverage_5mm);
      std::printf(
          "%-9s grasp %u: model %.1f mm from the truth (p90 %.1f mm), tooltip error %.1f mm (%.1f mm with "
          "the true frame), symmetry plane off by %.0f deg\n",
          to_string(family).c_str(), g, 1000 * e.model_median_m, 1000 * e.model.p90_m, 1000 * e.tool.tooltip_m,
          1000 * e.tool.tooltip_true_frame_m, e.tool.symmetry_plane_deg);
      if (g > 0) continue;
      // One session per family without kinematic error: each cropped view against the true surface.
      config.kinematic_error_m = config.kinematic_error_deg = 0;
      const SimulatedSession session = simulate_session(config);
      const Points truth = transform_points(generate_tool(config.shape, 1).points, config.hand_from_canonical);
      for (std::size_t v = 0; v < session.views.size(); ++v) {
        for (const bool filter : {false, true}) {
          const Points cropped =
              crop_view(session.info, session.info.views[v], session.views[v], filter ? pipeline.crop : CropConfig{})
                  .cloud.points;
          const std::vector<double> d = nearest_distances(cropped, truth);
          const int far = static_cast<int>(std::count_if(d.begin(), d.end(), [](double x) { return x > 0.005; }));
          (filter ? far_with : far_without) += far;
          (filter ? points_with : points_without) += static_cast<int>(cropped.size());
        }
      }
    }
  std::printf("beyond 5 mm: %d of %d points with crop's defaults, %d of %d with its matched settings\n", far_without,
              points_without, far_with, points_with);
  // Measured: 20 % fewer far points, 12 % fewer near ones (with SGBM's 2 px depth-edge drop as well, 29 %
  // and 29 %: it shaves the tool's true edges).
  EXPECT_LT(far_with, 0.85 * far_without);
  EXPECT_GT(points_with - far_with, 0.8 * (points_without - far_without));
  // A regression floor, not the 3 mm: the robot's reconstructions' median is 3.4 mm.
  EXPECT_LT(median(model_errors), 0.005);
  // Regression floors below the measured: the tooltip within 20 mm in 16 of 16 sessions, 16 with the
  // true frame on the same merged models (SGBM: 7 and 11); the true tip within 10 mm of the merged model
  // in 14 (the cloud holds the tip, as the robot's always do); coverage of the true surface within
  // 5 mm 0.66 in the median (the robot's reconstructions: 0.65).
  std::printf(
      "tooltip within 20 mm in %d of 16 sessions, %d with the true frame; the true tip within 10 mm of "
      "the merged model in %d, coverage within 5 mm %.2f\n",
      tips_within_20mm, true_frame_within_20mm, tips_in_cloud, median(coverage_5mm));
  EXPECT_GE(tips_within_20mm, 14);
  EXPECT_GE(true_frame_within_20mm, 14);
  EXPECT_GE(tips_in_cloud, 13);
  EXPECT_GE(median(coverage_5mm), 0.55);
}

TEST(SessionPipeline, CommandsFailCleanlyOnBadInput) {
  const auto dir = scratch_dir("session-bad");
  ASSERT_EQ(run_tool("simulate-session", "-q --family hoe --seed 2 -o " + (dir / "s").string()).exit_code, 0);
  const auto expect_failure = [&](const std::string& tool, const std::string& args, int code, const std::string& word,
                                  const fs::path& output) {
    const auto run = run_tool(tool, args);
    SCOPED_TRACE(tool + " " + args + "\n" + run.err);
    EXPECT_EQ(run.exit_code, code);
    EXPECT_NE(run.err.find(word), std::string::npos);
    EXPECT_FALSE(fs::exists(output));
  };
  const auto copy = [&](const std::string& name) {
    fs::copy(dir / "s", dir / name, fs::copy_options::recursive);
    return dir / name;
  };
  const fs::path out = dir / "out.ply";
  expect_failure("crop-cloud", (dir / "nothing").string() + " -o " + out.string(), 2, "nothing", out);
  const auto no_disparity = copy("no-disparity");
  fs::remove(no_disparity / "views/001/disparity.png");
  expect_failure("crop-cloud", no_disparity.string() + " --view 1 -o " + out.string(), 2, "disparity.png", out);
  const auto empty_blob = copy("empty-blob");
  {
    const SessionInfo info = read_session(empty_blob.string());
    ViewData view = read_view(empty_blob.string(), info, 0);
    std::ofstream(empty_blob / "views/000/blob.png", std::ios::binary).close();
  }
  expect_failure("crop-cloud", empty_blob.string() + " --view 0 -o " + out.string(), 2, "blob.png", out);
  const auto version = copy("version");
  {
    std::ifstream in(version / "session.json");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.replace(text.find("\"version\": 1"), 12, "\"version\": 7");
    std::ofstream(version / "session.json") << text;
  }
  expect_failure("crop-cloud", version.string() + " -o " + out.string(), 2, "version", out);
  // merge-views: a reference view of 200 points is too few (exit 3), the report says why, with the settings.
  PointCloud few;
  for (int i = 0; i < 200; ++i) few.points.emplace_back(0.1 + 0.001 * i, -0.15, 0.0);
  write_ply((dir / "few.ply").string(), few);
  expect_failure("merge-views",
                 (dir / "few.ply").string() + " -o " + out.string() + " --report " + (dir / "r.json").string() +
                     " --min-points 250",
                 3, "200 points", out);
  const Json report = read_json((dir / "r.json").string());
  EXPECT_FALSE(report["ok"].get<bool>());
  EXPECT_EQ(report["settings"]["min-points"], 250);
}

// A view crop-cloud finds no tool in never reaches merge-views, yet what it alone saw (the head, maybe) is
// missing from the model as surely as a view that did not fit: each crop says how many views its session
// recorded, the model how many of them it lacks, and the tooltip on it is doubtful and says why.
TEST(SessionPipeline, AViewWithNoToolFoundMakesTheTooltipDoubtful) {
  const auto dir = scratch_dir("session-view-missing");
  ASSERT_EQ(run_tool("simulate-session", "-q --family hook --seed 3 -o " + (dir / "s").string()).exit_code, 0);
  const std::string why = "of the session's views are missing from the cloud";
  const auto tooltip_of = [&](const std::string& name) {
    const std::string out = (dir / (name + "_out")).string();
    EXPECT_EQ(run_tool("crop-cloud", "-q " + (dir / name).string() + " --all -o " + out + "/views").exit_code, 0);
    // In name order, as the shell's glob gives them: the first is merge-views' reference.
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(out + "/views")) files.push_back(entry.path().string());
    std::sort(files.begin(), files.end());
    std::string views;
    for (const auto& file : files) views += " " + file;
    EXPECT_EQ(
        run_tool("merge-views", "-q" + views + " -o " + out + "/model.ply --report " + out + "/merge.json").exit_code,
        0);
    EXPECT_EQ(run_tool("find-tooltip", "-q " + out + "/model.ply -o " + out + "/tooltip.json").exit_code, 0);
    return std::pair{read_json(out + "/merge.json"), read_json(out + "/tooltip.json")};
  };
  fs::copy(dir / "s", dir / "missing", fs::copy_options::recursive);
  {  // view 2 without a blob, a disparity or points: no tool is found in it
    const SessionInfo info = read_session((dir / "missing").string());
    const fs::path view = dir / "missing" / info.views[2].dir;
    const cv::Mat zeros(info.camera.height, info.camera.width, CV_8UC1, cv::Scalar(0));
    ASSERT_TRUE(cv::imwrite((view / "blob.png").string(), zeros));
    ASSERT_TRUE(cv::imwrite((view / "disparity.png").string(), zeros));
    fs::remove(view / "points.pcd");
  }
  const auto [merge, tooltip] = tooltip_of("missing");
  EXPECT_EQ(merge["views"].size(), 4u);
  EXPECT_EQ(merge["recorded_views"], 5);
  const auto accepted = std::count_if(merge["views"].begin(), merge["views"].end(),
                                      [](const Json& v) { return v["accepted"].get<bool>(); });
  EXPECT_EQ(merge["unmerged_views"], 5 - accepted);
  EXPECT_EQ(read_cloud((dir / "missing_out/views/view_000.ply").string()).recorded_views, 5);
  EXPECT_EQ(read_cloud((dir / "missing_out/model.ply").string()).unmerged_views, merge["unmerged_views"].get<int>());
  EXPECT_FALSE(tooltip["confidence"]["confident"].get<bool>());
  EXPECT_NE(tooltip["confidence"]["doubts"].dump().find(why), std::string::npos) << tooltip["confidence"].dump();
  // The whole session: every view recorded is in the model, and nothing of this doubt is said.
  const auto [whole_merge, whole_tooltip] = tooltip_of("s");
  EXPECT_EQ(whole_merge["recorded_views"], 5);
  EXPECT_EQ(whole_merge["views"].size(), 5u);
  ASSERT_EQ(whole_merge["unmerged_views"], 0);
  EXPECT_EQ(whole_tooltip["confidence"]["doubts"].dump().find(why), std::string::npos);
}

TEST(SessionPipeline, MakefileRunsEveryStepOnEverySession) {
  const auto dir = scratch_dir("pipeline-make");
  for (const std::string family : {"hoe", "stick"})
    ASSERT_EQ(
        run_tool("simulate-session", "-q --family " + family + " --seed 3 -o " + (dir / "sessions" / family).string())
            .exit_code,
        0);
  const std::string command = "make -s -f " + std::string(toolinc::testing::kSourceDir) +
                              "/scripts/pipeline.mk SESSIONS=" + (dir / "sessions").string() +
                              " OUT=" + (dir / "out").string() + " BIN=" + toolinc::testing::kBinDir + " -j2 >" +
                              (dir / "make.log").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << slurp(dir / "make.log");
  for (const std::string family : {"hoe", "stick"})
    for (const std::string file : {"views/view_000.ply", "model.ply", "merge_report.json", "frame.json", "tooltip.json",
                                   "evaluation.json", "model.png", "sheet.png", "report.html"}) {
      EXPECT_TRUE(fs::exists(dir / "out" / family / file)) << family << "/" << file;
    }
  const Json evaluation = read_json((dir / "out/hoe/evaluation.json").string());
  EXPECT_LT(evaluation["tooltip"]["error_m"].get<double>(), 0.02);
}
