// Internals shared by the PLY and PCD readers (private to lib/io): scalar decoding, header lines,
// whitespace tokens with line numbers, and the per-format entry points read_cloud dispatches to.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "toolinc/core/point_cloud.hpp"

namespace toolinc::io_detail {

enum class ScalarType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

std::size_t scalar_size(ScalarType type);
bool host_is_big_endian();

template <class T>
T load_raw(const char* p, bool swap) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  }
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

// Decodes one binary value at p (which must hold scalar_size(type) bytes), swapping bytes when the
// file's byte order differs from the host's.
inline double load_scalar(const char* p, ScalarType type, bool swap) {
  switch (type) {
    case ScalarType::Int8:
      return load_raw<std::int8_t>(p, swap);
    case ScalarType::UInt8:
      return load_raw<std::uint8_t>(p, swap);
    case ScalarType::Int16:
      return load_raw<std::int16_t>(p, swap);
    case ScalarType::UInt16:
      return load_raw<std::uint16_t>(p, swap);
    case ScalarType::Int32:
      return load_raw<std::int32_t>(p, swap);
    case ScalarType::UInt32:
      return load_raw<std::uint32_t>(p, swap);
    case ScalarType::Int64:
      return static_cast<double>(load_raw<std::int64_t>(p, swap));
    case ScalarType::UInt64:
      return static_cast<double>(load_raw<std::uint64_t>(p, swap));
    case ScalarType::Float32:
      return load_raw<float>(p, swap);
    case ScalarType::Float64:
      return load_raw<double>(p, swap);
  }
  return 0.0;
}

// An ascii value of a float property reads as the float a binary file would hold, so both encodings
// of the same cloud read the same.
inline double as_stored(double value, ScalarType type) {
  return type == ScalarType::Float32 ? static_cast<float>(value) : value;
}

// Header lines one at a time, without the line break (a trailing '\r' is dropped too).
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}
  bool next(std::string_view& line);
  std::size_t position() const { return pos_; }   // offset just past the last line returned
  std::size_t number() const { return number_; }  // 1-based number of the last line returned

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t number_ = 0;
};

std::vector<std::string_view> split_words(std::string_view line);

// Whitespace-separated tokens of an ascii body, tracking the line number for error messages.
class TokenCursor {
 public:
  TokenCursor(std::string_view text, std::size_t first_line) : text_(text), line_(first_line) {}
  bool next(std::string_view& token);         // false at the end of the text
  std::size_t line() const { return line_; }  // line of the last token returned

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_;
};

// Whole-token parses; false when the token is not entirely a number.
bool parse_number(std::string_view token, double& value);
bool parse_float(std::string_view token, float& value);
bool parse_count(std::string_view token, std::size_t& value);

std::string quoted(std::string_view text);  // 'text', for error messages

bool looks_like_pcd(std::string_view data);
// Throws InputError(path, ...) for a finite point beyond kMaxCoordinate (limits.hpp) on any axis.
void check_coordinate_range(const std::string& path, const Points& points);

PointCloud parse_ply(const std::string& path, std::string_view data);
PointCloud parse_pcd(const std::string& path, std::string_view data);

}  // namespace toolinc::io_detail
