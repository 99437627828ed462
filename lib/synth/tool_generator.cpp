// Procedural tools: each family is a union of simple solid parts (cylinders, balls, boxes, a curved
// shell) and the cloud samples the boundary of that union. Every part's surface is sampled uniformly and
// a sample is kept only where no other part covers it, which trims handles where they enter heads, hides
// caps inside joints and removes faces in contact, so only the outer surface remains.
#include "toolinc/synth/tool_generator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "toolinc/core/random.hpp"

namespace toolinc {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxPoints = 5e6;
// A sample this close to another part counts as covered by it, so that coincident faces of parts in
// contact (a handle end on a head's face) both vanish although rounding may put them a hair apart.
constexpr double kCoverTolerance = 1e-12;
constexpr double kPlateThickness = 0.006;      // flat-top plate, along Y
constexpr double kBladeHalfThickness = 0.002;  // shovel blade, along X
constexpr double kMinBladeLength = 0.10;       // shovel blade, along Y
constexpr double kBarRadiusRatio = 0.8;        // rake crossbar radius / handle radius
constexpr double kToothRadius = 0.004;
constexpr double kToothPitch = 0.02;
constexpr double kToothReach = 0.6;  // rake teeth reach this fraction of head_length (shorter than a hoe)

// How far a shovel's rims rise above the middle of its scoop.
double scoop_depth(const ToolShape& shape) { return shape.head_length / 5.0; }

struct Surfel {
  Vec3 point, normal;
};

// A piece of a part's surface: its area and a draw of one point uniformly distributed on it, with the
// outward unit normal there.
struct Patch {
  double area;
  std::function<Surfel(Rng&)> draw;
};

// A solid piece of a tool: its whole boundary, and which points it covers.
struct Part {
  std::vector<Patch> surface;
  std::function<bool(const Vec3&)> covers;  // closed solid: points on its boundary count as covered
};

struct Basis {
  Vec3 u, v;
};

// Completes the unit `axis` to a right-handed orthonormal frame. The helper axis is a coordinate axis,
// so for an axis-aligned `axis` the result has exact zeros and a cap on a coordinate plane stays exactly
// on it (which the contact test relies on).
Basis perpendicular_basis(const Vec3& axis) {
  Eigen::Index k;
  axis.cwiseAbs().minCoeff(&k);
  const Vec3 u = axis.cross(Vec3::Unit(k)).normalized();
  return {u, axis.cross(u)};
}

Vec3 on_circle(const Basis& basis, double angle) { return std::cos(angle) * basis.u + std::sin(angle) * basis.v; }

// --- Surface patches ------------------------------------------------------------------------------

Patch cylinder_side(const Vec3& a, const Vec3& b, double radius) {
  const Basis basis = perpendicular_basis((b - a).normalized());
  return {2.0 * kPi * radius * (b - a).norm(), [=](Rng& rng) {
            const double t = rng.uniform();
            const Vec3 radial = on_circle(basis, rng.uniform(0.0, 2.0 * kPi));
            return Surfel{a + t * (b - a) + radius * radial, radial};
          }};
}

Patch disk(const Vec3& centre, const Vec3& normal, double radius) {
  const Basis basis = perpendicular_basis(normal);
  return {kPi * radius * radius, [=](Rng& rng) {
            const double rho = radius * std::sqrt(rng.uniform());  // sqrt: uniform per area
            return Surfel{centre + rho * on_circle(basis, rng.uniform(0.0, 2.0 * kPi)), normal};
          }};
}

Patch sphere(const Vec3& centre, double radius) {
  return {4.0 * kPi * radius * radius, [=](Rng& rng) {
            const double z = rng.uniform(-1.0, 1.0);  // Archimedes: uniform height is uniform per area
            const double phi = rng.uniform(0.0, 2.0 * kPi);
            const double ring = std::sqrt(1.0 - z * z);
            const Vec3 direction(ring * std::cos(phi), ring * std::sin(phi), z);
            return Surfel{centre + radius * direction, direction};
          }};
}

Patch rectangle(const Vec3& corner, const Vec3& edge_u, const Vec3& edge_v, const Vec3& normal) {
  return {edge_u.cross(edge_v).norm(), [=](Rng& rng) {
            const double s = rng.uniform();
            const double t = rng.uniform();
            return Surfel{corner + s * edge_u + t * edge_v, normal};
          }};
}

std::vector<Patch> box_faces(const Vec3& lo, const Vec3& hi) {
  std::vector<Patch> faces;
  const Vec3 size = hi - lo;
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    Vec3 top_corner = lo;
    top_corner[k] = hi[k];
    const Vec3 edge_u = size[i] * Vec3::Unit(i), edge_v = size[j] * Vec3::Unit(j);
    faces.push_back(rectangle(lo, edge_u, edge_v, -Vec3::Unit(k)));
    faces.push_back(rectangle(top_corner, edge_u, edge_v, Vec3::Unit(k)));
  }
  return faces;
}

// The shovel blade: the solid |x - mid(z)| <= half_thickness, |z| <= half_width, y in [y_lo, y_hi], with
// the parabolic mid-surface mid(z) = offset + depth * (z / half_width)^2. The thickness is measured along
// X, which keeps both faces graphs over (y, z) and the covering test exact.
struct Shell {
  double y_lo, y_hi, half_width, depth, half_thickness, offset;

  double mid(double z) const { return offset + depth * (z / half_width) * (z / half_width); }
  double slope(double z) const { return 2.0 * depth * z / (half_width * half_width); }
  // Length of the mid-surface curve over |z| <= half_width (closed form for a parabola).
  double arc_length() const {
    const double k = 2.0 * depth / (half_width * half_width), w = half_width;
    if (k == 0.0) return 2.0 * w;  // a flat blade
    return w * std::sqrt(1.0 + k * k * w * w) + std::asinh(k * w) / k;
  }
};

// One face x = mid(z) + side * half_thickness (side = +1 faces +X, -1 faces -X).
Patch shell_face(const Shell& shell, double side) {
  const double max_stretch = std::sqrt(1.0 + std::pow(shell.slope(shell.half_width), 2));
  return {(shell.y_hi - shell.y_lo) * shell.arc_length(), [=](Rng& rng) {
            // Rejection on z by the area stretch of the curved face over the flat (y, z) rectangle.
            double z, stretch;
            do {
              z = rng.uniform(-shell.half_width, shell.half_width);
              stretch = std::sqrt(1.0 + std::pow(shell.slope(z), 2));
            } while (rng.uniform() * max_stretch >= stretch);
            const double y = rng.uniform(shell.y_lo, shell.y_hi);
            const Vec3 point(shell.mid(z) + side * shell.half_thickness, y, z);
            return Surfel{point, side * Vec3(1.0, 0.0, -shell.slope(z)) / stretch};
          }};
}

// The rim across the blade's thickness at height y (normal +Y or -Y).
Patch shell_end(const Shell& shell, double y, double normal_y) {
  return {4.0 * shell.half_thickness * shell.half_width, [=](Rng& rng) {
            const double z = rng.uniform(-shell.half_width, shell.half_width);
            const double dx = rng.uniform(-shell.half_thickness, shell.half_thickness);
            return Surfel{Vec3(shell.mid(z) + dx, y, z), Vec3(0.0, normal_y, 0.0)};
          }};
}

std::vector<Patch> shell_surfaces(const Shell& shell) {
  std::vector<Patch> patches{shell_face(shell, 1.0), shell_face(shell, -1.0), shell_end(shell, shell.y_hi, 1.0),
                             shell_end(shell, shell.y_lo, -1.0)};
  const Vec3 across(2.0 * shell.half_thickness, 0.0, 0.0), along(0.0, shell.y_hi - shell.y_lo, 0.0);
  for (double side : {-1.0, 1.0}) {
    const double z = side * shell.half_width;
    const Vec3 corner(shell.mid(z) - shell.half_thickness, shell.y_lo, z);
    patches.push_back(rectangle(corner, across, along, Vec3(0.0, 0.0, side)));
  }
  return patches;
}

// --- Solid parts ----------------------------------------------------------------------------------

Part cylinder(const Vec3& a, const Vec3& b, double radius) {
  const Vec3 axis = (b - a).normalized();
  const double length = (b - a).norm();
  return {{cylinder_side(a, b, radius), disk(a, -axis, radius), disk(b, axis, radius)}, [=](const Vec3& p) {
            const double along = (p - a).dot(axis);
            return along >= -kCoverTolerance && along <= length + kCoverTolerance &&
                   (p - a - along * axis).norm() <= radius + kCoverTolerance;
          }};
}

Part ball(const Vec3& centre, double radius) {
  return {{sphere(centre, radius)}, [=](const Vec3& p) { return (p - centre).norm() <= radius + kCoverTolerance; }};
}

Part box(const Vec3& lo, const Vec3& hi) {
  return {box_faces(lo, hi), [=](const Vec3& p) {
            return (p.array() >= lo.array() - kCoverTolerance).all() &&
                   (p.array() <= hi.array() + kCoverTolerance).all();
          }};
}

Part blade(const Shell& shell) {
  return {shell_surfaces(shell), [=](const Vec3& p) {
            return p.y() >= shell.y_lo - kCoverTolerance && p.y() <= shell.y_hi + kCoverTolerance &&
                   std::abs(p.z()) <= shell.half_width + kCoverTolerance &&
                   std::abs(p.x() - shell.mid(p.z())) <= shell.half_thickness + kCoverTolerance;
          }};
}

// --- Families -------------------------------------------------------------------------------------

Vec3 on_handle_axis(double y) { return Vec3(0.0, y, 0.0); }

// About one tooth per kToothPitch across the bar, odd so that one sits at z = 0, between 5 and 7.
int rake_tooth_count(double head_width) {
  const long odd = 2 * std::lround((head_width / kToothPitch - 1.0) / 2.0) + 1;
  return static_cast<int>(std::clamp(odd, 5L, 7L));
}

std::vector<Part> rake_parts(const ToolShape& shape) {
  const double bar_radius = kBarRadiusRatio * shape.handle_radius;
  const double bar_y = -shape.handle_length - bar_radius;
  const double half_width = 0.5 * shape.head_width;
  // The handle runs on to the bar's axis so that the two are joined by more than a tangent line.
  std::vector<Part> parts{cylinder(Vec3::Zero(), on_handle_axis(bar_y), shape.handle_radius),
                          cylinder(Vec3(0.0, bar_y, -half_width), Vec3(0.0, bar_y, half_width), bar_radius)};
  const int teeth = rake_tooth_count(shape.head_width);
  const double pitch = 2.0 * (half_width - kToothRadius) / (teeth - 1);  // outer teeth flush with the bar ends
  const double reach = kToothReach * shape.head_length;
  for (int i = 0; i < teeth; ++i) {
    const double z = (i - (teeth - 1) / 2) * pitch;
    parts.push_back(cylinder(Vec3(0.0, bar_y, z), Vec3(reach, bar_y, z), kToothRadius));
  }
  return parts;
}

std::vector<Part> tool_parts(const ToolShape& shape) {
  const double r = shape.handle_radius, length = shape.head_length, half_width = 0.5 * shape.head_width;
  const double head_y = -shape.handle_length;       // where the head starts
  const double far_y = head_y - shape.head_height;  // the far end of the stick-like families
  const Vec3 hand = Vec3::Zero(), corner = on_handle_axis(far_y);
  switch (shape.family) {
    case ToolFamily::stick:
      return {cylinder(hand, corner, r)};
    case ToolFamily::hoe:
      return {cylinder(hand, on_handle_axis(head_y), r),
              box(Vec3(-r, far_y, -half_width), Vec3(length, head_y, half_width))};
    case ToolFamily::hook: {
      const Vec3 bend(length, far_y, 0.0);
      return {cylinder(hand, corner, r), ball(corner, r), cylinder(corner, bend, r), ball(bend, r),
              cylinder(bend, bend + Vec3(0.0, shape.head_height, 0.0), r)};
    }
    case ToolFamily::rake:
      return rake_parts(shape);
    case ToolFamily::shovel: {
      const double blade_length = std::max(shape.head_height, kMinBladeLength);
      return {cylinder(hand, on_handle_axis(head_y), r),
              blade({head_y - blade_length, head_y, half_width, scoop_depth(shape), kBladeHalfThickness,
                     shape.head_offset})};
    }
    case ToolFamily::l_stick:
      return {cylinder(hand, corner, r), ball(corner, r), cylinder(corner, Vec3(length, far_y, 0.0), r)};
    case ToolFamily::t_bar:
      return {cylinder(hand, corner, r), cylinder(Vec3(-0.5 * length, far_y, 0.0), Vec3(0.5 * length, far_y, 0.0), r)};
    case ToolFamily::flat_top:
      return {cylinder(hand, corner, r),
              box(Vec3(-0.5 * length, far_y - kPlateThickness, -half_width), Vec3(0.5 * length, far_y, half_width))};
    case ToolFamily::blade: {
      const double blade_length = std::max(shape.head_height, kMinBladeLength);
      return {cylinder(hand, on_handle_axis(head_y), r),
              blade({head_y - blade_length, head_y, half_width, 0.0, kBladeHalfThickness, shape.head_offset})};
    }
    case ToolFamily::square_plate:
      return {cylinder(hand, corner, r), box(Vec3(-0.5 * length, far_y - kPlateThickness, -0.5 * length),
                                             Vec3(0.5 * length, far_y, 0.5 * length))};
    case ToolFamily::cross:
      return {cylinder(hand, corner, r), cylinder(Vec3(-0.5 * length, far_y, 0.0), Vec3(0.5 * length, far_y, 0.0), r),
              cylinder(Vec3(0.0, far_y, -0.5 * length), Vec3(0.0, far_y, 0.5 * length), r)};
  }
  throw std::invalid_argument("unknown tool family");
}

void check_shape(const ToolShape& shape) {
  if (!std::isfinite(shape.head_offset))
    throw std::invalid_argument("tool shape: head_offset must be finite, got " + std::to_string(shape.head_offset));
  const std::pair<const char*, double> dimensions[] = {
      {"handle_length", shape.handle_length}, {"handle_radius", shape.handle_radius},
      {"head_length", shape.head_length},     {"head_width", shape.head_width},
      {"head_height", shape.head_height},     {"spacing", shape.spacing}};
  for (const auto& [name, value] : dimensions) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string("tool shape: ") + name + " must be positive and finite, got " +
                                  std::to_string(value));
    }
  }
}

// Samples each patch with round(area / spacing^2) draws and keeps those no other part covers.
PointCloud sample_union(const std::vector<Part>& parts, double spacing, std::uint32_t seed) {
  const double per_area = 1.0 / (spacing * spacing);
  double draws = 0.0;
  for (const Part& part : parts)
    for (const Patch& patch : part.surface) draws += std::round(patch.area * per_area);
  if (!(draws <= kMaxPoints)) {
    throw std::invalid_argument("tool shape: spacing " + std::to_string(spacing) + " would give about " +
                                std::to_string(draws) + " points (at most 5 million)");
  }
  PointCloud cloud;
  cloud.frame = "canonical";
  cloud.points.reserve(static_cast<std::size_t>(draws));
  cloud.normals.reserve(static_cast<std::size_t>(draws));
  Rng rng(seed);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    for (const Patch& patch : parts[i].surface) {
      const auto count = static_cast<std::size_t>(std::round(patch.area * per_area));
      for (std::size_t n = 0; n < count; ++n) {
        const Surfel s = patch.draw(rng);
        bool covered = false;
        for (std::size_t j = 0; j < parts.size() && !covered; ++j) covered = j != i && parts[j].covers(s.point);
        if (covered) continue;
        cloud.points.push_back(s.point);
        cloud.normals.push_back(s.normal);
      }
    }
  }
  return cloud;
}

}  // namespace

std::vector<ToolFamily> all_families() {
  return {ToolFamily::stick,  ToolFamily::hoe,     ToolFamily::hook,  ToolFamily::rake,
          ToolFamily::shovel, ToolFamily::l_stick, ToolFamily::t_bar, ToolFamily::flat_top};
}

std::vector<ToolFamily> real_shape_families() {
  return {ToolFamily::blade, ToolFamily::square_plate, ToolFamily::cross};
}

std::string to_string(ToolFamily family) {
  switch (family) {
    case ToolFamily::blade:
      return "blade";
    case ToolFamily::square_plate:
      return "square-plate";
    case ToolFamily::cross:
      return "cross";
    case ToolFamily::stick:
      return "stick";
    case ToolFamily::hoe:
      return "hoe";
    case ToolFamily::hook:
      return "hook";
    case ToolFamily::rake:
      return "rake";
    case ToolFamily::shovel:
      return "shovel";
    case ToolFamily::l_stick:
      return "l-stick";
    case ToolFamily::t_bar:
      return "t-bar";
    case ToolFamily::flat_top:
      return "flat-top";
  }
  throw std::invalid_argument("unknown tool family");
}

ToolFamily family_from_string(const std::string& name) {
  std::string known;
  std::vector<ToolFamily> families = all_families();
  for (ToolFamily family : real_shape_families()) families.push_back(family);
  for (ToolFamily family : families) {
    if (to_string(family) == name) return family;
    known += (known.empty() ? "" : ", ") + to_string(family);
  }
  throw std::invalid_argument("unknown tool family '" + name + "' (known: " + known + ")");
}

ToolSymmetry symmetry_of(ToolFamily family) {
  switch (family) {
    case ToolFamily::stick:
      return ToolSymmetry::axial;
    case ToolFamily::t_bar:
    case ToolFamily::flat_top:
    case ToolFamily::blade:
      return ToolSymmetry::front_back;
    case ToolFamily::square_plate:
    case ToolFamily::cross:
      return ToolSymmetry::fourfold;
    default:
      return ToolSymmetry::mirror;
  }
}

std::string to_string(ToolSymmetry symmetry) {
  switch (symmetry) {
    case ToolSymmetry::mirror:
      return "mirror";
    case ToolSymmetry::front_back:
      return "front_back";
    case ToolSymmetry::fourfold:
      return "fourfold";
    case ToolSymmetry::axial:
      return "axial";
  }
  throw std::invalid_argument("unknown tool symmetry");
}

ToolSymmetry symmetry_from_string(const std::string& name) {
  for (ToolSymmetry s : {ToolSymmetry::mirror, ToolSymmetry::front_back, ToolSymmetry::fourfold, ToolSymmetry::axial})
    if (to_string(s) == name) return s;
  throw std::invalid_argument("unknown tool symmetry '" + name + "' (known: mirror, front_back, fourfold, axial)");
}

bool has_salient_effector(ToolFamily family) { return symmetry_of(family) == ToolSymmetry::mirror; }

ToolShape default_shape(ToolFamily family) {
  ToolShape shape;  // handle radius 0.010 and spacing 0.002 throughout
  shape.family = family;
  switch (family) {
    case ToolFamily::stick:  // 0.30 long
      shape.handle_length = 0.26;
      shape.head_height = 0.04;
      break;
    case ToolFamily::hoe:  // blade 0.095 forward, 0.08 wide, 0.04 tall; 0.26 long
      shape.handle_length = 0.22;
      shape.head_length = 0.095;
      break;
    case ToolFamily::hook:  // 0.11 forward, 0.05 return; about 0.28 long
      shape.handle_length = 0.22;
      shape.head_length = 0.11;
      shape.head_height = 0.05;
      break;
    case ToolFamily::rake:  // 0.13 wide, teeth 0.06 forward; about 0.27 long
      shape.handle_length = 0.25;
      shape.head_width = 0.13;
      break;
    case ToolFamily::shovel:  // 0.09 wide, 0.10 long blade, 0.02 deep; 0.28 long
      shape.handle_length = 0.18;
      shape.head_width = 0.09;
      shape.head_height = 0.10;
      break;
    case ToolFamily::l_stick:  // 0.10 forward; about 0.27 long
    case ToolFamily::t_bar:    // 0.10 across; about 0.27 long
      shape.handle_length = 0.22;
      break;
    case ToolFamily::flat_top:  // 0.10 x 0.05 top: longer along X, so the effector axis is defined
      shape.handle_length = 0.22;
      shape.head_length = 0.10;
      shape.head_width = 0.05;
      break;
    case ToolFamily::blade:  // a flat spatula: 0.08 wide, 0.10 long, 4 mm thick; 0.28 long
      shape.handle_length = 0.18;
      shape.head_width = 0.08;
      shape.head_height = 0.10;
      break;
    case ToolFamily::square_plate:  // 0.08 x 0.08 plate across the handle's end
    case ToolFamily::cross:         // two 0.10 bars crossing at the handle's end
      shape.handle_length = 0.22;
      shape.head_length = family == ToolFamily::cross ? 0.10 : 0.08;
      break;
  }
  return shape;
}

ToolShape belly_behind(ToolShape shovel) {
  shovel.head_offset = -scoop_depth(shovel);
  return shovel;
}

PointCloud generate_tool(const ToolShape& shape, std::uint32_t seed) {
  check_shape(shape);
  return sample_union(tool_parts(shape), shape.spacing, seed);
}

}  // namespace toolinc
