// PLY reading (ascii, binary little/big endian, any property layout and extra elements) and writing.
#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cloud_formats.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/limits.hpp"

namespace toolinc {
namespace io_detail {
namespace {

enum class PlyFormat { Ascii, BinaryLittle, BinaryBig };

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::Float32;  // the item type for lists
  bool is_list = false;
  ScalarType count_type = ScalarType::UInt8;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::string frame;
  Points viewpoints;
  int recorded_views = 0;
  int unmerged_views = 0;
  std::size_t data_offset = 0;
  std::size_t lines = 0;
};

// What a vertex property means to us; kNone for properties we skip.
enum Role { kX, kY, kZ, kRed, kGreen, kBlue, kNx, kNy, kNz, kViews, kRoleCount };
constexpr int kNone = kRoleCount;
// More views than any session records is no count but a corrupt file.
constexpr double kMaxViews = 1e6;

bool ply_scalar(std::string_view name, ScalarType& type) {
  static const std::pair<std::string_view, ScalarType> kTypes[] = {
      {"char", ScalarType::Int8},      {"int8", ScalarType::Int8},       {"uchar", ScalarType::UInt8},
      {"uint8", ScalarType::UInt8},    {"short", ScalarType::Int16},     {"int16", ScalarType::Int16},
      {"ushort", ScalarType::UInt16},  {"uint16", ScalarType::UInt16},   {"int", ScalarType::Int32},
      {"int32", ScalarType::Int32},    {"uint", ScalarType::UInt32},     {"uint32", ScalarType::UInt32},
      {"float", ScalarType::Float32},  {"float32", ScalarType::Float32}, {"double", ScalarType::Float64},
      {"float64", ScalarType::Float64}};
  for (const auto& [type_name, scalar] : kTypes) {
    if (type_name == name) {
      type = scalar;
      return true;
    }
  }
  return false;
}

// "header line N: problem", naming the offending line.
InputError header_error(const std::string& path, std::size_t line_number, const std::string& problem) {
  return InputError(path, "header line " + std::to_string(line_number) + ": " + problem);
}

ScalarType property_type(const std::string& path, std::size_t line_number, std::string_view name) {
  ScalarType type;
  if (!ply_scalar(name, type)) throw header_error(path, line_number, "unknown property type " + quoted(name));
  return type;
}

// "comment viewpoint x y z": where a sensor saw the cloud from, in the cloud's frame.
Vec3 parse_viewpoint(const std::string& path, std::size_t line_number, const std::vector<std::string_view>& words) {
  Vec3 v;
  for (int i = 0; i < 3; ++i)
    if (!parse_number(words[2 + i], v[i]) || !std::isfinite(v[i]))
      throw header_error(path, line_number, "bad viewpoint comment");
  return v;
}

// "comment recorded-views N" and "comment unmerged-views N": a count of views, a whole number.
int parse_view_count(const std::string& path, std::size_t line_number, const std::vector<std::string_view>& words) {
  double n = 0.0;
  if (!parse_number(words[2], n) || !(n >= 0.0 && n <= kMaxViews) || n != std::floor(n))
    throw header_error(path, line_number, fmt::format("bad {} comment (a whole number of views expected)", words[1]));
  return static_cast<int>(n);
}

PlyFormat parse_format(const std::string& path, std::size_t line_number, const std::vector<std::string_view>& words) {
  if (words.size() != 3) throw header_error(path, line_number, "bad format line");
  if (words[1] == "ascii") return PlyFormat::Ascii;
  if (words[1] == "binary_little_endian") return PlyFormat::BinaryLittle;
  if (words[1] == "binary_big_endian") return PlyFormat::BinaryBig;
  throw header_error(path, line_number, "unknown PLY format " + quoted(words[1]));
}

PlyElement parse_element(const std::string& path, std::size_t line_number, std::string_view line,
                         const std::vector<std::string_view>& words) {
  PlyElement element;
  if (words.size() != 3 || !parse_count(words[2], element.count)) {
    throw header_error(path, line_number, "bad element line " + quoted(line));
  }
  element.name = std::string(words[1]);
  return element;
}

PlyProperty parse_property(const std::string& path, std::size_t line_number, std::string_view line,
                           const std::vector<std::string_view>& words) {
  PlyProperty property;
  if (words.size() == 5 && words[1] == "list") {
    property.is_list = true;
    property.count_type = property_type(path, line_number, words[2]);
    property.type = property_type(path, line_number, words[3]);
    property.name = std::string(words[4]);
  } else if (words.size() == 3) {
    property.type = property_type(path, line_number, words[1]);
    property.name = std::string(words[2]);
  } else {
    throw header_error(path, line_number, "bad property line " + quoted(line));
  }
  return property;
}

// The words from words[first] to the end of the line, with their inner spacing kept.
std::string words_from(const std::vector<std::string_view>& words, std::size_t first) {
  if (words.size() <= first) return {};
  const char* begin = words[first].data();
  return std::string(begin, words.back().data() + words.back().size() - begin);
}

PlyHeader parse_header(const std::string& path, std::string_view data) {
  PlyHeader header;
  LineReader lines(data);
  std::string_view line;
  lines.next(line);  // "ply", checked by the caller
  bool has_format = false, ended = false;
  while (!ended && lines.next(line)) {
    const auto words = split_words(line);
    const std::size_t number = lines.number();
    if (words.empty() || words[0] == "obj_info") continue;
    if (words[0] == "end_header") {
      ended = true;
    } else if (words[0] == "format") {
      header.format = parse_format(path, number, words);
      has_format = true;
    } else if (words[0] == "comment") {
      if (words.size() >= 2 && words[1] == "frame") header.frame = words_from(words, 2);
      if (words.size() == 5 && words[1] == "viewpoint")
        header.viewpoints.push_back(parse_viewpoint(path, number, words));
      if (words.size() == 3 && words[1] == "recorded-views")
        header.recorded_views = parse_view_count(path, number, words);
      if (words.size() == 3 && words[1] == "unmerged-views")
        header.unmerged_views = parse_view_count(path, number, words);
    } else if (words[0] == "element") {
      header.elements.push_back(parse_element(path, number, line, words));
    } else if (words[0] == "property") {
      if (header.elements.empty()) throw header_error(path, number, "property before any element");
      header.elements.back().properties.push_back(parse_property(path, number, line, words));
    } else {
      throw header_error(path, number, "unknown PLY header keyword " + quoted(words[0]));
    }
  }
  if (!ended) throw InputError(path, "PLY header has no end_header");
  if (!has_format) throw InputError(path, "PLY header has no format line");
  header.data_offset = lines.position();
  header.lines = lines.number();
  return header;
}

// Colours may also be named diffuse_red, diffuse_green, diffuse_blue.
int role_of(std::string_view name) {
  static const std::string_view kNames[kRoleCount] = {"x", "y", "z", "red", "green", "blue", "nx", "ny", "nz", "views"};
  const bool diffuse = name.substr(0, 8) == "diffuse_";
  if (diffuse) name.remove_prefix(8);
  for (int role = 0; role < kRoleCount; ++role) {
    if (kNames[role] == name) return !diffuse || (role >= kRed && role <= kBlue) ? role : kNone;
  }
  return kNone;
}

// How the vertex element's properties map onto a point.
struct VertexLayout {
  std::vector<int> roles;               // per property, a Role or kNone
  std::array<double, 3> color_scale{};  // 255 for float colours in 0..1, 1 for integer ones
  bool xyz = false;
  bool colors = false;
  bool normals = false;
  bool views = false;
};

VertexLayout vertex_layout(const PlyElement& vertex) {
  VertexLayout layout;
  std::array<bool, kRoleCount> present{};
  for (const PlyProperty& property : vertex.properties) {
    const int role = property.is_list ? kNone : role_of(property.name);
    layout.roles.push_back(role);
    if (role == kNone) continue;
    present[role] = true;
    const bool is_float = property.type == ScalarType::Float32 || property.type == ScalarType::Float64;
    if (role >= kRed && role <= kBlue) layout.color_scale[role - kRed] = is_float ? 255.0 : 1.0;
  }
  layout.xyz = present[kX] && present[kY] && present[kZ];
  layout.colors = present[kRed] && present[kGreen] && present[kBlue];
  layout.normals = present[kNx] && present[kNy] && present[kNz];
  layout.views = present[kViews];
  return layout;
}

// Clamped to 0..255; NaN reads as 0.
std::uint8_t to_color(double value, double scale) {
  const double scaled = std::round(value * scale);
  if (!(scaled > 0.0)) return 0;
  return static_cast<std::uint8_t>(std::min(scaled, 255.0));
}

// False when the vertex's views are no bit mask (a whole number below 2^32).
bool append_vertex(const VertexLayout& layout, const double* values, PointCloud& cloud) {
  if (layout.views &&
      !(values[kViews] >= 0.0 && values[kViews] < 0x1p32 && values[kViews] == std::floor(values[kViews])))
    return false;
  cloud.points.emplace_back(values[kX], values[kY], values[kZ]);
  if (layout.colors) {
    cloud.colors.push_back({to_color(values[kRed], layout.color_scale[0]),
                            to_color(values[kGreen], layout.color_scale[1]),
                            to_color(values[kBlue], layout.color_scale[2])});
  }
  if (layout.normals) cloud.normals.emplace_back(values[kNx], values[kNy], values[kNz]);
  if (layout.views) cloud.views.push_back(static_cast<std::uint32_t>(values[kViews]));
  return true;
}

// A list length must be a whole, non-negative number.
bool list_length(double value, std::size_t& length) {
  if (!(value >= 0.0) || value != std::floor(value) || value > 1e15) return false;
  length = static_cast<std::size_t>(value);
  return true;
}

class BinarySource {
 public:
  BinarySource(const std::string& path, std::string_view body, bool swap) : path_(path), body_(body), swap_(swap) {}

  bool read(ScalarType type, double& value) {
    const std::size_t size = scalar_size(type);
    if (size > body_.size() - pos_) return false;
    value = load_scalar(body_.data() + pos_, type, swap_);
    pos_ += size;
    return true;
  }

  bool skip_list(ScalarType count_type, ScalarType item_type) {
    double count;
    if (!read(count_type, count)) return false;
    std::size_t length;
    if (!list_length(count, length)) throw InputError(path_, "bad list length at byte " + std::to_string(pos_));
    const std::size_t bytes = length * scalar_size(item_type);
    if (bytes > body_.size() - pos_) return false;
    pos_ += bytes;
    return true;
  }

 private:
  const std::string& path_;
  std::string_view body_;
  std::size_t pos_ = 0;
  bool swap_;
};

class AsciiSource {
 public:
  AsciiSource(const std::string& path, std::string_view body, std::size_t first_line)
      : path_(path), tokens_(body, first_line) {}

  bool read(ScalarType type, double& value) {
    std::string_view token;
    if (!tokens_.next(token)) return false;
    if (!parse_number(token, value)) throw error("bad number " + quoted(token));
    value = as_stored(value, type);
    return true;
  }

  bool skip_list(ScalarType count_type, ScalarType item_type) {
    double count, item;
    if (!read(count_type, count)) return false;
    std::size_t length;
    if (!list_length(count, length)) throw error("bad list length");
    for (std::size_t i = 0; i < length; ++i) {
      if (!read(item_type, item)) return false;
    }
    return true;
  }

 private:
  InputError error(const std::string& problem) const {
    return InputError(path_, "line " + std::to_string(tokens_.line()) + ": " + problem);
  }

  const std::string& path_;
  TokenCursor tokens_;
};

// Reads one record; values of properties with a role land in values[role]. False when the data ends
// inside the record.
template <class Source>
bool read_record(Source& source, const PlyElement& element, const std::vector<int>* roles, double* values) {
  for (std::size_t i = 0; i < element.properties.size(); ++i) {
    const PlyProperty& property = element.properties[i];
    if (property.is_list) {
      if (!source.skip_list(property.count_type, property.type)) return false;
      continue;
    }
    double value;
    if (!source.read(property.type, value)) return false;
    if (roles && (*roles)[i] != kNone) values[(*roles)[i]] = value;
  }
  return true;
}

std::string plural(const std::string& element) { return element == "vertex" ? "vertices" : element + " elements"; }

// The fewest bytes a record of element can take: its binary scalars (a list at least its count), or in
// ASCII one character and a separator per value.
std::size_t min_record_bytes(const PlyElement& element, PlyFormat format) {
  if (format == PlyFormat::Ascii) return 2 * element.properties.size();
  std::size_t bytes = 0;
  for (const PlyProperty& property : element.properties)
    bytes += scalar_size(property.is_list ? property.count_type : property.type);
  return bytes;
}

template <class Source>
void read_body(const std::string& path, Source& source, const PlyHeader& header, const PlyElement& vertex,
               const VertexLayout& layout, std::size_t body_bytes, PointCloud& cloud) {
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;  // no data, however large the count
    const bool is_vertex = &element == &vertex;
    // Reserve no more than the data could hold, so a lying count cannot exhaust memory.
    if (is_vertex) {
      cloud.points.reserve(std::min(element.count, body_bytes / min_record_bytes(element, header.format)));
      if (layout.colors) cloud.colors.reserve(cloud.points.capacity());
      if (layout.normals) cloud.normals.reserve(cloud.points.capacity());
      if (layout.views) cloud.views.reserve(cloud.points.capacity());
    }
    double values[kRoleCount] = {};
    for (std::size_t k = 0; k < element.count; ++k) {
      if (!read_record(source, element, is_vertex ? &layout.roles : nullptr, values)) {
        throw InputError(path, "truncated: expected " + std::to_string(element.count) + " " + plural(element.name) +
                                   ", file ends at " + element.name + " " + std::to_string(k));
      }
      if (is_vertex && !append_vertex(layout, values, cloud))
        throw InputError(path, "vertex " + std::to_string(k) + ": views " + fmt::format("{}", values[kViews]) +
                                   " is no bit mask of views (a whole number from 0 to 2^32 - 1)");
    }
  }
}

}  // namespace

PointCloud parse_ply(const std::string& path, std::string_view data) {
  const PlyHeader header = parse_header(path, data);
  const auto vertex = std::find_if(header.elements.begin(), header.elements.end(),
                                   [](const PlyElement& element) { return element.name == "vertex"; });
  const VertexLayout layout = vertex == header.elements.end() ? VertexLayout{} : vertex_layout(*vertex);
  if (!layout.xyz) throw InputError(path, "PLY has no x/y/z vertex properties");
  if (vertex->count > kMaxCloudPoints)
    throw InputError(path, "PLY header: " + std::to_string(vertex->count) + " vertices, more than the " +
                               std::to_string(kMaxCloudPoints) + " a cloud may hold");

  PointCloud cloud;
  cloud.frame = header.frame;
  cloud.viewpoints = header.viewpoints;
  cloud.recorded_views = header.recorded_views;
  cloud.unmerged_views = header.unmerged_views;
  const std::string_view body = data.substr(header.data_offset);
  if (header.format == PlyFormat::Ascii) {
    AsciiSource source(path, body, header.lines + 1);
    read_body(path, source, header, *vertex, layout, body.size(), cloud);
  } else {
    BinarySource source(path, body, (header.format == PlyFormat::BinaryBig) != host_is_big_endian());
    read_body(path, source, header, *vertex, layout, body.size(), cloud);
  }
  return cloud;
}

}  // namespace io_detail

namespace {

// Header comments must stay on one line.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  return text;
}

std::string ply_header(const PointCloud& cloud, const PlyWriteOptions& options) {
  std::string header = "ply\nformat ";
  header += options.ascii ? "ascii 1.0\n" : "binary_little_endian 1.0\n";
  header += "comment generated by toolinc\n";
  if (!cloud.frame.empty()) header += "comment frame " + one_line(cloud.frame) + "\n";
  for (const auto& v : cloud.viewpoints)
    header += fmt::format("comment viewpoint {:.9g} {:.9g} {:.9g}\n", v.x(), v.y(), v.z());
  if (cloud.recorded_views > 0) header += fmt::format("comment recorded-views {}\n", cloud.recorded_views);
  if (cloud.unmerged_views > 0) header += fmt::format("comment unmerged-views {}\n", cloud.unmerged_views);
  if (!options.command.empty()) header += "comment command " + one_line(options.command) + "\n";
  header += "element vertex " + std::to_string(cloud.size()) + "\n";
  header += "property float x\nproperty float y\nproperty float z\n";
  if (cloud.has_colors()) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (cloud.has_normals()) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (cloud.has_views()) header += "property uint views\n";
  header += "end_header\n";
  return header;
}

void append_float_le(std::string& out, double value, bool swap) {
  const float f = static_cast<float>(value);
  char bytes[sizeof f];
  std::memcpy(bytes, &f, sizeof f);
  if (swap) std::reverse(std::begin(bytes), std::end(bytes));
  out.append(bytes, sizeof bytes);
}

void append_binary(const PointCloud& cloud, std::string& out) {
  const bool swap = io_detail::host_is_big_endian();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) append_float_le(out, cloud.points[i][axis], swap);
    if (cloud.has_colors()) out.append(reinterpret_cast<const char*>(cloud.colors[i].data()), 3);
    if (cloud.has_normals()) {
      for (int axis = 0; axis < 3; ++axis) append_float_le(out, cloud.normals[i][axis], swap);
    }
    if (cloud.has_views()) {
      char bytes[sizeof(std::uint32_t)];
      std::memcpy(bytes, &cloud.views[i], sizeof bytes);
      if (swap) std::reverse(std::begin(bytes), std::end(bytes));
      out.append(bytes, sizeof bytes);
    }
  }
}

// %.9g of the float value: round-trips a float and is the same on every run.
void append_ascii(const PointCloud& cloud, std::string& out) {
  char line[256];
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto f = [](double v) { return static_cast<double>(static_cast<float>(v)); };
    const Vec3& p = cloud.points[i];
    int n = std::snprintf(line, sizeof line, "%.9g %.9g %.9g", f(p.x()), f(p.y()), f(p.z()));
    if (cloud.has_colors()) {
      const Rgb& c = cloud.colors[i];
      n += std::snprintf(line + n, sizeof line - n, " %u %u %u", unsigned{c[0]}, unsigned{c[1]}, unsigned{c[2]});
    }
    if (cloud.has_normals()) {
      const Vec3& m = cloud.normals[i];
      n += std::snprintf(line + n, sizeof line - n, " %.9g %.9g %.9g", f(m.x()), f(m.y()), f(m.z()));
    }
    if (cloud.has_views()) n += std::snprintf(line + n, sizeof line - n, " %u", unsigned{cloud.views[i]});
    out.append(line, static_cast<std::size_t>(n));
    out += '\n';
  }
}

}  // namespace

void write_ply(const std::string& path, const PointCloud& cloud, const PlyWriteOptions& options) {
  if ((cloud.has_colors() && cloud.colors.size() != cloud.size()) ||
      (cloud.has_normals() && cloud.normals.size() != cloud.size()) ||
      (cloud.has_views() && cloud.views.size() != cloud.size())) {
    throw std::invalid_argument("write_ply: colours, normals or views do not match the points in number");
  }
  std::string out = ply_header(cloud, options);
  if (options.ascii) {
    append_ascii(cloud, out);
  } else {
    append_binary(cloud, out);
  }
  write_file_atomic(
      path, [&out](std::ostream& stream) { stream.write(out.data(), static_cast<std::streamsize>(out.size())); },
      !options.ascii);
}

}  // namespace toolinc
