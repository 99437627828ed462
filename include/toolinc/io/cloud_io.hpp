// Reading and writing point clouds: PLY (ascii, binary little/big endian) and PCD (ascii, binary,
// binary_compressed). Readers drop non-finite points and count them; they throw InputError naming the
// file and the problem for anything malformed.
#pragma once

#include <cstddef>
#include <string>

#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

struct CloudReadStats {
  std::size_t points_in_file = 0;
  std::size_t non_finite_dropped = 0;
};

// Dispatches on the file's magic ("ply" or a PCD header), not on its extension.
PointCloud read_cloud(const std::string& path, CloudReadStats* stats = nullptr);

struct PlyWriteOptions {
  bool ascii = false;   // binary little-endian by default
  std::string command;  // the producing command, recorded as a header comment
};

// Writes atomically (temporary file in the same folder, then rename). The frame goes in a
// "comment frame <name>" header line.
void write_ply(const std::string& path, const PointCloud& cloud, const PlyWriteOptions& options = {});

}  // namespace toolinc
