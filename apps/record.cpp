// record --robot icub --hand right --label hoe -o SESSION: the exploration on the robot. Moves
// the hand holding the tool through the exploration poses, fixates the tool and records each view into a
// session (docs/formats.md). --backend yarp talks to the iCub's modules; --backend sim to the simulated robot.
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <ctime>
#include <memory>

#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/record/parameters.hpp"
#include "toolinc/record/recorder.hpp"
#include "toolinc/record/sim_backend.hpp"
#include "toolinc/record/static_motion.hpp"
#include "toolinc/record/yarp_config.hpp"
#include "toolinc/synth/grasp.hpp"
#ifdef TOOLINC_WITH_YARP
#include "yarp_robot.hpp"
#endif

namespace {

std::atomic<bool> g_stop{false};

// Only sets the flag (async-signal-safe); the recorder sees it within a poll period and stops the
// motions. The default action is restored, so a second Ctrl-C kills at once.
extern "C" void on_sigint(int) { g_stop = true; }

void install_sigint_handler() {
  struct sigaction action {};
  action.sa_handler = on_sigint;
  action.sa_flags = SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

std::string utc_now_iso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

std::vector<Eigen::Vector2d> wrist_poses(const std::vector<double>& flat) {
  if (flat.empty() || flat.size() % 2 != 0)
    throw std::invalid_argument("--poses takes wrist X Y pairs in degrees, e.g. --poses 0 0 -40 -20");
  std::vector<Eigen::Vector2d> poses;
  for (std::size_t i = 0; i < flat.size(); i += 2) poses.emplace_back(flat[i], flat[i + 1]);
  return poses;
}

Eigen::Vector3d vec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

}  // namespace

int main(int argc, char** argv) {
  toolinc::Command command("record", "Record a tool-exploration session on the robot (or the simulated one)");
  toolinc::RecordConfig config;
  toolinc::YarpBackendConfig yarp;
  std::string backend = "yarp", label, static_poses, sim_family = "hoe", sim_silent;
  std::uint32_t sim_seed = 1;
  double sim_real_time = 0.0;
  bool no_other_arm = false;
  std::vector<double> poses;
  for (const auto& p : config.exploration.poses) poses.insert(poses.end(), {p.x(), p.y()});
  const auto& e = config.exploration;
  std::vector<double> hand_position{e.hand_position.x(), e.hand_position.y(), e.hand_position.z()};
  std::vector<double> other_position{e.other_arm_position.x(), e.other_arm_position.y(), e.other_arm_position.z()};
  const auto& g = config.gaze;
  std::vector<double> first_guess{g.first_guess.x(), g.first_guess.y(), g.first_guess.z()};

  auto& cli = command.cli();
  command.add_output("Session folder to create (must not exist or be empty)");
  cli.add_option("--backend", backend, "yarp (the robot) or sim (the simulated robot, no YARP needed)")
      ->check(CLI::IsMember({"yarp", "sim"}))
      ->capture_default_str();
  cli.add_option("--robot", config.robot, "The robot's name (port prefix)")->capture_default_str();
  cli.add_option("--hand", config.hand, "The hand holding the tool")
      ->check(CLI::IsMember({"left", "right"}))
      ->capture_default_str();
  cli.add_option("--label", label, "The tool's label recorded in session.json");
  cli.add_option("--poses", poses, "Wrist X Y pairs (deg), in order; |X| <= 90 and |Y| <= 70")->capture_default_str();
  toolinc::add_xyz_option(cli, "--hand-position", hand_position,
                          "Root-frame hand position for the right hand (m; y mirrored for the left)");
  toolinc::add_xyz_option(cli, "--other-arm-position", other_position,
                          "Where the other arm goes first (right-hand y, mirrored; m)");
  cli.add_flag("--no-other-arm", no_other_arm, "Leave the other arm where it is");
  toolinc::add_xyz_option(cli, "--first-guess", first_guess, "First fixation in the hand frame (m)");
  toolinc::add_record_options(cli, config);
  cli.add_option("--gaze-remote", yarp.gaze_remote, "Gaze controller")->capture_default_str();
  cli.add_option("--arm-remote", yarp.arm_remote,
                 "Cartesian controller (default /<robot>/cartesianController/<hand>_arm)");
  cli.add_option("--other-arm-remote", yarp.other_arm_remote,
                 "The other arm's cartesian controller (default likewise)");
  cli.add_option("--left-port", yarp.left_port, "Left image (PixelRgb)")->capture_default_str();
  cli.add_option("--disparity-port", yarp.disparity_port, "8-bit disparity (PixelMono)")->capture_default_str();
  cli.add_option("--blob-mask-port", yarp.blob_mask_port, "Blob mask (PixelMono)")->capture_default_str();
  cli.add_option("--blob-roi-port", yarp.blob_roi_port, "Blob box ((tlx tly brx bry))")->capture_default_str();
  cli.add_option("--blobs-port", yarp.blobs_port, "Blob centroid ((cx cy area))")->capture_default_str();
  cli.add_option("--sfm-rpc", yarp.sfm_rpc, "Stereo module's RPC (Rect)")->capture_default_str();
  cli.add_option("--local-prefix", yarp.local_prefix, "Prefix of the local port names")->capture_default_str();
  cli.add_option("--connect-timeout", yarp.connect_timeout, "s to find the name server, a port or a controller")
      ->capture_default_str()
      ->check(toolinc::in_range({0, true, toolinc::kMaxWait, "s"}));
  cli.add_option(
         "--static-poses", static_poses,
         "JSON with root_from_hand, root_from_camera and camera: no controllers, nothing moves (checks the ports)")
      ->check(CLI::ExistingFile);
  cli.add_option("--sim-family", sim_family, "sim: the tool family held")->capture_default_str();
  cli.add_option("--sim-seed", sim_seed, "sim: seed of the grasp and the noise")->capture_default_str();
  std::string sim_stereo = "elas";
  cli.add_option("--sim-stereo", sim_stereo, "sim: the stereo model, as simulate-session --stereo")
      ->check(CLI::IsMember({"ideal", "sgbm", "elas"}))
      ->capture_default_str();
  cli.add_option("--sim-real-time", sim_real_time, "sim: fraction of the simulated waits really waited")
      ->capture_default_str()
      ->check(toolinc::in_range({0, false, 1, ""}));
  cli.add_option("--sim-silent", sim_silent,
                 "sim: a stream that never answers (left, disparity, blob_mask, blob_box, points)");

  const int code = command.run(argc, argv, [&] {
    config.exploration.poses = wrist_poses(poses);
    config.exploration.hand_position = vec3(hand_position);
    config.exploration.other_arm_position = vec3(other_position);
    config.exploration.move_other_arm = !no_other_arm;
    config.gaze.first_guess = vec3(first_guess);
    config.created = utc_now_iso8601();
    config.notes =
        "recorded with --backend " + backend + (static_poses.empty() ? "" : ", static poses from " + static_poses);
    if (!label.empty()) config.tool_label = label;
    toolinc::plan_exploration(config.exploration, config.hand);  // refuse a bad plan before connecting

    toolinc::StaticMotion fixed;
    if (!static_poses.empty()) fixed = toolinc::read_static_motion(static_poses);
    std::unique_ptr<toolinc::Clock> clock;
    std::unique_ptr<toolinc::SimRobot> sim;
    toolinc::Arm *arm = nullptr, *other_arm = nullptr;
    toolinc::Gaze* gaze = nullptr;
    toolinc::Sources* sources = nullptr;
    if (backend == "sim") {
      toolinc::SimBackendConfig sim_config;
      sim_config.scene.shape = toolinc::default_shape(toolinc::family_from_string(sim_family));
      sim_config.scene.hand = config.hand;
      sim_config.scene.seed = sim_seed;
      sim_config.scene.stereo = toolinc::stereo_model_from_string(sim_stereo);
      sim_config.scene.hand_from_canonical = toolinc::exploration_grasp(sim_seed);  // as simulate-session draws it
      if (!sim_silent.empty()) sim_config.silent = toolinc::stream_from_string(sim_silent);
      clock = std::make_unique<toolinc::SimulatedClock>(sim_real_time);
      sim = std::make_unique<toolinc::SimRobot>(sim_config, *clock);
      arm = &sim->arm(), other_arm = &sim->other_arm(), gaze = &sim->gaze(), sources = &sim->sources();
    }
#ifdef TOOLINC_WITH_YARP
    std::unique_ptr<toolinc::YarpRobot> robot;
    if (backend == "yarp") {
      yarp.robot = config.robot;
      yarp.hand = config.hand;
      yarp.controllers = static_poses.empty();
      yarp.other_arm = config.exploration.move_other_arm;
      yarp.rpc_timeout = config.read_timeout;
      clock = std::make_unique<toolinc::SteadyClock>();
      robot = std::make_unique<toolinc::YarpRobot>(yarp);
      arm = robot->arm(), other_arm = robot->other_arm(), gaze = robot->gaze(), sources = &robot->sources();
    }
#else
    if (backend == "yarp")
      throw std::invalid_argument(
          "this record was built without YARP: use --backend sim for the simulated robot, or rebuild with "
          "-DTOOLINC_WITH_YARP=ON");
#endif
    if (fixed.arm) arm = fixed.arm.get(), gaze = fixed.gaze.get(), other_arm = nullptr;

    install_sigint_handler();
    toolinc::Robot parts{*arm, other_arm, *gaze, *sources, *clock};
    const auto result = toolinc::record_session(command.output(), config, parts, g_stop);
    if (result.stopped)
      spdlog::warn("stopped: {} holds the views captured so far ({})", command.output(), result.views);
    else
      spdlog::info("{} views -> {}", result.views, command.output());
  });
  return code == 0 && g_stop ? 130 : code;
}
