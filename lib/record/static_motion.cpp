#include "toolinc/record/static_motion.hpp"

#include <cmath>

#include "toolinc/core/error.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/io/limits.hpp"

namespace toolinc {
namespace {

Eigen::Matrix4d rigid(const Json& json, const std::string& key, const std::string& file) {
  const Eigen::Matrix4d m = matrix4_field(json, key, file);
  if (!is_rigid(m, 1e-5)) throw InputError(file, key + " is not a rigid transform");
  return m;
}

class StaticArm : public Arm {
 public:
  StaticArm(const Eigen::Matrix4d& pose, std::string file) : pose_(pose), name_("static arm (" + file + ")") {}
  void go_to(const Eigen::Matrix4d&) override {}
  bool motion_done() override { return true; }
  Eigen::Matrix4d pose() override { return pose_; }
  void stop() override {}
  std::string name() const override { return name_; }

 private:
  Eigen::Matrix4d pose_;
  std::string name_;
};

class StaticGaze : public Gaze {
 public:
  StaticGaze(const Eigen::Matrix4d& pose, const CameraModel& camera, std::string file)
      : pose_(pose), camera_(camera), name_("static gaze (" + file + ")") {}
  void look_at(const Vec3&) override {}
  bool motion_done() override { return true; }
  Eigen::Matrix4d left_eye_pose() override { return pose_; }
  CameraModel intrinsics() override { return camera_; }
  void stop() override {}
  std::string name() const override { return name_; }

 private:
  Eigen::Matrix4d pose_;
  CameraModel camera_;
  std::string name_;
};

}  // namespace

StaticMotion read_static_motion(const std::string& path) {
  const Json json = read_json(path);
  if (!json.is_object() || !json.contains("camera") || !json["camera"].is_object())
    throw InputError(path, "missing \"camera\" {width, height, fx, fy, cx, cy}");
  const Json& c = json["camera"];
  CameraModel camera;
  constexpr int kMaxSide = static_cast<int>(kMaxImageSide);
  camera.width = int_field(c, "width", path, 1, kMaxSide);
  camera.height = int_field(c, "height", path, 1, kMaxSide);
  try {
    camera.fx = c.at("fx").get<double>();
    camera.fy = c.at("fy").get<double>();
    camera.cx = c.at("cx").get<double>();
    camera.cy = c.at("cy").get<double>();
  } catch (const nlohmann::json::exception&) {
    throw InputError(path, "camera needs numbers width, height, fx, fy, cx, cy");
  }
  for (const double v : {camera.fx, camera.fy, camera.cx, camera.cy})
    if (!std::isfinite(v)) throw InputError(path, "camera fx, fy, cx, cy must be finite");
  if (!(camera.fx > 0) || !(camera.fy > 0)) throw InputError(path, "camera focal lengths must be positive");
  StaticMotion motion;
  motion.arm = std::make_unique<StaticArm>(rigid(json, "root_from_hand", path), path);
  motion.gaze = std::make_unique<StaticGaze>(rigid(json, "root_from_camera", path), camera, path);
  return motion;
}

}  // namespace toolinc
