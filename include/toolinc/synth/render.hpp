// The simulated exploration scene rendered with a z-buffer on the left camera's image: the tool (splatted
// surface samples), the hand (a box), the table and the wall. Shared by the session simulator, which turns
// a render into what the robot records, and the partial-view renderer, which keeps the tool's visible
// points.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/session/session.hpp"
#include "toolinc/synth/session_simulator.hpp"

namespace toolinc::scene {

using Pose = Eigen::Matrix4d;

enum class Surface : std::uint8_t { nothing, wall, table, hand, tool };

// BGR, as the images are written.
using Colour = Eigen::Vector3f;

// The tool as it is rendered: dense surface samples in the canonical pose, with colours.
struct RenderModel {
  Points points, normals;  // normals may be empty
  std::vector<Colour> colours;
  double spacing = 0;  // m, typical distance between neighbouring samples
};

// The configured procedural shape sampled at render_spacing, or the configured model as it is.
RenderModel render_model(const SessionSimulatorConfig& config);

// One rendered view: per pixel the camera depth (z), what is seen and its shaded colour.
struct Render {
  int width, height;
  std::vector<double> depth;
  std::vector<Surface> surface;
  std::vector<Colour> colour;
  Render(int w, int h)
      : width(w),
        height(h),
        depth(static_cast<std::size_t>(w) * h, std::numeric_limits<double>::infinity()),
        surface(depth.size(), Surface::nothing),
        colour(depth.size(), Colour::Zero()) {}
  void offer(int u, int v, double z, Surface what, const Colour& c) {
    const std::size_t i = static_cast<std::size_t>(v) * width + u;
    if (z < depth[i]) depth[i] = z, surface[i] = what, colour[i] = c;
  }
};

// The ray through pixel (u, v) in camera coordinates, scaled so that its z is 1: the ray parameter at a
// hit is then the hit's camera depth.
Vec3 pixel_ray(const CameraModel& camera, int u, int v);

struct Box {
  Vec3 lo, hi;
};

// The configured hand, grown so that the fingers close around the handle's first centimetres wherever
// the grasp puts them (the canonical handle starts at the origin and runs along -Y).
Box hand_box(const SessionSimulatorConfig& config);

// Table and wall, and the hand box, by casting each pixel's ray.
void render_ray_cast(const SessionSimulatorConfig& config, const Box& hand, const Pose& root_from_camera,
                     const Pose& hand_from_camera, Render& render);

// Directional light in the camera frame (unit, towards the light) and the ambient share.
struct Lighting {
  Vec3 direction;
  double ambient;
};

// The tool by splatting its samples, each over the pixels within its footprint; shaded by `lighting`
// (Lambertian) when given, else by the cosine between the surface and the ray.
void render_tool(const RenderModel& model, const CameraModel& camera, const Pose& camera_from_canonical, Render& render,
                 const Lighting* lighting = nullptr);

// The whole scene: table, wall and hand by ray casting, then the tool held with config.hand_from_canonical;
// with config.stereo sgbm, textured and lit as config says.
Render render_scene(const SessionSimulatorConfig& config, const RenderModel& model, const Box& hand,
                    const Pose& root_from_hand, const Pose& root_from_camera);

// What the stereo module and the blob detector make of a render: the left image with pixel noise, the 8-bit
// disparity (noisy, quantised), the organised root-frame points triangulated from the un-quantised
// disparity (when config.write_points) and the hand-and-tool blob mask with its dispBlobber record (when
// config.write_blob and the blob is in view). Shared by the session simulator and the recorder's
// simulated backend.
ViewData observe(const Render& render, const SessionSimulatorConfig& config, const Pose& root_from_camera, Rng& rng,
                 std::optional<BlobInfo>& blob);

// What SFM (with --use_sgbm) and dispBlobber make of a rendered rectified pair: the noisy left image,
// SFM's published 8-bit disparity, the points triangulated from its 16x disparity (when
// config.write_points) and the closest blob of the disparity, or the renderer's mask when
// config.renderer_blob (when config.write_blob and there is a blob).
ViewData observe_stereo(const Render& left, const Render& right, const SessionSimulatorConfig& config,
                        const Pose& root_from_camera, Rng& rng, std::optional<BlobInfo>& blob);

// One view as config.stereo says: the left render observed (ideal), or both eyes rendered and matched.
// true_tool_mask, when given, receives the tool's own pixels in the left image (255; the hand's not).
ViewData record_view(const SessionSimulatorConfig& config, const RenderModel& model, const Box& hand,
                     const Pose& root_from_hand, const Pose& root_from_camera, Rng& rng, std::optional<BlobInfo>& blob,
                     cv::Mat* true_tool_mask = nullptr);

// The gaze: like lookAtTool, which refines the fixation from the image, the eye looks at the tool's
// bounding-box centre and then twice re-aims at the centre of the tool's extent in the image, so the
// tool, which matters, is centred despite perspective; the hand may leave the image at the bottom.
// Returns root_from_camera.
Pose fixate_tool(const SessionSimulatorConfig& config, const RenderModel& model, const Pose& root_from_canonical);

}  // namespace toolinc::scene
