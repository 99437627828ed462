// Procedural tools in the canonical pose (docs/formats.md): the handle starts at the origin (the hand) and
// runs along -Y, the effector points towards +X, and every tool is mirror-symmetric about z = 0.
// Points are sampled uniformly on the outer surface with outward normals.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

// The first eight are the regression set (all_families); blade, square-plate and cross are shapes of
// real tools those never had (real_shape_families): a flat spatula, a square plate, a four-armed star.
enum class ToolFamily { stick, hoe, hook, rake, shovel, l_stick, t_bar, flat_top, blade, square_plate, cross };

// Which symmetries besides the mirror about z = 0 a family has; ground truth comparisons use it.
enum class ToolSymmetry {
  mirror,      // only z = 0: the effector has a salient side (+X)
  front_back,  // also x = 0 (a half turn about the handle): either end of the head counts (T, flat-top)
  fourfold,    // also quarter turns about the handle: any of four tips counts (square plate, cross)
  axial,       // any rotation about the handle (stick)
};

struct ToolShape {
  ToolFamily family = ToolFamily::hoe;
  double handle_length = 0.20;   // m, from the origin along -Y to where the head starts
  double handle_radius = 0.010;  // m
  double head_length = 0.10;     // m, reach of the head towards +X (hoe blade, hook, L bar, rake teeth,
                                 //    shovel scoop depth is head_length / 5); full length along X for
                                 //    the T bar and the flat top
  double head_width = 0.08;      // m, extent across Z (hoe blade, rake bar, shovel blade, flat top)
  double head_height = 0.04;     // m, extent along Y (hoe blade, hook return, shovel blade length)
  double spacing = 0.002;        // m, mean distance between neighbouring surface samples
  double head_offset = 0.0;      // m along X, shovel and blade: the head's shift off the handle's axis
};

std::vector<ToolFamily> all_families();
std::vector<ToolFamily> real_shape_families();
std::string to_string(ToolFamily family);
// Throws std::invalid_argument listing the known names.
ToolFamily family_from_string(const std::string& name);
ToolSymmetry symmetry_of(ToolFamily family);
std::string to_string(ToolSymmetry symmetry);  // mirror, front_back, fourfold, axial
// Throws std::invalid_argument listing the known names.
ToolSymmetry symmetry_from_string(const std::string& name);
bool has_salient_effector(ToolFamily family);  // symmetry_of(family) == ToolSymmetry::mirror

// The shape a family has when nothing else is said (similar in size to the original's tools).
ToolShape default_shape(ToolFamily family);

// The shovel with its scoop lowered by its depth: its belly behind the handle's axis and its rims level
// with it, as many real scoops are held (the lab's SHO1 bulges 17 mm behind, reaches 12 mm in front).
ToolShape belly_behind(ToolShape shovel);

// Deterministic for a given seed. Each surface patch gets round(area / spacing^2) uniform samples, so the
// single nearest neighbour is at about spacing / 2 and the six nearest average about spacing.
// Throws std::invalid_argument on non-positive or non-finite dimensions, or on a spacing that would give
// more than 5 million points.
PointCloud generate_tool(const ToolShape& shape, std::uint32_t seed);

}  // namespace toolinc
