// The recorder's devices over YARP. Everything is checked when the robot is opened, each with a timeout,
// so a missing module is one clear error naming it instead of the original's endless wait.
#include "yarp_robot.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>
#include <yarp/dev/CartesianControl.h>
#include <yarp/dev/Drivers.h>
#include <yarp/dev/GazeControl.h>
#include <yarp/dev/PolyDriver.h>
#include <yarp/os/Bottle.h>
#include <yarp/os/BufferedPort.h>
#include <yarp/os/ContactStyle.h>
#include <yarp/os/Network.h>
#include <yarp/os/Property.h>
#include <yarp/os/RpcClient.h>
#include <yarp/sig/Image.h>
#include <yarp/sig/Vector.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"

namespace toolinc {
namespace {

using yarp::sig::ImageOf;
using yarp::sig::PixelMono;
using yarp::sig::PixelRgb;

Eigen::Matrix4d pose_from(const yarp::sig::Vector& x, const yarp::sig::Vector& o) {
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  pose.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(o[3], Eigen::Vector3d(o[0], o[1], o[2]).normalized()).toRotationMatrix();
  pose.topRightCorner<3, 1>() = Eigen::Vector3d(x[0], x[1], x[2]);
  return pose;
}

bool port_exists(const std::string& port, double timeout) {
  yarp::os::ContactStyle style;
  style.quiet = true;
  style.timeout = timeout;
  return yarp::os::Network::exists(port, style);
}

// Opens a controller client, after checking that this YARP has the device and that its server runs.
void open_client(yarp::dev::PolyDriver& driver, const std::string& device, const std::string& remote,
                 const std::string& server_port, const std::string& local, const std::string& server, double timeout) {
  if (yarp::dev::Drivers::factory().find(device.c_str()) == nullptr)
    throw InputError(device,
                     "this YARP has no such device (the iCub's controller clients come with icub-main); "
                     "without the controllers, --static-poses FILE checks the ports alone");
  if (!port_exists(server_port, timeout))
    throw InputError(remote, "no controller there (" + server_port + " not found): is " + server + " running?");
  yarp::os::Property options;
  options.put("device", device);
  options.put("remote", remote);
  options.put("local", local);
  if (!driver.open(options)) throw InputError(remote, "cannot open " + device + " on it");
}

class YarpArm : public Arm {
 public:
  YarpArm(const std::string& remote, const std::string& local, double timeout) : remote_(remote) {
    open_client(driver_, "cartesiancontrollerclient", remote, remote + "/rpc:i", local, "iKinCartesianSolver", timeout);
    if (!driver_.view(control_) || control_ == nullptr) throw InputError(remote, "no ICartesianControl interface");
  }
  ~YarpArm() override { driver_.close(); }
  void go_to(const Eigen::Matrix4d& root_from_hand) override {
    const Eigen::Vector4d axis_angle_o = axis_angle(root_from_hand.topLeftCorner<3, 3>());
    yarp::sig::Vector x(3), o(4);
    for (int i = 0; i < 3; ++i) x[i] = root_from_hand(i, 3);
    for (int i = 0; i < 4; ++i) o[i] = axis_angle_o[i];
    if (!control_->goToPoseSync(x, o)) throw MethodError(remote_ + ": goToPoseSync failed");
  }
  bool motion_done() override {
    bool done = false;
    if (!control_->checkMotionDone(&done)) throw MethodError(remote_ + ": checkMotionDone failed");
    return done;
  }
  Eigen::Matrix4d pose() override {
    yarp::sig::Vector x, o;
    if (!control_->getPose(x, o) || x.size() < 3 || o.size() < 4) throw MethodError(remote_ + ": getPose failed");
    return pose_from(x, o);
  }
  void stop() override { control_->stopControl(); }
  std::string name() const override { return remote_; }

 private:
  std::string remote_;
  yarp::dev::PolyDriver driver_;
  yarp::dev::ICartesianControl* control_ = nullptr;
};

class YarpGaze : public Gaze {
 public:
  YarpGaze(const std::string& remote, const std::string& local, double timeout) : remote_(remote) {
    open_client(driver_, "gazecontrollerclient", remote, remote + "/rpc", local, "iKinGazeCtrl", timeout);
    if (!driver_.view(control_) || control_ == nullptr) throw InputError(remote, "no IGazeControl interface");
  }
  ~YarpGaze() override { driver_.close(); }
  void look_at(const Vec3& root_point) override {
    yarp::sig::Vector fp(3);
    for (int i = 0; i < 3; ++i) fp[i] = root_point[i];
    if (!control_->lookAtFixationPoint(fp)) throw MethodError(remote_ + ": lookAtFixationPoint failed");
  }
  bool motion_done() override {
    bool done = false;
    if (!control_->checkMotionDone(&done)) throw MethodError(remote_ + ": checkMotionDone failed");
    return done;
  }
  Eigen::Matrix4d left_eye_pose() override {
    yarp::sig::Vector x, o;
    if (!control_->getLeftEyePose(x, o) || x.size() < 3 || o.size() < 4)
      throw MethodError(remote_ + ": getLeftEyePose failed");
    return pose_from(x, o);
  }
  // getInfo: camera_intrinsics_left (3x4 row-major), camera_width_left, camera_height_left.
  CameraModel intrinsics() override {
    yarp::os::Bottle info;
    if (!control_->getInfo(info)) throw InputError(remote_, "getInfo failed");
    const yarp::os::Bottle* k = info.find("camera_intrinsics_left").asList();
    const yarp::os::Value &width = info.find("camera_width_left"), &height = info.find("camera_height_left");
    if (k == nullptr || k->size() < 12 || width.isNull() || height.isNull())
      throw InputError(remote_, "getInfo lacks camera_intrinsics_left, camera_width_left or camera_height_left");
    CameraModel camera;
    camera.width = width.asInt32();
    camera.height = height.asInt32();
    camera.fx = k->get(0).asFloat64();
    camera.cx = k->get(2).asFloat64();
    camera.fy = k->get(5).asFloat64();
    camera.cy = k->get(6).asFloat64();
    return camera;
  }
  void stop() override { control_->stopControl(); }
  std::string name() const override { return remote_; }

 private:
  std::string remote_;
  yarp::dev::PolyDriver driver_;
  yarp::dev::IGazeControl* control_ = nullptr;
};

// A port read from `remote` into a local port.
template <typename T>
class Input {
 public:
  Input(const std::string& remote, const std::string& local, double timeout) : remote_(remote) {
    if (!port_exists(remote, timeout)) throw InputError(remote, "no such port: is the module that writes it running?");
    if (!port_.open(local)) throw InputError(local, "cannot open the local port");
    if (!yarp::os::Network::connect(remote, local, "tcp")) throw InputError(remote, "cannot connect it to " + local);
  }
  ~Input() { port_.close(); }
  void drain() {
    while (port_.read(false) != nullptr) {
    }
  }
  T* read() { return port_.read(false); }

 private:
  std::string remote_;
  yarp::os::BufferedPort<T> port_;
};

cv::Mat to_mat(const ImageOf<PixelRgb>& image) {
  const cv::Mat rgb(static_cast<int>(image.height()), static_cast<int>(image.width()), CV_8UC3,
                    const_cast<unsigned char*>(image.getRawImage()), image.getRowSize());
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

cv::Mat to_mat(const ImageOf<PixelMono>& image) {
  return cv::Mat(static_cast<int>(image.height()), static_cast<int>(image.width()), CV_8UC1,
                 const_cast<unsigned char*>(image.getRawImage()), image.getRowSize())
      .clone();
}

// The first list of a dispBlobber bottle ((a b c ...)) with at least n numbers.
const yarp::os::Bottle* first_list(yarp::os::Bottle& bottle, std::size_t n) {
  const yarp::os::Bottle* list = bottle.size() > 0 ? bottle.get(0).asList() : nullptr;
  return list != nullptr && list->size() >= n ? list : nullptr;
}

class YarpSources : public Sources {
 public:
  YarpSources(const YarpBackendConfig& config, const std::string& local)
      : config_(config),
        left_(config.left_port, local + "/left:i", config.connect_timeout),
        disparity_(config.disparity_port, local + "/disp:i", config.connect_timeout),
        mask_(config.blob_mask_port, local + "/blob:i", config.connect_timeout),
        roi_(config.blob_roi_port, local + "/roi:i", config.connect_timeout),
        blobs_(config.blobs_port, local + "/blobs:i", config.connect_timeout) {
    if (!port_exists(config.sfm_rpc, config.connect_timeout))
      throw InputError(config.sfm_rpc, "no such port: is the stereo module (SFM) running?");
    // A timeout on the RPC must be set before connecting.
    sfm_.asPort().setTimeout(static_cast<float>(config.rpc_timeout));
    if (!sfm_.open(local + "/sfm:rpc")) throw InputError(local + "/sfm:rpc", "cannot open the local port");
    if (!yarp::os::Network::connect(local + "/sfm:rpc", config.sfm_rpc, "tcp"))
      throw InputError(config.sfm_rpc, "cannot connect to it");
  }
  ~YarpSources() override { sfm_.close(); }

  void drain() override {
    left_.drain(), disparity_.drain(), mask_.drain(), roi_.drain(), blobs_.drain();
    roi_seen_.reset(), blob_seen_.reset();
  }
  std::optional<cv::Mat> left() override {
    if (auto* image = left_.read()) return to_mat(*image);
    return std::nullopt;
  }
  std::optional<cv::Mat> disparity() override {
    if (auto* image = disparity_.read()) return to_mat(*image);
    return std::nullopt;
  }
  std::optional<cv::Mat> blob_mask() override {
    if (auto* image = mask_.read()) return to_mat(*image);
    return std::nullopt;
  }
  // The box and the centroid come on two ports: each is kept until the other has arrived too.
  std::optional<BlobInfo> blob_box() override {
    if (auto* bottle = roi_.read())
      if (const auto* roi = first_list(*bottle, 4))
        roi_seen_ = {static_cast<int>(std::lround(roi->get(0).asFloat64())),
                     static_cast<int>(std::lround(roi->get(1).asFloat64())),
                     static_cast<int>(std::lround(roi->get(2).asFloat64())),
                     static_cast<int>(std::lround(roi->get(3).asFloat64()))};
    if (auto* bottle = blobs_.read())
      if (const auto* blob = first_list(*bottle, 3))
        blob_seen_ = Eigen::Vector3d(blob->get(0).asFloat64(), blob->get(1).asFloat64(), blob->get(2).asFloat64());
    if (!roi_seen_ || !blob_seen_) return std::nullopt;
    return BlobInfo{blob_seen_->x(), blob_seen_->y(), blob_seen_->z(), *roi_seen_};
  }
  std::optional<Points> points(const SfmRect& rect) override {
    yarp::os::Bottle command, reply;
    command.addString("Rect");
    for (int v : {rect.tlx, rect.tly, rect.w, rect.h, rect.step}) command.addInt32(v);
    if (!sfm_.write(command, reply) || reply.size() == 0) return std::nullopt;
    Points points;
    for (std::size_t i = 0; i + 2 < reply.size(); i += 3)
      points.emplace_back(reply.get(i).asFloat64(), reply.get(i + 1).asFloat64(), reply.get(i + 2).asFloat64());
    return points;
  }
  std::string name(Stream stream) const override {
    switch (stream) {
      case Stream::left:
        return config_.left_port;
      case Stream::disparity:
        return config_.disparity_port;
      case Stream::blob_mask:
        return config_.blob_mask_port;
      case Stream::blob_box:
        return config_.blob_roi_port + " and " + config_.blobs_port;
      case Stream::points:
        return config_.sfm_rpc;
    }
    return "?";
  }

 private:
  YarpBackendConfig config_;
  Input<ImageOf<PixelRgb>> left_;
  Input<ImageOf<PixelMono>> disparity_, mask_;
  Input<yarp::os::Bottle> roi_, blobs_;
  yarp::os::RpcClient sfm_;
  std::optional<std::array<int, 4>> roi_seen_;
  std::optional<Eigen::Vector3d> blob_seen_;
};

// Checked before anything else: without a name server every other check would only time out.
yarp::os::Network& network(double timeout) {
  static yarp::os::Network network;
  if (!yarp::os::Network::checkNetwork(timeout))
    throw InputError("YARP name server", "not found (is yarpserver running? `yarp detect` checks)");
  return network;
}

}  // namespace

struct YarpRobot::Impl {
  std::unique_ptr<YarpGaze> gaze;
  std::unique_ptr<YarpArm> arm, other_arm;
  std::unique_ptr<YarpSources> sources;
};

YarpRobot::YarpRobot(const YarpBackendConfig& config) : impl_(std::make_unique<Impl>()) {
  network(config.connect_timeout);
  // Unique local names: two recorders (or a stale one) must not clash.
  const std::string local = config.local_prefix + "/" + std::to_string(::getpid());
  if (config.controllers) {
    const std::string other = config.hand == "right" ? "left" : "right";
    impl_->gaze = std::make_unique<YarpGaze>(config.gaze_remote, local + "/gaze", config.connect_timeout);
    impl_->arm = std::make_unique<YarpArm>(arm_remote_for(config, config.hand, config.arm_remote),
                                           local + "/cartesian/" + config.hand, config.connect_timeout);
    if (config.other_arm)
      impl_->other_arm = std::make_unique<YarpArm>(arm_remote_for(config, other, config.other_arm_remote),
                                                   local + "/cartesian/" + other, config.connect_timeout);
  }
  impl_->sources = std::make_unique<YarpSources>(config, local);
  spdlog::info("connected to the robot's modules (local ports under {})", local);
}

YarpRobot::~YarpRobot() = default;
Arm* YarpRobot::arm() { return impl_->arm.get(); }
Arm* YarpRobot::other_arm() { return impl_->other_arm.get(); }
Gaze* YarpRobot::gaze() { return impl_->gaze.get(); }
Sources& YarpRobot::sources() { return *impl_->sources; }

}  // namespace toolinc
