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
#include "toolinc/io/results_json.hpp"
#include "toolinc/synth/grasp.hpp"

namespace toolinc {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kBlobMargin = 20;            // dispBlobber's ROI margin, px
// px: each sample covers the pixels within this (square) radius, so that a surface sampled at random
// leaves almost no holes for its back to show through (at 0.7 mm spacing and 26 cm, about 8 samples
// reach each pixel); silhouettes grow by up to a pixel.
constexpr double kMinSplatRadius = 1.0;
constexpr double kGripLength = 0.05;       // m of the handle the fingers close around

using Rotation = Eigen::Matrix3d;
using Pose = Eigen::Matrix4d;

Pose rigid(const Rotation& rotation, const Vec3& translation) {
  Pose pose = Pose::Identity();
  pose.topLeftCorner<3, 3>() = rotation;
  pose.topRightCorner<3, 1>() = translation;
  return pose;
}

Pose inverse(const Pose& pose) {
  const Rotation r = pose.topLeftCorner<3, 3>();
  return rigid(r.transpose(), -r.transpose() * pose.topRightCorner<3, 1>());
}

Vec3 apply(const Pose& pose, const Vec3& p) { return pose.topLeftCorner<3, 3>() * p + pose.topRightCorner<3, 1>(); }

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

// --- The scene ---------------------------------------------------------------------------------------

enum class Surface : std::uint8_t { nothing, wall, table, hand, tool };

// BGR, as the images are written.
using Colour = Eigen::Vector3f;
Colour bgr(float r, float g, float b) { return {b, g, r}; }

Colour family_colour(ToolFamily family) {
  switch (family) {
    case ToolFamily::stick: return bgr(170, 60, 40);
    case ToolFamily::hoe: return bgr(40, 150, 60);
    case ToolFamily::hook: return bgr(40, 90, 190);
    case ToolFamily::rake: return bgr(230, 140, 30);
    case ToolFamily::shovel: return bgr(210, 190, 40);
    case ToolFamily::l_stick: return bgr(140, 60, 170);
    case ToolFamily::t_bar: return bgr(30, 170, 180);
    case ToolFamily::flat_top: return bgr(200, 50, 110);
  }
  return bgr(128, 128, 128);
}
const Colour kModelColour = bgr(90, 160, 220);
const Colour kSkin = bgr(225, 180, 150);
const Colour kWood = bgr(150, 105, 60);
const Colour kWall = bgr(200, 200, 190);

// Lambert-like shading with some ambient light, from the cosine between the surface and the ray.
float shade(double cosine) { return static_cast<float>(0.35 + 0.65 * std::abs(cosine)); }

// The tool as it is rendered: dense surface samples in the canonical pose, with colours.
struct RenderModel {
  Points points, normals;     // normals may be empty
  std::vector<Colour> colours;
  double spacing = 0;         // m, typical distance between neighbouring samples
};

double median_neighbour_distance(const Points& points) {
  const KdTree tree(points);
  std::vector<double> distances;
  const std::size_t step = std::max<std::size_t>(1, points.size() / 1000);
  for (std::size_t i = 0; i < points.size(); i += step) {
    const auto near = tree.knn(points[i], 2);
    if (near.size() == 2) distances.push_back(std::sqrt(near[1].distance2));
  }
  if (distances.empty()) return 0.0;
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  return distances[distances.size() / 2];
}

RenderModel render_model(const SessionSimulatorConfig& config) {
  RenderModel model;
  if (config.model.empty()) {
    ToolShape shape = config.shape;
    shape.spacing = config.render_spacing;
    PointCloud cloud = generate_tool(shape, config.seed);
    model.points = std::move(cloud.points);
    model.normals = std::move(cloud.normals);
    model.colours.assign(model.points.size(), family_colour(shape.family));
    model.spacing = shape.spacing;
  } else {
    model.points = config.model.points;
    model.normals = config.model.normals;
    for (std::size_t i = 0; i < model.points.size(); ++i) {
      const auto& c = config.model.has_colors() ? config.model.colors[i] : Rgb{};
      model.colours.push_back(config.model.has_colors() ? bgr(c[0], c[1], c[2]) : kModelColour);
    }
    model.spacing = median_neighbour_distance(model.points);
  }
  return model;
}

// One rendered view: per pixel the camera depth (z), what is seen and its shaded colour.
struct Render {
  int width, height;
  std::vector<double> depth;
  std::vector<Surface> surface;
  std::vector<Colour> colour;
  Render(int w, int h)
      : width(w), height(h), depth(static_cast<std::size_t>(w) * h, std::numeric_limits<double>::infinity()),
        surface(depth.size(), Surface::nothing), colour(depth.size(), Colour::Zero()) {}
  void offer(int u, int v, double z, Surface what, const Colour& c) {
    const std::size_t i = static_cast<std::size_t>(v) * width + u;
    if (z < depth[i]) depth[i] = z, surface[i] = what, colour[i] = c;
  }
};

// The ray through pixel (u, v) in camera coordinates, scaled so that its z is 1: the ray parameter at a
// hit is then the hit's camera depth.
Vec3 pixel_ray(const CameraModel& camera, int u, int v) {
  return {(u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0};
}

struct Box {
  Vec3 lo, hi;
};

// The configured hand, grown so that the fingers close around the handle's first centimetres wherever
// the grasp puts them (the canonical handle starts at the origin and runs along -Y).
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

// Table and wall, and the hand box, by casting each pixel's ray.
void render_ray_cast(const SessionSimulatorConfig& config, const Box& hand, const Pose& root_from_camera,
                     const Pose& hand_from_camera, Render& render) {
  const Rotation root_r = root_from_camera.topLeftCorner<3, 3>(), hand_r = hand_from_camera.topLeftCorner<3, 3>();
  const Vec3 eye = root_from_camera.topRightCorner<3, 1>(), eye_in_hand = hand_from_camera.topRightCorner<3, 1>();
  const Vec3 &lo = hand.lo, &hi = hand.hi;
  for (int v = 0; v < render.height; ++v)
    for (int u = 0; u < render.width; ++u) {
      const Vec3 ray = pixel_ray(config.camera, u, v), d = root_r * ray;
      const double unit = 1.0 / ray.norm();
      if (d.z() < 0) {
        const double t = (config.table_height - eye.z()) / d.z();
        const Vec3 hit = eye + t * d;  // wood grain across root x, wavy along y
        const double grain = 0.85 + 0.15 * std::sin(60.0 * hit.x() + 4.0 * std::sin(15.0 * hit.y()));
        render.offer(u, v, t, Surface::table, kWood * static_cast<float>(grain) * shade(d.z() * unit));
      }
      if (d.x() < 0) {
        const double t = (-config.wall_distance - eye.x()) / d.x();
        render.offer(u, v, t, Surface::wall, kWall * shade(d.x() * unit));
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
      if (face >= 0 && t_in <= t_out) render.offer(u, v, t_in, Surface::hand, kSkin * shade(dh[face] * unit));
    }
}

// The tool by splatting its samples, each over the pixels within its footprint.
void render_tool(const RenderModel& model, const CameraModel& camera, const Pose& camera_from_canonical,
                 Render& render) {
  const Rotation r = camera_from_canonical.topLeftCorner<3, 3>();
  const Vec3 t = camera_from_canonical.topRightCorner<3, 1>();
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    const Vec3 q = r * model.points[i] + t;
    if (q.z() <= 0.01) continue;
    const double u = camera.fx * q.x() / q.z() + camera.cx, v = camera.fy * q.y() / q.z() + camera.cy;
    const double radius = std::max(kMinSplatRadius, 0.8 * model.spacing * camera.fx / q.z());
    const float light = model.normals.empty() ? 1.0f : shade((r * model.normals[i]).dot(q.normalized()));
    const Colour c = model.colours[i] * light;
    const int u0 = std::max(0, static_cast<int>(std::ceil(u - radius)));
    const int u1 = std::min(render.width - 1, static_cast<int>(std::floor(u + radius)));
    const int v0 = std::max(0, static_cast<int>(std::ceil(v - radius)));
    const int v1 = std::min(render.height - 1, static_cast<int>(std::floor(v + radius)));
    for (int pv = v0; pv <= v1; ++pv)
      for (int pu = u0; pu <= u1; ++pu) render.offer(pu, pv, q.z(), Surface::tool, c);
  }
}

// What the stereo module and the blob detector make of a rendered view.
ViewData observe(const Render& render, const SessionSimulatorConfig& config, const Pose& root_from_camera, Rng& rng,
                 std::optional<BlobInfo>& blob) {
  const CameraModel& camera = config.camera;
  const double fb = camera.fx * camera.baseline;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ViewData data;
  data.disparity = cv::Mat::zeros(render.height, render.width, CV_8UC1);
  data.left = cv::Mat(render.height, render.width, CV_8UC3);
  cv::Mat mask = cv::Mat::zeros(render.height, render.width, CV_8UC1);
  Points points(render.depth.size(), Vec3::Constant(nan));
  for (int v = 0; v < render.height; ++v)
    for (int u = 0; u < render.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * render.width + u;
      if (render.surface[i] == Surface::nothing) continue;
      const double d = fb / render.depth[i] + config.disparity_noise_px * rng.gaussian();
      if (render.surface[i] == Surface::hand || render.surface[i] == Surface::tool) mask.at<uchar>(v, u) = 255;
      if (d <= 0 || d > camera.num_disparities) continue;  // beyond the search range: no match
      data.disparity.at<uchar>(v, u) = static_cast<uchar>(std::clamp<long>(std::lround(d * 255.0 / camera.num_disparities), 1, 255));
      points[i] = apply(root_from_camera, (fb / d) * pixel_ray(camera, u, v));
    }
  for (int v = 0; v < render.height; ++v)
    for (int u = 0; u < render.width; ++u) {
      const Colour& c = render.colour[static_cast<std::size_t>(v) * render.width + u];
      auto& pixel = data.left.at<cv::Vec3b>(v, u);
      for (int k = 0; k < 3; ++k) pixel[k] = cv::saturate_cast<uchar>(c[k] + config.pixel_noise * rng.gaussian());
    }
  if (config.write_points) data.points = std::move(points);
  const cv::Moments m = cv::moments(mask, true);
  if (config.write_blob && m.m00 > 0) {
    const cv::Rect box = cv::boundingRect(mask);
    blob = BlobInfo{m.m10 / m.m00, m.m01 / m.m00, m.m00,
                    {std::max(0, box.x - kBlobMargin), std::max(0, box.y - kBlobMargin),
                     std::min(render.width - 1, box.br().x - 1 + kBlobMargin),
                     std::min(render.height - 1, box.br().y - 1 + kBlobMargin)}};
    data.blob = mask;
  }
  return data;
}

// The gaze: like lookAtTool, which refines the fixation from the image, the eye looks at the tool's
// bounding-box centre and then twice re-aims at the centre of the tool's extent in the image, so the
// tool, which matters, is centred despite perspective; the hand may leave the image at the bottom.
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

void check(const SessionSimulatorConfig& config) {
  if (config.hand != "left" && config.hand != "right")
    throw std::invalid_argument("hand must be left or right, not \"" + config.hand + "\"");
  if (config.poses.empty()) throw std::invalid_argument("no exploration poses");
  for (const auto& gross : config.gross_errors)
    if (gross.view >= config.poses.size())
      throw std::invalid_argument(fmt::format("gross error for view {}, but there are {} views", gross.view,
                                              config.poses.size()));
  if (!is_rigid(config.hand_from_canonical)) throw std::invalid_argument("the grasp is not a rigid transform");
  if (!config.model.empty() && config.model.has_colors() && config.model.colors.size() != config.model.size())
    throw std::invalid_argument("the model's colours do not match its points");
}

ToolSymmetry tool_symmetry(const SessionSimulatorConfig& config) {
  return config.model.empty() ? symmetry_of(config.shape.family) : config.model_symmetry;
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

CameraModel icub_camera() { return {320, 240, 257.3, 257.3, 160.0, 120.0, 96, 0.068}; }

std::vector<Eigen::Vector2d> paper_exploration_poses() { return {{0, 0}, {-40, -20}, {30, -20}, {0, -20}, {0, 30}}; }

Pose exploration_hand_pose(const std::string& hand, const Eigen::Vector2d& wrist_deg) {
  const double sign = hand == "left" ? -1.0 : 1.0;
  Rotation base;  // columns: hand x = -root x, hand y = -root z, hand z = -root y (det +1)
  base.col(0) = Vec3(-1, 0, 0);
  base.col(1) = Vec3(0, 0, -1);
  base.col(2) = Vec3(0, -1, 0);
  const Rotation r = base * about(Vec3::UnitX(), sign * wrist_deg.x()) * about(Vec3::UnitY(), sign * wrist_deg.y());
  return rigid(r, Vec3(-0.25, sign * 0.15, 0.10));
}

Pose camera_looking_at(const Vec3& eye, const Vec3& target) {
  Rotation r;
  r.col(2) = (target - eye).normalized();
  r.col(0) = r.col(2).cross(Vec3::UnitZ()).normalized();
  r.col(1) = r.col(2).cross(r.col(0));
  return rigid(r, eye);
}

SimulatedSession simulate_session(const SessionSimulatorConfig& config) {
  check(config);
  const RenderModel model = render_model(config);
  const ToolGroundTruth truth = tool_ground_truth(model.points, tool_symmetry(config), config.hand_from_canonical);
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
  info.notes = fmt::format("simulated: {}, seed {}", config.model.empty() ? to_string(config.shape.family)
                                                                          : "model " + config.model_name,
                           config.seed);
  for (std::size_t i = 0; i < config.poses.size(); ++i) {
    const Pose root_from_hand = exploration_hand_pose(config.hand, config.poses[i]);
    const Pose root_from_camera = fixate_tool(config, model, root_from_hand * config.hand_from_canonical);
    const Pose camera_from_root = inverse(root_from_camera);

    ViewRecord record;
    record.dir = fmt::format("views/{:03d}", i);
    record.wrist_deg = config.poses[i];
    record.root_from_camera = root_from_camera;
    record.root_from_hand = root_from_hand * kinematic_error(config.kinematic_error_m, config.kinematic_error_deg, rng);
    for (const auto& gross : config.gross_errors)
      if (gross.view == i) record.root_from_hand = record.root_from_hand * gross_error(gross, rng);
    const double stamp = 2.0 * static_cast<double>(i);  // s: a move and the 1 s wait per pose
    record.stamps = {{"hand", stamp}, {"left", stamp}, {"disparity", stamp}};

    Render render(config.camera.width, config.camera.height);
    render_ray_cast(config, hand_model, root_from_camera, inverse(root_from_hand) * root_from_camera, render);
    render_tool(model, config.camera, camera_from_root * root_from_hand * config.hand_from_canonical, render);
    session.views.push_back(observe(render, config, root_from_camera, rng, record.blob));
    info.views.push_back(std::move(record));
    session.true_root_from_hand.push_back(root_from_hand);
  }
  session.ground_truth = ground_truth(config, model, truth, session.true_root_from_hand);
  return session;
}

}  // namespace toolinc
