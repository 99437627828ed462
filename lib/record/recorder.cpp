#include "toolinc/record/recorder.hpp"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <functional>
#include <stdexcept>

#include "toolinc/core/error.hpp"
#include "toolinc/record/sfm.hpp"

namespace toolinc {
namespace fs = std::filesystem;
namespace {

// Unwinds a recording from wherever the stop flag was seen.
struct Stopped {};

// A stream's read that timed out: retried by the capture, then reported.
struct NoMessage {
  std::string what;
};

class Recording {
 public:
  Recording(const std::string& dir, const RecordConfig& config, Robot& robot, const std::atomic<bool>& stop)
      : dir_(dir), config_(config), robot_(robot), stop_(stop), start_(robot.clock.now()) {}

  RecordResult run();

 private:
  void check_stop() const {
    if (stop_) throw Stopped{};
  }
  double stamp() const { return robot_.clock.now() - start_; }

  // Polls `read` until it gives a value, stop is set (Stopped) or timeout passes (NoMessage naming `what`).
  template <typename T>
  T await(const std::function<std::optional<T>()>& read, double timeout, const std::string& what) {
    const double deadline = robot_.clock.now() + timeout;
    for (;;) {
      check_stop();
      if (auto value = read()) return std::move(*value);
      if (robot_.clock.now() >= deadline) throw NoMessage{fmt::format("no message from {} within {} s", what, timeout)};
      robot_.clock.sleep(config_.poll_period);
    }
  }

  // Waits for each motion to be done, each within its own timeout from now.
  struct Motion {
    std::function<bool()> done;
    double timeout;
    std::string what;
  };
  void wait_motions(const std::vector<Motion>& motions) {
    const double start = robot_.clock.now();
    for (;;) {
      check_stop();
      bool all_done = true;
      for (const auto& motion : motions) {
        if (motion.done()) continue;
        all_done = false;
        if (robot_.clock.now() - start >= motion.timeout)
          throw MethodError(fmt::format("{} did not finish its motion within {} s", motion.what, motion.timeout));
      }
      if (all_done) return;
      robot_.clock.sleep(config_.poll_period);
    }
  }

  void stop_motions() {
    robot_.arm.stop();
    if (robot_.other_arm) robot_.other_arm->stop();
    robot_.gaze.stop();
  }

  void move_other_arm();
  void fixate(const Eigen::Matrix4d& target);
  void refine_gaze(Vec3 fixation);
  std::pair<ViewRecord, ViewData> capture(std::size_t index, const Eigen::Vector2d& wrist);
  std::pair<ViewRecord, ViewData> capture_once(std::size_t index, const Eigen::Vector2d& wrist);

  std::string dir_;
  const RecordConfig& config_;
  Robot& robot_;
  const std::atomic<bool>& stop_;
  double start_;
  SessionInfo info_;
};

void Recording::move_other_arm() {
  Arm& other = *robot_.other_arm;
  Eigen::Matrix4d pose = other.pose();
  pose.topRightCorner<3, 1>() =
      for_hand(config_.hand == "right" ? "left" : "right", config_.exploration.other_arm_position);
  spdlog::info("moving the other arm out of view ({})", other.name());
  other.go_to(pose);
  wait_motions({{[&] { return other.motion_done(); }, config_.arm_timeout, other.name()}});
}

void Recording::fixate(const Eigen::Matrix4d& target) {
  robot_.arm.go_to(target);
  const Vec3 fixation = first_fixation(target, config_.gaze);
  robot_.gaze.look_at(fixation);
  wait_motions({{[&] { return robot_.arm.motion_done(); }, config_.arm_timeout, robot_.arm.name()},
                {[&] { return robot_.gaze.motion_done(); }, config_.gaze_timeout, robot_.gaze.name()}});
  refine_gaze(fixation);
}

// lookAtTool: re-aim at the blob's far part until it is centred. A missing blob ends the refinement;
// the capture then waits for it with its own retries.
void Recording::refine_gaze(Vec3 fixation) {
  const CameraModel& camera = info_.camera;
  const Eigen::Vector2d centre(camera.cx, camera.cy);
  for (int i = 0; i < config_.gaze.refine_iterations; ++i) {
    robot_.sources.drain();
    cv::Mat mask;
    try {
      mask = await<cv::Mat>([&] { return robot_.sources.blob_mask(); }, config_.read_timeout,
                            robot_.sources.name(Sources::Stream::blob_mask));
    } catch (const NoMessage& e) {
      spdlog::warn("gaze not refined: {}", e.what);
      return;
    }
    const Eigen::Matrix4d root_from_camera = robot_.gaze.left_eye_pose();
    const auto hand = project(camera, root_from_camera, robot_.arm.pose().topRightCorner<3, 1>());
    const auto target = hand ? blob_target(mask, *hand, config_.gaze.refine_fraction) : std::nullopt;
    if (!target || (*target - centre).norm() <= config_.gaze.tolerance_px) return;
    const Eigen::Matrix3d r = root_from_camera.topLeftCorner<3, 3>();
    const double depth = (r.transpose() * (fixation - root_from_camera.topRightCorner<3, 1>())).z();
    fixation = point_at_pixel(camera, root_from_camera, *target, depth);
    spdlog::debug("gaze: re-fixating pixel ({:.0f}, {:.0f})", target->x(), target->y());
    robot_.gaze.look_at(fixation);
    wait_motions({{[&] { return robot_.gaze.motion_done(); }, config_.gaze_timeout, robot_.gaze.name()}});
  }
}

std::pair<ViewRecord, ViewData> Recording::capture_once(std::size_t index, const Eigen::Vector2d& wrist) {
  Sources& sources = robot_.sources;
  using Stream = Sources::Stream;
  const CameraModel& camera = info_.camera;
  sources.drain();
  ViewRecord record;
  record.dir = fmt::format("views/{:03d}", index);
  record.wrist_deg = wrist;
  ViewData data;
  const auto image = [&](Stream stream, const std::function<std::optional<cv::Mat>()>& read, int type) {
    cv::Mat mat = await<cv::Mat>(read, config_.read_timeout, sources.name(stream));
    if (mat.type() != type || mat.cols != camera.width || mat.rows != camera.height)
      throw MethodError(fmt::format("{}: image is {}x{} with {} channels, expected {}x{} with {}", sources.name(stream),
                                    mat.cols, mat.rows, mat.channels(), camera.width, camera.height, CV_MAT_CN(type)));
    return mat;
  };
  data.left = image(
      Stream::left, [&] { return sources.left(); }, CV_8UC3);
  record.stamps["left"] = stamp();
  data.disparity = image(
      Stream::disparity, [&] { return sources.disparity(); }, CV_8UC1);
  record.stamps["disparity"] = stamp();
  data.blob = image(
      Stream::blob_mask, [&] { return sources.blob_mask(); }, CV_8UC1);
  const BlobInfo blob =
      await<BlobInfo>([&] { return sources.blob_box(); }, config_.read_timeout, sources.name(Stream::blob_box));
  record.blob = blob;
  record.stamps["blob"] = stamp();
  // The robot stands still: the poses read now are those of the images.
  record.root_from_hand = robot_.arm.pose();
  record.root_from_camera = robot_.gaze.left_eye_pose();
  record.stamps["hand"] = stamp();

  const SfmRect rect = clamp_rect(blob.roi, camera.width, camera.height, config_.sfm_step);
  if (rect.w == 0) {
    spdlog::warn("{}: the blob's box [{} {} {} {}] is outside the image: no exact 3D", record.dir, blob.roi[0],
                 blob.roi[1], blob.roi[2], blob.roi[3]);
    return {record, data};
  }
  check_stop();
  const auto reply = sources.points(rect);
  if (!reply)
    throw NoMessage{fmt::format("no answer from {} within {} s", sources.name(Stream::points), config_.read_timeout)};
  data.points = organised_points(rect, *reply, camera.width, camera.height);
  record.stamps["points"] = stamp();
  return {record, data};
}

std::pair<ViewRecord, ViewData> Recording::capture(std::size_t index, const Eigen::Vector2d& wrist) {
  for (int attempt = 1;; ++attempt) {
    try {
      return capture_once(index, wrist);
    } catch (const NoMessage& e) {
      if (attempt >= config_.attempts)
        throw MethodError(fmt::format("{} ({} attempts); is the module running and connected?", e.what, attempt));
      spdlog::warn("{}; retrying ({}/{})", e.what, attempt, config_.attempts);
    }
  }
}

RecordResult Recording::run() {
  const auto plan = plan_exploration(config_.exploration, config_.hand);
  if (config_.attempts < 1) throw std::invalid_argument("attempts must be at least 1");

  std::error_code ec;
  if (fs::exists(dir_, ec) && !(fs::is_directory(dir_, ec) && fs::is_empty(dir_, ec)))
    throw InputError(dir_, "already exists and is not empty (a session is never written over another)");
  info_.robot = config_.robot;
  info_.hand = config_.hand;
  info_.tool_label = config_.tool_label;
  info_.camera = robot_.gaze.intrinsics();
  info_.camera.num_disparities = config_.num_disparities > 0 ? config_.num_disparities
                                 : info_.camera.width <= 320 ? 96
                                                             : 128;
  info_.camera.baseline = config_.baseline;
  info_.created = config_.created;
  info_.recorder_name = "record";
  info_.recorder_version = TOOLINC_VERSION;
  info_.notes = config_.notes;
  fs::create_directories(dir_);
  write_session_json(dir_, info_);  // an empty but valid session from the start

  RecordResult result;
  try {
    if (config_.exploration.move_other_arm && robot_.other_arm) move_other_arm();
    for (std::size_t i = 0; i < plan.size(); ++i) {
      const Eigen::Vector2d& wrist = config_.exploration.poses[i];
      spdlog::info("pose {}/{}: wrist ({}, {}) deg", i + 1, plan.size(), wrist.x(), wrist.y());
      fixate(plan[i]);
      if (!sleep_unless_stopped(robot_.clock, config_.settle_time, stop_, config_.poll_period)) throw Stopped{};
      auto [record, data] = capture(i, wrist);
      check_stop();
      write_view(dir_, record, data);
      info_.views.push_back(record);
      write_session_json(dir_, info_);
      result.views = info_.views.size();
      spdlog::info("pose {}/{}: {} written (blob area {:.0f} px)", i + 1, plan.size(), record.dir,
                   record.blob ? record.blob->area : 0.0);
    }
  } catch (const Stopped&) {
    stop_motions();
    result.stopped = true;
  } catch (...) {
    stop_motions();
    throw;
  }
  return result;
}

}  // namespace

RecordResult record_session(const std::string& session_dir, const RecordConfig& config, Robot& robot,
                            const std::atomic<bool>& stop) {
  Recording recording(session_dir, config, robot, stop);
  return recording.run();
}

}  // namespace toolinc
