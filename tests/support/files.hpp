// Writing the inputs tests hand to the library and the executables.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "toolinc/core/point_cloud.hpp"

namespace toolinc::testing {

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline PointCloud as_cloud(const Points& points, const std::string& frame = "hand") {
  PointCloud cloud;
  cloud.points = points;
  cloud.frame = frame;
  return cloud;
}

}  // namespace toolinc::testing
