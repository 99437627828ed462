#include "toolinc/synth/model_kinds.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "toolinc/core/error.hpp"
#include "toolinc/io/json_file.hpp"

namespace toolinc {
namespace {

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

}  // namespace

std::string model_kind(const std::string& path, const KindMap& kinds) {
  const std::string stem = lower(std::filesystem::path(path).stem().string());
  std::string best_key, best_kind;
  for (const auto& [key, kind] : kinds) {
    const std::string k = lower(key);
    if (k == stem) return kind;
    if (stem.rfind(k, 0) == 0 && k.size() > best_key.size()) best_key = k, best_kind = kind;
  }
  if (!best_kind.empty()) return best_kind;
  std::size_t letters = 0;
  while (letters < stem.size() && std::isalpha(static_cast<unsigned char>(stem[letters]))) ++letters;
  const std::string prefix = letters == 0 ? stem : stem.substr(0, letters);
  static const KindMap abbreviations{{"hok", "hook"},  {"rak", "rake"},     {"sho", "shovel"},
                                     {"sti", "stick"}, {"lstk", "l-stick"}, {"flat", "flat-top"}};
  const auto it = abbreviations.find(prefix);
  return it == abbreviations.end() ? prefix : it->second;
}

KindMap read_kind_map(const std::string& path) {
  const Json json = read_json(path);
  if (!json.is_object()) throw InputError(path, "a kind map must be a JSON object {\"stem or prefix\": \"kind\"}");
  KindMap kinds;
  for (const auto& [key, value] : json.items()) {
    if (!value.is_string() || key.empty())
      throw InputError(path, "\"" + key + "\": a kind map's keys and values must be non-empty strings");
    kinds[key] = value.get<std::string>();
  }
  return kinds;
}

std::vector<std::string> expand_model_paths(const std::vector<std::string>& paths) {
  std::vector<std::string> models;
  for (const auto& path : paths) {
    if (std::filesystem::is_regular_file(path)) {
      models.push_back(path);
    } else if (std::filesystem::is_directory(path)) {
      std::vector<std::string> found;
      for (const auto& entry : std::filesystem::directory_iterator(path)) {
        const std::string ext = lower(entry.path().extension().string());
        if (entry.is_regular_file() && (ext == ".pcd" || ext == ".ply")) found.push_back(entry.path().string());
      }
      if (found.empty()) throw InputError(path, "the folder holds no .pcd or .ply model");
      std::sort(found.begin(), found.end());
      models.insert(models.end(), found.begin(), found.end());
    } else {
      throw InputError(path, "no such file or folder");
    }
  }
  return models;
}

}  // namespace toolinc
