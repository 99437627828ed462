// PCD reading, the one reader of both read_cloud and the sessions' organised clouds: v0.7 headers (and
// 0.5/0.6 ones without VERSION/VIEWPOINT), DATA ascii, binary and binary_compressed (LZF via Debian's
// liblzf, fields stored one after another as PCL writes them).
#include <lzf.h>
#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "cloud_formats.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/limits.hpp"
#include "toolinc/io/pcd_write.hpp"
#include "toolinc/io/read_file.hpp"

namespace toolinc::io_detail {
namespace {

enum class PcdData { Ascii, Binary, BinaryCompressed };

struct PcdField {
  std::string name;
  std::size_t size = 4;
  std::size_t count = 1;
  char type = 'F';
  ScalarType scalar = ScalarType::Float32;
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::size_t points = 0;
  std::optional<std::size_t> width, height;
  std::optional<Vec3> viewpoint;
  PcdData data = PcdData::Ascii;
  std::size_t data_offset = 0;
  std::size_t lines = 0;
};

// The header's lines as written, before they are checked against each other.
struct RawHeader {
  std::vector<std::string_view> fields, sizes, types, counts;
  std::optional<std::size_t> width, height, points;
  std::optional<Vec3> viewpoint;
  std::optional<std::string_view> data;
  std::size_t data_offset = 0;
  std::size_t lines = 0;
};

bool is_header_keyword(std::string_view word) {
  static const std::string_view kKeywords[] = {"VERSION", "FIELDS", "COLUMNS",   "SIZE",   "TYPE", "COUNT",
                                               "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  for (std::string_view keyword : kKeywords) {
    if (word == keyword) return true;
  }
  return false;
}

bool is_comment_or_blank(const std::vector<std::string_view>& words) { return words.empty() || words[0][0] == '#'; }

std::size_t header_number(const std::string& path, std::string_view line, const std::vector<std::string_view>& words) {
  std::size_t value;
  if (words.size() != 2 || !parse_count(words[1], value))
    throw InputError(path, "PCD header: bad line " + quoted(line));
  return value;
}

// "VIEWPOINT tx ty tz qw qx qy qz": the sensor's pose in the cloud's frame. Its origin is where the
// points were seen from; PCL writes 0 0 0 1 0 0 0 when it does not know, so a zero origin is no viewpoint.
std::optional<Vec3> parse_viewpoint(const std::string& path, std::string_view line,
                                    const std::vector<std::string_view>& words) {
  double values[7];
  bool ok = words.size() == 8;
  for (std::size_t i = 0; ok && i < 7; ++i) ok = parse_number(words[i + 1], values[i]) && std::isfinite(values[i]);
  if (!ok) throw InputError(path, "PCD header: bad VIEWPOINT line " + quoted(line) + " (expected 7 numbers)");
  const Vec3 origin(values[0], values[1], values[2]);
  if (origin.isZero(0.0)) return std::nullopt;
  return origin;
}

RawHeader read_raw_header(const std::string& path, std::string_view data) {
  RawHeader raw;
  LineReader lines(data);
  std::string_view line;
  while (!raw.data && lines.next(line)) {
    const auto words = split_words(line);
    if (is_comment_or_blank(words)) continue;
    const std::string_view key = words[0];
    const std::vector<std::string_view> args(words.begin() + 1, words.end());
    if (key == "FIELDS" || key == "COLUMNS") {  // COLUMNS: the 0.5 spelling
      raw.fields = args;
    } else if (key == "SIZE") {
      raw.sizes = args;
    } else if (key == "TYPE") {
      raw.types = args;
    } else if (key == "COUNT") {
      raw.counts = args;
    } else if (key == "WIDTH") {
      raw.width = header_number(path, line, words);
    } else if (key == "HEIGHT") {
      raw.height = header_number(path, line, words);
    } else if (key == "POINTS") {
      raw.points = header_number(path, line, words);
    } else if (key == "DATA") {
      if (words.size() != 2) throw InputError(path, "PCD header: bad line " + quoted(line));
      raw.data = words[1];
    } else if (key == "VIEWPOINT") {
      raw.viewpoint = parse_viewpoint(path, line, words);
    } else if (key != "VERSION") {
      throw InputError(path, "PCD header line " + std::to_string(lines.number()) + ": unknown keyword " + quoted(key));
    }
  }
  if (!raw.data) throw InputError(path, "PCD header has no DATA line");
  raw.data_offset = lines.position();
  raw.lines = lines.number();
  return raw;
}

std::optional<ScalarType> pcd_scalar(char type, std::size_t size) {
  if (type == 'F' && size == 4) return ScalarType::Float32;
  if (type == 'F' && size == 8) return ScalarType::Float64;
  static const ScalarType kUnsigned[] = {ScalarType::UInt8, ScalarType::UInt16, ScalarType::UInt32, ScalarType::UInt64};
  static const ScalarType kSigned[] = {ScalarType::Int8, ScalarType::Int16, ScalarType::Int32, ScalarType::Int64};
  const int index = size == 1 ? 0 : size == 2 ? 1 : size == 4 ? 2 : size == 8 ? 3 : -1;
  if (index < 0) return std::nullopt;
  if (type == 'U') return kUnsigned[index];
  if (type == 'I') return kSigned[index];
  return std::nullopt;
}

void check_entry_count(const std::string& path, const char* key, std::size_t entries, std::size_t fields) {
  if (entries != fields) {
    throw InputError(path, std::string("PCD header: ") + key + " has " + std::to_string(entries) +
                               " entries but FIELDS has " + std::to_string(fields));
  }
}

// No real point type comes near this; it keeps every record-width product far from overflowing.
constexpr std::size_t kMaxRecordBytes = std::size_t{1} << 20;

std::vector<PcdField> build_fields(const std::string& path, const RawHeader& raw) {
  if (raw.fields.empty()) throw InputError(path, "PCD header has no FIELDS line");
  if (raw.sizes.empty()) throw InputError(path, "PCD header has no SIZE line");
  if (raw.types.empty()) throw InputError(path, "PCD header has no TYPE line");
  const std::size_t n = raw.fields.size();
  check_entry_count(path, "SIZE", raw.sizes.size(), n);
  check_entry_count(path, "TYPE", raw.types.size(), n);
  if (!raw.counts.empty()) check_entry_count(path, "COUNT", raw.counts.size(), n);
  std::vector<PcdField> fields(n);
  for (std::size_t i = 0; i < n; ++i) {
    PcdField& field = fields[i];
    field.name = std::string(raw.fields[i]);
    const std::string which = " for field " + quoted(field.name);
    if (!parse_count(raw.sizes[i], field.size))
      throw InputError(path, "PCD header: bad SIZE " + quoted(raw.sizes[i]) + which);
    if (!raw.counts.empty() && (!parse_count(raw.counts[i], field.count) || field.count == 0)) {
      throw InputError(path, "PCD header: bad COUNT " + quoted(raw.counts[i]) + which);
    }
    const auto scalar = raw.types[i].size() == 1 ? pcd_scalar(raw.types[i][0], field.size) : std::nullopt;
    if (!scalar) {
      throw InputError(
          path, "PCD header: bad TYPE " + quoted(raw.types[i]) + " with SIZE " + std::string(raw.sizes[i]) + which);
    }
    field.type = raw.types[i][0];
    field.scalar = *scalar;
  }
  // A record (the sum of SIZE x COUNT) must be addressable: absurd counts are bad input, not a wrapped width.
  std::size_t record = 0;
  for (const PcdField& field : fields) {
    if (field.count > kMaxRecordBytes / field.size || record + field.size * field.count > kMaxRecordBytes)
      throw InputError(path, "PCD header: a point of more than " + std::to_string(kMaxRecordBytes) +
                                 " bytes (SIZE x COUNT of " + quoted(field.name) + ")");
    record += field.size * field.count;
  }
  return fields;
}

std::size_t point_count(const std::string& path, const RawHeader& raw) {
  if (raw.points) return *raw.points;
  if (!raw.width) throw InputError(path, "PCD header has no WIDTH or POINTS line");
  const std::size_t height = raw.height.value_or(1);
  if (height != 0 && *raw.width > std::numeric_limits<std::size_t>::max() / height) {
    throw InputError(path, "PCD header: WIDTH * HEIGHT is too large");
  }
  return *raw.width * height;
}

PcdHeader parse_header(const std::string& path, std::string_view data) {
  const RawHeader raw = read_raw_header(path, data);
  PcdHeader header;
  header.fields = build_fields(path, raw);
  header.points = point_count(path, raw);
  if (header.points > kMaxCloudPoints)
    throw InputError(path, "PCD header: " + std::to_string(header.points) + " points, more than the " +
                               std::to_string(kMaxCloudPoints) + " a cloud may hold");
  if (*raw.data == "ascii") {
    header.data = PcdData::Ascii;
  } else if (*raw.data == "binary") {
    header.data = PcdData::Binary;
  } else if (*raw.data == "binary_compressed") {
    header.data = PcdData::BinaryCompressed;
  } else {
    throw InputError(path, "unknown PCD DATA kind " + quoted(*raw.data));
  }
  header.data_offset = raw.data_offset;
  header.lines = raw.lines;
  header.width = raw.width;
  header.height = raw.height;
  header.viewpoint = raw.viewpoint;
  return header;
}

enum Role { kX, kY, kZ, kRgb, kNx, kNy, kNz, kRoleCount };
using Roles = std::array<int, kRoleCount>;  // field index per role, -1 when absent

Roles find_roles(const std::vector<PcdField>& fields) {
  Roles roles;
  roles.fill(-1);
  static const std::pair<std::string_view, int> kNames[] = {{"x", kX},         {"y", kY},        {"z", kZ},
                                                            {"rgb", kRgb},     {"rgba", kRgb},   {"normal_x", kNx},
                                                            {"normal_y", kNy}, {"normal_z", kNz}};
  for (std::size_t f = 0; f < fields.size(); ++f) {
    for (const auto& [name, role] : kNames) {
      if (fields[f].name == name && roles[role] < 0) roles[role] = static_cast<int>(f);
    }
  }
  // Colours are four packed bytes (0x00RRGGBB); other sizes are not colours we know.
  if (roles[kRgb] >= 0 && fields[roles[kRgb]].size != 4) roles[kRgb] = -1;
  return roles;
}

bool has_normals(const Roles& roles) { return roles[kNx] >= 0 && roles[kNy] >= 0 && roles[kNz] >= 0; }

Rgb unpack_rgb(std::uint32_t packed) {
  return {static_cast<std::uint8_t>(packed >> 16), static_cast<std::uint8_t>(packed >> 8),
          static_cast<std::uint8_t>(packed)};
}

InputError truncated(const std::string& path, std::size_t expected, std::size_t at) {
  return InputError(
      path, "truncated: expected " + std::to_string(expected) + " points, file ends at point " + std::to_string(at));
}

void reserve(PointCloud& cloud, std::size_t n, const Roles& roles) {
  cloud.points.reserve(n);
  if (roles[kRgb] >= 0) cloud.colors.reserve(n);
  if (has_normals(roles)) cloud.normals.reserve(n);
}

// A field's first value for point i sits at block + start + i * step (the binary layouts).
struct Column {
  std::size_t start = 0;
  std::size_t step = 0;
};

void extract_points(const char* block, const std::vector<PcdField>& fields, const std::vector<Column>& columns,
                    const Roles& roles, std::size_t n, PointCloud& cloud) {
  const bool swap = host_is_big_endian();  // PCD binary data is little-endian in practice
  const auto value = [&](int role, std::size_t i) {
    const Column& column = columns[roles[role]];
    return load_scalar(block + column.start + i * column.step, fields[roles[role]].scalar, swap);
  };
  reserve(cloud, n, roles);
  for (std::size_t i = 0; i < n; ++i) {
    cloud.points.emplace_back(value(kX, i), value(kY, i), value(kZ, i));
    if (roles[kRgb] >= 0) {
      const Column& column = columns[roles[kRgb]];
      cloud.colors.push_back(unpack_rgb(load_raw<std::uint32_t>(block + column.start + i * column.step, swap)));
    }
    if (has_normals(roles)) cloud.normals.emplace_back(value(kNx, i), value(kNy, i), value(kNz, i));
  }
}

void read_binary(const std::string& path, const PcdHeader& header, const Roles& roles, std::string_view body,
                 PointCloud& cloud) {
  std::vector<Column> columns;
  std::size_t stride = 0;
  for (const PcdField& field : header.fields) {
    columns.push_back({stride, 0});
    stride += field.size * field.count;
  }
  for (Column& column : columns) column.step = stride;  // >= 1: every field has SIZE and COUNT >= 1
  const std::size_t available = body.size() / stride;
  if (available < header.points) throw truncated(path, header.points, available);
  extract_points(body.data(), header.fields, columns, roles, header.points, cloud);
}

// PCL stores each field's values for all points together, and leaves out padding fields ("_").
void read_compressed(const std::string& path, const PcdHeader& header, const Roles& roles, std::string_view body,
                     PointCloud& cloud) {
  if (body.size() < 8) throw InputError(path, "truncated: binary_compressed data has no size words");
  const std::size_t compressed = load_raw<std::uint32_t>(body.data(), host_is_big_endian());
  const std::size_t uncompressed = load_raw<std::uint32_t>(body.data() + 4, host_is_big_endian());
  if (compressed > body.size() - 8) {
    throw InputError(path, "truncated: binary_compressed block of " + std::to_string(compressed) + " bytes, file has " +
                               std::to_string(body.size() - 8));
  }
  std::vector<Column> columns;
  std::size_t stride = 0;
  for (const PcdField& field : header.fields) {
    const std::size_t bytes = field.name == "_" ? 0 : field.size * field.count;
    columns.push_back({stride, bytes});
    stride += bytes;
  }
  // stride >= 12: x, y and z are never padding.
  if (header.points > std::numeric_limits<std::size_t>::max() / stride || uncompressed != header.points * stride) {
    throw InputError(path, "binary_compressed: uncompressed size " + std::to_string(uncompressed) + " does not match " +
                               std::to_string(header.points) + " points of " + std::to_string(stride) + " bytes");
  }
  for (Column& column : columns) column.start *= header.points;
  // Decompressed, the data is a binary PCD body: no larger than a file the reader accepts.
  if (uncompressed > kMaxFileBytes)
    throw InputError(path, "binary_compressed: " + std::to_string(uncompressed) +
                               " bytes uncompressed, more than the " + std::to_string(kMaxFileBytes) + " allowed");
  // An LZF back-reference of 3 bytes yields at most 264: a larger claim is corrupt, not worth allocating.
  if (uncompressed / 88 > compressed) throw InputError(path, "corrupt binary_compressed data (sizes do not fit LZF)");
  std::vector<std::uint8_t> block(uncompressed);
  // liblzf checks every run and back-reference against both buffers (CHECK_INPUT) and returns 0 on error.
  const unsigned written = uncompressed == 0 ? 0
                                             : lzf_decompress(body.data() + 8, static_cast<unsigned>(compressed),
                                                              block.data(), static_cast<unsigned>(block.size()));
  if (written != uncompressed) throw InputError(path, "corrupt binary_compressed data (LZF stream is invalid)");
  extract_points(reinterpret_cast<const char*>(block.data()), header.fields, columns, roles, header.points, cloud);
}

class AsciiReader {
 public:
  AsciiReader(const std::string& path, std::string_view body, std::size_t first_line)
      : path_(path), tokens_(body, first_line) {}

  // The next token, or false at the end of the data.
  bool next(std::string_view& token) { return tokens_.next(token); }

  double number(std::string_view token, ScalarType type) const {
    double value;
    if (!parse_number(token, value)) throw error("bad number " + quoted(token));
    return as_stored(value, type);
  }

  // A packed colour: the integer itself (PCL writes even TYPE F colours so, as opaque ones are NaN as
  // floats), else for TYPE F the bits of the float.
  std::uint32_t packed(std::string_view token, char type) const {
    std::size_t integer;
    if (parse_count(token, integer) && integer <= 0xffffffffu) return static_cast<std::uint32_t>(integer);
    if (type == 'F') {
      float value;
      if (!parse_float(token, value)) throw error("bad number " + quoted(token));
      return load_raw<std::uint32_t>(reinterpret_cast<const char*>(&value), false);
    }
    std::size_t value;
    if (!parse_count(token, value)) throw error("bad colour " + quoted(token));
    return static_cast<std::uint32_t>(value);
  }

 private:
  InputError error(const std::string& problem) const {
    return InputError(path_, "line " + std::to_string(tokens_.line()) + ": " + problem);
  }

  const std::string& path_;
  TokenCursor tokens_;
};

void read_ascii(const std::string& path, const PcdHeader& header, const Roles& roles, std::string_view body,
                PointCloud& cloud) {
  std::vector<int> role_of_field(header.fields.size(), -1);
  for (int role = 0; role < kRoleCount; ++role) {
    if (roles[role] >= 0) role_of_field[roles[role]] = role;
  }
  const bool normals = has_normals(roles);
  AsciiReader reader(path, body, header.lines + 1);
  // Reserve no more than the text could hold, so a lying POINTS cannot exhaust memory.
  reserve(cloud, std::min(header.points, body.size() / 2), roles);
  std::array<double, kRoleCount> values{};
  std::uint32_t packed = 0;
  std::string_view token;
  for (std::size_t i = 0; i < header.points; ++i) {
    for (std::size_t f = 0; f < header.fields.size(); ++f) {
      for (std::size_t k = 0; k < header.fields[f].count; ++k) {
        if (!reader.next(token)) throw truncated(path, header.points, i);
        const int role = k == 0 ? role_of_field[f] : -1;
        if (role == kRgb) {
          packed = reader.packed(token, header.fields[f].type);
        } else if (role >= 0) {
          values[role] = reader.number(token, header.fields[f].scalar);
        }
      }
    }
    cloud.points.emplace_back(values[kX], values[kY], values[kZ]);
    if (roles[kRgb] >= 0) cloud.colors.push_back(unpack_rgb(packed));
    if (normals) cloud.normals.emplace_back(values[kNx], values[kNy], values[kNz]);
  }
}

}  // namespace

bool looks_like_pcd(std::string_view data) {
  LineReader lines(data);
  std::string_view line;
  while (lines.next(line)) {
    const auto words = split_words(line);
    if (!is_comment_or_blank(words)) return is_header_keyword(words[0]);
  }
  return false;
}

namespace {

// The header and every point as stored (non-finite ones included).
PointCloud decode_pcd(const std::string& path, const PcdHeader& header, std::string_view data) {
  const Roles roles = find_roles(header.fields);
  if (roles[kX] < 0 || roles[kY] < 0 || roles[kZ] < 0) throw InputError(path, "PCD has no x/y/z fields");
  PointCloud cloud;
  const std::string_view body = data.substr(header.data_offset);
  switch (header.data) {
    case PcdData::Ascii:
      read_ascii(path, header, roles, body, cloud);
      break;
    case PcdData::Binary:
      read_binary(path, header, roles, body, cloud);
      break;
    case PcdData::BinaryCompressed:
      read_compressed(path, header, roles, body, cloud);
      break;
  }
  if (header.viewpoint) cloud.viewpoints.push_back(*header.viewpoint);
  return cloud;
}

}  // namespace

PointCloud parse_pcd(const std::string& path, std::string_view data) {
  return decode_pcd(path, parse_header(path, data), data);
}

}  // namespace toolinc::io_detail

namespace toolinc {

Points read_organised_pcd(const std::string& path, int width, int height) {
  const std::string data = read_file(path);
  const io_detail::PcdHeader header = io_detail::parse_header(path, data);
  const std::size_t w = header.width.value_or(header.points), h = header.height.value_or(1);
  if (w != static_cast<std::size_t>(width) || h != static_cast<std::size_t>(height) || header.points != w * h)
    throw InputError(
        path, fmt::format("organised cloud is {}x{} ({} points), expected {}x{}", w, h, header.points, width, height));
  Points points = io_detail::decode_pcd(path, header, data).points;
  io_detail::check_coordinate_range(path, points);
  return points;
}

}  // namespace toolinc
