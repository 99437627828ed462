// A point cloud as the tools exchange it: positions, optional colours and normals, and the frame name.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace toolinc {

using Vec3 = Eigen::Vector3d;
using Points = std::vector<Eigen::Vector3d>;
using Rgb = std::array<std::uint8_t, 3>;

struct PointCloud {
  Points points;
  std::vector<Rgb> colors;           // empty, or one per point
  Points normals;                    // empty, or one per point
  std::string frame;                 // e.g. "hand", "root", "canonical"; empty when unknown
  Points viewpoints;                 // where sensors saw these points from, in the same frame (may be empty)
  std::vector<std::uint32_t> views;  // empty, or one per point: which of the views merged into this cloud saw
                                     // it, a bit per view (bit v: merge-views' input v)
  int recorded_views = 0;            // how many views the session this cloud comes from recorded (0: unknown)
  int unmerged_views = 0;            // views of that session missing from this cloud (no tool found in them, or
                                     // they did not fit the others): what they alone saw is missing from it

  std::size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
  bool has_colors() const { return !colors.empty(); }
  bool has_normals() const { return !normals.empty(); }
  bool has_views() const { return !views.empty(); }
};

}  // namespace toolinc
