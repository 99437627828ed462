#include "toolinc/io/json_file.hpp"

#include <spdlog/fmt/fmt.h>

#include "toolinc/core/error.hpp"
#include "toolinc/io/atomic_file.hpp"

namespace toolinc {

Json read_json(const std::string& path) {
  const std::string text = read_file(path);
  try {
    return Json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path, fmt::format("not valid JSON (byte {})", e.byte));
  }
}

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
  if (!rows.is_array() || rows.size() != 4) throw InputError(file, fmt::format("{}: expected 4 rows of 4 numbers", key));
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    if (!rows[r].is_array() || rows[r].size() != 4)
      throw InputError(file, fmt::format("{}: expected 4 rows of 4 numbers", key));
    for (int c = 0; c < 4; ++c) m(r, c) = number_at(rows[r][c], key, file);
  }
  return m;
}

void check_type(const Json& json, const std::string& type, int supported_version, const std::string& file) {
  if (!json.is_object() || !json.contains("type") || !json["type"].is_string())
    throw InputError(file, fmt::format("not a {} file (no \"type\")", type));
  if (json["type"].get<std::string>() != type)
    throw InputError(file, fmt::format("expected type \"{}\", found \"{}\"", type, json["type"].get<std::string>()));
  if (!json.contains("version") || !json["version"].is_number_integer() ||
      json["version"].get<int>() < 1 || json["version"].get<int>() > supported_version)
    throw InputError(file, fmt::format("unsupported {} version (this build reads up to {})", type, supported_version));
}

}  // namespace toolinc
