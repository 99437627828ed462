// Kinds of tool for reports over many models: a model's kind from its file name, or from a user's map.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace toolinc {

// File-name stem (or prefix of it) -> kind, matched case-insensitively: an exact stem first, then the
// longest key the stem starts with.
using KindMap = std::map<std::string, std::string>;

// The kind of the model at `path`: from `kinds` when one of its keys matches, otherwise the stem's
// leading letters, lower-cased, with the original data set's abbreviations spelled out (hok -> hook,
// rak -> rake, sho -> shovel, sti -> stick, lstk -> l-stick, flat -> flat-top).
std::string model_kind(const std::string& path, const KindMap& kinds = {});

// A JSON object {"stem or prefix": "kind", ...}. Throws InputError naming the file.
KindMap read_kind_map(const std::string& path);

// The models in `paths`: a folder stands for its .pcd and .ply files, sorted by name. Throws
// InputError for a path that is neither a file nor a folder, or a folder without models.
std::vector<std::string> expand_model_paths(const std::vector<std::string>& paths);

}  // namespace toolinc
