#include "toolinc/io/pcd_write.hpp"

#include <spdlog/fmt/fmt.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "toolinc/core/error.hpp"
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
            << "WIDTH " << width << "\nHEIGHT " << height << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS "
            << points.size() << "\nDATA binary\n";
        std::vector<float> data;
        data.reserve(3 * points.size());
        for (const Vec3& p : points)
          for (int i = 0; i < 3; ++i) data.push_back(static_cast<float>(p[i]));
        out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size() * sizeof(float)));
      },
      true);
}

namespace {

struct OrganisedHeader {
  std::vector<std::string> fields;
  std::vector<std::size_t> sizes, counts;
  std::vector<std::string> types;
  long width = -1, height = 1;
  std::string data;
  std::size_t data_offset = 0;
};

OrganisedHeader parse_header(const std::string& path, const std::string& text) {
  OrganisedHeader header;
  std::size_t pos = 0;
  while (header.data.empty()) {
    if (pos >= text.size()) throw InputError(path, "PCD header has no DATA line");
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::istringstream line(text.substr(pos, end - pos));
    pos = end + 1;
    std::string key;
    if (!(line >> key) || key[0] == '#') continue;
    if (key == "FIELDS") {
      for (std::string word; line >> word;) header.fields.push_back(word);
    } else if (key == "SIZE" || key == "COUNT") {
      auto& target = key == "SIZE" ? header.sizes : header.counts;
      for (std::size_t n; line >> n;) target.push_back(n);
    } else if (key == "TYPE") {
      for (std::string word; line >> word;) header.types.push_back(word);
    } else if (key == "WIDTH") {
      line >> header.width;
    } else if (key == "HEIGHT") {
      line >> header.height;
    } else if (key == "DATA") {
      line >> header.data;
    }
  }
  header.data_offset = pos;
  if (header.counts.empty()) header.counts.assign(header.fields.size(), 1);
  if (header.fields.empty() || header.sizes.size() != header.fields.size() ||
      header.types.size() != header.fields.size() || header.counts.size() != header.fields.size())
    throw InputError(path, "PCD header: FIELDS, SIZE, TYPE and COUNT disagree");
  return header;
}

}  // namespace

Points read_organised_pcd(const std::string& path, int width, int height) {
  const std::string text = read_file(path);
  const OrganisedHeader header = parse_header(path, text);
  if (header.width != width || header.height != height)
    throw InputError(path, fmt::format("organised cloud is {}x{}, expected {}x{}", header.width, header.height,
                                       width, height));
  // Where x, y and z sit in a record: a byte offset (binary) or a column (ascii).
  std::array<std::size_t, 3> byte_at{}, column_at{};
  std::array<bool, 3> found{};
  std::size_t record_bytes = 0, columns = 0;
  for (std::size_t f = 0; f < header.fields.size(); ++f) {
    const int axis = header.fields[f] == "x" ? 0 : header.fields[f] == "y" ? 1 : header.fields[f] == "z" ? 2 : -1;
    if (axis >= 0) {
      if (header.types[f] != "F" || header.sizes[f] != 4 || header.counts[f] != 1)
        throw InputError(path, "PCD field " + header.fields[f] + " is not a single float32");
      byte_at[axis] = record_bytes, column_at[axis] = columns, found[axis] = true;
    }
    record_bytes += header.sizes[f] * header.counts[f];
    columns += header.counts[f];
  }
  if (!found[0] || !found[1] || !found[2]) throw InputError(path, "PCD has no x y z fields");

  const std::size_t n = static_cast<std::size_t>(width) * height;
  Points points(n);
  if (header.data == "binary") {
    if (text.size() - header.data_offset < n * record_bytes)
      throw InputError(path, fmt::format("PCD data truncated: {} points expected", n));
    const char* data = text.data() + header.data_offset;
    for (std::size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) {
        float value;
        std::memcpy(&value, data + i * record_bytes + byte_at[a], sizeof value);
        points[i][a] = value;
      }
  } else if (header.data == "ascii") {
    std::istringstream in(text.substr(header.data_offset));
    std::vector<double> row(columns);
    for (std::size_t i = 0; i < n; ++i) {
      for (auto& value : row) {
        std::string word;  // strtod, not >>, so that "nan" parses
        char* end = nullptr;
        if (!(in >> word) || (value = std::strtod(word.c_str(), &end), *end != '\0'))
          throw InputError(path, fmt::format("PCD point {}: expected {} numbers", i, columns));
      }
      for (int a = 0; a < 3; ++a) points[i][a] = row[column_at[a]];
    }
  } else {
    throw InputError(path, "PCD DATA " + header.data + " is not supported for organised clouds (ascii, binary)");
  }
  return points;
}

}  // namespace toolinc
