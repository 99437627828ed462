// The recorder without a robot: its core driven by the simulated backend, by fakes that time
// out, never answer or are interrupted, and the `record` executable with --backend sim, including a real
// Ctrl-C. The waits all run on simulated time (except the SIGINT test, which must let a process run).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spdlog/fmt/fmt.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/record/recorder.hpp"
#include "toolinc/record/sfm.hpp"
#include "toolinc/record/sim_backend.hpp"
#include "toolinc/record/static_motion.hpp"
#include "toolinc/synth/grasp.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

namespace {

SimBackendConfig sim_config(std::uint32_t seed = 4) {
  SimBackendConfig config;
  config.scene.seed = seed;
  config.scene.stereo = StereoModel::ideal;  // the recorder's mechanics, not the matcher
  config.scene.hand_from_canonical = exploration_grasp(seed);
  return config;
}

// The simulated robot with its clock, and the Robot the recorder gets; parts can be swapped for fakes.
struct SimRig {
  SimulatedClock clock;
  SimRobot sim;
  Robot robot;
  explicit SimRig(const SimBackendConfig& config = sim_config())
      : sim(config, clock), robot{sim.arm(), &sim.other_arm(), sim.gaze(), sim.sources(), clock} {}
};

// An arm that passes everything on but, from its `from`-th move on, never finishes moving; counts stops.
class StuckArm : public Arm {
 public:
  StuckArm(Arm& arm, int from) : arm_(arm), from_(from) {}
  void go_to(const Eigen::Matrix4d& pose) override { ++moves_, arm_.go_to(pose); }
  bool motion_done() override { return moves_ < from_ && arm_.motion_done(); }
  Eigen::Matrix4d pose() override { return arm_.pose(); }
  void stop() override { ++stops, arm_.stop(); }
  std::string name() const override { return "stuck-arm"; }
  int stops = 0;

 private:
  Arm& arm_;
  int from_, moves_ = 0;
};

// An arm that sets the stop flag (as the SIGINT handler does) when sent on its `at`-th move.
class InterruptingArm : public Arm {
 public:
  InterruptingArm(Arm& arm, int at, std::atomic<bool>& stop) : arm_(arm), at_(at), stop_(stop) {}
  void go_to(const Eigen::Matrix4d& pose) override {
    if (++moves_ == at_) stop_ = true;
    arm_.go_to(pose);
  }
  bool motion_done() override { return arm_.motion_done(); }
  Eigen::Matrix4d pose() override { return arm_.pose(); }
  void stop() override { ++stops, arm_.stop(); }
  std::string name() const override { return arm_.name(); }
  int stops = 0;

 private:
  Arm& arm_;
  int at_, moves_ = 0;
  std::atomic<bool>& stop_;
};

// Every view of the session can be read back as the offline tools read it.
void expect_readable(const fs::path& dir, std::size_t views) {
  const SessionInfo session = read_session(dir.string());
  ASSERT_EQ(session.views.size(), views);
  for (std::size_t v = 0; v < views; ++v) {
    const ViewData data = read_view(dir.string(), session, v);
    EXPECT_FALSE(data.blob.empty()) << v;
    EXPECT_FALSE(data.points.empty()) << v;
  }
}

std::size_t views_listed(const fs::path& session_json) {
  try {
    return read_json(session_json.string())["views"].size();
  } catch (const std::exception&) {
    return 0;  // not written yet
  }
}

}  // namespace

TEST(RecordSfm, BoxIsClampedToTheImage) {
  const SfmRect inside = clamp_rect({10, 20, 29, 49}, 320, 240);
  EXPECT_EQ(inside.tlx, 10);
  EXPECT_EQ(inside.tly, 20);
  EXPECT_EQ(inside.w, 20);
  EXPECT_EQ(inside.h, 30);
  const SfmRect clipped = clamp_rect({-15, -3, 330, 250}, 320, 240, 2);
  EXPECT_EQ(clipped.tlx, 0);
  EXPECT_EQ(clipped.tly, 0);
  EXPECT_EQ(clipped.w, 320);
  EXPECT_EQ(clipped.h, 240);
  EXPECT_EQ(clipped.step, 2);
  const SfmRect outside = clamp_rect({400, 10, 450, 20}, 320, 240);
  EXPECT_EQ(outside.w * outside.h, 0);
  EXPECT_TRUE(sfm_rect_pixels(outside).empty());
}

TEST(RecordSfm, ReplyOrderIsColumnsOuterRowsInner) {
  const auto pixels = sfm_rect_pixels({10, 20, 3, 5, 2});  // u 10, 12; v 20, 22, 24
  const std::vector<Eigen::Vector2i> expected = {{10, 20}, {10, 22}, {10, 24}, {12, 20}, {12, 22}, {12, 24}};
  EXPECT_EQ(pixels, expected);

  // The reply lands at its pixels; SFM's (0, 0, 0) and every pixel not asked for are NaN.
  Points reply;
  for (std::size_t i = 0; i < pixels.size(); ++i) reply.push_back(i == 1 ? Vec3::Zero() : Vec3(i + 1.0, 0.5, 0.25));
  const Points organised = organised_points({10, 20, 3, 5, 2}, reply, 320, 240);
  ASSERT_EQ(organised.size(), 320u * 240u);
  EXPECT_EQ(organised[20 * 320 + 10], Vec3(1, 0.5, 0.25));
  EXPECT_EQ(organised[24 * 320 + 12], Vec3(6, 0.5, 0.25));
  EXPECT_EQ(organised[20 * 320 + 12], Vec3(4, 0.5, 0.25));
  EXPECT_TRUE(std::isnan(organised[22 * 320 + 10].x()));  // answered 0 0 0
  EXPECT_TRUE(std::isnan(organised[21 * 320 + 10].x()));  // not asked (step 2)
  std::size_t finite = 0;
  for (const auto& p : organised) finite += p.allFinite();
  EXPECT_EQ(finite, 5u);
  reply.pop_back();
  EXPECT_THROW(organised_points({10, 20, 3, 5, 2}, reply, 320, 240), MethodError);
}

TEST(RecordPlan, PaperPosesAndRefusedOnes) {
  ExplorationConfig config;
  const auto plan = plan_exploration(config, "right");
  ASSERT_EQ(plan.size(), 5u);
  EXPECT_TRUE((plan[0].topRightCorner<3, 1>()).isApprox(Vec3(-0.25, 0.15, 0.10)));
  // The tool (hand -Y) points up at the first pose.
  EXPECT_TRUE((plan[0].topLeftCorner<3, 3>() * -Vec3::UnitY()).isApprox(Vec3::UnitZ()));
  EXPECT_TRUE((plan_exploration(config, "left")[0].topRightCorner<3, 1>()).isApprox(Vec3(-0.25, -0.15, 0.10)));

  config.poses = {{90, 70}, {-90, -70}};
  EXPECT_NO_THROW(plan_exploration(config, "right"));
  for (const Eigen::Vector2d& refused : {Eigen::Vector2d(0, 71), Eigen::Vector2d(-91, 0), Eigen::Vector2d(NAN, 0)}) {
    config.poses = {{0, 0}, refused};
    EXPECT_THROW(plan_exploration(config, "right"), std::invalid_argument) << refused.transpose();
  }
  config.poses.clear();
  EXPECT_THROW(plan_exploration(config, "right"), std::invalid_argument);
  EXPECT_THROW(plan_exploration(ExplorationConfig{}, "middle"), std::invalid_argument);
}

TEST(RecordPlan, RefusedPoseMovesNothingAndWritesNothing) {
  const auto dir = scratch_dir("record-refused");
  SimRig rig;
  RecordConfig config;
  config.exploration.poses = {{0, 0}, {0, 80}};
  const std::atomic<bool> stop{false};
  EXPECT_THROW(record_session((dir / "s").string(), config, rig.robot, stop), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "s"));
  EXPECT_EQ(rig.clock.now(), 0.0);  // nothing waited for, so nothing moved

  const auto run = run_tool("record", "--backend sim --poses 0 0 0 80 -o " + (dir / "t").string());
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("(0, 80) refused"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir / "t"));
}

TEST(RecordGaze, FirstGuessAndBlobTarget) {
  const Eigen::Matrix4d hand = exploration_hand_pose("right", {0, 0});
  // 16 cm along the hand's X (root -x) and 16 cm up the tool (root +z).
  EXPECT_TRUE(first_fixation(hand, GazeConfig{}).isApprox(Vec3(-0.25 - 0.16, 0.15, 0.10 + 0.16)));

  cv::Mat mask = cv::Mat::zeros(240, 320, CV_8UC1);
  EXPECT_FALSE(blob_target(mask, {100, 200}, 0.75));
  cv::rectangle(mask, cv::Rect(90, 40, 30, 170), cv::Scalar(255), cv::FILLED);  // up from the hand at (100, 200)
  const auto target = blob_target(mask, {100, 200}, 0.75);
  ASSERT_TRUE(target);
  // The farthest pixel is the top-right corner (119, 40): 3/4 of the way there.
  EXPECT_TRUE(target->isApprox(Eigen::Vector2d(100 + 0.75 * 19, 200 - 0.75 * 160)));

  // A point seen at a pixel projects back to it.
  const CameraModel camera{320, 240, 257.3, 257.3, 160, 120};
  const Eigen::Matrix4d eye = camera_looking_at({-0.02, -0.034, 0.46}, {-0.3, 0.1, 0.1});
  const auto pixel = project(camera, eye, point_at_pixel(camera, eye, {40, 200}, 0.4));
  ASSERT_TRUE(pixel);
  EXPECT_TRUE(pixel->isApprox(Eigen::Vector2d(40, 200), 1e-9));
}

TEST(RecordCore, FiveViewSessionThroughCropCloudAndMergeViews) {
  const auto dir = scratch_dir("record-five-views");
  SimRig rig;
  RecordConfig config;
  config.tool_label = "hoe";
  const std::atomic<bool> stop{false};
  const RecordResult result = record_session((dir / "session").string(), config, rig.robot, stop);
  EXPECT_EQ(result.views, 5u);
  EXPECT_FALSE(result.stopped);
  expect_readable(dir / "session", 5);
  const SessionInfo session = read_session((dir / "session").string());
  EXPECT_EQ(session.camera.num_disparities, 96);
  EXPECT_EQ(session.tool_label.value_or(""), "hoe");
  for (std::size_t v = 0; v < 5; ++v) {
    EXPECT_EQ(session.views[v].wrist_deg, paper_exploration_poses()[v]);
    // The recorded hand pose is where the arm was sent (the simulated arm has no error).
    EXPECT_TRUE(session.views[v].root_from_hand.isApprox(exploration_hand_pose("right", paper_exploration_poses()[v])));
    EXPECT_TRUE(session.views[v].blob.has_value());
  }
  // The other arm went out of view first (left arm: y mirrored).
  EXPECT_TRUE((rig.sim.other_arm().pose().topRightCorner<3, 1>()).isApprox(Vec3(-0.20, -0.35, 0.15)));

  const auto crop = run_tool("crop-cloud", (dir / "session").string() + " --all -q -o " + (dir / "views").string());
  ASSERT_EQ(crop.exit_code, 0) << crop.err;
  std::string views;
  for (int v = 0; v < 5; ++v) views += " " + (dir / "views" / fmt::format("view_{:03d}.ply", v)).string();
  const auto merge = run_tool(
      "merge-views", views + " -q -o " + (dir / "model.ply").string() + " --report " + (dir / "report.json").string());
  ASSERT_EQ(merge.exit_code, 0) << merge.err;
  const Json report = read_json((dir / "report.json").string());
  int accepted = 0;
  for (const auto& view : report["views"]) accepted += view["accepted"].get<bool>();
  EXPECT_EQ(accepted, 5) << report.dump(2);
}

TEST(RecordCore, ArmTimeoutStopsAndKeepsTheViewsSoFar) {
  const auto dir = scratch_dir("record-arm-timeout");
  SimRig rig;
  StuckArm arm(rig.sim.arm(), 3);  // the third move never ends
  Robot robot{arm, nullptr, rig.sim.gaze(), rig.sim.sources(), rig.clock};
  RecordConfig config;
  config.arm_timeout = 7.0;
  const std::atomic<bool> stop{false};
  try {
    record_session((dir / "s").string(), config, robot, stop);
    FAIL() << "no timeout";
  } catch (const MethodError& e) {
    EXPECT_NE(std::string(e.what()).find("stuck-arm did not finish its motion within 7 s"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(arm.stops, 1);  // the motion is stopped
  expect_readable(dir / "s", 2);
}

TEST(RecordCore, SilentPortIsABoundedWaitThenAClearError) {
  for (const auto stream : {Sources::Stream::disparity, Sources::Stream::points}) {
    const auto dir = scratch_dir("record-silent");
    SimBackendConfig backend = sim_config();
    backend.silent = stream;
    SimRig rig(backend);
    RecordConfig config;
    config.attempts = 2;
    config.read_timeout = 1.5;
    const std::atomic<bool> stop{false};
    try {
      record_session((dir / "s").string(), config, rig.robot, stop);
      FAIL() << "no error";
    } catch (const MethodError& e) {
      const std::string name = rig.sim.sources().name(stream);
      EXPECT_NE(std::string(e.what()).find(name + " within 1.5 s (2 attempts)"), std::string::npos) << e.what();
    }
    expect_readable(dir / "s", 0);
  }
}

TEST(RecordCore, StopFlagLeavesAConsistentSessionWithTheViewsSoFar) {
  const auto dir = scratch_dir("record-stop");
  SimRig rig;
  std::atomic<bool> stop{false};
  InterruptingArm arm(rig.sim.arm(), 3, stop);  // Ctrl-C while moving to the third pose
  Robot robot{arm, nullptr, rig.sim.gaze(), rig.sim.sources(), rig.clock};
  const RecordResult result = record_session((dir / "s").string(), RecordConfig{}, robot, stop);
  EXPECT_TRUE(result.stopped);
  EXPECT_EQ(result.views, 2u);
  EXPECT_EQ(arm.stops, 1);
  expect_readable(dir / "s", 2);
  EXPECT_FALSE(fs::exists(dir / "s" / "views" / "002"));
}

TEST(RecordCore, RefusesANonEmptyFolder) {
  const auto dir = scratch_dir("record-not-empty");
  write_json((dir / "something.json").string(), Json::object());
  SimRig rig;
  const std::atomic<bool> stop{false};
  EXPECT_THROW(record_session(dir.string(), RecordConfig{}, rig.robot, stop), InputError);
}

TEST(RecordCore, StaticPosesFile) {
  const auto dir = scratch_dir("record-static");
  const Eigen::Matrix4d hand = exploration_hand_pose("right", {0, 0});
  Json json = {{"root_from_hand", to_json(hand)},
               {"root_from_camera", to_json(camera_looking_at({-0.02, -0.034, 0.46}, {-0.4, 0.15, 0.25}))},
               {"camera", {{"width", 320}, {"height", 240}, {"fx", 257.3}, {"fy", 257.3}, {"cx", 160}, {"cy", 120}}}};
  write_json((dir / "poses.json").string(), json);
  const StaticMotion motion = read_static_motion((dir / "poses.json").string());
  motion.arm->go_to(Eigen::Matrix4d::Identity());
  EXPECT_TRUE(motion.arm->motion_done());
  EXPECT_TRUE(motion.arm->pose().isApprox(hand));
  EXPECT_EQ(motion.gaze->intrinsics().width, 320);
  json["root_from_hand"][0][0] = 2.0;
  write_json((dir / "bad.json").string(), json);
  EXPECT_THROW(read_static_motion((dir / "bad.json").string()), InputError);
}

TEST(RecordApp, SimBackendEndToEndAndASilentPort) {
  const auto dir = scratch_dir("record-app");
  const auto ok = run_tool("record", "--backend sim --label hoe -o " + (dir / "s").string());
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  for (int pose = 1; pose <= 5; ++pose)
    EXPECT_NE(ok.err.find(fmt::format("pose {}/5", pose)), std::string::npos) << ok.err;
  expect_readable(dir / "s", 5);

  // The blob detector never writes: a bounded wait, one error line naming it, exit 3, an empty session.
  const auto silent = run_tool("record", "--backend sim --sim-silent blob_box --attempts 2 -o " + (dir / "t").string());
  EXPECT_EQ(silent.exit_code, 3) << silent.err;
  std::size_t errors = 0;
  for (std::size_t at = silent.err.find(": error: "); at != std::string::npos;
       at = silent.err.find(": error: ", at + 1))
    ++errors;
  EXPECT_EQ(errors, 1u) << silent.err;
  EXPECT_NE(silent.err.find("no message from sim:blob_box"), std::string::npos) << silent.err;
  expect_readable(dir / "t", 0);
}

TEST(RecordApp, SimBackendWithSgbmStereo) {
  // The simulated robot's stereo module can be SGBM's too (ELAS by default): a whole session, other
  // disparities than ideal's.
  const auto dir = scratch_dir("record-app-sgbm");
  const auto sgbm = run_tool("record", "--backend sim --sim-stereo sgbm -q -o " + (dir / "sgbm").string());
  ASSERT_EQ(sgbm.exit_code, 0) << sgbm.err;
  expect_readable(dir / "sgbm", 5);
  const auto ideal = run_tool("record", "--backend sim --sim-stereo ideal -q -o " + (dir / "ideal").string());
  ASSERT_EQ(ideal.exit_code, 0) << ideal.err;
  EXPECT_NE(slurp(dir / "sgbm" / "views" / "000" / "disparity.png"),
            slurp(dir / "ideal" / "views" / "000" / "disparity.png"));
}

TEST(RecordApp, CtrlCStopsTheRealProcess) {
  // Simulated waits are really waited (settle 2 s per pose), so the recording is still running when the
  // first view is listed; SIGINT then must end it with that session consistent.
  const auto dir = scratch_dir("record-sigint");
  const std::string bin = std::string(toolinc::testing::kBinDir) + "/record", out = (dir / "s").string();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int err = ::open((dir / "stderr.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(err, STDERR_FILENO);
    execl(bin.c_str(), bin.c_str(), "--backend", "sim", "--sim-real-time", "1", "--settle-time", "2", "-o", out.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  bool exited = false;
  // Polls until the first view is listed; the 120 s cap only keeps a broken build from hanging the suite.
  for (int i = 0; i < 2400 && views_listed(dir / "s" / "session.json") == 0; ++i) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_FALSE(exited) << "record ended before it could be interrupted:\n" << slurp(dir / "stderr.txt");
  kill(pid, SIGINT);
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << slurp(dir / "stderr.txt");
  EXPECT_EQ(WEXITSTATUS(status), 130) << slurp(dir / "stderr.txt");
  const std::size_t views = read_session(out).views.size();
  EXPECT_GE(views, 1u);
  EXPECT_LT(views, 5u);
  expect_readable(out, views);
  EXPECT_NE(slurp(dir / "stderr.txt").find("stopped:"), std::string::npos) << slurp(dir / "stderr.txt");
}
