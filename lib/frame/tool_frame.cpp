#include "toolinc/frame/tool_frame.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>

#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/frame/cylinder_fit.hpp"
#include "toolinc/frame/symmetry.hpp"

namespace toolinc {
namespace {

constexpr double kDeg = M_PI / 180.0;

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

void check_not_degenerate(const Points& input, const Points& outside, const Points& cloud,
                          const PrincipalAxes& axes, const ToolFrameConfig& config) {
  if (!input.empty() && outside.empty())
    throw MethodError(fmt::format("all {} points lie within the hand radius ({} m)", input.size(),
                                  config.hand_radius));
  if (static_cast<int>(outside.size()) < config.min_points)
    throw MethodError(fmt::format("too few points: {} outside the hand radius, at least {} needed",
                                  outside.size(), config.min_points));
  if (cloud.size() < 10)
    throw MethodError(fmt::format("too few points after removing stray points: {}", cloud.size()));
  double lo = 0.0, hi = 0.0;
  for (const auto& p : cloud) {
    const double t = (p - axes.centroid).dot(axes.axes.col(0));
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  if (hi - lo < config.min_length)
    throw MethodError(fmt::format("the points span only {:.4f} m along their major axis (min_length {} m)",
                                  hi - lo, config.min_length));
  if (std::sqrt(axes.eigenvalues[1]) < config.min_thickness)
    throw MethodError(fmt::format("the points are collinear: RMS spread across the major axis {:.2e} m "
                                  "(min_thickness {} m)", std::sqrt(axes.eigenvalues[1]), config.min_thickness));
  if (std::sqrt(axes.eigenvalues[2]) < config.min_thickness)
    throw MethodError(fmt::format("the points are planar: RMS spread across their plane {:.2e} m "
                                  "(min_thickness {} m)", std::sqrt(axes.eigenvalues[2]), config.min_thickness));
}

struct HandleFit {
  Vec3 axis;   // towards the hand
  Vec3 point;  // on the axis line
  int points = 0;
  double radius = 0.0, rms = 0.0;
  bool cylinder = true;  // false: the handle's points did not form a surface, their principal axis is used
};

// The major axis is tilted by a heavy head (7-26 degrees on hooks and L-shapes in the original), so
// the handle axis is refitted from the handle's own points: those in the hand-side part of the tool's
// length that lie on the current handle cylinder. A cylinder fit, unlike a principal axis, is not
// tilted by the slanted cut the hand sphere leaves or by uneven coverage of the handle.
HandleFit fit_handle(const Points& cloud, const PrincipalAxes& principal, const ToolFrameConfig& config) {
  Cylinder handle;
  handle.axis = principal.axes.col(0);
  handle.point = principal.centroid;
  if (handle.axis.dot(-principal.centroid) < 0) handle.axis = -handle.axis;
  HandleFit fit{handle.axis, handle.point, 0, 0.0, 0.0, true};
  std::vector<double> along(cloud.size()), radial;
  Points slab;
  for (int iteration = 0; iteration < config.handle_iterations; ++iteration) {
    for (std::size_t i = 0; i < cloud.size(); ++i) along[i] = (cloud[i] - handle.point).dot(handle.axis);
    const double hand_end = quantile(along, 0.99), far_end = quantile(along, 0.01);
    const double start = hand_end - config.handle_fraction * (hand_end - far_end);
    slab.clear();
    radial.clear();
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (along[i] >= start) {
        slab.push_back(cloud[i]);
        radial.push_back(radial_distance(handle, cloud[i]));
      }
    if (slab.size() < 10) break;
    // On the first pass the radius is unknown: points far beyond the median radius are not handle.
    const double expected = iteration == 0 ? quantile(radial, 0.5) : handle.radius;
    const double band = iteration == 0 ? (config.handle_radial_factor - 1.0) * expected + 0.5 * config.voxel_size
                                       : std::max(3.0 * handle.rms, config.voxel_size);
    Points on_handle;
    for (std::size_t j = 0; j < slab.size(); ++j)
      if (std::abs(radial[j] - expected) <= band) on_handle.push_back(slab[j]);
    if (on_handle.size() < 10) break;
    Cylinder refit = fit_cylinder(on_handle, {handle.point, handle.axis, expected, 0.0}, config.handle_residual_scale);
    // A surface leaves no points near its axis; a filled model leaves about a quarter inside half the radius.
    int inside = 0, within = 0;
    for (const auto& p : slab) {
      const double r = radial_distance(refit, p);
      within += r <= refit.radius + band;
      inside += r < 0.5 * refit.radius;
    }
    // A cylinder far wider than a handle is a fit that ran off on a half-seen handle: not trusted either.
    const bool surface = inside <= config.handle_solid_fraction * within && refit.radius <= config.handle_max_radius;
    if (!surface) {
      // Not a surface (a filled model, or no handle cylinder to speak of): the points' own line.
      const PrincipalAxes line = principal_axes(on_handle);
      refit = {line.centroid, line.axes.col(0), quantile(radial, 0.5), refit.rms};
    }
    if (refit.axis.dot(handle.axis) < 0) refit.axis = -refit.axis;
    const double change = std::acos(std::clamp(refit.axis.dot(handle.axis), -1.0, 1.0));
    handle = refit;
    fit = {handle.axis, handle.point, static_cast<int>(on_handle.size()), handle.radius, handle.rms, surface};
    if (change < 1e-5) break;
  }
  return fit;
}

struct Reach {
  double positive, negative;  // m, along +X and -X from the handle axis
};

// Seen along the handle, the head of a bar-like tool (L, T, hook) lies along a line, and the symmetry
// plane contains it. Returns the angle (in the u, v basis about the handle) of the plane's normal when
// the head's points beyond min_distance from the handle axis are spread along a line at least
// min_elongation times more than across it; nothing for plates and combs (hoe, rake, flat top).
std::optional<double> head_line_normal_angle(const Points& cloud, const Vec3& handle_point, const Vec3& centroid,
                                             const Vec3& y_axis, const Vec3& u, const Vec3& v,
                                             double min_distance, double min_elongation) {
  std::vector<Eigen::Vector2d> head;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : cloud) {
    const Eigen::Vector2d q((p - handle_point).dot(u), (p - handle_point).dot(v));
    if (q.norm() < min_distance || (p - centroid).dot(y_axis) >= 0) continue;
    head.push_back(q);
    mean += q;
  }
  if (head.size() < 20) return std::nullopt;
  mean /= static_cast<double>(head.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const auto& q : head) covariance += (q - mean) * (q - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(covariance);
  if (solver.eigenvalues()(1) < min_elongation * std::max(solver.eigenvalues()(0), 1e-12)) return std::nullopt;
  const Eigen::Vector2d line = solver.eigenvectors().col(1);
  return std::atan2(line.y(), line.x()) + M_PI / 2;
}

// How far the effector reaches on each side of the handle axis along x_axis, measured robustly on the
// effector side of the handle plane.
Reach effector_reach(const Points& cloud, const Vec3& centre, const Vec3& handle_point, const Vec3& y_axis,
                     const Vec3& x_axis, double q) {
  std::vector<double> forward, backward;
  for (const auto& p : cloud) {
    if ((p - centre).dot(y_axis) >= 0) continue;
    const double x = (p - handle_point).dot(x_axis);
    forward.push_back(x);
    backward.push_back(-x);
  }
  return {quantile(forward, q), quantile(backward, q)};
}

// Golden-section search for the minimum of f on [lo, hi].
template <typename F>
double golden_minimum(F&& f, double lo, double hi, int iterations) {
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
  double fa = f(a), fb = f(b);
  for (int i = 0; i < iterations; ++i) {
    if (fa <= fb) {
      hi = b, b = a, fb = fa;
      a = hi - ratio * (hi - lo), fa = f(a);
    } else {
      lo = a, a = b, fa = fb;
      b = lo + ratio * (hi - lo), fb = f(b);
    }
  }
  return fa <= fb ? a : b;
}

}  // namespace

Eigen::Matrix4d ToolFrame::hand_from_tool() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = axes;
  m.topRightCorner<3, 1>() = origin;
  return m;
}

ToolFrame estimate_tool_frame(const Points& input, const ToolFrameConfig& config, const Points& viewpoints) {
  ToolFrame frame;
  const Points outside = remove_within(input, Vec3::Zero(), config.hand_radius);
  const Points cloud = outside.empty() ? Points{}
                                       : remove_isolated(voxel_downsample(outside, config.voxel_size),
                                                         config.isolated_radius, config.isolated_min_neighbors);
  const PrincipalAxes principal = principal_axes(cloud);
  check_not_degenerate(input, outside, cloud, principal, config);
  frame.points_input = static_cast<int>(input.size());
  frame.points_outside_hand = static_cast<int>(outside.size());
  frame.points_used = static_cast<int>(cloud.size());
  frame.centroid = principal.centroid;
  frame.principal = principal.axes;
  frame.eigenvalues = principal.eigenvalues;

  // Handle axis (Y), signed towards the hand at the origin.
  const HandleFit handle = fit_handle(cloud, principal, config);
  const Vec3 y_axis = handle.axis.normalized();
  frame.handle_point = handle.point;
  frame.handle_points = handle.points;
  frame.handle_radius = handle.radius;
  frame.handle_rms = handle.rms;
  frame.handle_cylinder = handle.cylinder;
  frame.handle_refinement_deg = std::acos(std::min(1.0, std::abs(y_axis.dot(principal.axes.col(0))))) / kDeg;
  frame.handle_sign_rule = "towards the hand: the hand origin lies on the +Y side of the handle";

  // Symmetry plane: it contains the handle axis, so sweep its normal about Y, then refine the best
  // angle and the plane's offset. The plane across the handle is scored for the record only.
  Vec3 u = principal.axes.col(1) - principal.axes.col(1).dot(y_axis) * y_axis;
  if (u.norm() < 1e-6) u = principal.axes.col(2) - principal.axes.col(2).dot(y_axis) * y_axis;
  u.normalize();
  const Vec3 v = y_axis.cross(u);
  const auto normal_at = [&](double angle) -> Vec3 { return std::cos(angle) * u + std::sin(angle) * v; };
  const FreeSpace free_space(cloud, viewpoints);
  const Points normals = estimate_normals(cloud, config.symmetry_normal_neighbors);
  const SymmetryScorer scorer(cloud, static_cast<std::size_t>(std::max(1, config.symmetry_samples)),
                              config.symmetry_tolerance, viewpoints.empty() ? nullptr : &free_space, &normals);
  // The sweep chooses among planes by contradiction: a mirror image landing where a sensor saw empty
  // space. A never-seen image is no evidence, and a matched image's distance is mostly sampling.
  const MirrorWeights choosing{0.0, config.symmetry_match_weight};
  // The chosen plane is refined on the plain distance score, where unseen mirror images count
  // unseen_score so that the plane does not drift towards the never-seen side.
  const MirrorWeights refining{config.unseen_score, 1.0};
  // The symmetry plane contains the handle's axis line, not only its direction: the handle's fitted
  // axis fixes the plane's offset even when part of the tool was never seen and the centroid is off it.
  const Vec3& centre = handle.point;
  const double step = config.symmetry_step_deg * kDeg;
  for (double angle = 0.0; angle < M_PI - 1e-9; angle += step)
    frame.symmetry_candidates.push_back({angle / kDeg, normal_at(angle), scorer.score(normal_at(angle), centre, choosing)});
  // Tools like a T or a flat top have two mirror planes through the handle. Among the sweep's local
  // minima that score as well as the best (within the tie margin), the symmetry plane is the one
  // across which the effector reaches farthest, since the effector axis is the head's forward extent.
  const auto& sweep = frame.symmetry_candidates;
  const std::size_t n = sweep.size();
  const double best_score = std::min_element(sweep.begin(), sweep.end(), [](auto& a, auto& b) {
                              return a.score < b.score;
                            })->score;
  double best_angle = 0.0, best_reach = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool local_minimum = sweep[i].score <= sweep[(i + n - 1) % n].score && sweep[i].score <= sweep[(i + 1) % n].score;
    if (!local_minimum || sweep[i].score > best_score + config.symmetry_tie_margin) continue;
    const Reach r = effector_reach(cloud, principal.centroid, handle.point, y_axis, y_axis.cross(sweep[i].normal),
                                   config.salience_quantile);
    if (std::max(r.positive, r.negative) > best_reach) {
      best_reach = std::max(r.positive, r.negative);
      best_angle = sweep[i].angle_deg * kDeg;
    }
  }
  // The angle first (about the handle's axis line), then the plane's offset from it. A bar's half-seen
  // surface mirrors best across planes facing the cameras, but the bar's direction does not depend on
  // which side was seen: when the head is such a line near the chosen plane, the plane contains it.
  const auto head_line = head_line_normal_angle(cloud, handle.point, principal.centroid, y_axis, u, v,
                                                2.5 * handle.radius, config.head_line_elongation);
  const double to_head_line = head_line ? std::remainder(*head_line - best_angle, M_PI) : M_PI;
  if (std::abs(to_head_line) <= 1.5 * step) {
    best_angle += to_head_line;
    frame.symmetry_plane_rule = "contains the head's line seen along the handle";
  } else {
    best_angle = golden_minimum([&](double a) { return scorer.score(normal_at(a), centre, refining); }, best_angle - step,
                                best_angle + step, 8);
    frame.symmetry_plane_rule = "best mirror about the handle axis";
  }
  const Vec3 z_normal = normal_at(best_angle);
  const double offset = golden_minimum([&](double d) { return scorer.score(z_normal, centre + d * z_normal, refining); },
                                       -config.symmetry_tolerance, config.symmetry_tolerance, 8);
  frame.symmetry_score = scorer.score(z_normal, centre + offset * z_normal, refining);
  frame.symmetry_candidates.push_back({best_angle / kDeg, z_normal, scorer.score(z_normal, centre + offset * z_normal, choosing)});
  frame.across_handle_score = scorer.score(y_axis, principal.centroid, refining);

  // Effector axis X = Y x Z, signed towards the side where the effector reaches farther.
  Vec3 x_axis = y_axis.cross(z_normal).normalized();
  Reach reach = effector_reach(cloud, principal.centroid, handle.point, y_axis, x_axis, config.salience_quantile);
  if (reach.negative > reach.positive) {
    x_axis = -x_axis;
    std::swap(reach.positive, reach.negative);
  }
  frame.effector_reach_positive = reach.positive;
  frame.effector_reach_negative = reach.negative;
  frame.salient_effector = reach.positive - reach.negative >= config.salience_min &&
                           reach.positive >= config.salience_ratio * std::max(reach.negative, 0.0);
  frame.effector_sign_rule = frame.salient_effector
                                 ? "salient side: the effector reaches farther along +X than along -X"
                                 : "no salient effector: +X is the marginally longer reach, sign arbitrary";

  frame.axes.col(0) = x_axis;
  frame.axes.col(1) = y_axis;
  frame.axes.col(2) = x_axis.cross(y_axis);  // right-handed by construction
  // The centroid projected onto the symmetry plane.
  frame.origin = principal.centroid - (principal.centroid - (centre + offset * z_normal)).dot(z_normal) * z_normal;
  return frame;
}

}  // namespace toolinc
