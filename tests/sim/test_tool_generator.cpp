// Procedural tools: determinism, surface and normal validity against a reference solid written here from
// the canonical geometry, symmetry, extents, sampling density and argument checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "toolinc/synth/tool_generator.hpp"

namespace toolinc {
namespace {

constexpr std::uint32_t kSeeds[] = {1, 42, 20240601};
constexpr double kPi = 3.14159265358979323846;

struct Box3 {
  Vec3 lo, hi;
};

Box3 bounds(const Points& points) {
  Box3 box{Vec3::Constant(std::numeric_limits<double>::infinity()),
           Vec3::Constant(-std::numeric_limits<double>::infinity())};
  for (const Vec3& p : points) {
    box.lo = box.lo.cwiseMin(p);
    box.hi = box.hi.cwiseMax(p);
  }
  return box;
}

// --- Reference solids (independent of the generator's code) -------------------------------------------

bool in_cylinder(const Vec3& p, const Vec3& a, const Vec3& b, double r) {
  const Vec3 d = b - a;
  const double t = (p - a).dot(d) / d.squaredNorm();
  return t >= 0.0 && t <= 1.0 && (p - a - t * d).norm() <= r;
}
bool in_ball(const Vec3& p, const Vec3& c, double r) { return (p - c).norm() <= r; }
bool in_box(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
}

// The rake's numbers as the brief gives them: the odd count nearest one tooth per 2 cm, from 5 to 7.
double bar_radius(const ToolShape& s) { return 0.8 * s.handle_radius; }
int tooth_count(double width) {
  return std::clamp(2 * static_cast<int>(std::lround((width / 0.02 - 1) / 2)) + 1, 5, 7);
}

bool inside_tool(const ToolShape& s, const Vec3& p) {
  const double r = s.handle_radius, hl = s.handle_length, L = hl + s.head_height, w = s.head_width;
  const Vec3 hand(0, 0, 0), corner(0, -L, 0);
  switch (s.family) {
    case ToolFamily::stick:
      return in_cylinder(p, hand, corner, r);
    case ToolFamily::hoe:
      return in_cylinder(p, hand, Vec3(0, -hl, 0), r) ||
             in_box(p, Vec3(-r, -L, -w / 2), Vec3(s.head_length, -hl, w / 2));
    case ToolFamily::hook: {
      const Vec3 bend(s.head_length, -L, 0);
      return in_cylinder(p, hand, corner, r) || in_ball(p, corner, r) || in_cylinder(p, corner, bend, r) ||
             in_ball(p, bend, r) || in_cylinder(p, bend, Vec3(s.head_length, -hl, 0), r);
    }
    case ToolFamily::rake: {
      const double rb = bar_radius(s), y = -hl - rb;
      if (in_cylinder(p, hand, Vec3(0, y, 0), r) || in_cylinder(p, Vec3(0, y, -w / 2), Vec3(0, y, w / 2), rb))
        return true;
      const int n = tooth_count(w);
      for (int i = 0; i < n; ++i) {
        const double z = -(w / 2 - 0.004) + i * (w - 0.008) / (n - 1);
        if (in_cylinder(p, Vec3(0, y, z), Vec3(0.6 * s.head_length, y, z), 0.004)) return true;
      }
      return false;
    }
    case ToolFamily::shovel: {
      const double blade = std::max(s.head_height, 0.10), c = s.head_length / 5, u = 2 * p.z() / w;
      return in_cylinder(p, hand, Vec3(0, -hl, 0), r) ||
             (p.y() <= -hl && p.y() >= -hl - blade && std::abs(u) <= 1 && std::abs(p.x() - c * u * u) <= 0.002);
    }
    case ToolFamily::l_stick:
      return in_cylinder(p, hand, corner, r) || in_ball(p, corner, r) ||
             in_cylinder(p, corner, Vec3(s.head_length, -L, 0), r);
    case ToolFamily::t_bar:
      return in_cylinder(p, hand, corner, r) ||
             in_cylinder(p, Vec3(-s.head_length / 2, -L, 0), Vec3(s.head_length / 2, -L, 0), r);
    case ToolFamily::flat_top:
      return in_cylinder(p, hand, corner, r) ||
             in_box(p, Vec3(-s.head_length / 2, -L - 0.006, -w / 2), Vec3(s.head_length / 2, -L, w / 2));
    case ToolFamily::blade:  // the real shapes' families have no closed form here
    case ToolFamily::square_plate:
    case ToolFamily::cross:
      ADD_FAILURE() << "no closed form for " << to_string(s.family);
  }
  return false;
}

// The bounding box each family should fill.
Box3 expected_bounds(const ToolShape& s) {
  const double r = s.handle_radius, hl = s.handle_length, L = hl + s.head_height, w = s.head_width;
  const double len = s.head_length;
  switch (s.family) {
    case ToolFamily::stick:
      return {Vec3(-r, -L, -r), Vec3(r, 0, r)};
    case ToolFamily::hoe:
      return {Vec3(-r, -L, -w / 2), Vec3(len, 0, w / 2)};
    case ToolFamily::hook:
      return {Vec3(-r, -L - r, -r), Vec3(len + r, 0, r)};
    case ToolFamily::rake:
      return {Vec3(-r, -hl - 2 * bar_radius(s), -w / 2), Vec3(0.6 * len, 0, w / 2)};
    case ToolFamily::shovel:
      return {Vec3(-r, -hl - std::max(s.head_height, 0.10), -w / 2), Vec3(len / 5 + 0.002, 0, w / 2)};
    case ToolFamily::l_stick:
      return {Vec3(-r, -L - r, -r), Vec3(len, 0, r)};
    case ToolFamily::t_bar:
      return {Vec3(-len / 2, -L - r, -r), Vec3(len / 2, 0, r)};
    case ToolFamily::flat_top:
      return {Vec3(-s.head_length / 2, -L - 0.006, -w / 2), Vec3(s.head_length / 2, 0, w / 2)};
    case ToolFamily::blade:
    case ToolFamily::square_plate:
    case ToolFamily::cross:
      ADD_FAILURE() << "no closed form for " << to_string(s.family);
  }
  return {};
}

// Indices of about `n` points spread over the cloud.
std::vector<std::size_t> subsample(std::size_t size, std::size_t n) {
  std::vector<std::size_t> picked;
  for (std::size_t i = 0; i < size; i += std::max<std::size_t>(1, size / n)) picked.push_back(i);
  return picked;
}

double nearest_distance(const Points& points, const Vec3& q) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3& p : points) best = std::min(best, (p - q).squaredNorm());
  return std::sqrt(best);
}

// Mean distance from points[i] to its k nearest other points.
double mean_knn_distance(const Points& points, std::size_t i, std::size_t k) {
  std::vector<double> d;
  d.reserve(points.size());
  for (std::size_t j = 0; j < points.size(); ++j)
    if (j != i) d.push_back((points[j] - points[i]).norm());
  std::partial_sort(d.begin(), d.begin() + k, d.end());
  double sum = 0;
  for (std::size_t j = 0; j < k; ++j) sum += d[j];
  return sum / k;
}

TEST(ToolGeneratorNames, RoundTripAndSymmetry) {
  ASSERT_EQ(all_families().size(), 8u);
  for (ToolFamily family : all_families()) {
    EXPECT_EQ(family_from_string(to_string(family)), family);
    EXPECT_EQ(default_shape(family).family, family);
    EXPECT_EQ(has_salient_effector(family), symmetry_of(family) == ToolSymmetry::mirror);
  }
  EXPECT_EQ(to_string(ToolFamily::l_stick), "l-stick");
  EXPECT_EQ(to_string(ToolFamily::flat_top), "flat-top");
  EXPECT_EQ(symmetry_of(ToolFamily::stick), ToolSymmetry::axial);
  EXPECT_EQ(symmetry_of(ToolFamily::t_bar), ToolSymmetry::front_back);
  EXPECT_EQ(symmetry_of(ToolFamily::flat_top), ToolSymmetry::front_back);
  EXPECT_EQ(symmetry_of(ToolFamily::hoe), ToolSymmetry::mirror);
  EXPECT_THROW(family_from_string("spoon"), std::invalid_argument);
}

TEST(ToolGenerator, DefaultsAreToolSized) {
  for (ToolFamily family : all_families()) {
    SCOPED_TRACE(to_string(family));
    const Box3 box = expected_bounds(default_shape(family));
    EXPECT_GE(-box.lo.y(), 0.24);
    EXPECT_LE(-box.lo.y(), 0.34);
  }
}

TEST(ToolGenerator, DeterministicPerSeed) {
  for (ToolFamily family : all_families()) {
    SCOPED_TRACE(to_string(family));
    const ToolShape shape = default_shape(family);
    for (std::uint32_t seed : kSeeds) {
      const PointCloud a = generate_tool(shape, seed), b = generate_tool(shape, seed);
      EXPECT_EQ(a.points, b.points);
      EXPECT_EQ(a.normals, b.normals);
      EXPECT_NE(generate_tool(shape, seed + 1).points, a.points);
    }
  }
}

// Every point lies on the boundary of the reference solid with its normal pointing out: a tiny step
// along the normal leaves the solid and one against it enters it. This also rules out points inside
// solid parts and on faces where parts touch.
TEST(ToolGenerator, PointsOnOuterSurfaceWithOutwardUnitNormals) {
  constexpr double step = 1e-7;
  for (ToolFamily family : all_families()) {
    SCOPED_TRACE(to_string(family));
    const ToolShape shape = default_shape(family);
    for (std::uint32_t seed : kSeeds) {
      const PointCloud cloud = generate_tool(shape, seed);
      EXPECT_EQ(cloud.frame, "canonical");
      EXPECT_FALSE(cloud.has_colors());
      ASSERT_EQ(cloud.normals.size(), cloud.size());
      std::size_t bad = 0;
      for (std::size_t i = 0; i < cloud.size(); ++i) {
        const Vec3& p = cloud.points[i];
        const Vec3& n = cloud.normals[i];
        const bool ok = p.allFinite() && std::abs(n.norm() - 1.0) < 1e-12 && inside_tool(shape, p - step * n) &&
                        !inside_tool(shape, p + step * n);
        bad += !ok;
      }
      EXPECT_EQ(bad, 0u) << "of " << cloud.size();
    }
  }
}

TEST(ToolGenerator, MirrorSymmetricAboutZ) {
  for (ToolFamily family : all_families()) {
    SCOPED_TRACE(to_string(family));
    const ToolShape shape = default_shape(family);
    for (std::uint32_t seed : kSeeds) {
      const PointCloud cloud = generate_tool(shape, seed);
      for (std::size_t i : subsample(cloud.size(), 150)) {
        const Vec3& p = cloud.points[i];
        ASSERT_LT(nearest_distance(cloud.points, Vec3(p.x(), p.y(), -p.z())), 2.5 * shape.spacing) << p.transpose();
      }
    }
  }
}

TEST(ToolGenerator, ExtentsMatchShapeAndHandStartsAtOrigin) {
  for (ToolFamily family : all_families()) {
    SCOPED_TRACE(to_string(family));
    const ToolShape shape = default_shape(family);
    const Box3 expected = expected_bounds(shape);
    for (std::uint32_t seed : kSeeds) {
      const PointCloud cloud = generate_tool(shape, seed);
      const Box3 box = bounds(cloud.points);
      EXPECT_LE(box.hi.y(), 1e-9);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(box.lo[k], expected.lo[k], shape.spacing) << "axis " << k;
        EXPECT_NEAR(box.hi[k], expected.hi[k], shape.spacing) << "axis " << k;
      }
      const auto cap =
          std::count_if(cloud.points.begin(), cloud.points.end(), [](const Vec3& p) { return std::abs(p.y()) < 1e-6; });
      const double cap_area = kPi * shape.handle_radius * shape.handle_radius;
      EXPECT_NEAR(cap, cap_area / (shape.spacing * shape.spacing), 1.0);
    }
  }
}

// A shovel whose belly is behind its handle: the blade moved back by the scoop's depth (its rims level with
// the handle's axis, its middle a depth behind); the handle stays.
TEST(ToolGenerator, BellyBehindMovesTheScoopBackByItsDepth) {
  const ToolShape shovel = default_shape(ToolFamily::shovel);
  const PointCloud front = generate_tool(shovel, 1), behind = generate_tool(belly_behind(shovel), 1);
  const auto blade_x = [&](const PointCloud& cloud) {
    double lo = 1.0, hi = -1.0;
    for (const Vec3& p : cloud.points)
      if (p.y() < -shovel.handle_length - shovel.handle_radius) lo = std::min(lo, p.x()), hi = std::max(hi, p.x());
    return std::pair{lo, hi};
  };
  const double depth = shovel.head_length / 5.0;
  const auto [front_lo, front_hi] = blade_x(front);
  const auto [behind_lo, behind_hi] = blade_x(behind);
  EXPECT_NEAR(behind_lo, front_lo - depth, shovel.spacing);
  EXPECT_NEAR(behind_hi, front_hi - depth, shovel.spacing);
  EXPECT_NEAR(behind_hi, 0.002, shovel.spacing);  // the rims' outer face, half the blade's thickness out
  EXPECT_EQ(bounds(front.points).hi.y(), bounds(behind.points).hi.y());
}

TEST(ToolGenerator, HeadExtentsTellSalientFromFrontBack) {
  for (ToolFamily family : all_families()) {
    SCOPED_TRACE(to_string(family));
    const ToolShape shape = default_shape(family);
    const PointCloud cloud = generate_tool(shape, kSeeds[0]);
    Points head;
    for (const Vec3& p : cloud.points)
      if (p.y() < -shape.handle_length - 1e-6) head.push_back(p);
    ASSERT_FALSE(head.empty());
    const Box3 box = bounds(head);
    if (has_salient_effector(family))
      EXPECT_GT(box.hi.x(), -box.lo.x() + 0.01);
    else
      EXPECT_NEAR(box.hi.x(), -box.lo.x(), shape.spacing);
  }
}

// Uniform random samples at density 1 / spacing^2 have a mean distance of about 0.98 spacing to their
// six nearest neighbours (the neighbours of a surface triangulation); the single nearest is only at
// about 0.5 spacing, so the six-neighbour mean is what `spacing` describes.
TEST(ToolGenerator, MeanNeighbourDistanceMatchesSpacing) {
  for (ToolFamily family : all_families()) {
    SCOPED_TRACE(to_string(family));
    const ToolShape shape = default_shape(family);
    for (std::uint32_t seed : kSeeds) {
      const PointCloud cloud = generate_tool(shape, seed);
      const auto picked = subsample(cloud.size(), 100);
      double sum = 0;
      for (std::size_t i : picked) sum += mean_knn_distance(cloud.points, i, 6);
      const double mean = sum / picked.size();
      EXPECT_GT(mean, 0.5 * shape.spacing);
      EXPECT_LT(mean, 2.0 * shape.spacing);
    }
  }
}

TEST(ToolGenerator, CountScalesWithInverseSquareSpacing) {
  for (ToolFamily family : all_families()) {
    SCOPED_TRACE(to_string(family));
    ToolShape shape = default_shape(family);
    const double fine = static_cast<double>(generate_tool(shape, 3).size());
    shape.spacing *= 2.0;
    const double coarse = static_cast<double>(generate_tool(shape, 3).size());
    EXPECT_NEAR(fine / coarse, 4.0, 0.2);
  }
}

// Uniform per area, not per parameter: half the hand-end cap lies within radius r / sqrt(2), and on the
// shovel's curved front face the share within |z| < w / 4 follows the arc length, not the z range.
TEST(ToolGenerator, UniformPerAreaOnDiskAndCurvedFace) {
  const ToolShape shovel = default_shape(ToolFamily::shovel);
  const double r = shovel.handle_radius, half_width = shovel.head_width / 2, depth = shovel.head_length / 5;
  const auto arc = [&](double z_max) {  // midpoint rule for the length of x = depth (z / half_width)^2
    double sum = 0;
    for (int i = 0; i < 1000; ++i) {
      const double z = (i + 0.5) * z_max / 1000, slope = 2 * depth * z / (half_width * half_width);
      sum += std::sqrt(1 + slope * slope) * z_max / 1000;
    }
    return sum;
  };
  const double expected_central = arc(half_width / 2) / arc(half_width);  // about 0.46 (0.5 per z)
  double cap = 0, cap_inner = 0, face = 0, face_central = 0;
  for (std::uint32_t seed : kSeeds) {
    const PointCloud cloud = generate_tool(shovel, seed);
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const Vec3& p = cloud.points[i];
      if (std::abs(p.y()) < 1e-6) {
        cap += 1;
        cap_inner += std::hypot(p.x(), p.z()) < r / std::sqrt(2.0);
      } else if (p.y() < -shovel.handle_length - 1e-6 && cloud.normals[i].x() > 0.5 &&
                 std::abs(p.x() - depth * std::pow(p.z() / half_width, 2) - 0.002) < 1e-9) {
        face += 1;
        face_central += std::abs(p.z()) < half_width / 2;
      }
    }
  }
  EXPECT_NEAR(cap_inner / cap, 0.5, 0.08);                    // about 2.5 sigma for 237 points
  EXPECT_NEAR(face_central / face, expected_central, 0.015);  // about 2.5 sigma for 7500 points
}

// The stick has no hidden parts, so its count is exactly the sum of its patches' counts.
TEST(ToolGenerator, StickCountIsAreaOverSpacingSquared) {
  const ToolShape shape = default_shape(ToolFamily::stick);
  const double r = shape.handle_radius, length = shape.handle_length + shape.head_height;
  const double per_area = 1.0 / (shape.spacing * shape.spacing);
  const double expected = std::round(2 * kPi * r * length * per_area) + 2 * std::round(kPi * r * r * per_area);
  EXPECT_EQ(static_cast<double>(generate_tool(shape, 5).size()), expected);
}

TEST(ToolGenerator, InvalidShapesThrow) {
  const ToolShape good = default_shape(ToolFamily::hoe);
  double ToolShape::*const fields[] = {&ToolShape::handle_length, &ToolShape::handle_radius, &ToolShape::head_length,
                                       &ToolShape::head_width,    &ToolShape::head_height,   &ToolShape::spacing};
  for (auto field : fields) {
    for (double bad : {0.0, -0.01, std::nan(""), std::numeric_limits<double>::infinity()}) {
      ToolShape shape = good;
      shape.*field = bad;
      EXPECT_THROW(generate_tool(shape, 1), std::invalid_argument) << bad;
    }
  }
  ToolShape dense = good;
  dense.spacing = 1e-5;  // about 4.6e8 points
  EXPECT_THROW(generate_tool(dense, 1), std::invalid_argument);
}

}  // namespace
}  // namespace toolinc
