// merge-views on synthetic partial views with kinematic error, against the true model (issue: sessions
// end to end). Views: the generated tool held with a random grasp, the points facing each of 5 viewing
// directions, the hand removed, sigma 1.5 mm noise, and each view's hand pose off by N(0, 3 mm) per
// axis and N(0, 1.5 deg) as the robot's kinematics are.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "support/synthetic_cases.hpp"
#include "toolinc/ann/nearest_distance.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/registration/merge_views.hpp"

using namespace toolinc;
using toolinc::testing::make_held_tool;

namespace {

Eigen::Matrix4d perturbation(Rng& rng, double translation_sigma, double rotation_sigma_deg) {
  Eigen::Matrix4d e = Eigen::Matrix4d::Identity();
  const Vec3 axis = Vec3(rng.gaussian(), rng.gaussian(), rng.gaussian()).normalized();
  e.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(rng.gaussian() * rotation_sigma_deg * M_PI / 180, axis).toRotationMatrix();
  e.topRightCorner<3, 1>() = translation_sigma * Vec3(rng.gaussian(), rng.gaussian(), rng.gaussian());
  return e;
}

Eigen::Matrix4d rigid(double angle_deg, const Vec3& axis, const Vec3& translation) {
  Eigen::Matrix4d e = Eigen::Matrix4d::Identity();
  e.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle_deg * M_PI / 180, axis.normalized()).toRotationMatrix();
  e.topRightCorner<3, 1>() = translation;
  return e;
}

// The view as recorded: points facing `towards` (a direction in the hand frame), expressed in a hand
// frame that is off by `recorded_error` (hand_true_from_hand_recorded).
PointCloud partial_view(const PointCloud& model, const Eigen::Matrix4d& grasp, const Vec3& towards,
                        const Eigen::Matrix4d& recorded_error, Rng& rng) {
  const Eigen::Matrix3d r = grasp.topLeftCorner<3, 3>();
  Points facing;
  for (std::size_t i = 0; i < model.size(); ++i)
    if ((r * model.normals[i]).dot(towards) > 0.2) facing.push_back(model.points[i]);
  const Points in_hand = observe_in_hand(facing, grasp, 0.06, 0.0015, rng);
  PointCloud view;
  view.points = transform_points(in_hand, recorded_error.inverse());
  return view;
}

int accepted_views(const MergeResult& merged) {
  return static_cast<int>(
      std::count_if(merged.views.begin(), merged.views.end(), [](const ViewMerge& v) { return v.accepted; }));
}

const std::vector<Vec3> kViewDirections = {Vec3(1, 0, 0.3), Vec3(0.6, 0.3, 0.8), Vec3(0.6, -0.3, -0.8),
                                           Vec3(0.2, 0.5, 1.0), Vec3(0.9, 0.2, -0.5)};

}  // namespace

TEST(MergeViewsAccuracy, EveryFamilyWithKinematicError) {
  std::vector<double> chamfers;
  for (ToolFamily family : all_families()) {
    for (int g = 0; g < 10; ++g) {
      const auto held = make_held_tool(family, 500u + g);
      Rng rng(900u + g);
      std::vector<PointCloud> views;
      for (const auto& direction : kViewDirections)
        views.push_back(
            partial_view(held.model, held.grasp, direction.normalized(), perturbation(rng, 0.003, 1.5), rng));
      const MergeResult merged = merge_views(views);
      for (const auto& v : merged.views) EXPECT_TRUE(v.accepted) << to_string(family) << " " << g << ": " << v.reason;
      Rng clean(1);
      const Points truth = observe_in_hand(held.model.points, held.grasp, 0.06, 0.0, clean);
      chamfers.push_back(median_chamfer_distance(merged.model.points, voxel_downsample(truth, 0.002)));
      EXPECT_LT(chamfers.back(), 0.004) << to_string(family) << " grasp " << g;
    }
  }
  std::sort(chamfers.begin(), chamfers.end());
  std::printf("median symmetric Chamfer over %zu merges: median %.2f mm, worst %.2f mm\n", chamfers.size(),
              1000 * chamfers[chamfers.size() / 2], 1000 * chamfers.back());
  EXPECT_LT(chamfers[chamfers.size() / 2], 0.003);
}

// The original's merge leaves each view where its recorded pose put it and keeps every one, kinematic error
// and all (merge-views registers it away): the views above, 8 mm and 4 degrees off. Its model is their
// union on the 2 mm grid, less the stray points.
TEST(MergeViews, TheOriginalMergeKeepsTheRecordedPoses) {
  for (int g = 0; g < 6; ++g) {
    const auto held = make_held_tool(g % 2 ? ToolFamily::hook : ToolFamily::shovel, 60u + g);
    Rng rng(80u + g);
    std::vector<PointCloud> views;
    Points recorded;
    for (const auto& direction : kViewDirections) {
      views.push_back(partial_view(held.model, held.grasp, direction.normalized(), perturbation(rng, 0.008, 4.0), rng));
      recorded.insert(recorded.end(), views.back().points.begin(), views.back().points.end());
    }
    const MergeConfig config = original_merge();
    const MergeResult original = merge_views(views, config);
    for (const auto& v : original.views) {
      EXPECT_TRUE(v.accepted) << "grasp " << g << ": " << v.reason;
      EXPECT_TRUE(v.correction.isIdentity()) << "grasp " << g;
    }
    const Points expected = remove_isolated(voxel_downsample(recorded, config.voxel_size), config.clean_radius,
                                            static_cast<std::size_t>(config.clean_min_neighbors));
    ASSERT_EQ(original.model.points.size(), expected.size()) << "grasp " << g;
    const std::vector<double> d = nearest_distances(original.model.points, expected);
    EXPECT_LT(*std::max_element(d.begin(), d.end()), 1e-6) << "grasp " << g;
  }
}

namespace {

// Grasp g's five views, the third with a gross error: moved 15 cm (every third grasp) or turned 60 degrees.
std::vector<PointCloud> views_with_a_gross_error(int g) {
  const auto held = make_held_tool(g % 2 ? ToolFamily::hoe : ToolFamily::rake, 40u + g);
  Rng rng(70u + g);
  std::vector<PointCloud> views;
  for (std::size_t k = 0; k < kViewDirections.size(); ++k) {
    Eigen::Matrix4d error = perturbation(rng, 0.003, 1.5);
    if (k == 2) error = error * rigid(0, Vec3::UnitX(), Vec3(0.15, 0, 0) * (g % 3 == 0 ? 1 : 0) + Vec3(0, 0, 0));
    if (k == 2 && g % 3 != 0) error = error * rigid(60, Vec3(g, 1, 2), Vec3::Zero());
    views.push_back(partial_view(held.model, held.grasp, kViewDirections[k].normalized(), error, rng));
  }
  return views;
}

}  // namespace

TEST(MergeViews, GrossErrorsAreRejectedAndTheRestMerged) {
  for (int g = 0; g < 6; ++g) {
    const MergeResult merged = merge_views(views_with_a_gross_error(g));
    for (std::size_t k = 0; k < merged.views.size(); ++k)
      EXPECT_EQ(merged.views[k].accepted, k != 2) << "grasp " << g << " view " << k << ": " << merged.views[k].reason;
    EXPECT_EQ(merged.model.unmerged_views, 1) << "grasp " << g;
  }
}

// The reference need not see the most: when the blob of every view but one stops short of the head (at a
// depth edge along the handle), the view that sees the head lands mostly off their model. With
// revisit_views it is merged, with the reference changed to it, and the model reaches the head; without, it
// is rejected. The short views are bare handle stubs, which ICP may turn about themselves when the far view
// is the reference, and then the head can still be lost: the far view was merged in 12 of the 12 grasps
// built with GCC 12 and in 9 with Clang 14 (lost in 11 and 12 of them without revisiting).
TEST(MergeViews, RevisitedViewsMergeOneSeeingFartherThanTheReference) {
  MergeConfig config;
  config.revisit_views = true;
  const int grasps = 12;
  int unfit_alone = 0, lost_without = 0, head_merged = 0;
  for (int g = 0; g < grasps; ++g) {
    const auto held = make_held_tool(g % 2 ? ToolFamily::hook : ToolFamily::rake, 60u + g);
    Rng rng(90u + g);
    double reach = 0;
    for (const Vec3& p : held.observed) reach = std::max(reach, p.norm());
    std::vector<PointCloud> views;
    Points short_union;
    for (std::size_t k = 0; k < kViewDirections.size(); ++k) {
      PointCloud view =
          partial_view(held.model, held.grasp, kViewDirections[k].normalized(), perturbation(rng, 0.003, 1.5), rng);
      if (k != 1) {
        Points kept;
        for (const Vec3& p : view.points)
          if (p.norm() < 0.5 * reach) kept.push_back(p);
        view.points = kept;
        short_union.insert(short_union.end(), kept.begin(), kept.end());
      }
      views.push_back(view);
    }
    // What makes the case: the far-seeing view fails the inlier test against the others' model (23-38 %
    // of it lands there, against the 40 % asked).
    const IcpTarget short_model(voxel_downsample(short_union, config.voxel_size));
    const IcpResult alone = align_point_to_plane(voxel_downsample(views[1].points, config.registration_voxel),
                                                 short_model, Eigen::Matrix4d::Identity(), config.icp);
    const bool case_made = alone.inlier_ratio < config.min_inlier_ratio;
    unfit_alone += case_made;

    const MergeResult merged = merge_views(views, config);
    double model_reach = 0;
    for (const Vec3& p : merged.model.points) model_reach = std::max(model_reach, p.norm());
    const bool head = merged.views[1].accepted && model_reach > 0.95 * reach;
    head_merged += head;
    if (head) EXPECT_GE(accepted_views(merged), 4) << "grasp " << g;
    if (case_made) {
      if (head) EXPECT_EQ(merged.views[1].reason, "reference") << "grasp " << g;
      lost_without += !merge_views(views).views[1].accepted;
    }
  }
  std::printf("far view and head merged in %d of %d grasps\n", head_merged, grasps);
  EXPECT_GE(head_merged, grasps - 4);
  EXPECT_GE(unfit_alone, grasps - 2);
  // Without, the far view is lost unless it is the first that more than half the views fail to fit.
  std::printf("far view lost without revisiting in %d of %d grasps\n", lost_without, grasps);
  EXPECT_GE(lost_without, grasps / 2);
}

TEST(MergeViews, TooFewPoints) {
  PointCloud few, whole;
  few.points.assign(200, Vec3(0.1, -0.1, 0));
  EXPECT_THROW(merge_views({few}), MethodError);
  whole.points = make_held_tool(ToolFamily::hoe, 1).observed;
  const MergeResult merged = merge_views({whole, few});
  EXPECT_FALSE(merged.views[1].accepted);
  EXPECT_NE(merged.views[1].reason.find("too few"), std::string::npos);
}

// Smear by what the other view saw: a plate seen by two cameras, and points that only the first view has,
// floating 5 cm above the plate on its ray. The second camera sees the plate through them: dropped. The
// same points seen by both views are a real part (a thin one the first resolves): kept. Without
// viewpoints there is nothing to test against: kept.
TEST(MergeViews, PointsAnotherViewSawThroughAreSmear) {
  Points plate;
  for (int i = -25; i <= 25; ++i)
    for (int j = -25; j <= 25; ++j) plate.emplace_back(0.002 * i, 0.002 * j, 0.0);
  Points floating;
  for (int k = 0; k < 5; ++k) floating.emplace_back(0.0, 0.0, 0.04 + 0.005 * k);
  const Vec3 first_camera(0.0, 0.0, 0.4), second_camera(0.2, 0.0, 0.4);
  const auto view = [&](const Points& extra, const Vec3& camera) {
    PointCloud cloud;
    cloud.points = plate;
    cloud.points.insert(cloud.points.end(), extra.begin(), extra.end());
    cloud.viewpoints = {camera};
    return cloud;
  };
  const auto merged_points = [](const std::vector<PointCloud>& views) {
    MergeConfig config;
    config.clean_min_neighbors = 0;  // the floating points are few: only the smear rule may drop them
    const MergeResult merged = merge_views(views, config);
    EXPECT_TRUE(merged.views[0].accepted && merged.views[1].accepted);
    return std::make_pair(merged.model.points, merged.views[0].smear_dropped);
  };
  const auto above_plate = [](const Points& points) {
    return std::count_if(points.begin(), points.end(), [](const Vec3& p) { return p.z() > 0.03; });
  };

  const auto [smeared, dropped] = merged_points({view(floating, first_camera), view({}, second_camera)});
  EXPECT_EQ(above_plate(smeared), 0);
  EXPECT_EQ(dropped, 5);

  const auto [seen_by_both, none_dropped] =
      merged_points({view(floating, first_camera), view(floating, second_camera)});
  EXPECT_EQ(above_plate(seen_by_both), 5);
  EXPECT_EQ(none_dropped, 0);

  PointCloud first = view(floating, first_camera), second = view({}, second_camera);
  first.viewpoints.clear();
  second.viewpoints.clear();
  EXPECT_EQ(above_plate(merged_points({first, second}).first), 5);
}

// Which views saw each point of the model: every point carries the bit of at least one accepted view and
// none of the rejected one's; every accepted view's bit is somewhere; and a PLY round trip, binary and
// ASCII, gives the labels back.
TEST(MergeViews, ViewLabelsSurviveTheMergeAndAPlyRoundTrip) {
  const auto held = make_held_tool(ToolFamily::hoe, 41);
  Rng rng(71);
  std::vector<PointCloud> views;
  for (std::size_t k = 0; k < kViewDirections.size(); ++k) {
    Eigen::Matrix4d error = perturbation(rng, 0.003, 1.5);
    if (k == 2) error = error * rigid(60, Vec3(1, 1, 2), Vec3::Zero());  // a gross error: rejected
    views.push_back(partial_view(held.model, held.grasp, kViewDirections[k].normalized(), error, rng));
  }
  const MergeResult merged = merge_views(views);
  ASSERT_FALSE(merged.views[2].accepted);
  ASSERT_EQ(merged.model.views.size(), merged.model.size());
  std::uint32_t seen = 0;
  for (const auto v : merged.model.views) {
    EXPECT_NE(v, 0u);
    seen |= v;
  }
  EXPECT_EQ(seen, 0b11011u);
  const auto dir = std::filesystem::temp_directory_path() / ("toolinc_view_labels_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const bool ascii : {false, true}) {
    const std::string path = (dir / (ascii ? "model_ascii.ply" : "model.ply")).string();
    write_ply(path, merged.model, {ascii, "test"});
    const PointCloud back = read_cloud(path);
    EXPECT_EQ(back.views, merged.model.views) << path;
    EXPECT_EQ(back.size(), merged.model.size()) << path;
    EXPECT_EQ(back.recorded_views, 5) << path;
    EXPECT_EQ(back.unmerged_views, 1) << path;
  }
  std::filesystem::remove_all(dir);
}

// A view left out of the model may have been the only one to see the head: whatever the frame and the
// tooltip score, the tooltip on that model is doubtful, and says why. The same points as one whole model
// carry no such doubt.
TEST(MergeViews, ATooltipOnAModelAViewWasLeftOutOfIsDoubtful) {
  const std::string why = "of the session's views are missing from the cloud";
  for (int g = 0; g < 6; ++g) {
    PointCloud model = merge_views(views_with_a_gross_error(g)).model;
    ASSERT_EQ(model.unmerged_views, 1) << "grasp " << g;
    const auto [frame, left_out] = estimate_frame_and_tooltip(model, {}, {});
    EXPECT_FALSE(left_out.confidence.confident) << "grasp " << g;
    const auto& doubts = left_out.confidence.doubts;
    EXPECT_TRUE(std::any_of(doubts.begin(), doubts.end(), [&](const auto& d) { return d.find(why) != d.npos; }))
        << "grasp " << g;
    const Tooltip given_frame = find_tooltip(model, frame, {});
    EXPECT_FALSE(given_frame.confidence.confident) << "grasp " << g;
    EXPECT_EQ(given_frame.position, left_out.position) << "grasp " << g;
    model.unmerged_views = 0;
    const Tooltip whole = find_tooltip(model, frame, {});
    EXPECT_EQ(whole.position, left_out.position) << "grasp " << g;
    for (const auto& d : whole.confidence.doubts) EXPECT_EQ(d.find(why), d.npos) << "grasp " << g << ": " << d;
  }
}
