#include "toolinc/frame/tool_frame.hpp"

#include <spdlog/fmt/fmt.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "frame/cylinder_fit.hpp"
#include "frame/symmetry.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/scatter.hpp"
#include "toolinc/core/statistics.hpp"
#include "toolinc/frame/frame_search.hpp"
#include "toolinc/frame/tooltip.hpp"

namespace toolinc {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kBarBand = 2.0;           // handle radii: how far a bar-like head's points lie from its line
constexpr std::size_t kMinBarPoints = 20;  // fewer cannot pin a cylinder's axis under stereo noise
// A blade passes by the handle's axis: the middle of its depth, seen along the handle, lies within this
// share of its width from it (a scoop's rims rise 0.1-0.3 of its width; a hoe's blade stands a head's
// length, about its width or more, in front).
constexpr double kBladeDepthOffset = 0.5;
// The symmetry sweep's first pass mirrors 1 in kSweepSampleShare of the samples, and rescores with them all
// the angles within kSweepRescoreMargin of its best: what the sweep decides lies within the doubt margin
// (0.1) of the best, and the margin leaves twice that again for the first pass's sampling noise.
constexpr int kSweepSampleShare = 4;
constexpr double kSweepRescoreMargin = 0.3;

// A plane is refined within a sweep step either side by this many golden-section steps: they leave a
// bracket 0.056 of the two steps wide (0.84 degrees at the default step of 7.5), the plane within half that.
constexpr int kGoldenIterations = 6;

// The points a symmetry scorer mirrors: the head's, or (no head: a stick) null, every point.
const std::vector<std::uint32_t>* mirrored_points(const std::vector<std::uint32_t>& head,
                                                  const ToolFrameConfig& config) {
  return static_cast<int>(head.size()) >= config.min_head_points ? &head : nullptr;
}

void check_not_degenerate(const Points& input, const Points& outside, const Points& cloud, const PrincipalAxes& axes,
                          const ToolFrameConfig& config) {
  if (!input.empty() && outside.empty())
    throw MethodError(fmt::format("all {} points lie within the hand radius ({} m)", input.size(), config.hand_radius));
  if (static_cast<int>(outside.size()) < config.min_points)
    throw MethodError(fmt::format("too few points: {} outside the hand radius and joined to it, at least {} needed",
                                  outside.size(), config.min_points));
  if (cloud.size() < 10) throw MethodError(fmt::format("too few points after removing stray points: {}", cloud.size()));
  double lo = 0.0, hi = 0.0;
  for (const auto& p : cloud) {
    const double t = (p - axes.centroid).dot(axes.axes.col(0));
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  if (hi - lo < config.min_length)
    throw MethodError(fmt::format("the points span only {:.4f} m along their major axis (min_length {} m)", hi - lo,
                                  config.min_length));
  if (std::sqrt(axes.eigenvalues[1]) < config.min_thickness)
    throw MethodError(
        fmt::format("the points are collinear: RMS spread across the major axis {:.2e} m "
                    "(min_thickness {} m)",
                    std::sqrt(axes.eigenvalues[1]), config.min_thickness));
  if (std::sqrt(axes.eigenvalues[2]) < config.min_thickness)
    throw MethodError(
        fmt::format("the points are planar: RMS spread across their plane {:.2e} m "
                    "(min_thickness {} m)",
                    std::sqrt(axes.eigenvalues[2]), config.min_thickness));
}

struct HandleFit {
  Vec3 axis;   // towards the hand
  Vec3 point;  // on the axis line
  int points = 0;
  double radius = 0.0, rms = 0.0;
  bool cylinder = true;  // false: the handle's points did not form a surface, their principal axis is used
};

// The line through point along axis, its direction signed towards the hand at the origin.
Cylinder line_towards_hand(const Vec3& point, const Vec3& axis) {
  return {point, axis.dot(-point) < 0 ? Vec3(-axis) : axis, 0.0, 0.0};
}

// The part of the tool the hand holds: the points nearer the hand (the origin) than `share` of the way
// from the tool's nearest point to its farthest. A heavy head (most of a reconstruction's points) tilts
// the whole tool's principal axis towards it, but not this part's.
Points held_part(const Points& cloud, double share) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const auto& p : cloud) lo = std::min(lo, p.norm()), hi = std::max(hi, p.norm());
  Points near;
  for (const auto& p : cloud)
    if (p.norm() <= lo + share * (hi - lo)) near.push_back(p);
  return near;
}

// The line of a handle whose points form no surface (a filled model, a noisy or half-seen handle): the
// principal line of those of its points that lie within radial_factor times their median distance of it,
// refitted until those points stay the same. A handle's points lie within its radius of its axis (a filled
// disc's within 1.4 times their median distance); a remnant of the hand or a lobe of smear beside the handle
// lies farther, and would tilt a line fitted through everything.
Cylinder trimmed_line(const Points& points, double radial_factor, int iterations) {
  PrincipalAxes fit = principal_axes(points);
  std::vector<double> radial(points.size());
  Points kept;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const Cylinder line{fit.centroid, fit.axes.col(0), 0.0, 0.0};
    for (std::size_t i = 0; i < points.size(); ++i) radial[i] = radial_distance(line, points[i]);
    const double limit = radial_factor * quantile(radial, 0.5);
    Points next;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (radial[i] <= limit) next.push_back(points[i]);
    if (next.size() < 10 || next == kept) break;
    kept = std::move(next);
    fit = principal_axes(kept);
  }
  return {fit.centroid, fit.axes.col(0), 0.0, 0.0};
}

// The major axis is tilted by a heavy head (7-26 degrees on hooks and L-shapes in the original), so
// the handle axis is refitted from the handle's own points: those in the hand-side part of the tool's
// length, less the hand_skip share at the hand end, that lie on the current handle cylinder. A
// cylinder fit, unlike a principal axis, is not tilted by the slanted cut the hand sphere leaves or by
// uneven coverage of the handle.
HandleFit fit_handle(const Points& cloud, const PrincipalAxes& start, const ToolFrameConfig& config, double hand_skip) {
  Cylinder handle = line_towards_hand(start.centroid, start.axes.col(0));
  HandleFit fit{handle.axis, handle.point, 0, 0.0, 0.0, true};
  std::vector<double> along(cloud.size()), radial;
  Points slab, fitted;
  for (int iteration = 0; iteration < config.handle_iterations; ++iteration) {
    for (std::size_t i = 0; i < cloud.size(); ++i) along[i] = (cloud[i] - handle.point).dot(handle.axis);
    const double hand_end = quantile(along, 0.99), far_end = quantile(along, 0.01);
    const double start = hand_end - config.handle_fraction * (hand_end - far_end);
    const double stop = hand_end - hand_skip * (hand_end - far_end);
    slab.clear();
    radial.clear();
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (along[i] >= start && along[i] <= stop) {
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
      const Cylinder line = trimmed_line(on_handle, config.handle_radial_factor, config.handle_iterations);
      refit = {line.point, line.axis, quantile(radial, 0.5), refit.rms};
    }
    if (refit.axis.dot(handle.axis) < 0) refit.axis = -refit.axis;
    const double change = std::acos(std::clamp(refit.axis.dot(handle.axis), -1.0, 1.0));
    handle = refit;
    fit = {handle.axis, handle.point, static_cast<int>(on_handle.size()), handle.radius, handle.rms, surface};
    fitted = on_handle;
    if (change < 1e-5) break;
  }
  // Coaxial parts of different widths (a grip, then a thinner shaft) tilt a one-radius cylinder fitted
  // across both: the converged fit is refined once more with a radius per section. Only once, from
  // the converged fit, since the sections' freedom could lead a fit from a poor start astray.
  if (fit.cylinder) {
    Cylinder refit = fit_cylinder(fitted, {handle.point, handle.axis, handle.radius, 0.0}, config.handle_residual_scale,
                                  15, config.handle_section_length);
    if (refit.axis.dot(handle.axis) < 0) refit.axis = -refit.axis;
    fit = {refit.axis, refit.point, static_cast<int>(fitted.size()), refit.radius, refit.rms, true};
  }
  return fit;
}

// How far the effector side (the points beyond side_point, away from the hand along line.axis, which
// points towards it) stands out from the line: the q-quantile of its points' distances from it.
double effector_extent(const Points& cloud, const Vec3& side_point, const Cylinder& line, double q) {
  std::vector<double> radial;
  for (const auto& p : cloud)
    if ((p - side_point).dot(line.axis) < 0) radial.push_back(radial_distance(line, p));
  return radial.empty() ? 0.0 : quantile(std::move(radial), q);
}

// A stick's handle: its principal line, signed towards the hand, the radius its points' median distance.
HandleFit stick_line(const Points& cloud, const Cylinder& line) {
  HandleFit fit;
  fit.axis = line.axis;
  fit.point = line.point;
  std::vector<double> radial;
  for (const auto& p : cloud) radial.push_back(radial_distance(line, p));
  fit.radius = median(radial);
  double sum = 0.0;
  for (const double r : radial) sum += (r - fit.radius) * (r - fit.radius);
  fit.rms = std::sqrt(sum / static_cast<double>(std::max<std::size_t>(radial.size(), 1)));
  fit.points = static_cast<int>(cloud.size());
  fit.cylinder = false;
  return fit;
}

// How a head curls across the symmetry plane: the quadratic x = a + b z + c z^2 fitted to its points
// (z along z_axis from the plane through plane_point), and its half width (its points' 90th
// percentile |z|). rise = c x half_width^2: how far its edges rise along x_axis above its middle,
// positive when the head is concave towards +x.
struct Curl {
  double rise, half_width;
};
Curl head_curl(const Points& cloud, const std::vector<std::uint32_t>& head, const Vec3& plane_point, const Vec3& x_axis,
               const Vec3& z_axis) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::Zero();
  std::vector<double> width;
  for (auto i : head) {
    const Vec3 d = cloud[i] - plane_point;
    const double z = d.dot(z_axis);
    const Eigen::Vector3d basis(1.0, z, z * z);
    normal += basis * basis.transpose();
    right += basis * d.dot(x_axis);
    width.push_back(std::abs(z));
  }
  const Eigen::Vector3d coefficients = normal.ldlt().solve(right);
  const double half_width = quantile(std::move(width), 0.9);
  return {coefficients(2) * half_width * half_width, half_width};
}

// The candidate planes of a sweep over half a turn: the lowest angle of each basin, a maximal
// (circular) run of angles scoring within `margin` of the best. One per basin: a plate's broad basin
// is flat and noisy, and another angle in it, towards the plate's diagonal, reaches farther than the
// true plane and would win the tie-break.
std::vector<std::size_t> basin_minima(const std::vector<SymmetryCandidate>& sweep, double margin) {
  const auto lower = [](const SymmetryCandidate& a, const SymmetryCandidate& b) { return a.score < b.score; };
  const auto lowest = static_cast<std::size_t>(std::min_element(sweep.begin(), sweep.end(), lower) - sweep.begin());
  const double ceiling = sweep[lowest].score + margin;
  const std::size_t n = sweep.size();
  std::size_t outside = 0;  // an angle in no basin, where the circular scan starts and ends
  while (outside < n && sweep[outside].score <= ceiling) ++outside;
  if (outside == n) return {lowest};
  std::vector<std::size_t> minima;
  bool in_basin = false;
  for (std::size_t k = 1; k <= n; ++k) {
    const std::size_t i = (outside + k) % n;
    if (sweep[i].score > ceiling) {
      in_basin = false;
    } else if (!in_basin || sweep[i].score < sweep[minima.back()].score) {
      if (in_basin)
        minima.back() = i;
      else
        minima.push_back(i);
      in_basin = true;
    }
  }
  return minima;
}

// The head's points seen along the handle: their coordinates along u and v (across the handle) from
// handle_point, as a mean and scatter.
Scatter<2> seen_along_handle(const Points& cloud, const std::vector<std::uint32_t>& head, const Vec3& handle_point,
                             const Vec3& u, const Vec3& v) {
  return scatter_of<2>(head.size(), [&](std::size_t j) {
    const Vec3 d = cloud[head[j]] - handle_point;
    return Eigen::Vector2d(d.dot(u), d.dot(v));
  });
}

// Seen along the handle, the head of a bar-like tool (L, T, hook) lies along a line, and the symmetry
// plane contains it. The line of the head's points when they spread along it at least head-line-elongation
// times more (variance) than across it; nothing for plates and combs (hoe, rake, flat top), nor when
// there is no head (fewer than min_head_points: a stick).
struct HeadLine {
  double normal_angle;  // of the plane containing the line, in the u, v basis about the handle
  double offset;        // of that plane from the handle's axis line, along its normal
};
std::optional<HeadLine> head_line(const Points& cloud, const std::vector<std::uint32_t>& head, const Vec3& handle_point,
                                  const Vec3& u, const Vec3& v, const ToolFrameConfig& config) {
  if (static_cast<int>(head.size()) < config.min_head_points) return std::nullopt;
  const Scatter<2> seen = seen_along_handle(cloud, head, handle_point, u, v);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(seen.scatter);
  if (solver.eigenvalues()(1) < config.head_line_elongation * std::max(solver.eigenvalues()(0), 1e-12))
    return std::nullopt;
  const Eigen::Vector2d normal = solver.eigenvectors().col(0);
  return HeadLine{std::atan2(normal.y(), normal.x()), normal.dot(seen.mean)};
}

// The axis of a bar-like head: a cylinder fitted to the head's points near its line (within
// kBarBand handle radii of it) and at its far end, where the bar lies (a hook's return rises from
// there towards the hand). Nothing when the fit finds no axis across the handle.
std::optional<Cylinder> fit_bar(const Points& cloud, const std::vector<std::uint32_t>& head, const Vec3& handle_point,
                                const Vec3& y_axis, const Vec3& line_normal, double line_offset, double handle_radius,
                                const ToolFrameConfig& config) {
  std::vector<double> along;
  for (auto i : head) along.push_back((cloud[i] - handle_point).dot(y_axis));
  const double band = kBarBand * handle_radius, far_end = quantile(std::move(along), 0.01);
  Points bar;
  Vec3 mean = Vec3::Zero();
  for (auto i : head) {
    const Vec3 q = cloud[i] - handle_point;
    if (std::abs(q.dot(line_normal) - line_offset) > band || q.dot(y_axis) > far_end + band) continue;
    bar.push_back(cloud[i]);
    mean += cloud[i];
  }
  if (bar.size() < kMinBarPoints) return std::nullopt;
  mean /= static_cast<double>(bar.size());
  const Cylinder axis = fit_cylinder(bar, {mean, y_axis.cross(line_normal).normalized(), handle_radius, 0.0},
                                     config.handle_residual_scale);
  if (y_axis.cross(axis.axis).norm() < 0.5) return std::nullopt;  // within 30 degrees of the handle
  return axis;
}

// The head's principal spreads (ascending) and its thinnest direction, the last column.
Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> head_spread(const Points& cloud,
                                                           const std::vector<std::uint32_t>& head) {
  const auto spread = scatter_of<3>(head.size(), [&](std::size_t j) { return cloud[head[j]]; });
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(spread.scatter);
}

// The extent of the values between their 5 % quantiles, which a tenth of smeared points does not move.
double inner_extent(std::vector<double> values) {
  const double low = quantile(values, 0.05);
  return quantile(std::move(values), 0.95) - low;
}

// A blade: a flat or curled plate continuing the handle (a shovel, a spatula). Seen along the handle, its
// points are wider than deep (RMS the narrow way at most blade-flatness of the wide way), centred on the
// handle's axis across (the middle of their extent within blade-centring of their width from it: a hook
// or an L reaches out on one side) and passing by it in depth (kBladeDepthOffset), and reach along the
// handle at least blade-min-aspect of their width. Decided without a symmetry plane, so
// that it can choose one: a thin plate mirrors onto itself across its own plane, whatever its outline,
// so that plane says nothing, and the tool's is the one across the plate. The direction across the
// handle the plate is wide along (the plane's normal), or nothing.
std::optional<Vec3> blade_across(const Points& cloud, const std::vector<std::uint32_t>& head, const Vec3& handle_point,
                                 const Vec3& y_axis, const Vec3& u, const Vec3& v, const ToolFrameConfig& config) {
  if (static_cast<int>(head.size()) < config.min_head_points) return std::nullopt;
  const Scatter<2> seen = seen_along_handle(cloud, head, handle_point, u, v);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(seen.scatter);
  if (solver.eigenvalues()(0) > config.blade_flatness * config.blade_flatness * solver.eigenvalues()(1))
    return std::nullopt;
  const Eigen::Vector2d wide = solver.eigenvectors().col(1), deep = solver.eigenvectors().col(0);
  std::vector<double> across, depth, along;
  for (auto i : head) {
    const Vec3 d = cloud[i] - handle_point;
    const Eigen::Vector2d q(d.dot(u), d.dot(v));
    across.push_back(q.dot(wide));
    depth.push_back(q.dot(deep));
    along.push_back(d.dot(y_axis));
  }
  // The middle of the values between their 5 % quantiles.
  const auto middle = [](const std::vector<double>& x) { return 0.5 * (quantile(x, 0.95) + quantile(x, 0.05)); };
  const double width = inner_extent(across);
  if (std::abs(middle(across)) > config.blade_centring * width || std::abs(middle(depth)) > kBladeDepthOffset * width ||
      inner_extent(std::move(along)) < config.blade_min_aspect * width)
    return std::nullopt;
  return Vec3(wide.x() * u + wide.y() * v);
}

// Whether the effector's front along x_axis is a face rather than a corner: the effector-side points
// within a band of the reach grow in number like the band on a face (a strip) and like its square at
// a corner (a wedge). Bands of front-band and three times that: a ratio below 5 (between 3 and 9)
// is a face. A square plate's mirror planes through its corners reach farther than those through its
// edges' middles; the effector is the edge.
bool front_is_face(const Points& cloud, const Vec3& centre, const Vec3& y_axis, const Vec3& x_axis, double band) {
  std::vector<double> front;
  for (const auto& p : cloud)
    if ((p - centre).dot(y_axis) < 0) front.push_back(p.dot(x_axis));
  const double reach = front.empty() ? 0.0 : *std::max_element(front.begin(), front.end());
  int narrow = 0, wide = 0;
  for (const double x : front) {
    narrow += reach - x <= band;
    wide += reach - x <= 3 * band;
  }
  return wide < 5 * std::max(narrow, 1);
}

// Golden-section search for the minimum of f on [lo, hi]: where it is, and f there.
template <typename F>
std::pair<double, double> golden_minimum(F&& f, double lo, double hi, int iterations) {
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
  return fa <= fb ? std::pair{a, fa} : std::pair{b, fb};
}

}  // namespace

Reach effector_reach(const Points& cloud, const Vec3& centre, const Vec3& handle_point, const Vec3& y_axis,
                     const Vec3& x_axis, double q) {
  std::vector<double> forward, backward;
  forward.reserve(cloud.size()), backward.reserve(cloud.size());
  for (const auto& p : cloud) {
    if ((p - centre).dot(y_axis) >= 0) continue;
    const double x = (p - handle_point).dot(x_axis);
    forward.push_back(x);
    backward.push_back(-x);
  }
  return {quantile(std::move(forward), q), quantile(std::move(backward), q)};
}

std::string to_string(HeadKind kind) {
  switch (kind) {
    case HeadKind::none:
      return "none";
    case HeadKind::bar:
      return "bar";
    case HeadKind::blade:
      return "blade";
    case HeadKind::scoop:
      return "scoop";
    case HeadKind::plate:
      return "plate";
    case HeadKind::other:
      break;
  }
  return "other";
}

HeadKind head_kind_from_string(const std::string& name) {
  for (const HeadKind kind :
       {HeadKind::none, HeadKind::bar, HeadKind::blade, HeadKind::scoop, HeadKind::plate, HeadKind::other})
    if (to_string(kind) == name) return kind;
  throw std::invalid_argument("unknown head kind '" + name + "' (none, bar, blade, scoop, plate, other)");
}

Eigen::Matrix4d ToolFrame::hand_from_tool() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = axes;
  m.topRightCorner<3, 1>() = origin;
  return m;
}

namespace {

HandleFit fit_handle_from(const Points& cloud, const PrincipalAxes& start, const ToolFrameConfig& config) {
  HandleFit fit = fit_handle(cloud, start, config, config.handle_hand_skip);
  // On a short handle the slab, once the hand end is skipped, reaches into the head and is no
  // cylinder: then the whole slab, hand end included, is the handle's.
  if (!fit.cylinder && config.handle_hand_skip > 0) fit = fit_handle(cloud, start, config, 0.0);
  return fit;
}

// Handle axis (Y), signed towards the hand at the origin, as the rules choose it. A stick (its effector
// side all within stick-width of its principal line) is its own handle: its line is the principal axis,
// which a bent or wavy stick's local cylinder would tilt. Any other tool's major axis is tilted by its
// head, so its handle is fitted, started from the whole tool's major axis and from that of the half the
// hand holds (which a heavy head does not tilt); the handle is the thinner fit, preferring a surface.
HandleFit rule_handle(const Points& cloud, const PrincipalAxes& principal, const ToolFrameConfig& config) {
  const Cylinder major_line = line_towards_hand(principal.centroid, principal.axes.col(0));
  if (effector_extent(cloud, principal.centroid, major_line, config.salience_quantile) < config.stick_width)
    return stick_line(cloud, major_line);
  HandleFit handle = fit_handle_from(cloud, principal, config);
  const HandleFit held = fit_handle_from(cloud, principal_axes(held_part(cloud, 0.5)), config);
  if (std::pair{!held.cylinder, held.radius} < std::pair{!handle.cylinder, handle.radius}) handle = held;
  return handle;
}

// The held part's own line (the points within held-share of the way from the tool's nearest point to its
// farthest, trimmed of what lies off it): it needs no handle surface, so a half-seen or smeared handle
// does not tilt it, and a head reaching into the handle's slab does not either.
HandleFit held_line(const Points& cloud, const ToolFrameConfig& config) {
  const Points held = held_part(cloud, config.held_share);
  if (held.size() < 10) return {};
  const Cylinder trimmed = trimmed_line(held, config.handle_radial_factor, config.handle_iterations);
  return stick_line(held, line_towards_hand(trimmed.point, trimmed.axis));
}

// Every handle the data allows, each with where it came from: the rules' fits from the whole tool's
// major axis and from the held half's, the held part's trimmed line, and the major axis's own line (a
// stick's). Near-duplicates (axes within a degree, lines within a millimetre at the hand) are kept once.
std::vector<std::pair<std::string, HandleFit>> handle_candidates(const Points& cloud, const PrincipalAxes& principal,
                                                                 const ToolFrameConfig& config) {
  const Cylinder major_line = line_towards_hand(principal.centroid, principal.axes.col(0));
  std::vector<std::pair<std::string, HandleFit>> all{
      {"whole tool's axis, fitted", fit_handle_from(cloud, principal, config)},
      {"held half's axis, fitted", fit_handle_from(cloud, principal_axes(held_part(cloud, 0.5)), config)},
      {"held part's line", held_line(cloud, config)},
      {"whole tool's principal line", stick_line(cloud, major_line)}};
  // The point of a handle's line nearest the hand.
  const auto at_hand = [](const HandleFit& h) -> Vec3 {
    const Vec3 axis = h.axis.normalized();
    return h.point - h.point.dot(axis) * axis;
  };
  std::vector<std::pair<std::string, HandleFit>> kept;
  for (auto& candidate : all) {
    const HandleFit& h = candidate.second;
    if (h.points == 0 || !h.axis.allFinite() || h.axis.norm() < 0.5) continue;
    const auto same = [&](const auto& other) {
      return h.axis.normalized().dot(other.second.axis.normalized()) >= std::cos(kDeg) &&
             (at_hand(h) - at_hand(other.second)).norm() < 0.001;
    };
    if (std::none_of(kept.begin(), kept.end(), same)) kept.push_back(std::move(candidate));
  }
  return kept;
}

// What the frame about a handle owes to the handle alone, whatever symmetry plane is then chosen about it:
// the directions across it, its head, the mirror sweep, the refined planes tied in it and the plane the
// rules choose. The search completes several planes about each handle and measures this once.
struct AboutHandle {
  // target: the cloud's, shared by every handle; free_space: where the sensors saw empty space (null
  // without viewpoints). Both must outlive this.
  AboutHandle(const Points& cloud, const PrincipalAxes& principal, const HandleFit& handle, const MirrorTarget& target,
              const FreeSpace* free_space, const ToolFrameConfig& config);

  Vec3 normal_at(double angle) const { return std::cos(angle) * u + std::sin(angle) * v; }
  // The mirror score of the plane through the handle's axis at angle; each angle is scored once, since
  // the planes the search asks for and the chosen planes were often scored by a refinement already.
  // images: those of the plane a coarser scorer recorded, taken where it shares the samples.
  double score_at(double angle, const SymmetryScorer::Recorded* images = nullptr) const {
    const auto known = std::find_if(scored.begin(), scored.end(), [&](const auto& s) { return s.first == angle; });
    if (known != scored.end()) return known->second;
    scored.emplace_back(angle, scorer.score(normal_at(angle), centre, nullptr, images));
    return scored.back().second;
  }

  Vec3 y_axis, u, v;
  // The symmetry plane contains the handle's axis line, not only its direction: the handle's fitted
  // axis fixes the plane's offset even when part of the tool was never seen and the centroid is off it.
  Vec3 centre;
  Cylinder line;  // the handle's axis line
  std::vector<std::uint32_t> head;
  double head_extent;
  SymmetryScorer scorer;
  double step;  // the sweep's, rad
  std::vector<SymmetryCandidate> sweep, tied_planes;
  std::optional<Vec3> blade;                              // across the head, when it is a blade
  std::optional<HeadLine> bar_line;                       // the head's line seen along the handle, when bar-like
  Vec3 head_thinnest = Vec3::Zero();                      // the head's thinnest direction, when it has a head
  double rules_angle = 0.0;                               // the rules' plane, before a bar along it moves it
  double across_handle_score;                             // of the plane across the handle, for the record only
  mutable std::vector<std::pair<double, double>> scored;  // angle, score
};

// Symmetry plane: it contains the handle axis, so sweep its normal about Y and refine the best angles.
AboutHandle::AboutHandle(const Points& cloud, const PrincipalAxes& principal, const HandleFit& handle,
                         const MirrorTarget& target, const FreeSpace* free_space, const ToolFrameConfig& config)
    : y_axis(handle.axis.normalized()),
      u(principal.axes.col(1) - principal.axes.col(1).dot(y_axis) * y_axis),
      centre(handle.point),
      line{centre, y_axis, 0.0, 0.0},
      // Only the head's points are mirrored. Points near the handle's axis mirror onto the handle across
      // every plane through it, so they say nothing about the plane, and the handle's never-seen back half
      // pulls the plane towards the cameras. A stick has no head: all its points are mirrored.
      head([&] {
        std::vector<std::uint32_t> head;
        for (std::uint32_t i = 0; i < cloud.size(); ++i)
          if ((cloud[i] - principal.centroid).dot(y_axis) < 0 &&
              radial_distance(line, cloud[i]) >= config.head_radius_factor * handle.radius)
            head.push_back(i);
        return head;
      }()),
      // A stick: nothing on the effector side stands out from the handle's axis by more than stick-width.
      head_extent(effector_extent(cloud, principal.centroid, line, config.salience_quantile)),
      scorer(target, static_cast<std::size_t>(std::max(1, config.symmetry_samples)), config.symmetry_match_weight,
             free_space, mirrored_points(head, config)),
      step(config.symmetry_step_deg * kDeg) {
  if (u.norm() < 1e-6) u = principal.axes.col(2) - principal.axes.col(2).dot(y_axis) * y_axis;
  u.normalize();
  v = y_axis.cross(u);
  // The sweep decides only near its best: the basins within the tie margin, the rivals within the doubt
  // margin. So every angle is scored with a share of the samples first, and only those that come within
  // kSweepRescoreMargin of the best that way (a margin above both and the share's noise) are scored with
  // them all; the others keep the cheap score, far above what decides.
  const SymmetryScorer coarse(target,
                              static_cast<std::size_t>(std::max(1, config.symmetry_samples / kSweepSampleShare)),
                              config.symmetry_match_weight, free_space, mirrored_points(head, config));
  std::vector<double> angles;
  for (double angle = 0.0; angle < M_PI - 1e-9; angle += step) angles.push_back(angle);
  double coarse_best = std::numeric_limits<double>::infinity();
  std::vector<std::vector<SymmetryScorer::Image>> coarse_images(angles.size());  // reused by the rescoring
  for (std::size_t k = 0; k < angles.size(); ++k) {
    sweep.push_back(
        {angles[k] / kDeg, normal_at(angles[k]), coarse.score(normal_at(angles[k]), centre, &coarse_images[k])});
    coarse_best = std::min(coarse_best, sweep.back().score);
  }
  for (std::size_t k = 0; k < angles.size(); ++k)
    if (sweep[k].score <= coarse_best + kSweepRescoreMargin) {
      const SymmetryScorer::Recorded images{coarse.samples(), coarse_images[k]};
      sweep[k].score = score_at(angles[k], &images);
    }
  // Tools like a T or a flat top have two mirror planes through the handle. The lowest angle of each
  // basin of the sweep that scores as well as the best (within the tie margin) is refined. A blade (a
  // plate along the handle: shovel, spatula) acts with its face, so its symmetry plane is the one across
  // it and the effector axis its normal. Otherwise the symmetry plane is the one across which the
  // effector reaches farthest, since the effector axis is the head's forward extent.
  blade = blade_across(cloud, head, centre, y_axis, u, v, config);
  bar_line = head_line(cloud, head, centre, u, v, config);
  if (static_cast<int>(head.size()) >= config.min_head_points)
    head_thinnest = head_spread(cloud, head).eigenvectors().col(0);
  // A front that is a corner, not a face, loses to one that is.
  std::pair<bool, double> best_merit{false, -std::numeric_limits<double>::infinity()};
  for (const std::size_t i : basin_minima(sweep, config.symmetry_tie_margin)) {
    const double lowest = sweep[i].angle_deg * kDeg;
    const auto [angle, score] =
        golden_minimum([&](double a) { return score_at(a); }, lowest - step, lowest + step, kGoldenIterations);
    const Vec3 x_axis = y_axis.cross(normal_at(angle));
    const Reach r = effector_reach(cloud, principal.centroid, centre, y_axis, x_axis, config.salience_quantile);
    const bool forward = r.positive >= r.negative;
    const bool face =
        front_is_face(cloud, principal.centroid, y_axis, forward ? x_axis : Vec3(-x_axis), config.front_band);
    tied_planes.push_back({angle / kDeg, normal_at(angle), score});
    const std::pair<bool, double> merit{face, std::max(r.positive, r.negative)};
    if (merit > best_merit) {
      best_merit = merit;
      rules_angle = angle;
    }
  }
  // A blade's plane is the one across it, refined by the mirror within a step: its own plane mirrors any
  // thin plate, and it often mirrors best.
  if (blade) {
    const double across = std::atan2(blade->dot(v), blade->dot(u));
    rules_angle =
        golden_minimum([&](double a) { return score_at(a); }, across - step, across + step, kGoldenIterations).first;
  }
  across_handle_score = scorer.score(y_axis, principal.centroid);
}

// A stick standing out beyond a clean stick's width: a straight stick whose far end a view merged off
// fringes to one side, or a bent stick, whose far end lies there; the two look alike.
void check_stick(ToolFrame& frame, const ToolFrameConfig& config) {
  if (!frame.stick) return;
  const double allowance = config.stick_width - config.clean_stick_width;
  const double beyond = frame.diagnostics.head_extent - config.clean_stick_width;
  if (beyond > 0.0)
    frame.confidence.check(allowance > 0.0 ? -beyond / allowance : -1.0,
                           fmt::format("a stick whose far end stands out {:.0f} mm from its axis, beyond a clean "
                                       "stick's {:.0f} mm: fringed or bent, the tip may lie off its middle",
                                       1000 * frame.diagnostics.head_extent, 1000 * config.clean_stick_width));
}

// The grasp's doubts, whatever the plane and side: a handle whose axis does not pass by the hand is not
// the one it holds, and one thicker than the hand closes on is not held. The search's probabilities are
// relative to its other hypotheses and cannot see that none is a grasp.
void check_grasp(ToolFrame& frame, const ToolFrameConfig& config) {
  frame.confidence.check(
      1.0 - frame.diagnostics.hand_to_handle / config.grasp_reach,
      fmt::format("the handle's axis passes {:.0f} mm from the hand, beyond grasp-reach ({:.0f} mm): "
                  "it is not what the hand holds",
                  1000 * frame.diagnostics.hand_to_handle, 1000 * config.grasp_reach));
  frame.confidence.check(1.0 - frame.handle_radius / config.grasp_max_radius,
                         fmt::format("the handle's fitted radius is {:.0f} mm, beyond grasp-max-radius ({:.0f} mm): "
                                     "thicker than the hand holds",
                                     1000 * frame.handle_radius, 1000 * config.grasp_max_radius));
}

// The doubts that hold whatever the plane and side: the grasp's and the stick's.
void check_any_plane(ToolFrame& frame, const ToolFrameConfig& config) {
  check_grasp(frame, config);
  check_stick(frame, config);
}

// The frame about a given handle: the symmetry plane through it, the effector axis and its side, the
// head's kind and the doubts. `frame` holds what preparing the cloud found; about, what the handle alone
// decides.
ToolFrame frame_about_handle(ToolFrame frame, const Points& cloud, const PrincipalAxes& principal,
                             const HandleFit& handle, const AboutHandle& about, const ToolFrameConfig& config,
                             std::optional<double> plane_angle_deg = std::nullopt) {
  const Vec3& y_axis = about.y_axis;
  const Vec3 &u = about.u, &v = about.v, &centre = about.centre;
  const auto& head = about.head;
  const auto& sweep = about.sweep;
  const Cylinder& handle_line = about.line;
  const double step = about.step;
  const auto normal_at = [&](double angle) { return about.normal_at(angle); };
  const auto score_at = [&](double angle) { return about.score_at(angle); };
  frame.handle_point = handle.point;
  frame.diagnostics.handle_points = handle.points;
  frame.handle_radius = handle.radius;
  frame.diagnostics.handle_rms = handle.rms;
  frame.diagnostics.handle_cylinder = handle.cylinder;
  frame.diagnostics.handle_refinement_deg =
      std::acos(std::min(1.0, std::abs(y_axis.dot(principal.axes.col(0))))) / kDeg;
  frame.diagnostics.handle_sign_rule = "towards the hand: the hand origin lies on the +Y side of the handle";
  frame.diagnostics.head_extent = about.head_extent;
  frame.stick = frame.diagnostics.head_extent < config.stick_width;
  frame.diagnostics.symmetry_candidates = about.sweep;
  frame.tied_planes = about.tied_planes;
  std::optional<Vec3> blade = about.blade;
  frame.diagnostics.head_is_blade = blade.has_value();
  double best_angle = about.rules_angle;
  // A plane the search asks for instead, refined by the mirror within a step; a blade only when that is
  // the plane across it.
  if (plane_angle_deg) {
    const double asked = *plane_angle_deg * kDeg;
    if (std::abs(std::remainder(asked - best_angle, M_PI)) > 1.5 * step) blade.reset();
    best_angle = golden_minimum(score_at, asked - step, asked + step, kGoldenIterations).first;
  }
  // A bar's half-seen surface mirrors best across planes facing the cameras, but the bar's axis does
  // not depend on which side was seen: when the head is a bar along the chosen plane, the plane is
  // parallel to the handle and contains the bar's axis. Otherwise it contains the handle's axis line.
  double offset = 0.0;
  frame.symmetry_plane_rule =
      plane_angle_deg ? "the search's alternative plane: another basin of the mirror sweep, or a quarter turn"
      : blade ? "across the blade (a plate continuing the handle, centred on its axis), whose own plane any thin "
                "plate mirrors across"
      : frame.tied_planes.size() < 2
          ? "best mirror about the handle axis"
          : fmt::format(
                "of {} planes mirroring as well, the one whose effector front is a face, not a corner, "
                "and reaches farthest",
                frame.tied_planes.size());
  if (const auto& line = about.bar_line) {
    const double to_line = std::remainder(line->normal_angle - best_angle, M_PI);
    std::optional<Cylinder> bar;
    if (std::abs(to_line) <= 1.5 * step)
      bar = fit_bar(cloud, head, centre, y_axis, normal_at(line->normal_angle), line->offset, handle.radius, config);
    if (bar) {
      frame.head_kind = HeadKind::bar;
      Vec3 normal = y_axis.cross(bar->axis).normalized();
      if (normal.dot(normal_at(best_angle + to_line)) < 0) normal = -normal;
      best_angle = std::atan2(normal.dot(v), normal.dot(u));
      offset = normal.dot(bar->point - centre);
      frame.symmetry_plane_rule = "contains the head's bar axis, parallel to the handle";
    }
  }
  const Vec3 z_normal = normal_at(best_angle);
  frame.symmetry_score =
      offset == 0.0 ? about.score_at(best_angle) : about.scorer.score(z_normal, centre + offset * z_normal);
  // Rivals: the sweep's local minima 30 degrees or more from the chosen plane that mirror the head nearly
  // as well. A stick has no head whose plane matters.
  const std::size_t n_sweep = sweep.size();
  for (std::size_t i = 0; i < n_sweep && !frame.stick; ++i) {
    const double score = sweep[i].score;
    if (score <= sweep[(i + 1) % n_sweep].score && score <= sweep[(i + n_sweep - 1) % n_sweep].score &&
        score <= frame.symmetry_score + config.symmetry_doubt_margin &&
        std::abs(sweep[i].normal.dot(z_normal)) < std::cos(30 * kDeg))
      frame.rival_planes.push_back(sweep[i]);
  }
  std::sort(frame.rival_planes.begin(), frame.rival_planes.end(),
            [](const SymmetryCandidate& a, const SymmetryCandidate& b) { return a.score < b.score; });
  frame.diagnostics.symmetry_candidates.push_back({best_angle / kDeg, z_normal, frame.symmetry_score});
  frame.diagnostics.across_handle_score = about.across_handle_score;

  // Effector axis X = Y x Z, signed towards the side where the effector reaches farther.
  Vec3 x_axis = y_axis.cross(z_normal).normalized();
  Reach reach = effector_reach(cloud, principal.centroid, handle.point, y_axis, x_axis, config.salience_quantile);
  if (reach.negative > reach.positive) {
    x_axis = -x_axis;
    std::swap(reach.positive, reach.negative);
  }
  frame.diagnostics.effector_reach_positive = reach.positive;
  frame.diagnostics.effector_reach_negative = reach.negative;
  frame.diagnostics.salient_effector = reach.positive - reach.negative >= config.salience_min &&
                                       reach.positive >= config.salience_ratio * std::max(reach.negative, 0.0);
  // Without a salient side, the reaches' extremes are where smear lies, on both sides alike; the head's
  // mean point, which a tenth of smeared points moves far less, tells the side its material is on. The
  // side stays doubtful.
  const bool has_head = static_cast<int>(head.size()) >= config.min_head_points;
  if (!frame.diagnostics.salient_effector && has_head) {
    double mean_x = 0.0;
    for (auto i : head) mean_x += (cloud[i] - centre).dot(x_axis) / static_cast<double>(head.size());
    if (mean_x < 0) {
      x_axis = -x_axis;
      std::swap(frame.diagnostics.effector_reach_positive, frame.diagnostics.effector_reach_negative);
    }
  }
  frame.diagnostics.effector_sign_rule =
      frame.diagnostics.salient_effector
          ? "salient side: the effector reaches farther along +X than along -X"
          : "no salient effector: +X towards the side the head's points lie on on average, "
            "sign doubtful";
  // A blade or a scoop (a head thinnest along the effector axis, reaching less far along it than it is
  // wide) works with its concave side: when its edges curl to one side, that side is the effector's,
  // whichever reaches farther (a scoop's belly may bulge behind the handle's axis).
  const bool thin_along_x = has_head && std::abs(about.head_thinnest.dot(x_axis)) >= std::cos(30 * kDeg);
  bool curled = false;
  if (thin_along_x) {
    const Curl curl = head_curl(cloud, head, centre + offset * z_normal, x_axis, z_normal);
    if (std::max(reach.positive, reach.negative) < curl.half_width) frame.diagnostics.head_curl = curl.rise;
    if (std::abs(frame.diagnostics.head_curl) >= config.head_curl_min) {
      curled = true;
      if (frame.diagnostics.head_curl < 0) {
        x_axis = -x_axis;
        std::swap(frame.diagnostics.effector_reach_positive, frame.diagnostics.effector_reach_negative);
        frame.diagnostics.head_curl = -frame.diagnostics.head_curl;
      }
      frame.diagnostics.effector_sign_rule =
          "the head is a blade or scoop facing +-X whose edges curl towards +X: it works "
          "with its concave side";
    }
  }

  frame.effector_side_clear = frame.diagnostics.salient_effector || curled;
  frame.axes.col(0) = x_axis;
  frame.axes.col(1) = y_axis;
  frame.axes.col(2) = x_axis.cross(y_axis);  // right-handed by construction
  frame.diagnostics.hand_to_handle = radial_distance(handle_line, Vec3::Zero());

  // The head's kind, once: a blade (curled: a scoop) continues the handle and works with its far end; a
  // plate thinnest along X that is no blade lies across the handle (a rake's comb, a hoe's blade).
  if (has_head) {
    std::vector<double> along, across;
    for (auto i : head) {
      along.push_back((cloud[i] - centre).dot(y_axis));
      across.push_back((cloud[i] - centre).dot(frame.axes.col(2)));
    }
    frame.diagnostics.head_length = inner_extent(std::move(along));
    frame.diagnostics.head_width = inner_extent(std::move(across));
  }
  if (frame.stick) {
    frame.head_kind = HeadKind::none;
  } else if (frame.head_kind != HeadKind::bar) {
    if (blade)
      frame.head_kind = curled ? HeadKind::scoop : HeadKind::blade;
    else if (thin_along_x)
      frame.head_kind = HeadKind::plate;
  }
  // Doubts: those of any plane; an effector whose two sides reach differently, but not by enough to be salient,
  // may have its side reversed (a tool whose sides reach alike within salience-min is symmetric: either
  // side is right).
  check_any_plane(frame, config);
  const double reach_difference = frame.diagnostics.effector_reach_positive - frame.diagnostics.effector_reach_negative;
  if (!frame.stick && !curled && !frame.diagnostics.salient_effector &&
      std::abs(reach_difference) >= config.salience_min)
    frame.confidence.check(0.0, fmt::format("the effector reaches {:.0f} mm along +X and {:.0f} mm along -X: too alike "
                                            "to tell its side, too different for a symmetric head",
                                            1000 * frame.diagnostics.effector_reach_positive,
                                            1000 * frame.diagnostics.effector_reach_negative));
  // The centroid projected onto the symmetry plane.
  frame.origin = principal.centroid - (principal.centroid - (centre + offset * z_normal)).dot(z_normal) * z_normal;
  return frame;
}

// The cloud as every method uses it: the pieces the hand holds (not the hand, nor what it does not hold),
// resampled, stray points dropped; its principal axes; and the frame's record of it.
struct Prepared {
  HeldPiece held;
  Points cloud;
  PrincipalAxes principal;
  ToolFrame frame;
};
// held_by_hand: held_piece of input with the config's hand-radius and piece-gap.
Prepared prepare(const Points& input, HeldPiece held_by_hand, const ToolFrameConfig& config) {
  if (config.handle_hand_skip >= config.handle_fraction)
    throw std::invalid_argument("handle-hand-skip must be below handle-fraction: nothing would be left to fit");
  Prepared p;
  p.held = std::move(held_by_hand);
  Points held;
  held.reserve(p.held.indices.size());
  for (const auto i : p.held.indices) held.push_back(input[i]);
  p.cloud = held.empty() ? Points{}
                         : remove_isolated(voxel_downsample(held, config.voxel_size), config.isolated_radius,
                                           config.isolated_min_neighbors);
  p.principal = principal_axes(p.cloud);
  check_not_degenerate(input, held, p.cloud, p.principal, config);
  p.frame.diagnostics.points_input = static_cast<int>(input.size());
  p.frame.diagnostics.points_outside_hand = static_cast<int>(held.size()) + p.held.detached_points;
  p.frame.diagnostics.points_detached = p.held.detached_points;
  p.frame.diagnostics.pieces_detached = p.held.detached_pieces;
  p.frame.diagnostics.points_used = static_cast<int>(p.cloud.size());
  p.frame.diagnostics.centroid = p.principal.centroid;
  p.frame.diagnostics.principal = p.principal.axes;
  p.frame.eigenvalues = p.principal.eigenvalues;
  return p;
}

// A frame as one hypothesis of the search: one plane and one side. The rules' tied and rival planes and
// their doubt of the side are other hypotheses there, weighed by the search, not alternatives of this one
// (nor does find-tooltip spend time on them); of its doubts only those of any plane stay, the search adds
// its own.
ToolFrame as_hypothesis(ToolFrame frame, const ToolFrameConfig& config) {
  frame.tied_planes = {frame.diagnostics.symmetry_candidates.back()};
  frame.rival_planes.clear();
  frame.effector_side_clear = true;
  frame.confidence = Confidence{};
  check_any_plane(frame, config);
  return frame;
}

// The same frame with the effector on the other side of the handle (X and Z turned, so it stays
// right-handed; the symmetry plane and the origin on it are the same).
ToolFrame other_side(ToolFrame frame) {
  frame.axes.col(0) = -frame.axes.col(0);
  frame.axes.col(2) = -frame.axes.col(2);
  std::swap(frame.diagnostics.effector_reach_positive, frame.diagnostics.effector_reach_negative);
  frame.diagnostics.head_curl = -frame.diagnostics.head_curl;
  frame.diagnostics.effector_sign_rule = "the search's other side: +X where the rules found the effector's back";
  return frame;
}

// What the features measure about a handle alone, whatever the plane and side: the head's points (the
// effector side's beyond head-radius-factor handle radii of its axis) and their summed distance from it,
// the share of the part the hand holds (held-share) that lies off the handle's line, beyond what the
// hand closes on, and the normal of a bar-like head's line seen along the handle.
struct HandleFeatures {
  const std::vector<std::uint32_t>& head;
  double head_out = 0.0;
  double held_off_line = 0.0;
  std::optional<Vec3> bar_normal;
};
HandleFeatures handle_features(const AboutHandle& about, const Points& cloud, const Points& held,
                               const ToolFrameConfig& c) {
  HandleFeatures features{about.head, 0.0, 0.0, std::nullopt};
  if (about.bar_line) features.bar_normal = about.normal_at(about.bar_line->normal_angle);
  for (const auto i : about.head) features.head_out += radial_distance(about.line, cloud[i]);
  int off_line = 0;
  for (const auto& p : held) off_line += radial_distance(about.line, p) > c.grasp_max_radius;
  if (!held.empty()) features.held_off_line = static_cast<double>(off_line) / static_cast<double>(held.size());
  return features;
}

// The mirror score of a perfect mirror seen through the stereo noise: matched images' distances of about
// 1.2 mm (the noise's mean absolute value) per 10 mm of symmetry-tolerance, weighed by symmetry-match-weight
// (0.25), are 0.03; a tenth of that is below any plane's residual, so a noiseless mirror's 0 is floored there.
constexpr double kMirrorScoreFloor = 0.003;

// A hypothesis's features, each in units of the parameter that gives it its physical scale and each
// comparable between hypotheses (measured the same way whatever the candidate handle came from).
std::array<double, kFrameFeatures> features_of(const ToolFrame& f, const Points& cloud, const HandleFeatures& handle,
                                               bool rules_plane, const ToolFrameConfig& c) {
  const Vec3 x = f.effector_axis();
  // The head's mean point along +X, against its points' mean distance from the handle's axis: the side its
  // material lies on (-1 to 1), which smear moves little.
  double head_x = 0.0;
  for (const auto i : handle.head) head_x += (cloud[i] - f.handle_point).dot(x);
  const double head_out = handle.head_out;
  // Seen along the handle, a bar-like head (L, T, hook) lies along the effector axis, as the tool's frame
  // defines it; a T's two mirror planes, or a plane tilted by a slightly tilted handle, mirror alike. The
  // bar lies along X as its line's normal lies along Z.
  const double bar_along_x = handle.bar_normal ? std::pow(handle.bar_normal->dot(f.symmetry_axis()), 2) : 0.0;
  const double forward = f.diagnostics.effector_reach_positive, backward = f.diagnostics.effector_reach_negative;
  const double reach = f.diagnostics.hand_to_handle / c.grasp_reach, radius = f.handle_radius / c.grasp_max_radius;
  return {
      reach,  // the handle's line's distance from the hand
      std::max(0.0, f.diagnostics.hand_to_handle - c.grasp_hold) / c.grasp_hold,  // ... beyond the hand's hold
      radius,                       // the handle's radius against what the hand closes on
      std::max(0.0, radius - 1.0),  // ... beyond it
      handle.held_off_line,         // the held part off it (the hand closes on the handle)
      f.symmetry_score,             // the head's mirror residual
      rules_plane ? 1.0 : 0.0,      // the plane the rules choose about this handle, not an alternative
      // How much farther the effector reaches along +X than along -X, as a share of both (-1 to 1; a reach
      // is negative where the whole effector side lies on the other side of the handle's line)
      std::abs(forward) + std::abs(backward) > 0.0 ? (forward - backward) / (std::abs(forward) + std::abs(backward))
                                                   : 0.0,
      // The head's edges rising towards +X (a scoop's concave side), saturating once clear of the noise
      std::tanh(f.diagnostics.head_curl / c.head_curl_min),
      head_out > 0.0 ? head_x / head_out : 0.0,  // the head's side
      f.tip_at_far_end() ? 1.0 : 0.0,            // a blade or scoop continuing the handle: its tip its far end
      bar_along_x,  // a bar-like head (head-line-elongation) along X: cos^2 of their angle; 0 for other heads
      // The mirror residual's order of magnitude: a plane the head truly mirrors across leaves the noise's
      // residual, a wrong one several times that, whatever the residual's own scale
      std::log(std::max(f.symmetry_score, kMirrorScoreFloor)),
  };
}

// The normal of the plane through the handle's axis that maps a frame's tooltip onto the tool's other end:
// the plane a quarter turn from the symmetry plane (normal to the effector axis), refined by the mirror within
// a sweep step, when the head mirrors across both planes as well as across the best plane about the handle
// (within symmetry-tie-margin: a T, a flat top, whose two ends are alike). None for a tool with one end, for a
// plane that mirrors it worse (a wrong plane's quarter turn may be as bad), and for a stick or a blade, whose
// tip lies on that plane.
std::optional<Vec3> other_end_mirror(const ToolFrame& frame, const AboutHandle& about, const ToolFrameConfig& c) {
  if (frame.stick || frame.tip_at_far_end() || about.tied_planes.empty()) return std::nullopt;
  const auto best = std::min_element(about.tied_planes.begin(), about.tied_planes.end(),
                                     [](const auto& a, const auto& b) { return a.score < b.score; });
  const double tie = best->score + c.symmetry_tie_margin;
  if (frame.symmetry_score > tie) return std::nullopt;
  // As alternative_planes_deg asks for it: about the rules' plane, the search's quarter turn, whose mirror
  // scores are then known.
  const double quarter_turn = (frame.diagnostics.symmetry_candidates.back().angle_deg + 90.0) * kDeg;
  // Refined only where the sweep scored an angle within a step of it near its best, as the sweep refines
  // nothing else: a plane that far above it within a step is no tie.
  double best_swept = std::numeric_limits<double>::infinity(), near_swept = best_swept;
  for (const auto& s : about.sweep) {
    best_swept = std::min(best_swept, s.score);
    if (std::abs(std::remainder(s.angle_deg * kDeg - quarter_turn, M_PI)) <= about.step)
      near_swept = std::min(near_swept, s.score);
  }
  if (near_swept > best_swept + kSweepRescoreMargin) return std::nullopt;
  const auto [angle, score] = golden_minimum([&](double a) { return about.score_at(a); }, quarter_turn - about.step,
                                             quarter_turn + about.step, kGoldenIterations);
  if (score > tie) return std::nullopt;
  return about.normal_at(angle);
}

// The planes the search tries about a handle: the rules' own, its quarter turn (a T or a flat top has
// two mirror planes) and the sweep's rival basins, best first; each at most once (15 degrees apart), at
// most kSearchPlanes.
constexpr std::size_t kSearchPlanes = 3;
std::vector<double> alternative_planes_deg(const ToolFrame& rules) {
  const double chosen = rules.diagnostics.symmetry_candidates.back().angle_deg;
  std::vector<double> taken{chosen}, asked{chosen + 90.0};
  for (const auto& rival : rules.rival_planes) asked.push_back(rival.angle_deg);
  std::vector<double> alternatives;
  for (const double angle : asked) {
    if (taken.size() >= kSearchPlanes) break;
    if (std::none_of(taken.begin(), taken.end(),
                     [&](double t) { return std::abs(std::remainder(angle - t, 180.0)) < 15.0; })) {
      taken.push_back(angle);
      alternatives.push_back(angle);
    }
  }
  return alternatives;
}

}  // namespace

const std::array<const char*, kFrameFeatures>& frame_feature_names() {
  static const std::array<const char*, kFrameFeatures> names{"hand_to_handle_per_grasp_reach",
                                                             "beyond_grasp_hold",
                                                             "handle_radius_per_grasp_max_radius",
                                                             "beyond_grasp_max_radius",
                                                             "held_share_off_handle",
                                                             "mirror_score",
                                                             "rules_plane",
                                                             "effector_reach_asymmetry",
                                                             "head_curl_saturated",
                                                             "head_side",
                                                             "blade_or_scoop",
                                                             "head_bar_along_effector",
                                                             "mirror_score_log"};
  return names;
}

namespace {

// Whether a tooltip agrees with a chosen one: both exist and it lies within radius of the chosen tip or of
// the chosen one's other end.
bool agrees(const std::optional<Vec3>& tip, const std::optional<Vec3>& chosen, const std::optional<Vec3>& other_end,
            double radius) {
  if (!tip || !chosen) return false;
  return (*tip - *chosen).norm() <= radius || (other_end && (*tip - *other_end).norm() <= radius);
}

}  // namespace

const ScoredHypothesis* next_tip_elsewhere(const ToolFrame& frame, double radius) {
  const auto& all = frame.diagnostics.hypotheses;
  if (all.empty()) return nullptr;
  const ScoredHypothesis& chosen = all.front();
  const auto elsewhere = std::find_if(all.begin() + 1, all.end(), [&](const ScoredHypothesis& h) {
    return !agrees(h.tooltip, chosen.tooltip, chosen.other_end, radius);
  });
  return elsewhere == all.end() ? nullptr : &*elsewhere;
}

double tooltip_probability(const std::vector<double>& scores, const std::vector<std::optional<Vec3>>& tooltips,
                           std::size_t chosen, double radius, const std::vector<std::optional<Vec3>>& other_ends) {
  if (tooltips.size() != scores.size() || (!other_ends.empty() && other_ends.size() != scores.size()))
    throw std::invalid_argument("tooltip_probability: one tooltip (and other end, if any) per score");
  if (!tooltips[chosen]) return 0.0;
  double agreeing = 0.0, total = 0.0;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    const double weight = std::exp(scores[i] - scores[chosen]);
    total += weight;
    if (agrees(tooltips[i], tooltips[chosen], other_ends.empty() ? std::nullopt : other_ends[chosen], radius))
      agreeing += weight;
  }
  return agreeing / total;
}

Vec3 effector_side(const ToolFrame& frame) { return frame.stick ? Vec3::Zero() : frame.effector_axis(); }

std::size_t most_probable_tooltip(const std::vector<double>& scores, const std::vector<std::optional<Vec3>>& tooltips,
                                  const std::vector<Vec3>& effector_sides, double radius) {
  if (tooltips.size() != scores.size() || effector_sides.size() != scores.size())
    throw std::invalid_argument("most_probable_tooltip: one tooltip and one effector side per score");
  std::size_t centre = 0;
  double best = -1.0;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    const double p = tooltip_probability(scores, tooltips, i, radius);
    if (p > best || (p == best && scores[i] > scores[centre])) best = p, centre = i;
  }
  if (!tooltips[centre]) return centre;
  std::vector<std::size_t> agreeing;
  for (std::size_t i = 0; i < scores.size(); ++i)
    if (agrees(tooltips[i], tooltips[centre], std::nullopt, radius)) agreeing.push_back(i);
  // Of those, the side with the most probability, then its likeliest: its frame is the one to give. Each
  // side's sum runs over the same hypotheses in the same order, so a side's members tie exactly.
  std::size_t chosen = centre;
  double chosen_side = -1.0;
  for (const std::size_t i : agreeing) {
    double side = 0.0;
    for (const std::size_t j : agreeing)
      if (effector_sides[j].dot(effector_sides[i]) >= 0.0) side += std::exp(scores[j] - scores[centre]);
    if (side > chosen_side || (side == chosen_side && scores[i] > scores[chosen])) chosen_side = side, chosen = i;
  }
  return chosen;
}

double FrameScoreModel::log_odds(const std::array<double, kFrameFeatures>& features) const {
  double sum = 0.0;
  for (int i = 0; i < kFrameFeatures; ++i) sum += weights[i] * features[i];
  return sum;
}

namespace {

// The tooltips of a frame estimated alone: find-tooltip's defaults with the frame's hand settings.
TooltipConfig hypotheses_tooltip_config(const ToolFrameConfig& config) {
  TooltipConfig tooltip_config;
  share_hand_settings(config, tooltip_config);
  return tooltip_config;
}

// The cache's held piece is the frame's only with the same hand settings.
void check_hand_settings(const TooltipCache& tooltips, const ToolFrameConfig& config) {
  if (tooltips.config().hand_radius != config.hand_radius || tooltips.config().piece_gap != config.piece_gap)
    throw std::invalid_argument("the tooltip cache's hand-radius and piece-gap must be the frame's");
}

}  // namespace

std::vector<FrameHypothesis> frame_hypotheses(const Points& input, const ToolFrameConfig& config,
                                              const Points& viewpoints, const FrameScoreModel& model,
                                              const std::vector<std::uint32_t>& views) {
  const KdTree tree(input);
  return frame_hypotheses(TooltipCache(input, tree, hypotheses_tooltip_config(config), views), config, viewpoints,
                          model);
}

std::vector<FrameHypothesis> frame_hypotheses(const TooltipCache& cache, const ToolFrameConfig& config,
                                              const Points& viewpoints, const FrameScoreModel& model) {
  check_hand_settings(cache, config);
  const Prepared p = prepare(cache.points(), cache.held(), config);
  const FreeSpace free_space(p.cloud, viewpoints);
  const FreeSpace* seen = viewpoints.empty() ? nullptr : &free_space;
  const Points held = held_part(p.cloud, config.held_share);
  // The hand holds the handle: a candidate whose line passes beyond grasp-reach from it is no hypothesis,
  // unless every candidate does.
  auto candidates = handle_candidates(p.cloud, p.principal, config);
  const auto beyond_reach = [&](const auto& candidate) {
    const HandleFit& h = candidate.second;
    return radial_distance(Cylinder{h.point, h.axis.normalized(), 0.0, 0.0}, Vec3::Zero()) > config.grasp_reach;
  };
  if (!std::all_of(candidates.begin(), candidates.end(), beyond_reach))
    candidates.erase(std::remove_if(candidates.begin(), candidates.end(), beyond_reach), candidates.end());
  std::vector<FrameHypothesis> hypotheses;
  const MirrorTarget target(p.cloud, config.symmetry_tolerance, config.symmetry_normal_neighbors);
  for (const auto& [source, handle] : candidates) {
    const AboutHandle about(p.cloud, p.principal, handle, target, seen, config);
    const ToolFrame rules = frame_about_handle(p.frame, p.cloud, p.principal, handle, about, config);
    const HandleFeatures handle_measures = handle_features(about, p.cloud, held, config);
    std::vector<ToolFrame> frames{as_hypothesis(rules, config)};
    for (const double angle : alternative_planes_deg(rules))
      frames.push_back(
          as_hypothesis(frame_about_handle(p.frame, p.cloud, p.principal, handle, about, config, angle), config));
    for (std::size_t plane = 0; plane < frames.size(); ++plane) {
      const std::optional<Vec3> mirror_normal = other_end_mirror(frames[plane], about, config);
      for (const bool reversed : {false, true}) {
        FrameHypothesis h{reversed ? other_side(frames[plane]) : frames[plane],
                          source,
                          plane == 0,
                          reversed,
                          {},
                          0.0,
                          std::nullopt,
                          std::nullopt};
        h.features = features_of(h.frame, p.cloud, handle_measures, plane == 0, config);
        h.log_odds = model.log_odds(h.features);
        // None: nothing dense on its effector side. A stick's tip and a blade's far end do not depend on the
        // side (the rule ignores the effector axis, and the plane is the same), so the other side's is the one's.
        h.tooltip = reversed && (h.frame.stick || h.frame.tip_at_far_end()) ? hypotheses.back().tooltip
                                                                            : tooltip_position(cache, h.frame);
        if (mirror_normal && h.tooltip) h.other_end = mirror_image(*h.tooltip, *mirror_normal, about.centre);
        hypotheses.push_back(std::move(h));
      }
    }
  }
  return hypotheses;
}

namespace {

// Each axis decided once, as the rules decide it.
ToolFrame rules_frame(const Points& input, HeldPiece held, const ToolFrameConfig& config, const Points& viewpoints) {
  const Prepared p = prepare(input, std::move(held), config);
  const FreeSpace free_space(p.cloud, viewpoints);
  const HandleFit handle = rule_handle(p.cloud, p.principal, config);
  const MirrorTarget target(p.cloud, config.symmetry_tolerance, config.symmetry_normal_neighbors);
  return frame_about_handle(
      p.frame, p.cloud, p.principal, handle,
      AboutHandle(p.cloud, p.principal, handle, target, viewpoints.empty() ? nullptr : &free_space, config), config);
}

}  // namespace

ToolFrame estimate_tool_frame(const Points& input, const ToolFrameConfig& config, const Points& viewpoints,
                              const std::vector<std::uint32_t>& views) {
  if (config.method == FrameMethod::rules)
    return rules_frame(input, held_piece(input, config.hand_radius, config.piece_gap), config, viewpoints);
  const KdTree tree(input);
  return estimate_tool_frame(TooltipCache(input, tree, hypotheses_tooltip_config(config), views), config, viewpoints);
}

ToolFrame estimate_tool_frame(const TooltipCache& cache, const ToolFrameConfig& config, const Points& viewpoints) {
  check_hand_settings(cache, config);
  if (config.method == FrameMethod::search) {
    const auto hypotheses = frame_hypotheses(cache, config, viewpoints, fitted_frame_score());
    std::vector<double> scores;
    std::vector<std::optional<Vec3>> tooltips, other_ends;
    std::vector<Vec3> sides;
    for (const auto& h : hypotheses) {
      scores.push_back(h.log_odds), tooltips.push_back(h.tooltip), other_ends.push_back(h.other_end);
      sides.push_back(effector_side(h.frame));
    }
    const double radius = cache.config().ambiguity_distance;
    const std::size_t chosen = most_probable_tooltip(scores, tooltips, sides, radius);
    // The chosen first, then by score.
    std::vector<std::size_t> order(hypotheses.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return std::pair{a == chosen, hypotheses[a].log_odds} > std::pair{b == chosen, hypotheses[b].log_odds};
    });
    const FrameHypothesis& best = hypotheses[chosen];
    ToolFrame frame = best.frame;
    // The choice model's probabilities: each hypothesis's share of exp(score) among them all.
    double total = 0.0;
    for (const double z : scores) total += std::exp(z - best.log_odds);
    for (const std::size_t i : order) {
      const FrameHypothesis& h = hypotheses[i];
      frame.diagnostics.hypotheses.push_back({h.handle_source, h.rules_plane, h.side_reversed,
                                              std::exp(h.log_odds - best.log_odds) / total, h.frame.effector_axis(),
                                              h.frame.handle_axis(), h.tooltip, h.other_end,
                                              std::vector<double>(h.features.begin(), h.features.end())});
    }
    // The rules' doubts are the search's features and alternatives: the confidence is the probability that
    // the chosen tooltip lies within the confident tolerance (15 mm) of the truth, the hypotheses whose tips
    // lie that near it or its other end (either end of a T is right) summed, against the level calibrated so, on
    // sessions the fit did not see, for 98 % of confident tooltips within it. The choice itself is the Bayes choice for
    // the 10 mm a tool's use needs.
    const FrameScoreModel& model = fitted_frame_score();
    const double probability = tooltip_probability(scores, tooltips, chosen, model.confident_tolerance, other_ends);
    const double needed = model.confident_probability;
    frame.diagnostics.tooltip_probability = probability;
    frame.confidence.check(probability >= needed ? std::max((probability - needed) / std::max(1.0 - needed, 1e-9), 1e-9)
                                                 : probability - needed,
                           fmt::format("the search's tooltip ({}{}{}) is right with probability {:.2f}, below {:.2f}",
                                       best.handle_source, best.rules_plane ? "" : ", another plane",
                                       best.side_reversed ? ", other side" : "", probability, needed));
    return frame;
  }
  return rules_frame(cache.points(), cache.held(), config, viewpoints);
}

std::string to_string(FrameMethod method) { return method == FrameMethod::search ? "search" : "rules"; }

FrameMethod frame_method_from_string(const std::string& name) {
  if (name == "rules") return FrameMethod::rules;
  if (name == "search") return FrameMethod::search;
  throw std::invalid_argument("unknown frame method '" + name + "' (rules or search)");
}

}  // namespace toolinc
