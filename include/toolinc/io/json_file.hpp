// JSON files: reading with errors that name the file, atomic writing, and the small codecs every
// result uses (4x4 row-major matrices, vectors).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace toolinc {

using Json = nlohmann::ordered_json;

// Limits checked before parsing, so a hostile file is one clear error rather than a stack overflow
// (copies and dumps of a JSON value recurse once per level) or an allocation failure. Every JSON file
// the tools write or read nests fewer than 10 levels and weighs well under a megabyte per session.
constexpr std::size_t kMaxJsonDepth = 64;
constexpr std::size_t kMaxJsonBytes = std::size_t{64} << 20;

// Throws InputError(file, ...) when text is larger than kMaxJsonBytes or nests arrays/objects deeper
// than kMaxJsonDepth (brackets inside strings do not count).
void check_json_limits(std::string_view text, const std::string& file);
// check_json_limits, then parses; every parse failure (syntax, a number out of range such as 1e400)
// is an InputError naming the file.
Json parse_json(std::string_view text, const std::string& file);

// Throws InputError(path, ...) when the file is missing, too large, too deep or not valid JSON.
Json read_json(const std::string& path);
// Pretty-printed, newline-terminated, written atomically; "-" is standard output.
void write_json(const std::string& path, const Json& json);

Json to_json(const Eigen::Vector3d& v);
Json to_json(const Eigen::Matrix4d& m);  // 4 rows of 4

// Readers for fields of a result file; they throw InputError(file, "<key>: <problem>").
Eigen::Vector3d vector3_field(const Json& json, const std::string& key, const std::string& file);
std::string string_field(const Json& json, const std::string& key, const std::string& file);
// A JSON integer (not 2.0, not 1e20) within [lo, hi]; otherwise InputError naming what and the range. Read
// through 64 bits first: casting an out-of-range number to int is undefined or wraps (2^32 + 1 would read 1).
int int_value(const Json& value, const std::string& what, const std::string& file, int lo, int hi);
int int_field(const Json& json, const std::string& key, const std::string& file, int lo, int hi);
Eigen::Matrix4d matrix4_field(const Json& json, const std::string& key, const std::string& file);
// Checks "type" and "version" (<= supported) and throws InputError otherwise.
void check_type(const Json& json, const std::string& type, int supported_version, const std::string& file);

}  // namespace toolinc
