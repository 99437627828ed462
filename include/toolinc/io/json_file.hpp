// JSON files: reading with errors that name the file, atomic writing, and the small codecs every
// result uses (4x4 row-major matrices, vectors).
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>

namespace toolinc {

using Json = nlohmann::ordered_json;

// Throws InputError(path, ...) when the file is missing or not valid JSON.
Json read_json(const std::string& path);
// Pretty-printed, newline-terminated, written atomically; "-" is standard output.
void write_json(const std::string& path, const Json& json);

Json to_json(const Eigen::Vector3d& v);
Json to_json(const Eigen::Matrix4d& m);  // 4 rows of 4

// Readers for fields of a result file; they throw InputError(file, "<key>: <problem>").
Eigen::Vector3d vector3_field(const Json& json, const std::string& key, const std::string& file);
Eigen::Matrix4d matrix4_field(const Json& json, const std::string& key, const std::string& file);
// Checks "type" and "version" (<= supported) and throws InputError otherwise.
void check_type(const Json& json, const std::string& type, int supported_version, const std::string& file);

}  // namespace toolinc
