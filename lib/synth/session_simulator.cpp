#include "toolinc/synth/session_simulator.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/ground_truth_file.hpp"
#include "toolinc/synth/model_kinds.hpp"
#include "toolinc/synth/render.hpp"

namespace toolinc {
namespace {

using namespace scene;

constexpr double kDeg = M_PI / 180.0;

using Rotation = Eigen::Matrix3d;

Pose rigid(const Rotation& rotation, const Vec3& translation) {
  Pose pose = Pose::Identity();
  pose.topLeftCorner<3, 3>() = rotation;
  pose.topRightCorner<3, 1>() = translation;
  return pose;
}

Vec3 random_unit(Rng& rng) { return Vec3(rng.gaussian(), rng.gaussian(), rng.gaussian()).normalized(); }

Rotation about(const Vec3& axis, double deg) { return Eigen::AngleAxisd(deg * kDeg, axis).toRotationMatrix(); }

// The recorded pose's error: N(0, sigma_m) per axis, N(0, sigma_deg) about a random axis.
Pose kinematic_error(double sigma_m, double sigma_deg, Rng& rng) {
  const Vec3 t(rng.gaussian(), rng.gaussian(), rng.gaussian());
  const Vec3 axis = random_unit(rng);
  return rigid(about(axis, sigma_deg * rng.gaussian()), sigma_m * t);
}

Pose gross_error(const GrossError& gross, Rng& rng) {
  const Vec3 direction = random_unit(rng);
  return rigid(about(random_unit(rng), gross.rotation_deg), gross.translation * direction);
}

void check(const SessionSimulatorConfig& config) {
  if (config.hand != "left" && config.hand != "right")
    throw std::invalid_argument("hand must be left or right, not \"" + config.hand + "\"");
  if (config.poses.empty()) throw std::invalid_argument("no exploration poses");
  for (const auto& gross : config.gross_errors)
    if (gross.view >= config.poses.size())
      throw std::invalid_argument(
          fmt::format("gross error for view {}, but there are {} views", gross.view, config.poses.size()));
  if (!(config.scene_variation >= 0 && config.scene_variation < 1))
    throw std::invalid_argument(fmt::format("scene variation {} is not in [0, 1)", config.scene_variation));
  if (config.tool_rgb)
    for (const int c : *config.tool_rgb)
      if (c < 0 || c > 255) throw std::invalid_argument(fmt::format("tool colour value {} is not in 0-255", c));
  if (!is_rigid(config.hand_from_canonical)) throw std::invalid_argument("the grasp is not a rigid transform");
  if (!config.model.empty() && config.model.has_colors() && config.model.colors.size() != config.model.size())
    throw std::invalid_argument("the model's colours do not match its points");
}

// ground_truth_json describes a procedural shape; a model file replaces that description.
Json ground_truth(const SessionSimulatorConfig& config, const RenderModel& model, const ToolGroundTruth& truth,
                  const std::vector<Pose>& true_root_from_hand) {
  ToolShape shape = config.shape;
  shape.spacing = model.spacing;
  Json json = ground_truth_json(truth, shape);
  if (!config.model.empty())
    json["model"] = {{"family", "model"}, {"name", config.model_name}, {"points", model.points.size()}};
  Json poses = Json::array();
  for (const auto& pose : true_root_from_hand) poses.push_back(to_json(pose));
  json["true_root_from_hand"] = poses;
  return json;
}

}  // namespace

ToolSymmetry tool_symmetry(const SessionSimulatorConfig& config) {
  return config.model.empty() ? symmetry_of(config.shape.family) : config.model_symmetry;
}

TruthTip tool_truth_tip(const SessionSimulatorConfig& config) {
  return config.model.empty() ? truth_tip_of(config.shape.family) : truth_tip_of_kind(model_kind(config.model_name));
}

StereoModel stereo_model_from_string(const std::string& name) {
  if (name == "ideal") return StereoModel::ideal;
  if (name == "sgbm") return StereoModel::sgbm;
  if (name == "elas") return StereoModel::elas;
  throw std::invalid_argument("unknown stereo model \"" + name + "\" (ideal, sgbm, elas)");
}

std::string to_string(StereoModel model) {
  switch (model) {
    case StereoModel::ideal:
      return "ideal";
    case StereoModel::sgbm:
      return "sgbm";
    case StereoModel::elas:
      return "elas";
  }
  return "";
}

const std::vector<std::array<int, 3>>& tool_palette() {
  static const std::vector<std::array<int, 3>> palette = {{128, 128, 128}, {50, 50, 55},   {190, 40, 35},
                                                          {40, 80, 180},   {220, 190, 40}, {50, 140, 60}};
  return palette;
}

CameraModel icub_camera() { return {320, 240, 257.3, 257.3, 160.0, 120.0, 96, 0.068}; }

Pose camera_looking_at(const Vec3& eye, const Vec3& target) {
  Rotation r;
  r.col(2) = (target - eye).normalized();
  r.col(0) = r.col(2).cross(Vec3::UnitZ()).normalized();
  r.col(1) = r.col(2).cross(r.col(0));
  return rigid(r, eye);
}

SessionSimulatorConfig family_session(ToolFamily family, std::uint32_t seed, ExplorationGrasps grasps) {
  SessionSimulatorConfig config;
  config.shape = default_shape(family);
  config.seed = seed;
  config.hand_from_canonical = exploration_grasp(seed, grasps);
  return config;
}

SessionSimulatorConfig model_session(const PointCloud& model, const std::string& name, ToolSymmetry symmetry,
                                     std::uint32_t seed, ExplorationGrasps grasps) {
  SessionSimulatorConfig config;
  config.model = model;
  config.model_name = name;
  config.model_symmetry = symmetry;
  config.seed = seed;
  config.hand_from_canonical = exploration_grasp(seed, grasps);
  return config;
}

SimulatedSession simulate_session(const SessionSimulatorConfig& config) {
  check(config);
  const RenderModel model = render_model(config);
  const ToolGroundTruth truth =
      tool_ground_truth(model.points, tool_symmetry(config), tool_truth_tip(config), config.hand_from_canonical);
  const Box hand_model = hand_box(config);
  // Callers draw the grasp from the same seed; a different stream keeps the two independent.
  Rng rng(config.seed ^ 0x5eed5e55u);

  SimulatedSession session;
  SessionInfo& info = session.info;
  info.robot = "simulated-icub";
  info.hand = config.hand;
  info.tool_label = config.tool_label;
  info.camera = config.camera;
  info.created = config.created;
  info.recorder_name = "simulate-session";
  info.recorder_version = TOOLINC_VERSION;
  info.notes =
      fmt::format("simulated: {}, seed {}",
                  config.model.empty() ? to_string(config.shape.family) : "model " + config.model_name, config.seed);
  for (std::size_t i = 0; i < config.poses.size(); ++i) {
    const Pose root_from_hand = exploration_hand_pose(config.hand, config.poses[i]);
    const Pose root_from_camera = fixate_tool(config, model, root_from_hand * config.hand_from_canonical);

    ViewRecord record;
    record.dir = fmt::format("views/{:03d}", i);
    record.wrist_deg = config.poses[i];
    record.root_from_camera = root_from_camera;
    record.root_from_hand = root_from_hand * kinematic_error(config.kinematic_error_m, config.kinematic_error_deg, rng);
    for (const auto& gross : config.gross_errors)
      if (gross.view == i) record.root_from_hand = record.root_from_hand * gross_error(gross, rng);
    const double stamp = 2.0 * static_cast<double>(i);  // s: a move and the 1 s wait per pose
    record.stamps = {{"hand", stamp}, {"left", stamp}, {"disparity", stamp}};

    session.true_tool_masks.emplace_back();
    session.views.push_back(record_view(config, model, hand_model, root_from_hand, root_from_camera, rng, record.blob,
                                        &session.true_tool_masks.back()));
    info.views.push_back(std::move(record));
    session.true_root_from_hand.push_back(root_from_hand);
  }
  session.ground_truth = ground_truth(config, model, truth, session.true_root_from_hand);
  return session;
}

}  // namespace toolinc
