#include "toolinc/synth/render.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/session/blob.hpp"
#include "toolinc/synth/elas_stereo.hpp"
#include "toolinc/synth/sfm_stereo.hpp"

namespace toolinc::scene {
namespace {

using Rotation = Eigen::Matrix3d;

// px: each sample covers the pixels within this (square) radius, so that a surface sampled at random
// leaves almost no holes for its back to show through (at 0.7 mm spacing and 26 cm, about 8 samples
// reach each pixel); silhouettes grow by up to a pixel.
constexpr double kMinSplatRadius = 1.0;
constexpr double kGripLength = 0.05;  // m of the handle the fingers close around
constexpr int kBlobMargin = 20;       // dispBlobber's ROI margin, px

Colour bgr(float r, float g, float b) { return {b, g, r}; }

const Colour kSkin = bgr(225, 180, 150);
const Colour kWood = bgr(150, 105, 60);
const Colour kWall = bgr(200, 200, 190);

// The session's look: its tool colour and light, and the wall's and table's tint, drawn from a stream of
// the seed of their own so that the geometry and the noise do not change with them.
struct Look {
  Colour tool, wall, wood, skin;
};

Look scene_look(const SessionSimulatorConfig& config) {
  Rng rng(config.seed ^ 0xc0105eedu);
  const auto& palette = tool_palette();
  const auto drawn = palette[rng.index(static_cast<std::uint32_t>(palette.size()))];
  const auto rgb = config.tool_rgb.value_or(drawn);
  const double v = config.scene_variation;
  const auto light = static_cast<float>(1.0 + v * rng.uniform(-1, 1));
  const auto tint = [&](Colour c) {
    for (int k = 0; k < 3; ++k) c[k] *= static_cast<float>(1.0 + 0.5 * v * rng.uniform(-1, 1));
    return Colour(c * light);
  };
  const Colour wall = tint(kWall), wood = tint(kWood);
  return {bgr(rgb[0], rgb[1], rgb[2]) * light, wall, wood, kSkin * light};
}

// Lambert-like shading with some ambient light, from the cosine between the surface and the ray.
float shade(double cosine) { return static_cast<float>(0.35 + 0.65 * std::abs(cosine)); }

// Smooth value noise in [-1, 1] with features about `scale` apart: a hashed random value at each corner
// of the lattice of p / scale, interpolated with smoothstep weights. A function of the position alone,
// so both eyes see the same texture.
double value_noise(const Vec3& p, double scale) {
  const Vec3 q = p / scale;
  const Eigen::Vector3d base = q.array().floor();
  const Eigen::Vector3d f = q - base, w = f.array() * f.array() * (3.0 - 2.0 * f.array());
  double value = 0;
  for (int corner = 0; corner < 8; ++corner) {
    std::uint32_t h = 0x9e3779b9u;
    double weight = 1;
    for (int a = 0; a < 3; ++a) {
      const int bit = (corner >> a) & 1;
      h = (h ^ static_cast<std::uint32_t>(static_cast<std::int64_t>(base[a]) + bit)) * 0x85ebca6bu;
      h ^= h >> 13;
      weight *= bit ? w[a] : 1 - w[a];
    }
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    value += weight * (h * (2.0 / 4294967295.0) - 1.0);
  }
  return value;
}

// A surface texture: two octaves of value noise, the coarse one `scale` apart.
float texture(const Vec3& p, double scale, double contrast) {
  return static_cast<float>(1.0 + contrast * (0.65 * value_noise(p, scale) + 0.35 * value_noise(p, scale / 2.9)));
}

// Lambertian reflection of a light from `light` (unit, towards it) plus ambient light, the normal turned
// towards the viewer (`view` runs from the eye to the surface).
float lambert(Vec3 normal, const Vec3& view, const Vec3& light, double ambient) {
  if (normal.dot(view) > 0) normal = -normal;
  return static_cast<float>(ambient + (1.0 - ambient) * std::max(0.0, normal.dot(light)));
}

constexpr double kToolTextureScale = 0.004;  // m: a few pixels on a tool at 45 cm
constexpr double kHandTextureScale = 0.003;
constexpr double kTableTextureScale = 0.006;
constexpr double kWallTextureScale = 0.02;  // at 1 m and more, 1 px is 4 mm

double median_neighbour_distance(const Points& points) {
  const KdTree tree(points);
  std::vector<double> distances;
  const std::size_t step = std::max<std::size_t>(1, points.size() / 1000);
  for (std::size_t i = 0; i < points.size(); i += step) {
    const auto near = tree.knn(points[i], 2);
    if (near.size() == 2) distances.push_back(std::sqrt(near[1].distance2));
  }
  return distances.empty() ? 0.0 : median(std::move(distances));
}

}  // namespace

RenderModel render_model(const SessionSimulatorConfig& config) {
  RenderModel model;
  if (config.model.empty()) {
    ToolShape shape = config.shape;
    shape.spacing = config.render_spacing;
    PointCloud cloud = generate_tool(shape, config.seed);
    model.points = std::move(cloud.points);
    model.normals = std::move(cloud.normals);
    model.colours.assign(model.points.size(), scene_look(config).tool);
    model.spacing = shape.spacing;
  } else {
    model.points = config.model.points;
    model.normals = config.model.normals;
    const Colour plain = scene_look(config).tool;
    for (std::size_t i = 0; i < model.points.size(); ++i) {
      const auto& c = config.model.has_colors() ? config.model.colors[i] : Rgb{};
      model.colours.push_back(config.model.has_colors() ? bgr(c[0], c[1], c[2]) : plain);
    }
    model.spacing = median_neighbour_distance(model.points);
  }
  if (config.stereo != StereoModel::ideal)
    for (std::size_t i = 0; i < model.points.size(); ++i)
      model.colours[i] *= texture(model.points[i], kToolTextureScale, config.tool_texture);
  return model;
}

Vec3 pixel_ray(const CameraModel& camera, int u, int v) {
  return {(u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0};
}

Box hand_box(const SessionSimulatorConfig& config) {
  const double radius = config.model.empty() ? config.shape.handle_radius : 0.01;
  Box box{config.hand_box_min, config.hand_box_max};
  for (const Vec3& end : {Vec3(0, 0, 0), Vec3(0, -kGripLength, 0)}) {
    const Vec3 p = apply(config.hand_from_canonical, end);
    box.lo = box.lo.cwiseMin(p - Vec3::Constant(radius));
    box.hi = box.hi.cwiseMax(p + Vec3::Constant(radius));
  }
  return box;
}

void render_ray_cast(const SessionSimulatorConfig& config, const Box& hand, const Pose& root_from_camera,
                     const Pose& hand_from_camera, Render& render) {
  const Rotation root_r = root_from_camera.topLeftCorner<3, 3>(), hand_r = hand_from_camera.topLeftCorner<3, 3>();
  const Vec3 eye = root_from_camera.topRightCorner<3, 1>(), eye_in_hand = hand_from_camera.topRightCorner<3, 1>();
  const Vec3 &lo = hand.lo, &hi = hand.hi;
  const bool lit = config.stereo != StereoModel::ideal;
  const Vec3 light = config.light_direction.normalized(), light_in_hand = hand_r * root_r.transpose() * light;
  const Look look = scene_look(config);
  for (int v = 0; v < render.height; ++v)
    for (int u = 0; u < render.width; ++u) {
      const Vec3 ray = pixel_ray(config.camera, u, v), d = root_r * ray;
      const double unit = 1.0 / ray.norm();
      if (d.z() < 0) {
        const double t = (config.table_height - eye.z()) / d.z();
        const Vec3 hit = eye + t * d;  // wood grain across root x, wavy along y
        const double grain = 0.85 + 0.15 * std::sin(60.0 * hit.x() + 4.0 * std::sin(15.0 * hit.y()));
        const Colour wood = look.wood * static_cast<float>(grain);
        render.offer(u, v, t, Surface::table,
                     lit ? Colour(wood * texture(hit, kTableTextureScale, config.table_texture) *
                                  lambert(Vec3::UnitZ(), d, light, config.ambient))
                         : Colour(wood * shade(d.z() * unit)));
      }
      if (d.x() < 0) {
        const double t = (-config.wall_distance - eye.x()) / d.x();
        render.offer(u, v, t, Surface::wall,
                     lit ? Colour(look.wall * texture(eye + t * d, kWallTextureScale, config.wall_texture) *
                                  lambert(Vec3::UnitX(), d, light, config.ambient))
                         : Colour(look.wall * shade(d.x() * unit)));
      }
      // Slab test in the hand frame; the entry face's axis shades it.
      const Vec3 dh = hand_r * ray;
      double t_in = 0, t_out = std::numeric_limits<double>::infinity();
      int face = -1;
      for (int a = 0; a < 3 && t_in <= t_out; ++a) {
        if (std::abs(dh[a]) < 1e-12) {
          if (eye_in_hand[a] < lo[a] || eye_in_hand[a] > hi[a]) t_out = -1;
          continue;
        }
        double t0 = (lo[a] - eye_in_hand[a]) / dh[a], t1 = (hi[a] - eye_in_hand[a]) / dh[a];
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > t_in) t_in = t0, face = a;
        t_out = std::min(t_out, t1);
      }
      if (face < 0 || t_in > t_out) continue;
      render.offer(u, v, t_in, Surface::hand,
                   lit ? Colour(look.skin * texture(eye_in_hand + t_in * dh, kHandTextureScale, config.hand_texture) *
                                lambert(Vec3::Unit(face), dh, light_in_hand, config.ambient))
                       : Colour(look.skin * shade(dh[face] * unit)));
    }
}

// The tool by splatting its samples, each over the pixels within its footprint.
void render_tool(const RenderModel& model, const CameraModel& camera, const Pose& camera_from_canonical, Render& render,
                 const Lighting* lighting) {
  const Rotation r = camera_from_canonical.topLeftCorner<3, 3>();
  const Vec3 t = camera_from_canonical.topRightCorner<3, 1>();
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    const Vec3 q = r * model.points[i] + t;
    if (q.z() <= 0.01) continue;
    const double u = camera.fx * q.x() / q.z() + camera.cx, v = camera.fy * q.y() / q.z() + camera.cy;
    const double radius = std::max(kMinSplatRadius, 0.8 * model.spacing * camera.fx / q.z());
    const float light = model.normals.empty() ? 1.0f
                        : lighting            ? lambert(r * model.normals[i], q, lighting->direction, lighting->ambient)
                                              : shade((r * model.normals[i]).dot(q.normalized()));
    const Colour c = model.colours[i] * light;
    const int u0 = std::max(0, static_cast<int>(std::ceil(u - radius)));
    const int u1 = std::min(render.width - 1, static_cast<int>(std::floor(u + radius)));
    const int v0 = std::max(0, static_cast<int>(std::ceil(v - radius)));
    const int v1 = std::min(render.height - 1, static_cast<int>(std::floor(v + radius)));
    for (int pv = v0; pv <= v1; ++pv)
      for (int pu = u0; pu <= u1; ++pu) render.offer(pu, pv, q.z(), Surface::tool, c);
  }
}

Render render_scene(const SessionSimulatorConfig& config, const RenderModel& model, const Box& hand,
                    const Pose& root_from_hand, const Pose& root_from_camera) {
  Render render(config.camera.width, config.camera.height);
  render_ray_cast(config, hand, root_from_camera, inverse(root_from_hand) * root_from_camera, render);
  const Lighting lighting{root_from_camera.topLeftCorner<3, 3>().transpose() * config.light_direction.normalized(),
                          config.ambient};
  render_tool(model, config.camera, inverse(root_from_camera) * root_from_hand * config.hand_from_canonical, render,
              config.stereo != StereoModel::ideal ? &lighting : nullptr);
  return render;
}

namespace {

// The view's blob: the mask and its dispBlobber record (centroid, area, box grown by the ROI margin).
void set_blob(const cv::Mat& mask, ViewData& data, std::optional<BlobInfo>& blob) {
  const cv::Moments m = cv::moments(mask, true);
  if (m.m00 <= 0) return;
  const cv::Rect box = cv::boundingRect(mask);
  blob = BlobInfo{
      m.m10 / m.m00,
      m.m01 / m.m00,
      m.m00,
      {std::max(0, box.x - kBlobMargin), std::max(0, box.y - kBlobMargin),
       std::min(mask.cols - 1, box.br().x - 1 + kBlobMargin), std::min(mask.rows - 1, box.br().y - 1 + kBlobMargin)}};
  data.blob = mask;
}

cv::Mat surface_mask(const Render& render, bool with_hand) {
  cv::Mat mask = cv::Mat::zeros(render.height, render.width, CV_8UC1);
  for (int v = 0; v < render.height; ++v)
    for (int u = 0; u < render.width; ++u) {
      const Surface s = render.surface[static_cast<std::size_t>(v) * render.width + u];
      if (s == Surface::tool || (with_hand && s == Surface::hand)) mask.at<uchar>(v, u) = 255;
    }
  return mask;
}

cv::Mat hand_and_tool_mask(const Render& render) { return surface_mask(render, true); }

cv::Mat camera_image(const Render& render, double noise, Rng& rng) {
  cv::Mat image(render.height, render.width, CV_8UC3);
  for (int v = 0; v < render.height; ++v)
    for (int u = 0; u < render.width; ++u) {
      const Colour& c = render.colour[static_cast<std::size_t>(v) * render.width + u];
      auto& pixel = image.at<cv::Vec3b>(v, u);
      for (int k = 0; k < 3; ++k) pixel[k] = cv::saturate_cast<uchar>(c[k] + noise * rng.gaussian());
    }
  return image;
}

}  // namespace

ViewData observe(const Render& render, const SessionSimulatorConfig& config, const Pose& root_from_camera, Rng& rng,
                 std::optional<BlobInfo>& blob) {
  const CameraModel& camera = config.camera;
  const double fb = camera.fx * camera.baseline;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ViewData data;
  data.disparity = cv::Mat::zeros(render.height, render.width, CV_8UC1);
  Points points(render.depth.size(), Vec3::Constant(nan));
  for (int v = 0; v < render.height; ++v)
    for (int u = 0; u < render.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * render.width + u;
      if (render.surface[i] == Surface::nothing) continue;
      const double d = fb / render.depth[i] + config.disparity_noise_px * rng.gaussian();
      if (d <= 0 || d > camera.num_disparities) continue;  // beyond the search range: no match
      data.disparity.at<uchar>(v, u) =
          static_cast<uchar>(std::clamp<long>(std::lround(d * 255.0 / camera.num_disparities), 1, 255));
      points[i] = apply(root_from_camera, (fb / d) * pixel_ray(camera, u, v));
    }
  data.left = camera_image(render, config.pixel_noise, rng);
  if (config.write_points) data.points = std::move(points);
  if (config.write_blob) set_blob(hand_and_tool_mask(render), data, blob);
  return data;
}

ViewData observe_stereo(const Render& left, const Render& right, const SessionSimulatorConfig& config,
                        const Pose& root_from_camera, Rng& rng, std::optional<BlobInfo>& blob) {
  const CameraModel& camera = config.camera;
  ViewData data;
  data.left = camera_image(left, config.pixel_noise, rng);
  const cv::Mat right_image = camera_image(right, config.pixel_noise, rng);
  const cv::Mat disparity16 = config.stereo == StereoModel::elas ? elas_disparity16(data.left, right_image, config.elas)
                                                                 : sfm_disparity16(data.left, right_image, config.sfm);
  data.disparity = sfm_disparity8(disparity16, config.sfm);
  if (config.write_points) {
    // SFM's RPC: the unfiltered 16x disparity through the rectified pair's reprojection; no match -> NaN.
    const double fb = camera.fx * camera.baseline;
    data.points.assign(static_cast<std::size_t>(left.width) * left.height,
                       Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
    for (int v = 0; v < left.height; ++v)
      for (int u = 0; u < left.width; ++u) {
        const int value = disparity16.at<std::int16_t>(v, u);
        if (value > 0)
          data.points[static_cast<std::size_t>(v) * left.width + u] =
              apply(root_from_camera, (16.0 * fb / value) * pixel_ray(camera, u, v));
      }
  }
  if (config.write_blob)
    set_blob(config.renderer_blob ? hand_and_tool_mask(left) : closest_blob_mask(data.disparity), data, blob);
  return data;
}

ViewData record_view(const SessionSimulatorConfig& config, const RenderModel& model, const Box& hand,
                     const Pose& root_from_hand, const Pose& root_from_camera, Rng& rng, std::optional<BlobInfo>& blob,
                     cv::Mat* true_tool_mask) {
  const Render left = render_scene(config, model, hand, root_from_hand, root_from_camera);
  if (true_tool_mask) *true_tool_mask = surface_mask(left, false);
  if (config.stereo == StereoModel::ideal) return observe(left, config, root_from_camera, rng, blob);
  Pose root_from_right = root_from_camera;
  root_from_right.topRightCorner<3, 1>() += config.camera.baseline * root_from_camera.topLeftCorner<3, 1>();
  const Render right = render_scene(config, model, hand, root_from_hand, root_from_right);
  return observe_stereo(left, right, config, root_from_camera, rng, blob);
}

Pose fixate_tool(const SessionSimulatorConfig& config, const RenderModel& model, const Pose& root_from_canonical) {
  Points tool;
  tool.reserve(model.points.size());
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& p : model.points) {
    tool.push_back(apply(root_from_canonical, p));
    lo = lo.cwiseMin(tool.back()), hi = hi.cwiseMax(tool.back());
  }
  const CameraModel& camera = config.camera;
  Vec3 target = (lo + hi) / 2;
  Pose root_from_camera = camera_looking_at(config.eye_position, target);
  for (int step = 0; step < 2; ++step) {
    const Pose camera_from_root = inverse(root_from_camera);
    Eigen::Vector2d image_lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), image_hi = -image_lo;
    for (const Vec3& p : tool) {
      const Vec3 q = apply(camera_from_root, p);
      if (q.z() <= 0.01) continue;
      const Eigen::Vector2d pixel(camera.fx * q.x() / q.z() + camera.cx, camera.fy * q.y() / q.z() + camera.cy);
      image_lo = image_lo.cwiseMin(pixel), image_hi = image_hi.cwiseMax(pixel);
    }
    const Eigen::Vector2d centre = (image_lo + image_hi) / 2;
    const double depth = apply(camera_from_root, target).z();
    const Vec3 ray((centre.x() - camera.cx) / camera.fx, (centre.y() - camera.cy) / camera.fy, 1.0);
    target = apply(root_from_camera, depth * ray);
    root_from_camera = camera_looking_at(config.eye_position, target);
  }
  return root_from_camera;
}

}  // namespace toolinc::scene
