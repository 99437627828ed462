#include "toolinc/record/sim_backend.hpp"

#include <limits>
#include <stdexcept>

#include "toolinc/record/sfm.hpp"
#include "toolinc/synth/render.hpp"

namespace toolinc {
namespace {

using scene::Pose;

// A motion that takes `duration` of the clock, jumping to its target at the end; stop() ends it where it
// is (an unfinished motion has not left its start).
class SimMotion {
 public:
  SimMotion(Clock& clock, double duration, const Pose& start)
      : clock_(clock), duration_(duration), from_(start), to_(start) {}
  void start(const Pose& target) {
    from_ = current();
    to_ = target;
    started_ = clock_.now();
  }
  bool done() const { return clock_.now() - started_ >= duration_; }
  Pose current() const { return done() ? to_ : from_; }
  void stop() {
    from_ = to_ = current();
    started_ = clock_.now() - duration_;
  }

 private:
  Clock& clock_;
  double duration_;
  Pose from_, to_;
  double started_ = -std::numeric_limits<double>::infinity();  // long done
};

struct World {
  SimBackendConfig config;
  Clock& clock;
  scene::RenderModel model;
  scene::Box hand_box;
  Rng rng;
  SimMotion hand, other_hand, eye;

  World(const SimBackendConfig& c, Clock& k)
      : config(c),
        clock(k),
        model(scene::render_model(c.scene)),
        hand_box(scene::hand_box(c.scene)),
        rng(c.scene.seed ^ 0x2ec02d5u),
        hand(k, c.motion_time, exploration_hand_pose(c.scene.hand, {0, 0})),
        other_hand(k, c.motion_time, exploration_hand_pose(c.scene.hand == "right" ? "left" : "right", {0, 0})),
        eye(k, c.motion_time, camera_looking_at(c.scene.eye_position, c.scene.eye_position + Vec3(-1, 0, -1))) {
    config.scene.write_points = config.scene.write_blob = true;
  }
};

class SimArm : public Arm {
 public:
  SimArm(SimMotion& motion, std::string name) : motion_(motion), name_(std::move(name)) {}
  void go_to(const Eigen::Matrix4d& root_from_hand) override { motion_.start(root_from_hand); }
  bool motion_done() override { return motion_.done(); }
  Eigen::Matrix4d pose() override { return motion_.current(); }
  void stop() override { motion_.stop(); }
  std::string name() const override { return name_; }

 private:
  SimMotion& motion_;
  std::string name_;
};

class SimGaze : public Gaze {
 public:
  explicit SimGaze(World& world) : world_(world) {}
  void look_at(const Vec3& root_point) override {
    world_.eye.start(camera_looking_at(world_.config.scene.eye_position, root_point));
  }
  bool motion_done() override { return world_.eye.done(); }
  Eigen::Matrix4d left_eye_pose() override { return world_.eye.current(); }
  CameraModel intrinsics() override { return world_.config.scene.camera; }
  void stop() override { world_.eye.stop(); }
  std::string name() const override { return "sim:gaze"; }

 private:
  World& world_;
};

class SimSources : public Sources {
 public:
  explicit SimSources(World& world) : world_(world) {}
  void drain() override { frame_.reset(); }
  std::optional<cv::Mat> left() override {
    if (const Frame* f = frame(Stream::left)) return f->data.left;
    return std::nullopt;
  }
  std::optional<cv::Mat> disparity() override {
    if (const Frame* f = frame(Stream::disparity)) return f->data.disparity;
    return std::nullopt;
  }
  // dispBlobber writes only when it finds a blob.
  std::optional<cv::Mat> blob_mask() override {
    if (const Frame* f = frame(Stream::blob_mask); f && f->blob) return f->data.blob;
    return std::nullopt;
  }
  std::optional<BlobInfo> blob_box() override {
    if (const Frame* f = frame(Stream::blob_box)) return f->blob;
    return std::nullopt;
  }
  std::optional<Points> points(const SfmRect& rect) override {
    const Frame* f = frame(Stream::points);
    if (!f) return std::nullopt;
    Points reply;
    const int width = world_.config.scene.camera.width;
    for (const auto& pixel : sfm_rect_pixels(rect)) {
      const Vec3& p = f->data.points[static_cast<std::size_t>(pixel.y()) * width + pixel.x()];
      reply.push_back(p.allFinite() ? p : Vec3::Zero());  // SFM's "no depth"
    }
    return reply;
  }
  std::string name(Stream stream) const override {
    static const char* names[] = {"sim:left", "sim:disparity", "sim:blob_mask", "sim:blob_box", "sim:points"};
    return names[static_cast<int>(stream)];
  }

 private:
  struct Frame {
    ViewData data;
    std::optional<BlobInfo> blob;
  };

  // The scene as it is at the first read after a drain; nothing from a silent stream.
  const Frame* frame(Stream stream) {
    if (world_.config.silent == stream) return nullptr;
    if (!frame_) {
      const Pose root_from_camera = world_.eye.current();
      frame_.emplace();
      frame_->data = scene::record_view(world_.config.scene, world_.model, world_.hand_box, world_.hand.current(),
                                        root_from_camera, world_.rng, frame_->blob);
    }
    return &*frame_;
  }

  World& world_;
  std::optional<Frame> frame_;
};

}  // namespace

struct SimRobot::Impl {
  World world;
  SimArm arm, other_arm;
  SimGaze gaze;
  SimSources sources;
  Impl(const SimBackendConfig& config, Clock& clock)
      : world(config, clock),
        arm(world.hand, "sim:" + config.scene.hand + "_arm"),
        other_arm(world.other_hand, std::string("sim:") + (config.scene.hand == "right" ? "left" : "right") + "_arm"),
        gaze(world),
        sources(world) {}
};

SimRobot::SimRobot(const SimBackendConfig& config, Clock& clock) : impl_(std::make_unique<Impl>(config, clock)) {}
SimRobot::~SimRobot() = default;
Arm& SimRobot::arm() { return impl_->arm; }
Arm& SimRobot::other_arm() { return impl_->other_arm; }
Gaze& SimRobot::gaze() { return impl_->gaze; }
Sources& SimRobot::sources() { return impl_->sources; }

Sources::Stream stream_from_string(const std::string& name) {
  using Stream = Sources::Stream;
  if (name == "left") return Stream::left;
  if (name == "disparity") return Stream::disparity;
  if (name == "blob_mask") return Stream::blob_mask;
  if (name == "blob_box") return Stream::blob_box;
  if (name == "points") return Stream::points;
  throw std::invalid_argument("unknown stream \"" + name + "\" (left, disparity, blob_mask, blob_box, points)");
}

}  // namespace toolinc
