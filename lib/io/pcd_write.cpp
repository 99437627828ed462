#include "toolinc/io/pcd_write.hpp"

#include <spdlog/fmt/fmt.h>

#include <stdexcept>
#include <vector>

#include "toolinc/io/atomic_file.hpp"

namespace toolinc {

void write_pcd(const std::string& path, const Points& points, int width, int height) {
  if (width <= 0 || height <= 0 || points.size() != static_cast<std::size_t>(width) * height)
    throw std::invalid_argument(fmt::format("write_pcd: {} points for a {}x{} cloud", points.size(), width, height));
  write_file_atomic(
      path,
      [&](std::ostream& out) {
        out << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
               "COUNT 1 1 1\n"
            << "WIDTH " << width << "\nHEIGHT " << height << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << points.size()
            << "\nDATA binary\n";
        std::vector<float> data;
        data.reserve(3 * points.size());
        for (const Vec3& p : points)
          for (int i = 0; i < 3; ++i) data.push_back(static_cast<float>(p[i]));
        out.write(reinterpret_cast<const char*>(data.data()),
                  static_cast<std::streamsize>(data.size() * sizeof(float)));
      },
      true);
}

}  // namespace toolinc
