#include "toolinc/io/json_file.hpp"

#include <spdlog/fmt/fmt.h>

#include <cstdint>
#include <limits>
#include <optional>

#include "toolinc/core/error.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/read_file.hpp"

namespace toolinc {

void check_json_limits(std::string_view text, const std::string& file) {
  if (text.size() > kMaxJsonBytes)
    throw InputError(file,
                     fmt::format("JSON of {} bytes is larger than the {} bytes allowed", text.size(), kMaxJsonBytes));
  std::size_t depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;  // the escaped character cannot end the string
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw InputError(file, fmt::format("JSON nested more than {} levels deep (byte {})", kMaxJsonDepth, i));
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

Json parse_json(std::string_view text, const std::string& file) {
  check_json_limits(text, file);
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(file, fmt::format("not valid JSON (byte {})", e.byte));
  } catch (const nlohmann::json::exception& e) {  // e.g. out_of_range for 1e400
    throw InputError(file, fmt::format("not valid JSON ({})", e.what()));
  }
}

Json read_json(const std::string& path) { return parse_json(read_file(path, kMaxJsonBytes), path); }

void write_json(const std::string& path, const Json& json) {
  write_file_atomic(path, [&](std::ostream& out) { out << json.dump(2) << '\n'; });
}

Json to_json(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json to_json(const Eigen::Matrix4d& m) {
  Json rows = Json::array();
  for (int r = 0; r < 4; ++r) rows.push_back(Json::array({m(r, 0), m(r, 1), m(r, 2), m(r, 3)}));
  return rows;
}

namespace {
double number_at(const Json& value, const std::string& key, const std::string& file) {
  if (!value.is_number()) throw InputError(file, fmt::format("{}: expected numbers", key));
  const double x = value.get<double>();
  if (!std::isfinite(x)) throw InputError(file, fmt::format("{}: non-finite number", key));
  return x;
}
}  // namespace

Eigen::Vector3d vector3_field(const Json& json, const std::string& key, const std::string& file) {
  if (!json.contains(key)) throw InputError(file, fmt::format("missing \"{}\"", key));
  const Json& v = json.at(key);
  if (!v.is_array() || v.size() != 3) throw InputError(file, fmt::format("{}: expected an array of 3 numbers", key));
  return {number_at(v[0], key, file), number_at(v[1], key, file), number_at(v[2], key, file)};
}

Eigen::Matrix4d matrix4_field(const Json& json, const std::string& key, const std::string& file) {
  if (!json.contains(key)) throw InputError(file, fmt::format("missing \"{}\"", key));
  const Json& rows = json.at(key);
  if (!rows.is_array() || rows.size() != 4)
    throw InputError(file, fmt::format("{}: expected 4 rows of 4 numbers", key));
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    if (!rows[r].is_array() || rows[r].size() != 4)
      throw InputError(file, fmt::format("{}: expected 4 rows of 4 numbers", key));
    for (int c = 0; c < 4; ++c) m(r, c) = number_at(rows[r][c], key, file);
  }
  return m;
}

std::string string_field(const Json& json, const std::string& key, const std::string& file) {
  if (!json.is_object() || !json.contains(key)) throw InputError(file, fmt::format("missing \"{}\"", key));
  if (!json.at(key).is_string()) throw InputError(file, fmt::format("\"{}\" must be a string", key));
  return json.at(key).get<std::string>();
}

int int_value(const Json& value, const std::string& what, const std::string& file, int lo, int hi) {
  std::optional<std::int64_t> n;
  if (value.is_number_unsigned()) {
    if (value.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      n = static_cast<std::int64_t>(value.get<std::uint64_t>());
  } else if (value.is_number_integer()) {
    n = value.get<std::int64_t>();
  }
  if (!n || *n < lo || *n > hi)
    throw InputError(file,
                     fmt::format("\"{}\" must be an integer from {} to {} (found {})", what, lo, hi, value.dump()));
  return static_cast<int>(*n);
}

int int_field(const Json& json, const std::string& key, const std::string& file, int lo, int hi) {
  if (!json.is_object() || !json.contains(key)) throw InputError(file, fmt::format("missing \"{}\"", key));
  return int_value(json.at(key), key, file, lo, hi);
}

void check_type(const Json& json, const std::string& type, int supported_version, const std::string& file) {
  if (!json.is_object() || !json.contains("type") || !json["type"].is_string())
    throw InputError(file, fmt::format("not a {} file (no \"type\")", type));
  if (json["type"].get<std::string>() != type)
    throw InputError(file, fmt::format("expected type \"{}\", found \"{}\"", type, json["type"].get<std::string>()));
  const Json& version = json.value("version", Json());
  if (!version.is_number_integer() || version.get<std::int64_t>() < 1 ||
      version.get<std::int64_t>() > supported_version)
    throw InputError(file, fmt::format("unsupported {} version (this build reads up to {})", type, supported_version));
}

}  // namespace toolinc
