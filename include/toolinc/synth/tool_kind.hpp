// The kind of a tool named by a model file, for per-kind tables: the file name's prefix up to the first
// digit, '_' or '.', lower-cased, with the spellings of one kind grouped (hook -> hok).
#pragma once

#include <string>

namespace toolinc {

// "…/HOK1.pcd" -> "hok", "hook_ICRA.pcd" -> "hok", "sti3.pcd" -> "sti", "flaT.pcd" -> "flat".
std::string tool_kind(const std::string& path);

}  // namespace toolinc
