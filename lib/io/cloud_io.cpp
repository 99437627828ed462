#include "toolinc/io/cloud_io.hpp"

#include <spdlog/fmt/fmt.h>

#include <charconv>
#include <cstdint>

#include "cloud_formats.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/limits.hpp"
#include "toolinc/io/read_file.hpp"

namespace toolinc {
namespace io_detail {

std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
    case ScalarType::UInt8:
      return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16:
      return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32:
      return 4;
    case ScalarType::Int64:
    case ScalarType::UInt64:
    case ScalarType::Float64:
      return 8;
  }
  return 0;
}

bool host_is_big_endian() {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 0;
}

bool LineReader::next(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = text_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line = text_.substr(pos_, stop - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end == std::string_view::npos ? text_.size() : end + 1;
  ++number_;
  return true;
}

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

}  // namespace

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && is_space(line[pos])) ++pos;
    const std::size_t start = pos;
    while (pos < line.size() && !is_space(line[pos])) ++pos;
    if (pos > start) words.push_back(line.substr(start, pos - start));
  }
  return words;
}

bool TokenCursor::next(std::string_view& token) {
  while (pos_ < text_.size() && is_space(text_[pos_])) {
    if (text_[pos_] == '\n') ++line_;
    ++pos_;
  }
  if (pos_ == text_.size()) return false;
  const std::size_t start = pos_;
  while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
  token = text_.substr(start, pos_ - start);
  return true;
}

namespace {

// from_chars rejects a leading '+', which some writers emit.
std::string_view without_plus(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  return token;
}

template <class T>
bool parse_whole(std::string_view token, T& value) {
  token = without_plus(token);
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

}  // namespace

bool parse_number(std::string_view token, double& value) { return parse_whole(token, value); }
bool parse_float(std::string_view token, float& value) { return parse_whole(token, value); }
bool parse_count(std::string_view token, std::size_t& value) { return parse_whole(token, value); }

std::string quoted(std::string_view text) { return "'" + std::string(text) + "'"; }

void check_coordinate_range(const std::string& path, const Points& points) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    if (p.allFinite() && p.cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw InputError(path, fmt::format("point {} at ({:g}, {:g}, {:g}) lies beyond the {:g} m a cloud may reach "
                                         "from the origin",
                                         i, p.x(), p.y(), p.z(), kMaxCoordinate));
  }
}

}  // namespace io_detail

namespace {

bool looks_like_ply(std::string_view data) { return data.substr(0, 4) == "ply\n" || data.substr(0, 5) == "ply\r\n"; }

// Compacts the cloud to its finite points (with their colours, normals and views); returns how many went.
std::size_t drop_non_finite(PointCloud& cloud) {
  const std::size_t n = cloud.size();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!cloud.points[i].allFinite()) continue;
    if (kept != i) {
      cloud.points[kept] = cloud.points[i];
      if (cloud.has_colors()) cloud.colors[kept] = cloud.colors[i];
      if (cloud.has_normals()) cloud.normals[kept] = cloud.normals[i];
      if (cloud.has_views()) cloud.views[kept] = cloud.views[i];
    }
    ++kept;
  }
  cloud.points.resize(kept);
  if (cloud.has_colors()) cloud.colors.resize(kept);
  if (cloud.has_normals()) cloud.normals.resize(kept);
  if (cloud.has_views()) cloud.views.resize(kept);
  return n - kept;
}

}  // namespace

PointCloud read_cloud(const std::string& path, CloudReadStats* stats) {
  const std::string data = read_file(path);
  if (data.empty()) throw InputError(path, "empty file");
  PointCloud cloud;
  if (looks_like_ply(data)) {
    cloud = io_detail::parse_ply(path, data);
  } else if (io_detail::looks_like_pcd(data)) {
    cloud = io_detail::parse_pcd(path, data);
  } else {
    throw InputError(path, "not a PLY or PCD file");
  }
  const std::size_t in_file = cloud.size();
  const std::size_t dropped = drop_non_finite(cloud);
  io_detail::check_coordinate_range(path, cloud.points);
  if (stats) {
    stats->points_in_file = in_file;
    stats->non_finite_dropped = dropped;
  }
  return cloud;
}

}  // namespace toolinc
