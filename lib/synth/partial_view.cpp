#include "toolinc/synth/partial_view.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/synth/render.hpp"

namespace toolinc {

Points render_partial_view(const SessionSimulatorConfig& scene, const PartialViewConfig& config, Rng& rng) {
  using namespace toolinc::scene;
  const RenderModel model = render_model(scene);
  const Pose root_from_hand = exploration_hand_pose(scene.hand, config.wrist_deg);
  const Pose root_from_camera = fixate_tool(scene, model, root_from_hand * scene.hand_from_canonical);
  const Pose camera_from_canonical = inverse(root_from_camera) * root_from_hand * scene.hand_from_canonical;

  const CameraModel& camera = scene.camera;
  const Render render = render_scene(scene, model, hand_box(scene), root_from_hand, root_from_camera);

  // A sample is seen when its own splat is the front one at the pixel it projects to.
  Points seen;
  for (const Vec3& p : model.points) {
    const Vec3 q = apply(camera_from_canonical, p);
    if (q.z() <= 0.01) continue;
    const long u = std::lround(camera.fx * q.x() / q.z() + camera.cx);
    const long v = std::lround(camera.fy * q.y() / q.z() + camera.cy);
    if (u < 0 || v < 0 || u >= render.width || v >= render.height) continue;
    const std::size_t i = static_cast<std::size_t>(v) * render.width + static_cast<std::size_t>(u);
    if (render.surface[i] == Surface::tool && q.z() <= render.depth[i] + config.depth_tolerance)
      seen.push_back(apply(scene.hand_from_canonical, p));
  }
  Points view = remove_within(voxel_downsample(seen, config.spacing), Vec3::Zero(), config.hand_radius);
  for (Vec3& p : view) p += config.noise_sigma * Vec3(rng.gaussian(), rng.gaussian(), rng.gaussian());
  return view;
}

namespace {

// The case's grasp drawn from rng, the view rendered from `scene` (its tool set), the truth of `model`.
PartialViewCase held_case(SessionSimulatorConfig scene, PointCloud model, ToolSymmetry symmetry, Rng& rng,
                          const GraspRange& range, const PartialViewConfig& config) {
  PartialViewCase c;
  c.shape = scene.shape;
  c.grasp = random_grasp(range, rng);
  scene.hand_from_canonical = c.grasp;
  c.view = render_partial_view(scene, config, rng);
  c.model = std::move(model);
  c.truth = tool_ground_truth(c.model.points, symmetry, tool_truth_tip(scene), c.grasp);
  return c;
}

}  // namespace

PartialViewCase make_partial_view_case(ToolFamily family, std::uint32_t seed, const GraspRange& range,
                                       const PartialViewConfig& config) {
  Rng rng(seed * 7919u + static_cast<std::uint32_t>(family) * 104729u + 23u);
  SessionSimulatorConfig scene;
  scene.shape = default_shape(family);
  for (double* v : {&scene.shape.handle_length, &scene.shape.handle_radius, &scene.shape.head_length,
                    &scene.shape.head_width, &scene.shape.head_height})
    *v *= 1.0 + rng.uniform(-0.15, 0.15);
  scene.seed = seed;
  return held_case(scene, generate_tool(scene.shape, seed + 1), symmetry_of(family), rng, range, config);
}

PartialViewCase make_model_partial_view_case(const PointCloud& model, ToolSymmetry symmetry, std::uint32_t seed,
                                             const GraspRange& range, const PartialViewConfig& config) {
  Rng rng(seed * 7919u + 23u);
  SessionSimulatorConfig scene;
  scene.model = model;
  scene.model_symmetry = symmetry;
  scene.seed = seed;
  return held_case(scene, model, symmetry, rng, range, config);
}

PoseErrors pose_errors(const PartialViewCase& c, const Eigen::Matrix4d& estimate) {
  const Eigen::Matrix3d d = c.grasp.topLeftCorner<3, 3>().transpose() * estimate.topLeftCorner<3, 3>();
  PoseErrors e;
  switch (c.truth.symmetry) {
    case ToolSymmetry::axial:  // the angle between the handles
      e.rotation_deg = std::acos(std::clamp(d(1, 1), -1.0, 1.0)) * 180.0 / M_PI;
      break;
    case ToolSymmetry::front_back:
    case ToolSymmetry::fourfold: {  // the nearest of the turns about the handle that map the tool onto itself
      const int turns = c.truth.symmetry == ToolSymmetry::fourfold ? 4 : 2;
      e.rotation_deg = std::numeric_limits<double>::infinity();
      for (int k = 0; k < turns; ++k)
        e.rotation_deg =
            std::min(e.rotation_deg, rotation_angle_deg(d * Eigen::AngleAxisd(2 * M_PI * k / turns, Vec3::UnitY())));
      break;
    }
    case ToolSymmetry::mirror:
      e.rotation_deg = rotation_angle_deg(d);
      break;
  }
  e.translation_m = (estimate.topRightCorner<3, 1>() - c.grasp.topRightCorner<3, 1>()).norm();
  e.tooltip_m = tooltip_error(
      c.truth, tool_ground_truth(c.model.points, c.truth.symmetry, c.truth.tip, estimate).tooltips.front());
  return e;
}

}  // namespace toolinc
