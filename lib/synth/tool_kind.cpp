#include "toolinc/synth/tool_kind.hpp"

#include <cctype>
#include <map>

namespace toolinc {

std::string tool_kind(const std::string& path) {
  // Other spellings of one kind in the lab's file names (the CAD models and the real tools).
  static const std::map<std::string, std::string> grouped{{"hook", "hok"}};
  const std::string name = path.substr(path.find_last_of('/') + 1);
  std::string kind;
  for (const char c : name) {
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '_' || c == '.') break;
    kind += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  const auto g = grouped.find(kind);
  return g == grouped.end() ? kind : g->second;
}

}  // namespace toolinc
