// A recorded session made offline: the exploration of original-method.md sect. 3-4 (turnHand poses, the
// left eye fixating the tool) rendered with a z-buffer into what the robot records: the left image, the
// stereo module's 8-bit disparity, the closest-blob mask and the organised root-frame cloud, with the
// hand poses the kinematics would report (off by a small error, or a gross one where asked), plus the
// ground truth. Deterministic for a seed.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/record/exploration.hpp"
#include "toolinc/session/session.hpp"
#include "toolinc/synth/elas_stereo.hpp"
#include "toolinc/synth/grasp.hpp"
#include "toolinc/synth/sfm_stereo.hpp"
#include "toolinc/synth/tool_generator.hpp"

namespace toolinc {

// An iCub eye at 320x240: fx = fy = 257.3 px, principal point at the centre, 6.8 cm baseline, 96 disparities.
CameraModel icub_camera();

// A grossly wrong recorded hand pose for one view: a translation of `translation` metres along a random
// direction and a rotation of `rotation_deg` about a random axis, both drawn from the session's seed.
struct GrossError {
  std::size_t view = 0;
  double translation = 0.0;  // m
  double rotation_deg = 0.0;
};

// How the disparity is made: `ideal`, the truth plus Gaussian noise at every pixel of the scene; `sgbm`
// and `elas`, both cameras rendered and matched as the stereo module SFM does, with `SFM --use_sgbm`
// (StereoSGBM, sfm_stereo.hpp) or by default (LIBELAS, elas_stereo.hpp).
enum class StereoModel { ideal, sgbm, elas };

StereoModel stereo_model_from_string(const std::string& name);  // "ideal" | "sgbm" | "elas", else invalid_argument
std::string to_string(StereoModel model);

struct SessionSimulatorConfig {
  // The tool: a procedural shape, or, when `model` is not empty, that cloud in the canonical pose
  // (docs/formats.md) with the symmetry given here; model_name is recorded in the ground truth.
  ToolShape shape = default_shape(ToolFamily::hoe);
  PointCloud model;
  std::string model_name;
  ToolSymmetry model_symmetry = ToolSymmetry::mirror;
  Eigen::Matrix4d hand_from_canonical = Eigen::Matrix4d::Identity();  // the grasp
  std::string hand = "right";                                         // "left" | "right"
  std::optional<std::string> tool_label;
  std::vector<Eigen::Vector2d> poses = paper_exploration_poses();  // wrist (X, Y) degrees per view

  // Recorded root_from_hand = true * error, per view: N(0, kinematic_error_m) per axis and a rotation of
  // N(0, kinematic_error_deg) about a random axis (the arm's calibration and encoder errors).
  double kinematic_error_m = 0.003;
  double kinematic_error_deg = 1.5;
  std::vector<GrossError> gross_errors;  // applied on top of the kinematic error

  StereoModel stereo = StereoModel::elas;
  double disparity_noise_px = 0.15;  // ideal: Gaussian, on the sub-pixel disparity (depth sigma = z^2 sigma / (fx b))
  double pixel_noise = 2.0;          // Gaussian sensor noise per colour channel of each image, in grey levels

  // sgbm and elas: the right eye is the left one moved by camera.baseline along its x (a rectified pair);
  // the disparity is SFM's (sfm; elas matches with `elas`, then SFM's 8-bit scaling and bilateral filter
  // of `sfm`), the points are triangulated from its 16x disparity as SFM's RPC does, and blob.png is the
  // closest blob of the published disparity (dispBlobber) unless renderer_blob, which keeps the
  // renderer's hand-and-tool mask.
  SfmStereoConfig sfm;
  ElasConfig elas;
  bool renderer_blob = false;
  // sgbm's and elas's scene: Lambertian surfaces lit from light_direction (root frame, towards the light: above
  // and in front of the robot) plus ambient light, each surface's albedo modulated by a fixed texture
  // (value noise in the surface's own frame, so both eyes see the same) of this relative contrast:
  Eigen::Vector3d light_direction{-0.5, 0.3, 1.0};
  double ambient = 0.3;         // share of the light that does not depend on the surface's orientation
  double tool_texture = 0.12;   // a plain-coloured tool: moulded plastic or paint with its scuffs and dirt
  double hand_texture = 0.10;   // skin or glove
  double table_texture = 0.30;  // wood grain and stains, on top of the grain's stripes
  double wall_texture = 0.30;   // posters, shelves, paint
  // The tool's colour, r, g, b in 0-255; empty: drawn by the seed from tool_palette(), which every
  // family shares, so colour says little about which tool it is. A model with colours keeps its own.
  std::optional<std::array<int, 3>> tool_rgb;
  // Sessions are recorded on different days: the light's brightness (+/- this share) and the wall's and
  // table's tint (+/- half of it per channel) drawn by the seed. 0: always the same scene.
  double scene_variation = 0.15;
  bool write_points = true;  // points.pcd
  bool write_blob = true;    // blob.png and the view's blob record

  CameraModel camera = icub_camera();
  // The left eye in the root frame, the head bent down towards the hand about 46 cm away: at 320x240
  // (50 deg vertical field) a 30 cm tool pointing up at the head fits whole only from about this far.
  Eigen::Vector3d eye_position{-0.02, -0.034, 0.46};
  // The hand, as an axis-aligned box in the hand frame around the palm and the closed fingers: 9 cm
  // across the palm (X), 7 cm along the handle covering its first 5 cm (Y), 4 cm thick (Z); grown to
  // enclose the handle's first 5 cm when the grasp puts the handle elsewhere.
  Eigen::Vector3d hand_box_min{-0.045, -0.05, -0.02};
  Eigen::Vector3d hand_box_max{0.045, 0.02, 0.02};
  double table_height = -0.05;     // root z of the table top
  double wall_distance = 1.0;      // a wall across root x = -wall_distance, in front of the robot
  double render_spacing = 0.0007;  // m, surface sampling of a procedural tool for rendering

  std::string created = "2026-01-01T00:00:00Z";
  std::uint32_t seed = 1;
};

struct SimulatedSession {
  SessionInfo info;
  std::vector<ViewData> views;
  std::vector<Eigen::Matrix4d> true_root_from_hand;  // per view, without the kinematic and gross errors
  std::vector<cv::Mat> true_tool_masks;              // per view, the tool's own pixels (255; not the hand's)
  Json ground_truth;                                 // also holds true_root_from_hand
};

// root_from_camera of an eye at `eye` looking at `target`: optical z towards it, x to the image's right
// (horizontal in the root frame), y down.
Eigen::Matrix4d camera_looking_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

// The colours tools are painted in (r, g, b), shared by all families: grey, black, red, blue, yellow,
// green, as lab tools are.
const std::vector<std::array<int, 3>>& tool_palette();

// What simulate-session --family F --seed S [--grasp G] records: the family's default shape held with
// exploration_grasp(S, G), everything else at its default.
SessionSimulatorConfig family_session(ToolFamily family, std::uint32_t seed,
                                      ExplorationGrasps grasps = ExplorationGrasps::recorded);
// The same for a canonical model (simulate-session --model FILE --seed S): its symmetry as given.
SessionSimulatorConfig model_session(const PointCloud& model, const std::string& name, ToolSymmetry symmetry,
                                     std::uint32_t seed, ExplorationGrasps grasps = ExplorationGrasps::recorded);

// The configured tool's symmetry and true tooltip rule (a model's from its name's kind, model_kinds.hpp).
ToolSymmetry tool_symmetry(const SessionSimulatorConfig& config);
TruthTip tool_truth_tip(const SessionSimulatorConfig& config);

// Throws std::invalid_argument on a bad hand name, an empty pose list, a gross error for a view that does
// not exist, or a grasp that is not rigid.
SimulatedSession simulate_session(const SessionSimulatorConfig& config);

}  // namespace toolinc
