// The session simulator: determinism, the scene's geometry (the tool in view near the fixation, valid
// disparities, points on the true surface within the stereo noise, the 8-bit disparity consistent with
// points.pcd), the recorded pose errors, and the simulate-session executable.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "support/run_tool.hpp"
#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/results/results_json.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/ground_truth_file.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc {
namespace {

namespace fs = std::filesystem;
using testing::run_tool;
using testing::scratch_dir;
using testing::slurp;

// Ideal stereo unless a test asks for a matcher: the renderer's geometry, exactly.
SessionSimulatorConfig config_for(std::uint32_t seed, ToolFamily family = ToolFamily::hoe) {
  SessionSimulatorConfig config;
  config.stereo = StereoModel::ideal;
  config.shape = default_shape(family);
  config.seed = seed;
  Rng rng(seed);
  config.hand_from_canonical = random_grasp({}, rng);
  return config;
}

Vec3 translation(const Eigen::Matrix4d& m) { return m.topRightCorner<3, 1>(); }
Eigen::Matrix3d rotation(const Eigen::Matrix4d& m) { return m.topLeftCorner<3, 3>(); }

// Every file of a folder, by relative path.
std::map<std::string, std::string> files_of(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file()) files[fs::relative(entry.path(), dir).string()] = slurp(entry.path());
  return files;
}

fs::path simulate_to(const std::string& name, const SessionSimulatorConfig& config) {
  const fs::path dir = scratch_dir(name) / "session";
  const SimulatedSession s = simulate_session(config);
  write_session(dir.string(), s.info, s.views, s.ground_truth);
  return dir;
}

TEST(Simulator, SameSeedSameBytesOtherSeedDiffers) {
  SessionSimulatorConfig config = config_for(11);
  config.poses.resize(2);
  const auto a = files_of(simulate_to("det-a", config)), b = files_of(simulate_to("det-b", config));
  ASSERT_EQ(a.size(), 2u * 5u + 2u);  // per view: view.json, left, disparity, blob, points
  EXPECT_TRUE(a == b);
  config.seed = 12;
  const auto c = files_of(simulate_to("det-c", config));
  EXPECT_NE(a.at("views/000/left.png"), c.at("views/000/left.png"));
  EXPECT_NE(a.at("views/001/points.pcd"), c.at("views/001/points.pcd"));
}

// One simulated session, checked against the geometry it was made from.
class SimulatorGeometry : public ::testing::TestWithParam<std::string> {};

TEST_P(SimulatorGeometry, ToolInViewOnTheTrueSurfaceWithinStereoNoise) {
  SessionSimulatorConfig config = config_for(5, ToolFamily::rake);
  config.hand = GetParam();
  const SimulatedSession s = simulate_session(config);
  const CameraModel& camera = s.info.camera;
  ASSERT_EQ(s.views.size(), 5u);
  // An independent, denser sampling of the true surface, in the hand frame.
  ToolShape shape = config.shape;
  shape.spacing = 0.0005;
  Points surface;
  for (const Vec3& p : generate_tool(shape, 99).points) surface.push_back(apply(config.hand_from_canonical, p));
  const KdTree tree(surface);
  const double fb = camera.fx * camera.baseline;

  for (std::size_t v = 0; v < s.views.size(); ++v) {
    SCOPED_TRACE("view " + std::to_string(v));
    const ViewData& view = s.views[v];
    const ViewRecord& record = s.info.views[v];
    // The blob (tool and hand) is in view around the fixation point, as the original's gaze keeps it.
    ASSERT_TRUE(record.blob.has_value());
    EXPECT_GT(record.blob->area, 3000);
    EXPECT_LT(record.blob->area, 0.5 * camera.width * camera.height);
    EXPECT_NEAR(record.blob->cx, camera.cx, 0.2 * camera.width);
    EXPECT_NEAR(record.blob->cy, camera.cy, 0.2 * camera.height);
    EXPECT_EQ(cv::countNonZero(view.blob), static_cast<int>(record.blob->area));

    const Eigen::Matrix4d hand_from_root = inverse(s.true_root_from_hand[v]);
    const Eigen::Matrix4d camera_from_root = inverse(record.root_from_camera);
    std::size_t tool_points = 0, near_surface = 0;
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        const int value = view.disparity.at<uchar>(y, x);
        const Vec3& p = view.points[static_cast<std::size_t>(y) * camera.width + x];
        ASSERT_EQ(value == 0, std::isnan(p.x()));
        if (value == 0) continue;
        // The 8-bit disparity reprojects to points.pcd within its quantisation (half a step in disparity).
        const double z = apply(camera_from_root, p).z();
        const double d = camera.disparity_px(value);
        const Vec3 ray((x - camera.cx) / camera.fx, (y - camera.cy) / camera.fy, 1.0);
        const double dz = z * z / fb * (0.5 * camera.num_disparities / 255.0) * 1.05;
        ASSERT_LE((apply(record.root_from_camera, fb / d * ray) - p).norm(), dz * ray.norm() + 1e-5);
        if (view.blob.at<uchar>(y, x) == 0) continue;
        // Tool points (beyond the hand) lie on the true surface, within 3 sigma of the stereo depth noise
        // plus a splat pixel and the reference sampling.
        const Vec3 q = apply(hand_from_root, p);
        if (q.norm() < 0.12) continue;
        ++tool_points;
        const double sigma = z * z * config.disparity_noise_px / fb;
        const double tolerance = 3.0 * sigma + z / camera.fx + 0.0005;
        near_surface += std::sqrt(tree.nearest(q).distance2) <= tolerance;
      }
    EXPECT_GT(tool_points, 500u);
    EXPECT_GE(near_surface, 0.99 * tool_points);
  }
}

INSTANTIATE_TEST_SUITE_P(Simulator, SimulatorGeometry, ::testing::Values("right", "left"));

TEST(Simulator, IdealStereoIgnoresTheSgbmScene) {
  // The sgbm scene's knobs (texture, light) do not touch an ideal session: the ideal model stays as it was.
  SessionSimulatorConfig config = config_for(7);
  config.poses.resize(2);
  const auto plain = files_of(simulate_to("ideal-plain", config));
  config.tool_texture = config.table_texture = 0.9;
  config.light_direction = Vec3(1, 0, 0);
  config.renderer_blob = true;
  EXPECT_TRUE(plain == files_of(simulate_to("ideal-knobs", config)));
}

TEST(Simulator, SgbmSessionIsDeterministicAndRobotLike) {
  SessionSimulatorConfig config = config_for(5, ToolFamily::rake);
  config.stereo = StereoModel::sgbm;
  config.poses.resize(3);
  const auto a = files_of(simulate_to("sgbm-a", config)), b = files_of(simulate_to("sgbm-b", config));
  EXPECT_TRUE(a == b);

  const SimulatedSession s = simulate_session(config);
  SessionSimulatorConfig renderer = config;
  renderer.renderer_blob = true;
  const SimulatedSession r = simulate_session(renderer);
  const CameraModel& camera = s.info.camera;
  ToolShape shape = config.shape;
  shape.spacing = 0.0005;
  Points surface;
  for (const Vec3& p : generate_tool(shape, 99).points) surface.push_back(apply(config.hand_from_canonical, p));
  const KdTree tree(surface);
  for (std::size_t v = 0; v < s.views.size(); ++v) {
    SCOPED_TRACE("view " + std::to_string(v));
    const ViewData& view = s.views[v];
    // Same images, disparity and points with either blob.
    EXPECT_EQ(cv::norm(view.disparity, r.views[v].disparity, cv::NORM_INF), 0.0);
    // The closest blob of the disparity lies on the hand and tool but for the fattened edges (it may be
    // only the nearest part of them, as dispBlobber's: where the tool's head is nearer than the hand and
    // its disparity steps, as in view 2 here).
    ASSERT_TRUE(s.info.views[v].blob.has_value());
    const cv::Mat& mask = r.views[v].blob;
    const double overlap = cv::countNonZero(view.blob & mask), blob = cv::countNonZero(view.blob);
    EXPECT_GT(overlap / blob, 0.7);
    // Tool points (beyond the hand): matched on most of the tool, near its surface in the median, but
    // with the robot's tail of smeared and wrong matches (the real reconstructions: a third beyond 5 mm).
    const Eigen::Matrix4d hand_from_root = inverse(s.true_root_from_hand[v]);
    int tool_pixels = 0, matched = 0;
    std::vector<double> distances;
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        if (!mask.at<uchar>(y, x)) continue;
        const Vec3& p = view.points[static_cast<std::size_t>(y) * camera.width + x];
        ++tool_pixels;
        if (std::isnan(p.x())) continue;
        ++matched;
        const Vec3 q = apply(hand_from_root, p);
        if (q.norm() >= 0.12) distances.push_back(std::sqrt(tree.nearest(q).distance2));
      }
    std::sort(distances.begin(), distances.end());
    const double median = distances[distances.size() / 2], p90 = distances[distances.size() * 9 / 10];
    std::printf("view %zu: %d of %d hand-and-tool pixels matched; tool points %zu, median %.1f mm, p90 %.1f mm\n", v,
                matched, tool_pixels, distances.size(), 1000 * median, 1000 * p90);
    EXPECT_GT(matched, 0.6 * tool_pixels);
    EXPECT_LT(matched, tool_pixels);  // holes and occlusions
    EXPECT_GT(distances.size(), 300u);
    EXPECT_LT(median, 0.006);
    EXPECT_GT(p90, 0.003);  // not the ideal model's clean surface
  }
}

TEST(Simulator, TurnHandPosesAndGaze) {
  const Eigen::Matrix4d base = exploration_hand_pose("right", {0, 0});
  EXPECT_TRUE(is_rigid(base));
  EXPECT_TRUE((rotation(base) * Vec3(0, -1, 0)).isApprox(Vec3(0, 0, 1)));  // the tool points up
  EXPECT_TRUE(translation(base).isApprox(Vec3(-0.25, 0.15, 0.10)));
  const Eigen::Matrix4d left = exploration_hand_pose("left", {-40, -20});
  EXPECT_TRUE(is_rigid(left));
  EXPECT_TRUE(translation(left).isApprox(Vec3(-0.25, -0.15, 0.10)));
  EXPECT_TRUE(rotation(left).isApprox(rotation(exploration_hand_pose("right", {40, 20}))));

  const Vec3 eye(-0.05, -0.034, 0.40), target(-0.4, 0.15, 0.2);
  const Eigen::Matrix4d camera = camera_looking_at(eye, target);
  EXPECT_TRUE(is_rigid(camera));
  const Vec3 seen = apply(inverse(camera), target);
  EXPECT_NEAR(seen.x(), 0.0, 1e-12);
  EXPECT_NEAR(seen.y(), 0.0, 1e-12);
  EXPECT_GT(seen.z(), 0.0);
  EXPECT_GT(apply(inverse(camera), target + Vec3(0, 0, 0.1)).y(), -1.0);
  EXPECT_LT(apply(inverse(camera), target + Vec3(0, 0, 0.1)).y(), 0.0);  // up in the world is up in the image
}

TEST(Simulator, RecordedPosesCarryTheConfiguredErrors) {
  SessionSimulatorConfig config = config_for(3);
  config.poses.resize(3);
  config.kinematic_error_m = 0.0;
  config.kinematic_error_deg = 0.0;
  config.gross_errors = {{1, 0.05, 20.0}};
  config.write_points = false;
  config.write_blob = false;
  const SimulatedSession exact = simulate_session(config);
  for (std::size_t v = 0; v < 3; ++v) {
    const Eigen::Matrix4d error = inverse(exact.true_root_from_hand[v]) * exact.info.views[v].root_from_hand;
    EXPECT_NEAR(translation(error).norm(), v == 1 ? 0.05 : 0.0, 1e-9);
    EXPECT_NEAR(rotation_angle_deg(rotation(error)), v == 1 ? 20.0 : 0.0, 1e-6);
    EXPECT_TRUE(exact.views[v].points.empty());
    EXPECT_TRUE(exact.views[v].blob.empty());
    EXPECT_FALSE(exact.info.views[v].blob.has_value());
  }
  config.kinematic_error_m = 0.003;
  config.kinematic_error_deg = 1.5;
  config.gross_errors.clear();
  const SimulatedSession noisy = simulate_session(config);
  for (std::size_t v = 0; v < 3; ++v) {
    const Eigen::Matrix4d error = inverse(noisy.true_root_from_hand[v]) * noisy.info.views[v].root_from_hand;
    EXPECT_TRUE(is_rigid(noisy.info.views[v].root_from_hand));
    EXPECT_GT(translation(error).norm(), 1e-5);
    EXPECT_LT(translation(error).norm(), 0.02);
    EXPECT_LT(rotation_angle_deg(rotation(error)), 8.0);
  }
  config.gross_errors = {{3, 0.05, 0.0}};
  EXPECT_THROW(simulate_session(config), std::invalid_argument);
}

TEST(Simulator, ExecutableWritesAReadableSessionWithGroundTruth) {
  const fs::path dir = scratch_dir("app");
  const auto ok = run_tool("simulate-session", "-q -o " + (dir / "s").string() +
                                                   " --family hook --seed 4 --label hook --gross-error 2:0.03:10");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const SessionInfo info = read_session((dir / "s").string());
  EXPECT_EQ(info.tool_label, std::optional<std::string>("hook"));
  EXPECT_EQ(info.views.size(), 5u);
  EXPECT_EQ(info.created, "2026-01-01T00:00:00Z");
  const ToolGroundTruth truth = read_ground_truth((dir / "s/ground_truth.json").string());
  Rng rng(4);
  EXPECT_TRUE(truth.hand_from_canonical.isApprox(random_grasp(exploration_grasp_range(), rng)));
  const ViewData view = read_view((dir / "s").string(), info, 2);
  EXPECT_EQ(view.points.size(), 320u * 240u);

  // A model file instead of a family, canonical grasp, no optional files.
  ToolShape shape = default_shape(ToolFamily::l_stick);
  shape.spacing = 0.002;
  write_ply((dir / "model.ply").string(), generate_tool(shape, 1));
  const auto model =
      run_tool("simulate-session", "-q -o " + (dir / "m").string() + " --model " + (dir / "model.ply").string() +
                                       " --grasp canonical --hand left --no-points --no-blob");
  ASSERT_EQ(model.exit_code, 0) << model.err;
  EXPECT_FALSE(fs::exists(dir / "m/views/000/points.pcd"));
  EXPECT_FALSE(fs::exists(dir / "m/views/000/blob.png"));
  EXPECT_NE(slurp(dir / "m/ground_truth.json").find("\"family\": \"model\""), std::string::npos);
  EXPECT_TRUE(read_ground_truth((dir / "m/ground_truth.json").string()).hand_from_canonical.isIdentity());

  const auto again = run_tool("simulate-session", "-q -o " + (dir / "s").string());
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("not empty"), std::string::npos) << again.err;
  const auto bad = run_tool("simulate-session", "-q -o " + (dir / "b").string() + " --gross-error 2:x");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("VIEW:TRANS_M:ROT_DEG"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "b"));
}

}  // namespace
}  // namespace toolinc
